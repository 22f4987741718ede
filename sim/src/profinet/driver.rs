//! The thin I/O driver: a [`PacketSocket`] on one interface for EtherType 0x8892 (Linux, needs
//! `CAP_NET_RAW`), the RPC endpoint's UDP socket ([`RpcSocket`]), [`serve_dcp`], the loop that
//! feeds received frames to the DCP machine alone, and [`serve`], the loop of the whole
//! [`Device`]. The protocol machines never see the sockets.

use std::io;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use edsgen_host::driver::MonotonicClock;

use crate::packet_socket::{interface_mac, PacketSocket};

use super::ar::Peer;
use super::dcp::{Dcp, DcpEvent};
use super::device::{Device, DeviceEvent, Link, Transmit};
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

    /// A second handle on the same socket, so that one thread may read while another sends
    /// (a read timeout goes by the kernel's ticks; a thread blocked in a read wakes when a frame
    /// comes).
    pub fn try_clone(&self) -> io::Result<RawSocket> {
        Ok(RawSocket {
            socket: self.socket.try_clone()?,
            mac: self.mac,
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
        use socket2::{Domain, Protocol, Socket, Type};
        let socket = Socket::new(Domain::IPV4, Type::DGRAM, Some(Protocol::UDP))?;
        socket.set_reuse_address(true)?;
        socket.bind_device(Some(iface.as_bytes()))?;
        let any = std::net::SocketAddr::from(([0, 0, 0, 0], super::wire::rpc::RPC_PORT));
        socket.bind(&any.into())?;
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

/// Serves the whole device until `until` passes (forever with `None`): a DCP Hello, then DCP
/// and cyclic frames on `raw` (opened with a short read timeout: it paces the loop), RPC
/// datagrams on `rpc`, the device's own datagrams and frames when due; each event is passed to
/// `on_event`.
pub fn serve(
    raw: &mut RawSocket,
    rpc: &RpcSocket,
    device: &mut Device,
    until: Option<Instant>,
    on_event: impl FnMut(&DeviceEvent),
) -> io::Result<()> {
    serve_with(
        raw,
        rpc,
        device,
        until,
        |_, _| ControlFlow::Continue(()),
        on_event,
    )
}

/// [`serve`], with `tick` given the device and the time once a round, before its timers (to
/// act on the device from outside, such as a drive fault switched by standard input); serving
/// ends when it breaks (a stop asked for).
pub fn serve_with(
    raw: &mut RawSocket,
    rpc: &RpcSocket,
    device: &mut Device,
    until: Option<Instant>,
    mut tick: impl FnMut(&mut Device, edsgen_runtime::Instant) -> ControlFlow<()>,
    mut on_event: impl FnMut(&DeviceEvent),
) -> io::Result<()> {
    let clock = MonotonicClock::new();
    let hello = device.dcp().hello();
    if let Err(e) = raw.send(&hello) {
        eprintln!("dropped the DCP Hello the socket refused: {e}");
    }
    let mut buf = vec![0u8; 1600];
    let mut dgram = vec![0u8; 4096];
    while until.is_none_or(|t| Instant::now() < t) {
        if let Some(n) = raw.recv(&mut buf)? {
            device.handle(clock.now(), Link::Ethernet, &buf[..n.min(buf.len())]);
            send(raw, rpc, device, clock.now())?;
        }
        while let Some((n, from)) = rpc.recv(&mut dgram)? {
            device.handle(clock.now(), Link::Rpc(from), &dgram[..n.min(dgram.len())]);
            send(raw, rpc, device, clock.now())?;
        }
        let now = clock.now();
        if tick(device, now).is_break() {
            break;
        }
        if device.poll_timeout().is_some_and(|t| t <= now) {
            device.handle_timeout(now);
        }
        send(raw, rpc, device, now)?;
        while let Some(event) = device.poll_event() {
            on_event(&event);
        }
    }
    Ok(())
}

/// Sends what the device has to send at `now`: frames on `raw`, datagrams on `rpc`. An answer
/// the socket refuses is said on standard error and dropped: one bad request never stops the
/// device (the errors that do are the sockets' reads).
fn send(
    raw: &mut RawSocket,
    rpc: &RpcSocket,
    device: &mut Device,
    now: edsgen_runtime::Instant,
) -> io::Result<()> {
    while let Some(transmit) = device.poll_transmit(now) {
        let (sent, what) = match &transmit {
            Transmit::Frame(frame) => {
                (raw.send(frame), format!("a frame of {} bytes", frame.len()))
            }
            Transmit::Datagram(to, pdu) => (
                rpc.send(*to, pdu),
                format!(
                    "a datagram of {} bytes to {}:{}",
                    pdu.len(),
                    core::net::Ipv4Addr::from(to.0),
                    to.1
                ),
            ),
        };
        if let Err(e) = sent {
            eprintln!("dropped {what} the socket refused: {e}");
        }
    }
    Ok(())
}
