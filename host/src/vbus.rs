//! A simulated CAN bus (feature `std`) that connects sans-IO devices in one process, for tests.
//!
//! The bus owns the clock: [`VirtualBus::run_until`] advances it from one device deadline to the
//! next, delivers every frame a device offers to all other devices at once (zero transmission
//! time, lowest identifier first when several wait, as CAN arbitration would) and logs it. No
//! threads, no sleeps: the same script gives the same frames at the same instants every time.

use edsgen_runtime::frame::{CanFrame, CanId};
use edsgen_runtime::master::{LssMaster, NodeMonitor, SdoClient, SyncProducer};
use edsgen_runtime::node::{Node, NodeHooks};
use edsgen_runtime::od::ObjectDictionary;
use edsgen_runtime::time::Instant;

/// Something that sits on the bus: the sans-IO shape every protocol core here has.
pub trait BusDevice {
    /// Takes a frame another device sent.
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame);
    /// The next frame this device wants to send.
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame>;
    /// When this device next needs [`BusDevice::handle_timeout`].
    fn poll_timeout(&self) -> Option<Instant>;
    /// Runs the device's timers due at `now`.
    fn handle_timeout(&mut self, now: Instant);
}

impl<O: ObjectDictionary, H: NodeHooks<O>, const R: usize, const T: usize> BusDevice
    for Node<O, H, R, T>
{
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        Node::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        Node::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        Node::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: Instant) {
        Node::handle_timeout(self, now)
    }
}

impl<D: BusDevice + ?Sized> BusDevice for Box<D> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        (**self).handle_frame(now, frame)
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        (**self).poll_transmit(now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        (**self).poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        (**self).handle_timeout(now)
    }
}

impl<const BUF: usize> BusDevice for SdoClient<BUF> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        SdoClient::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        SdoClient::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        SdoClient::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: Instant) {
        SdoClient::handle_timeout(self, now)
    }
}

impl<const N: usize> BusDevice for NodeMonitor<N> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        NodeMonitor::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        NodeMonitor::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        NodeMonitor::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: Instant) {
        NodeMonitor::handle_timeout(self, now)
    }
}

impl BusDevice for LssMaster {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        LssMaster::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        LssMaster::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        LssMaster::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: Instant) {
        LssMaster::handle_timeout(self, now)
    }
}

impl BusDevice for SyncProducer {
    fn handle_frame(&mut self, _now: Instant, _frame: &CanFrame) {}
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        SyncProducer::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        SyncProducer::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: Instant) {
        SyncProducer::handle_timeout(self, now)
    }
}

/// A peer that sends frames at scripted instants and records what it receives.
#[derive(Debug, Default, Clone)]
pub struct ScriptedPeer {
    script: Vec<(Instant, CanFrame)>,
    ready: Vec<CanFrame>,
    /// Every frame the peer received, with the instant.
    pub received: Vec<(Instant, CanFrame)>,
}

impl ScriptedPeer {
    /// A peer with nothing to say.
    pub fn new() -> Self {
        ScriptedPeer::default()
    }

    /// Schedules `frame` at `at`. Frames scheduled for the same instant go out in order.
    pub fn send_at(&mut self, at: Instant, frame: CanFrame) {
        let pos = self.script.partition_point(|(t, _)| *t <= at);
        self.script.insert(pos, (at, frame));
    }
}

impl BusDevice for ScriptedPeer {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.received.push((now, *frame));
    }
    fn poll_transmit(&mut self, _now: Instant) -> Option<CanFrame> {
        (!self.ready.is_empty()).then(|| self.ready.remove(0))
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.script.first().map(|(at, _)| *at)
    }
    fn handle_timeout(&mut self, now: Instant) {
        while self.script.first().is_some_and(|(at, _)| *at <= now) {
            let (_, frame) = self.script.remove(0);
            self.ready.push(frame);
        }
    }
}

