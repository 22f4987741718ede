//! The adapter on real sockets, a thin driver around the sans-IO core: encapsulation on TCP
//! (the address given, 44818 by default) and ListIdentity on UDP at the same port (and on every
//! address's, for broadcasts, when the address is unicast), class-1 I/O
//! on UDP 2222 (T→O to the originator's address, port 2222 or the one its Forward_Open's T→O
//! sockaddr item names). One thread, non-blocking sockets,
//! a millisecond tick. A bad client never stops the others: its bytes get the protocol's
//! refusal, and a client that sends what is no encapsulation header is dropped. What sits behind
//! the adapter is its application ([`EnipApplication`]), not the driver's business.

use std::collections::BTreeMap;
use std::io::{ErrorKind, Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};

use edsgen_host::driver::MonotonicClock;
use edsgen_runtime::enip::wire::io::IoDatagram;
use edsgen_runtime::Instant;

use super::{Adapter, EnipApplication, Event, Peer};

/// The class-1 I/O port.
pub const IO_PORT: u16 = 2222;

struct Client {
    stream: TcpStream,
    peer: IpAddr,
    buffer: Vec<u8>,
}

/// The adapter's sockets, bound: encapsulation on TCP and UDP at the address, class-1 I/O on
/// UDP 2222 of it (when that port is taken, explicit messages only), and for a unicast address
/// UDP at the same port of every address, where Linux delivers broadcasts (answered from the
/// unicast socket, so with the adapter's own address).
pub struct Sockets {
    listener: TcpListener,
    udp: UdpSocket,
    broadcast: Option<UdpSocket>,
    io: Option<UdpSocket>,
}

/// A non-blocking UDP socket on `address` sharing its port (SO_REUSEADDR): the unicast and the
/// wildcard socket of one adapter, and those of other adapters on the host, all receive a
/// broadcast.
fn shared_udp(address: SocketAddr) -> std::io::Result<UdpSocket> {
    let socket = socket2::Socket::new(
        socket2::Domain::IPV4,
        socket2::Type::DGRAM,
        Some(socket2::Protocol::UDP),
    )?;
    socket.set_reuse_address(true)?;
    socket.set_nonblocking(true)?;
    socket.bind(&address.into())?;
    Ok(socket.into())
}

/// What a run served, for the line it ends with.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Served {
    /// TCP clients accepted.
    pub clients: u64,
    /// Connections opened (class 1 and class 3).
    pub connections: u64,
}

/// Binds the adapter's sockets on `address`. `log` gets a line when class-1 I/O is off.
pub fn bind(address: SocketAddr, mut log: impl FnMut(String)) -> std::io::Result<Sockets> {
    let listener = TcpListener::bind(address)?;
    listener.set_nonblocking(true)?;
    let udp = match address.ip() {
        IpAddr::V4(ip) if !ip.is_unspecified() && !ip.is_loopback() => shared_udp(address)?,
        _ => {
            let udp = UdpSocket::bind(address)?;
            udp.set_nonblocking(true)?;
            udp
        }
    };
    let broadcast = match address.ip() {
        IpAddr::V4(ip) if !ip.is_unspecified() && !ip.is_loopback() => {
            let any = SocketAddr::new(IpAddr::V4(std::net::Ipv4Addr::UNSPECIFIED), address.port());
            match shared_udp(any) {
                Ok(socket) => Some(socket),
                Err(err) => {
                    log(format!("broadcast ListIdentity off: UDP {any}: {err}"));
                    None
                }
            }
        }
        _ => None,
    };
    let io = match UdpSocket::bind(SocketAddr::new(address.ip(), IO_PORT)) {
        Ok(socket) => {
            socket.set_nonblocking(true)?;
            Some(socket)
        }
        Err(err) => {
            log(format!(
                "class-1 I/O off: UDP {IO_PORT} on {}: {err}",
                address.ip()
            ));
            None
        }
    };
    Ok(Sockets {
        listener,
        udp,
        broadcast,
        io,
    })
}

