//! The thin I/O driver: a [`PacketSocket`] on one interface for EtherType 0x8892 (Linux, needs
//! `CAP_NET_RAW`), the RPC endpoint's UDP socket ([`RpcSocket`]) and [`serve_dcp`], the loop
//! that feeds received frames to the DCP machine alone; the loop of whole devices is
//! [`super::segment`]'s. The protocol machines never see the sockets.

use std::io;
use std::time::{Duration, Instant};

use crate::packet_socket::{interface_index, interface_mac, PacketSocket};

use super::ar::Peer;
use super::dcp::{Dcp, DcpEvent};
use super::wire::{Mac, ETHERTYPE_PROFINET};

/// A packet socket bound to one interface, receiving PROFINET frames.
#[derive(Debug)]
pub struct RawSocket {
    socket: PacketSocket,
    mac: Mac,
    index: i32,
}

impl RawSocket {
    /// Opens a packet socket on `name` for PROFINET frames; reads wait at most `timeout`.
    pub fn open(name: &str, timeout: Duration) -> io::Result<RawSocket> {
        let mac = interface_mac(name)?;
        let index = interface_index(name)?;
        let socket = PacketSocket::open(name, ETHERTYPE_PROFINET, timeout)?;
        Ok(RawSocket { socket, mac, index })
    }

    /// Has the interface accept frames to `mac` too (a simulated device's own address).
    pub fn accept_unicast(&self, mac: Mac) -> io::Result<()> {
        self.socket.accept_unicast(self.index, mac)
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

    /// A second handle on the same socket, so that one thread may read while another sends
    /// (a read timeout goes by the kernel's ticks; a thread blocked in a read wakes when a frame
    /// comes).
    pub fn try_clone(&self) -> io::Result<RawSocket> {
        Ok(RawSocket {
            socket: self.socket.try_clone()?,
            mac: self.mac,
            index: self.index,
        })
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
            if let Err(e) = socket.send(&answer) {
                eprintln!("dropped a DCP answer the socket refused: {e}");
            }
        }
        while let Some(event) = dcp.poll_event() {
            on_event(&event);
        }
    }
    Ok(())
}

/// The device's RPC endpoint: UDP 34964 on all addresses of one interface (`SO_BINDTODEVICE`),
/// non-blocking. Datagrams reach it for the addresses the interface has: the device's IP must
/// be one of them.
#[derive(Debug)]
pub struct RpcSocket {
    socket: std::net::UdpSocket,
}

impl RpcSocket {
    /// Binds UDP 34964 on `iface`.
    pub fn open(iface: &str) -> io::Result<RpcSocket> {
        Self::bind(iface, ([0; 4], super::wire::rpc::RPC_PORT), false)
    }

    /// Binds UDP 34964 at `ip` on `iface` (one device's endpoint among several), even before the
    /// interface has the address (`IP_FREEBIND`: datagrams come once it has).
    pub fn open_at(iface: &str, ip: [u8; 4]) -> io::Result<RpcSocket> {
        Self::bind(iface, (ip, super::wire::rpc::RPC_PORT), true)
    }

    /// Binds a port the system chooses on `iface`: a client's, for calls outside any AR.
    pub fn open_client(iface: &str) -> io::Result<RpcSocket> {
        Self::bind(iface, ([0; 4], 0), false)
    }

    fn bind(iface: &str, at: Peer, freebind: bool) -> io::Result<RpcSocket> {
        use socket2::{Domain, Protocol, Socket, Type};
        let socket = Socket::new(Domain::IPV4, Type::DGRAM, Some(Protocol::UDP))?;
        socket.set_reuse_address(true)?;
        socket.set_freebind_v4(freebind)?;
        socket.bind_device(Some(iface.as_bytes()))?;
        socket.bind(&std::net::SocketAddr::from(at).into())?;
        socket.set_nonblocking(true)?;
        Ok(RpcSocket {
            socket: socket.into(),
        })
    }

    /// The next datagram and its IPv4 sender, if one is waiting.
    pub fn recv(&self, buf: &mut [u8]) -> io::Result<Option<(usize, Peer)>> {
        match self.socket.recv_from(buf) {
            Ok((n, std::net::SocketAddr::V4(from))) => {
                Ok(Some((n, (from.ip().octets(), from.port()))))
            }
            Ok(_) => Ok(None),
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Sends `pdu` to `to`.
    pub fn send(&self, to: Peer, pdu: &[u8]) -> io::Result<()> {
        self.socket
            .send_to(pdu, std::net::SocketAddr::from((to.0, to.1)))
            .map(|_| ())
    }
}
