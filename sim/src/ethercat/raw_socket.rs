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
        // The SubDevices' answers are not read back. A kernel without the option (before 4.20)
        // still delivers them, and `serve` passes them by (their source address says so).
        let _ = socket.ignore_outgoing();
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

/// What to say when `iface` cannot be opened: the error, and for a permission error what the
/// raw socket needs.
pub fn open_error(iface: &str, err: &io::Error) -> String {
    if err.kind() == io::ErrorKind::PermissionDenied {
        format!(
            "cannot open {iface}: {err}: a raw socket needs root or CAP_NET_RAW (run as root, or \
             give the binary the capability: sudo setcap cap_net_raw+ep $(which edsgen))"
        )
    } else {
        format!("cannot open {iface}: {err}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_permission_error_names_root_and_cap_net_raw() {
        let denied = io::Error::from_raw_os_error(1);
        assert_eq!(
            open_error("ecs", &denied),
            "cannot open ecs: Operation not permitted (os error 1): a raw socket needs root or \
             CAP_NET_RAW (run as root, or give the binary the capability: sudo setcap \
             cap_net_raw+ep $(which edsgen))"
        );
        let missing = io::Error::from_raw_os_error(19);
        assert_eq!(
            open_error("ecs", &missing),
            "cannot open ecs: No such device (os error 19)"
        );
    }
}