/// Serves `adapter` on bound `sockets` until `stop` is set, on the runtime's clock. `log` gets
/// one line per connection event and per action of the application.
pub fn run<A: EnipApplication>(
    sockets: Sockets,
    mut adapter: Adapter<A>,
    stop: &AtomicBool,
    mut log: impl FnMut(String),
) -> Served {
    let Sockets {
        listener,
        udp,
        broadcast,
        io,
    } = sockets;
    let mut served = Served::default();
    let clock = MonotonicClock::new();
    let mut clients: BTreeMap<u64, Client> = BTreeMap::new();
    let mut next_client = 1u64;
    let mut buf = vec![0u8; 65_536];
    // Bound to 0.0.0.0: the adapter's address is the one each request reaches it at.
    let wildcard = udp.local_addr().is_ok_and(|a| a.ip().is_unspecified());
    while !stop.load(Ordering::Relaxed) {
        while let Ok((stream, peer)) = listener.accept() {
            let _ = stream.set_nonblocking(true);
            let _ = stream.set_nodelay(true);
            let client = Client {
                stream,
                peer: peer.ip(),
                buffer: Vec::new(),
            };
            clients.insert(next_client, client);
            next_client += 1;
            served.clients += 1;
        }
        let mut gone = Vec::new();
        let keys: Vec<u64> = clients.keys().copied().collect();
        for key in keys {
            let Some(client) = clients.get_mut(&key) else {
                continue;
            };
            match client.stream.read(&mut buf) {
                Ok(0) => gone.push(key),
                Ok(n) => client.buffer.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::WouldBlock => {}
                Err(_) => gone.push(key),
            }
            while let Some(client) = clients.get_mut(&key).filter(|c| !c.buffer.is_empty()) {
                let Ok(used) = adapter.handle(clock.now(), Peer::Tcp(key), &client.buffer) else {
                    break;
                };
                client.buffer.drain(..used);
                if !send(clock.now(), &mut adapter, &mut clients, &io, None) {
                    gone.push(key);
                    break;
                }
            }
        }
        for key in gone {
            clients.remove(&key);
            adapter.client_gone(clock.now(), key);
        }
        for socket in std::iter::once(&udp).chain(&broadcast) {
            while let Ok((n, from)) = socket.recv_from(&mut buf) {
                if let Some(own) = wildcard.then(|| address_toward(from)).flatten() {
                    adapter.device.address = own;
                }
                let _ = adapter.handle(clock.now(), Peer::Udp, &buf[..n]);
                send(
                    clock.now(),
                    &mut adapter,
                    &mut clients,
                    &io,
                    Some((&udp, from)),
                );
            }
        }
        if let Some(socket) = &io {
            while let Ok((n, from)) = socket.recv_from(&mut buf) {
                let key = clients
                    .iter()
                    .find(|(_, c)| c.peer == from.ip())
                    .map_or(u64::MAX, |(k, _)| *k);
                let _ = adapter.handle(clock.now(), Peer::Io(key), &buf[..n]);
            }
        }
        adapter.handle_timeout(clock.now());
        send(clock.now(), &mut adapter, &mut clients, &io, None);
        while let Some(event) = adapter.poll_event() {
            if matches!(event, Event::Opened(_)) {
                served.connections += 1;
            }
            if let Some(line) = event.log_line() {
                log(line);
            }
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    served
}

/// Sends what the adapter has to send: replies to their TCP client (or, for a UDP request, from
/// `udp` to its sender), T→O datagrams to their originator's address. False when writing to a
/// TCP client failed (the client is gone).
fn send<A: EnipApplication>(
    now: Instant,
    adapter: &mut Adapter<A>,
    clients: &mut BTreeMap<u64, Client>,
    io: &Option<UdpSocket>,
    udp: Option<(&UdpSocket, SocketAddr)>,
) -> bool {
    let mut ok = true;
    while let Some((to, bytes)) = adapter.poll_transmit(now) {
        match to {
            Peer::Tcp(key) => {
                if let Some(client) = clients.get_mut(&key) {
                    ok &= client.stream.write_all(&bytes).is_ok();
                }
            }
            Peer::Udp => {
                if let Some((socket, from)) = udp {
                    let _ = socket.send_to(&bytes, from);
                }
            }
            Peer::Io(key) => {
                let ip = clients.get(&key).map(|c| c.peer);
                if let (Some(io), Some(ip)) = (io, ip) {
                    let port = t_o_port(adapter, &bytes);
                    let _ = io.send_to(&bytes, SocketAddr::new(ip, port));
                }
            }
        }
    }
    ok
}

/// This host's address on the way to `peer` (the source address the system would send from),
/// as ListIdentity reports it when the adapter is bound to every address.
fn address_toward(peer: SocketAddr) -> Option<[u8; 4]> {
    let socket = UdpSocket::bind("0.0.0.0:0").ok()?;
    socket.connect(peer).ok()?;
    match socket.local_addr().ok()?.ip() {
        IpAddr::V4(ip) if !ip.is_unspecified() => Some(ip.octets()),
        _ => None,
    }
}

/// The UDP port a T→O datagram goes to: the one its connection's Forward_Open asked for, else
/// [`IO_PORT`].
fn t_o_port<A: EnipApplication>(adapter: &Adapter<A>, datagram: &[u8]) -> u16 {
    let id = IoDatagram::parse(datagram).ok().map(|d| d.connection);
    adapter
        .connections()
        .iter()
        .find(|c| Some(c.t_o_id) == id)
        .and_then(|c| c.t_o_port)
        .unwrap_or(IO_PORT)
}
