//! The adapter on real sockets, a thin driver around the sans-IO core: encapsulation on TCP
//! (the address given, 44818 by default) and ListIdentity on UDP at the same port (and on every
//! address's, for broadcasts, when the address is unicast), class-1 I/O
//! on UDP 2222 (T→O to the originator's address, port 2222 or the one its Forward_Open's T→O
//! sockaddr item names). One thread, non-blocking sockets,
//! a millisecond tick. A bad client never stops the others: its bytes get the protocol's
//! refusal, and a client that sends what is no encapsulation header is dropped.
//!
//! [`Card`] links the adapter to the Goodrive350's drive ([`PkwPzdDrive`], bus EtherNet/IP):
//! every O→T image the scanner writes is exchanged with the drive, whose answer becomes the T→O
//! image. The card's communication-loss actions: a connection that times out trips the drive
//! with E-EIP (it coasts to a stop, faulted until a fault reset); one that Forward_Close ends
//! decelerates it to a stop.

use std::collections::BTreeMap;
use std::io::{ErrorKind, Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};

use edsgen_runtime::enip::wire::io::IoDatagram;
use edsgen_runtime::pkw_pzd::{ByteOrder, Command, ControlWord, OutputImage};
use edsgen_runtime::Instant;

use super::{Adapter, Event};
use crate::drives::pkw_pzd::PkwPzdDrive;

/// The class-1 I/O port.
pub const IO_PORT: u16 = 2222;

/// The drive behind the adapter and the assemblies it reads and writes.
pub struct Card {
    /// The drive.
    pub drive: PkwPzdDrive,
    /// The O→T assembly (the scanner's image).
    pub output: u32,
    /// The T→O assembly (the drive's image).
    pub input: u32,
}

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

