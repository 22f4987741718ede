//! The thin I/O driver: a [`PacketSocket`] on one interface for EtherType 0x8892 (Linux, needs
//! `CAP_NET_RAW`), and [`serve_dcp`], the loop that feeds received frames to the DCP machine and
//! sends its answers. The protocol machines never see the socket.

use std::io;
use std::time::{Duration, Instant};

use crate::packet_socket::{interface_mac, PacketSocket};

use super::dcp::{Dcp, DcpEvent};
use super::wire::{Mac, ETHERTYPE_PROFINET};

/// A packet socket bound to one interface, receiving PROFINET frames.
#[derive(Debug)]
pub struct RawSocket {
    socket: PacketSocket,
    mac: Mac,
}

impl RawSocket {
    /// Opens a packet socket on `name` for PROFINET frames; reads wait at most `timeout`.
    pub fn open(name: &str, timeout: Duration) -> io::Result<RawSocket> {
        let mac = interface_mac(name)?;
        let socket = PacketSocket::open(name, ETHERTYPE_PROFINET, timeout)?;
        Ok(RawSocket { socket, mac })
    }

    /// The interface's MAC address.
    pub fn mac(&self) -> Mac {
        self.mac
    }

    /// Sends one frame, padded to Ethernet's 60-byte minimum.
    pub fn send(&mut self, frame: &[u8]) -> io::Result<()> {
        let mut frame = frame.to_vec();
        super::wire::pad(&mut frame);
        self.socket.send(&frame)
    }

    /// Reads one frame into `buf`; `Ok(None)` when the timeout passed first.
    pub fn recv(&mut self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        self.socket.recv(buf)
    }
}

/// Serves DCP on `socket` until `until` passes (forever with `None`): a Hello at start, then
/// every frame to the machine and its answers back; each event is passed to `on_event`.
pub fn serve_dcp(
    socket: &mut RawSocket,
    dcp: &mut Dcp,
    until: Option<Instant>,
    mut on_event: impl FnMut(&DcpEvent),
) -> io::Result<()> {
    socket.send(&dcp.hello())?;
    let mut buf = vec![0u8; 1600];
    while until.is_none_or(|t| Instant::now() < t) {
        let Some(n) = socket.recv(&mut buf)? else {
            continue;
        };
        if let Some(answer) = buf.get(..n).and_then(|frame| dcp.handle(frame)) {
            socket.send(&answer)?;
        }
        while let Some(event) = dcp.poll_event() {
            on_event(&event);
        }
    }
    Ok(())
}