/// The bus: a clock, the frames each device has offered but not yet won arbitration with, and
/// the log of every frame sent.
#[derive(Debug, Default)]
pub struct VirtualBus {
    now: Instant,
    waiting: Vec<Option<CanFrame>>,
    log: Vec<(Instant, usize, CanFrame)>,
}

/// How many frames may go out at one instant before the bus declares a device stuck.
const MAX_FRAMES_PER_INSTANT: usize = 10_000;

fn arbitration_key(frame: &CanFrame) -> (u32, bool) {
    match frame.id() {
        CanId::Standard(id) => (u32::from(id) << 18, frame.is_remote()),
        CanId::Extended(id) => (id, frame.is_remote()),
    }
}

impl VirtualBus {
    /// A bus whose clock starts at `now`.
    pub fn new(now: Instant) -> Self {
        VirtualBus {
            now,
            ..VirtualBus::default()
        }
    }

    /// The bus clock.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// Every frame sent so far: the instant, the index of the sending device in the slice given
    /// to the bus (`usize::MAX` for [`VirtualBus::inject`]), and the frame.
    pub fn log(&self) -> &[(Instant, usize, CanFrame)] {
        &self.log
    }

    /// Takes the log, leaving it empty.
    pub fn take_log(&mut self) -> Vec<(Instant, usize, CanFrame)> {
        core::mem::take(&mut self.log)
    }

    /// Sends a frame from outside the device slice (a test's master) now, delivers what the
    /// devices answer at this instant.
    pub fn inject(&mut self, frame: CanFrame, devices: &mut [&mut dyn BusDevice]) {
        self.log.push((self.now, usize::MAX, frame));
        for device in devices.iter_mut() {
            device.handle_frame(self.now, &frame);
        }
        self.deliver(devices);
    }

    /// Delivers every frame the devices offer at the current instant, lowest identifier first.
    fn deliver(&mut self, devices: &mut [&mut dyn BusDevice]) {
        self.waiting.resize(devices.len(), None);
        for _ in 0..MAX_FRAMES_PER_INSTANT {
            for (slot, device) in self.waiting.iter_mut().zip(devices.iter_mut()) {
                if slot.is_none() {
                    *slot = device.poll_transmit(self.now);
                }
            }
            let winner = self
                .waiting
                .iter()
                .enumerate()
                .filter_map(|(i, f)| f.map(|f| (arbitration_key(&f), i)))
                .min();
            let Some((_, sender)) = winner else {
                return;
            };
            let Some(frame) = self.waiting[sender].take() else {
                return;
            };
            self.log.push((self.now, sender, frame));
            for (i, device) in devices.iter_mut().enumerate() {
                if i != sender {
                    device.handle_frame(self.now, &frame);
                }
            }
        }
        panic!("virtual bus: more than {MAX_FRAMES_PER_INSTANT} frames at one instant");
    }

    /// Runs the devices until `until`: timers fire at their deadlines, frames are delivered at
    /// once. The clock ends at `until`.
    pub fn run_until(&mut self, until: Instant, devices: &mut [&mut dyn BusDevice]) {
        let mut rounds_at_instant = 0;
        loop {
            self.deliver(devices);
            let next = devices.iter().filter_map(|d| d.poll_timeout()).min();
            match next {
                Some(at) if at <= until => {
                    if at <= self.now {
                        rounds_at_instant += 1;
                        assert!(
                            rounds_at_instant < MAX_FRAMES_PER_INSTANT,
                            "virtual bus: a device keeps asking for a timeout at {:?}",
                            self.now
                        );
                    } else {
                        rounds_at_instant = 0;
                        self.now = at;
                    }
                    for device in devices.iter_mut() {
                        if device.poll_timeout().is_some_and(|t| t <= self.now) {
                            device.handle_timeout(self.now);
                        }
                    }
                }
                _ => {
                    self.now = until.max(self.now);
                    return;
                }
            }
        }
    }
}
