//! Runs a sans-IO device (anything that is a [`BusDevice`], such as a [`Node`](edsgen_runtime::Node)) on a
//! [`Transport`] in real time: received frames go in, offered frames go out, and the device's
//! timers fire at its deadlines, on a [`MonotonicClock`]. On the current thread until a stop flag
//! is set, or on a thread of its own ([`Driver::spawn`]).

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration as StdDuration, Instant as StdInstant};

use super::Transport;
use crate::vbus::BusDevice;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::time::Instant;

/// The runtime's [`Instant`] from the operating system's monotonic clock: microseconds since
/// the clock was made.
#[derive(Debug, Clone, Copy)]
pub struct MonotonicClock {
    origin: StdInstant,
}

impl MonotonicClock {
    /// A clock that reads [`Instant`] 0 now.
    pub fn new() -> Self {
        MonotonicClock {
            origin: StdInstant::now(),
        }
    }

    /// Now on this clock.
    pub fn now(&self) -> Instant {
        Instant::from_micros(self.origin.elapsed().as_micros() as u64)
    }
}

impl Default for MonotonicClock {
    fn default() -> Self {
        MonotonicClock::new()
    }
}

/// A device, the transport it talks through, and the clock it runs on.
#[derive(Debug)]
pub struct Driver<T, D> {
    transport: T,
    device: D,
    clock: MonotonicClock,
    max_wait: StdDuration,
}

/// How long the driver waits for a frame at most by default before it looks at its stop flag
/// (and at a device changed from another thread) again.
pub const DEFAULT_MAX_WAIT: StdDuration = StdDuration::from_millis(5);

impl<T: Transport, D: BusDevice> Driver<T, D> {
    /// A driver whose clock starts now. A device made before should have been given the
    /// instant 0 (or use [`Driver::with_clock`]).
    pub fn new(transport: T, device: D) -> Self {
        Driver::with_clock(transport, device, MonotonicClock::new())
    }

    /// A driver on `clock`, the clock the device was made with.
    pub fn with_clock(transport: T, device: D, clock: MonotonicClock) -> Self {
        Driver {
            transport,
            device,
            clock,
            max_wait: DEFAULT_MAX_WAIT,
        }
    }

    /// Sets how long the driver waits for a frame at most before it looks at its stop flag
    /// (and at the device, which another thread may have changed) again.
    pub fn set_max_wait(&mut self, max_wait: StdDuration) {
        self.max_wait = max_wait;
    }

    /// The driver's clock.
    pub fn clock(&self) -> MonotonicClock {
        self.clock
    }

    /// The device.
    pub fn device(&self) -> &D {
        &self.device
    }

    /// The device, to change it between steps.
    pub fn device_mut(&mut self) -> &mut D {
        &mut self.device
    }

    /// The transport.
    pub fn transport_mut(&mut self) -> &mut T {
        &mut self.transport
    }

    /// Gives back the transport and the device.
    pub fn into_parts(self) -> (T, D) {
        (self.transport, self.device)
    }

    /// One round: fires due timers, sends what the device offers, then waits at most
    /// `max_wait` (less if a deadline comes sooner) for a frame and hands it to the device.
    /// An error is the transport's: the bus is gone.
    pub fn step(&mut self, max_wait: StdDuration) -> io::Result<()> {
        let now = self.clock.now();
        if self.device.poll_timeout().is_some_and(|at| at <= now) {
            self.device.handle_timeout(now);
        }
        while let Some(frame) = self.device.poll_transmit(now) {
            self.transport.send(&frame)?;
        }
        let wait = match self.device.poll_timeout() {
            Some(at) => max_wait.min(StdDuration::from_micros((at - now).as_micros())),
            None => max_wait,
        };
        if let Some(frame) = self.transport.recv_timeout(wait)? {
            self.handle(&frame);
        }
        Ok(())
    }

    fn handle(&mut self, frame: &CanFrame) {
        let now = self.clock.now();
        self.device.handle_frame(now, frame);
    }

    /// Runs until `stop` is set (checked at least every [`Driver::set_max_wait`]) or the
    /// transport fails.
    pub fn run(&mut self, stop: &AtomicBool) -> io::Result<()> {
        while !stop.load(Ordering::Relaxed) {
            self.step(self.max_wait)?;
        }
        Ok(())
    }
}

impl<T, D> Driver<T, D>
where
    T: Transport + Send + 'static,
    D: BusDevice + Send + 'static,
{
    /// Runs the driver on a thread of its own. The handle reaches the device while it runs and
    /// stops the thread.
    pub fn spawn(self) -> io::Result<DriverHandle<T, D>> {
        let device = Arc::new(Mutex::new(self.device));
        let stop = Arc::new(AtomicBool::new(false));
        let mut driver = Driver {
            transport: self.transport,
            device: SharedDevice(Arc::clone(&device)),
            clock: self.clock,
            max_wait: self.max_wait,
        };
        let thread = {
            let stop = Arc::clone(&stop);
            thread::Builder::new()
                .name("edsgen-driver".into())
                .spawn(move || {
                    let result = driver.run(&stop);
                    (result, driver.transport)
                })?
        };
        Ok(DriverHandle {
            device,
            stop,
            clock: self.clock,
            thread,
        })
    }
}

/// A device shared between a driver thread and its handle.
struct SharedDevice<D>(Arc<Mutex<D>>);

fn lock<D>(device: &Mutex<D>) -> MutexGuard<'_, D> {
    device
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl<D: BusDevice> BusDevice for SharedDevice<D> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        lock(&self.0).handle_frame(now, frame);
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        lock(&self.0).poll_transmit(now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        lock(&self.0).poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        lock(&self.0).handle_timeout(now);
    }
}

/// A driver running on its own thread.
#[derive(Debug)]
pub struct DriverHandle<T, D> {
    device: Arc<Mutex<D>>,
    stop: Arc<AtomicBool>,
    clock: MonotonicClock,
    thread: JoinHandle<(io::Result<()>, T)>,
}

impl<T, D> DriverHandle<T, D> {
    /// Runs `f` on the device between two steps of the driver, with the driver's time now. What
    /// the device then offers goes out within the driver's maximum wait.
    pub fn with_device<R>(&self, f: impl FnOnce(&mut D, Instant) -> R) -> R {
        let mut device = lock(&self.device);
        f(&mut device, self.clock.now())
    }

    /// Whether the driver stopped by itself (its transport failed).
    pub fn is_finished(&self) -> bool {
        self.thread.is_finished()
    }

    /// Stops the driver and gives back how it ended (an error if the transport failed), the
    /// transport and the device.
    pub fn stop(self) -> (io::Result<()>, T, D) {
        self.stop.store(true, Ordering::Relaxed);
        let (result, transport) = match self.thread.join() {
            Ok(ended) => ended,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        let device = match Arc::try_unwrap(self.device) {
            Ok(device) => device.into_inner().unwrap_or_else(|p| p.into_inner()),
            // The driver thread has ended and dropped its handle on the device.
            Err(_) => unreachable!("the driver thread still holds the device"),
        };
        (result, transport, device)
    }
}