/// Serves `adapter` on bound `sockets` until `stop` is set. `log` gets one line per connection
/// event.
pub fn run(
    sockets: Sockets,
    mut adapter: Adapter,
    mut card: Option<Card>,
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
    let start = std::time::Instant::now();
    let now = || Instant::from_micros(start.elapsed().as_micros() as u64);
    let mut clients: BTreeMap<u64, Client> = BTreeMap::new();
    let mut next_client = 1u64;
    let mut buf = vec![0u8; 65_536];
    // Bound to 0.0.0.0: the adapter's address is the one each request reaches it at.
    let wildcard = udp.local_addr().is_ok_and(|a| a.ip().is_unspecified());
    while !stop.load(Ordering::Relaxed) {
        loop {
            match listener.accept() {
                Ok((stream, peer)) => {
                    let _ = stream.set_nonblocking(true);
                    let _ = stream.set_nodelay(true);
                    clients.insert(
                        next_client,
                        Client {
                            stream,
                            peer: peer.ip(),
                            buffer: Vec::new(),
                        },
                    );
                    next_client += 1;
                    served.clients += 1;
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(_) => break,
            }
        }
        let mut gone = Vec::new();
        for (&key, client) in clients.iter_mut() {
            match client.stream.read(&mut buf) {
                Ok(0) => gone.push(key),
                Ok(n) => client.buffer.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::WouldBlock => {}
                Err(_) => gone.push(key),
            }
            while !client.buffer.is_empty() {
                match adapter.handle(key, &client.buffer, now()) {
                    Ok((reply, used)) => {
                        client.buffer.drain(..used);
                        if let Some(reply) = reply {
                            if client.stream.write_all(&reply).is_err() {
                                gone.push(key);
                                break;
                            }
                        }
                    }
                    Err(_) => break,
                }
            }
        }
        for key in gone {
            clients.remove(&key);
            adapter.client_gone(key);
        }
        for socket in std::iter::once(&udp).chain(&broadcast) {
            while let Ok((n, from)) = socket.recv_from(&mut buf) {
                if let Some(own) = wildcard.then(|| address_toward(from)).flatten() {
                    adapter.device.address = own;
                }
                if let Ok((Some(reply), _)) = adapter.handle(u64::MAX, &buf[..n], now()) {
                    let _ = udp.send_to(&reply, from);
                }
            }
        }
        if let Some(io) = &io {
            while let Ok((n, from)) = io.recv_from(&mut buf) {
                let key = clients
                    .iter()
                    .find(|(_, c)| c.peer == from.ip())
                    .map_or(u64::MAX, |(k, _)| *k);
                adapter.receive_io(key, &buf[..n], now());
            }
        }
        let t = now();
        adapter.handle_timeout(t);
        served.connections += link(&mut adapter, card.as_mut(), t, &mut log);
        while let Some((peer, datagram)) = adapter.poll_transmit() {
            let ip = clients.get(&peer).map(|c| c.peer);
            if let (Some(io), Some(ip)) = (&io, ip) {
                let port = t_o_port(&adapter, &datagram);
                let _ = io.send_to(&datagram, SocketAddr::new(ip, port));
            }
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    served
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
fn t_o_port(adapter: &Adapter, datagram: &[u8]) -> u16 {
    let id = IoDatagram::parse(datagram).ok().map(|d| d.connection);
    adapter
        .connections()
        .iter()
        .find(|c| Some(c.t_o_id) == id)
        .and_then(|c| c.t_o_port)
        .unwrap_or(IO_PORT)
}

/// Hands the adapter's events since the last call to `card` at `now`: each O→T image the scanner
/// wrote is exchanged with the drive and its answer becomes the T→O image; a timed-out connection
/// trips the drive (E-EIP, `communication_lost`), one Forward_Close ended stops it; without a
/// connection the drive's ramps still move and the T→O assembly shows the drive as it stands.
/// `log` gets one line per connection event. Returns how many connections opened.
pub fn link(
    adapter: &mut Adapter,
    mut card: Option<&mut Card>,
    now: Instant,
    log: &mut impl FnMut(String),
) -> u64 {
    let mut opened = 0;
    while let Some(event) = adapter.poll_event() {
        match event {
            Event::Opened(id) => {
                opened += 1;
                log(format!("connection {id:#010x} opened"));
            }
            Event::Closed(id) => {
                log(format!("connection {id:#010x} closed"));
                if let Some(card) = card.as_deref_mut() {
                    connection_closed(adapter, card, now, log);
                }
            }
            Event::TimedOut(id) => {
                log(format!("connection {id:#010x} timed out"));
                if let Some(card) = card.as_deref_mut() {
                    communication_lost(adapter, card, now, log);
                }
            }
            Event::Expired(id) => log(format!("explicit connection {id:#010x} closed")),
            Event::Consumed(point) => {
                let Some(card) = card.as_deref_mut() else {
                    continue;
                };
                if point != card.output {
                    continue;
                }
                let output: Option<[u8; 32]> = adapter
                    .device
                    .assemblies
                    .get(&card.output)
                    .and_then(|a| a.data.as_slice().try_into().ok());
                if let Some(output) = output {
                    let input = card
                        .drive
                        .exchange_bytes(now, &output, ByteOrder::LittleEndian);
                    if let Some(a) = adapter.device.assemblies.get_mut(&card.input) {
                        a.data = input.to_vec();
                    }
                }
            }
        }
    }
    if let Some(card) = card {
        // The drive runs on (its ramps, its own timeout P16.54) with or without a connection.
        card.drive.handle_timeout(now);
        if adapter.connections().is_empty() {
            if let Some(a) = adapter.device.assemblies.get_mut(&card.input) {
                a.data = card.drive.inputs().emit(ByteOrder::LittleEndian).to_vec();
            }
        }
    }
    opened
}

/// Whether a class-1 connection still writes the drive's image.
fn still_written(adapter: &Adapter, card: &Card) -> bool {
    adapter
        .connections()
        .iter()
        .any(|c| c.o_t_point == card.output)
}

/// Forward_Close ended the connection writing the drive's image (an orderly end): unless another
/// connection still writes it, the drive decelerates to stop (command 5) with the last settings
/// kept and no PKW task, so explicit reads show it stopping and the next connection's run
/// command starts it from rest.
fn connection_closed(
    adapter: &mut Adapter,
    card: &mut Card,
    now: Instant,
    log: &mut impl FnMut(String),
) {
    if still_written(adapter, card) {
        return;
    }
    let last: Option<[u8; 32]> = adapter
        .device
        .assemblies
        .get(&card.output)
        .and_then(|a| a.data.as_slice().try_into().ok());
    let mut output = last
        .map(|bytes| OutputImage::parse(&bytes, ByteOrder::LittleEndian))
        .unwrap_or_default();
    output.pkw = OutputImage::default().pkw;
    output.control = ControlWord::new(Command::DecelerateToStop, card.drive.layout());
    card.drive.exchange(now, &output);
    log("drive decelerates to stop".to_owned());
}

/// The connection writing the drive's image timed out: unless another connection still writes
/// it, the drive trips with E-EIP (fault 70, P07.27) and coasts to a stop, so explicit reads show
/// it faulted, and the next connection finds it faulted until its control word resets the fault
/// (command 7).
fn communication_lost(
    adapter: &Adapter,
    card: &mut Card,
    now: Instant,
    log: &mut impl FnMut(String),
) {
    if still_written(adapter, card) || card.drive.vfd().fault().is_some() {
        return;
    }
    card.drive.communication_lost(now);
    log(format!("drive fault {}", card.drive.bus().fault_name()));
}
