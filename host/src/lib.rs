//! edsgen-host: the operating-system side of [`edsgen_runtime`], whose protocol cores are sans-IO
//! and `no_std`. Here live what needs threads, sockets or a clock.
//!
//! One trait, [`Transport`], that every transport implements: send a frame, receive one with a
//! timeout. A device node and a master are both driven through it, so the same driver code runs
//! over the in-memory bus in tests, a socketcand hub on loopback, and Linux SocketCAN.
//! Beside them, [`vbus`]: the deterministic in-memory bus that steps sans-IO devices by a
//! simulated clock, with no transport and no threads; and [`master`]: the blocking and the
//! async CANopen master, which run the runtime's master cores on a transport.
//!
//! Blocking by design: a transport is owned by one driver thread, which also owns the sans-IO core
//! it feeds; an async driver wraps a transport in its own task.
//!
//! Cargo features:
//! - `socketcan` (Linux): Linux SocketCAN as a transport, through the `socketcan` crate.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

use std::io;
use std::time::Duration as StdDuration;

use edsgen_runtime::frame::CanFrame;

pub mod dp_line;
pub mod driver;
pub mod hub;
pub mod master;
pub mod memory;
pub mod segment;
#[cfg(all(feature = "socketcan", target_os = "linux"))]
pub mod socketcan;
pub mod socketcand;
pub mod trace;
pub mod vbus;
pub mod wait;

/// A CAN bus as an operating system reaches it.
///
/// A transport does not echo a frame back to its own sender (CAN controllers and socketcand do
/// not either), so a driver sees only what other nodes sent.
pub trait Transport {
    /// Queues `frame` for sending. An error means the bus is gone (a closed socket), not that the
    /// frame was lost on a busy bus.
    fn send(&mut self, frame: &CanFrame) -> io::Result<()>;

    /// The next received frame, waiting at most `timeout`; `Ok(None)` if none arrived in time.
    /// A zero timeout polls.
    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>>;
}

impl<T: Transport + ?Sized> Transport for &mut T {
    fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
        (**self).send(frame)
    }
    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>> {
        (**self).recv_timeout(timeout)
    }
}

impl<T: Transport + ?Sized> Transport for Box<T> {
    fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
        (**self).send(frame)
    }
    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>> {
        (**self).recv_timeout(timeout)
    }
}
