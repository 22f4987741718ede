//! Waiting for a socket to become readable with `poll(2)`, the one way this crate's blocking
//! loops wait against a deadline.
//!
//! A socket's own read timeout (`SO_RCVTIMEO`) counts in scheduler ticks: on a 250 Hz kernel a
//! 1 ms wait took 8 ms and a 10 ms wait 16 ms, while `poll(2)` keeps its time to about the
//! microsecond. Loops with a period (a node's timers, an EtherNet/IP connection's RPI) wait here.

use std::io;
use std::os::fd::AsFd;
use std::time::Duration;

/// Waits until `socket` has something to read (`Ok(true)`) or `timeout` has passed (`Ok(false)`,
/// also when a signal interrupted the wait).
///
/// ```
/// use std::net::UdpSocket;
/// use std::time::Duration;
///
/// let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
/// assert!(!edsgen_host::wait::readable(&socket, Duration::from_millis(1)).unwrap());
/// socket.send_to(b"x", socket.local_addr().unwrap()).unwrap();
/// assert!(edsgen_host::wait::readable(&socket, Duration::from_secs(1)).unwrap());
/// ```
pub fn readable(socket: &impl AsFd, timeout: Duration) -> io::Result<bool> {
    use rustix::event::{poll, PollFd, PollFlags, Timespec};
    let mut fds = [PollFd::new(socket, PollFlags::IN)];
    let timeout = Timespec {
        tv_sec: i64::try_from(timeout.as_secs()).unwrap_or(i64::MAX),
        tv_nsec: i64::from(timeout.subsec_nanos()),
    };
    match poll(&mut fds, Some(&timeout)) {
        Ok(ready) => Ok(ready > 0),
        Err(rustix::io::Errno::INTR) => Ok(false),
        Err(e) => Err(e.into()),
    }
}
