//! The SubDevice's socket: a [`crate::packet_socket::PacketSocket`] for EtherCAT
//! frames (EtherType 0x88A4), the thin I/O under the sans-IO [`SubDevice`](super::SubDevice).

use std::io;
use std::time::Duration;

use crate::packet_socket::PacketSocket;

use edsgen_runtime::ethercat::wire::frame::ETHERTYPE;

/// A packet socket bound to one interface, receiving EtherCAT frames only.
#[derive(Debug)]
pub struct RawSocket {
    socket: PacketSocket,
}

impl RawSocket {
    /// Opens `iface` (root, or CAP_NET_RAW, is needed); reads wait at most `timeout`.
    pub fn open(iface: &str, timeout: Duration) -> io::Result<Self> {
        let socket = PacketSocket::open(iface, ETHERTYPE, timeout)?;
        Ok(RawSocket { socket })
    }

    /// Reads one frame into `buf`; `Ok(None)` when the timeout passed first.
    pub fn recv(&mut self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        self.socket.recv(buf)
    }

    /// Sends one frame.
    pub fn send(&mut self, frame: &[u8]) -> io::Result<()> {
        self.socket.send(frame)
    }
}
