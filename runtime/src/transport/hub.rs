//! A socketcand hub: a TCP server that plays one CAN bus for all its clients, relaying every
//! frame a client sends to every other client, in one order for all, as python-can 4.6.1 expects
//! (handshake, a quiet period after rawmode, no echo), with an optional `candump -L` log.
//!
//! Blocking std threads, chosen over tokio: a hub has a handful of clients, a thread per
//! connection keeps each client's failures (garbage, a close mid-message, a reader too slow to
//! keep up) to that client's own threads, and the runtime does not depend on an async runtime.
//! Each client has a reader thread (the handshake, then its `send` messages) and a writer thread
//! that drains a bounded queue of frames for it; a client whose queue overflows is dropped rather
//! than slowing the bus down for the others.

use std::collections::HashMap;
use std::io::{self, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration as StdDuration, Instant as StdInstant, SystemTime};

use super::socketcand::{rearm_quickack, tune, Message, MessageScanner};
use super::trace::{epoch_micros, TraceWriter};

/// How a hub treats its clients.
pub struct HubOptions {
    /// Where to write every relayed frame as a `candump -L` line (on the channel its sender
    /// opened), or nowhere.
    pub log: Option<Box<dyn Write + Send>>,
    /// How long after its rawmode `< ok >` a client gets nothing: python-can 4.6.1 fails the
    /// connect when a frame lands in the same read as that `< ok >`. 50 ms by default.
    pub quiet_period: StdDuration,
    /// How many frames may wait for one client before the hub drops it as too slow.
    pub queue_limit: usize,
    /// How long a client may take for the handshake (each message of it).
    pub handshake_timeout: StdDuration,
}

impl Default for HubOptions {
    fn default() -> Self {
        HubOptions {
            log: None,
            quiet_period: StdDuration::from_millis(50),
            queue_limit: 65_536,
            handshake_timeout: StdDuration::from_secs(5),
        }
    }
}

impl std::fmt::Debug for HubOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HubOptions")
            .field("log", &self.log.is_some())
            .field("quiet_period", &self.quiet_period)
            .field("queue_limit", &self.queue_limit)
            .field("handshake_timeout", &self.handshake_timeout)
            .finish()
    }
}

/// A running hub. Stops (and waits for its threads) on [`Hub::stop`] or when dropped.
#[derive(Debug)]
pub struct Hub {
    shared: Arc<Shared>,
    addr: SocketAddr,
    acceptor: Option<JoinHandle<()>>,
}

/// What the threads of a hub share.
struct Shared {
    stopping: AtomicBool,
    /// The clients in rawmode, which get frames.
    bus: Mutex<Bus>,
    /// Every open connection, to shut it down on stop; and the threads serving them.
    connections: Mutex<HashMap<u64, TcpStream>>,
    threads: Mutex<Vec<JoinHandle<()>>>,
    frames_relayed: AtomicU64,
    clients_dropped: AtomicU64,
    limits: Limits,
}

/// [`HubOptions`] but the log, which the bus owns.
#[derive(Debug, Clone, Copy)]
struct Limits {
    quiet_period: StdDuration,
    queue_limit: usize,
    handshake_timeout: StdDuration,
}

impl std::fmt::Debug for Shared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shared")
            .field("frames_relayed", &self.frames_relayed)
            .finish_non_exhaustive()
    }
}

/// The clients that get frames, and the log: one lock, so that every client and the log see the
/// frames in the same order.
struct Bus {
    clients: Vec<Listener>,
    log: Option<TraceWriter<Box<dyn Write + Send>>>,
    /// Why the log stopped, if it failed.
    log_error: Option<String>,
}

/// A client in rawmode: its queue, and its connection to shut down if it cannot keep up.
struct Listener {
    id: u64,
    queue: SyncSender<Arc<[u8]>>,
    stream: TcpStream,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panicking client thread must not take the hub down with it.
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Hub {
    /// Listens on `addr` (port 0 picks a free port: see [`Hub::local_addr`]) and serves clients
    /// on a thread of its own until stopped.
    pub fn start(addr: impl ToSocketAddrs, options: HubOptions) -> io::Result<Hub> {
        let listener = TcpListener::bind(addr)?;
        let addr = listener.local_addr()?;
        let log = options.log.map(|output| TraceWriter::new(output, "can0"));
        let shared = Arc::new(Shared {
            stopping: AtomicBool::new(false),
            bus: Mutex::new(Bus {
                clients: Vec::new(),
                log,
                log_error: None,
            }),
            connections: Mutex::new(HashMap::new()),
            threads: Mutex::new(Vec::new()),
            frames_relayed: AtomicU64::new(0),
            clients_dropped: AtomicU64::new(0),
            limits: Limits {
                quiet_period: options.quiet_period,
                queue_limit: options.queue_limit,
                handshake_timeout: options.handshake_timeout,
            },
        });
        let acceptor = {
            let shared = Arc::clone(&shared);
            thread::Builder::new()
                .name("hub-accept".into())
                .spawn(move || accept_loop(listener, &shared))?
        };
        Ok(Hub {
            shared,
            addr,
            acceptor: Some(acceptor),
        })
    }

    /// The address the hub listens on.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// How many frames clients have sent through the hub so far.
    pub fn frames_relayed(&self) -> u64 {
        self.shared.frames_relayed.load(Ordering::Relaxed)
    }

    /// How many clients are in rawmode now.
    pub fn clients(&self) -> usize {
        lock(&self.shared.bus).clients.len()
    }

    /// How many clients the hub dropped because they did not keep up with the bus.
    pub fn clients_dropped(&self) -> u64 {
        self.shared.clients_dropped.load(Ordering::Relaxed)
    }

    /// Why the log stopped, if writing it failed (the hub goes on relaying without it).
    pub fn log_error(&self) -> Option<String> {
        lock(&self.shared.bus).log_error.clone()
    }

    /// Closes every connection, stops listening and waits for all the hub's threads.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        let Some(acceptor) = self.acceptor.take() else {
            return;
        };
        self.shared.stopping.store(true, Ordering::SeqCst);
        // Wake the acceptor from its blocking accept.
        let mut wake = self.addr;
        if wake.ip().is_unspecified() {
            wake.set_ip(match wake {
                SocketAddr::V4(_) => std::net::Ipv4Addr::LOCALHOST.into(),
                SocketAddr::V6(_) => std::net::Ipv6Addr::LOCALHOST.into(),
            });
        }
        let _ = TcpStream::connect_timeout(&wake, StdDuration::from_secs(1));
        let _ = acceptor.join();
        for stream in lock(&self.shared.connections).values() {
            let _ = stream.shutdown(Shutdown::Both);
        }
        let threads = std::mem::take(&mut *lock(&self.shared.threads));
        for thread in threads {
            let _ = thread.join();
        }
    }
}

impl Drop for Hub {
    fn drop(&mut self) {
        self.shutdown();
    }
}

fn accept_loop(listener: TcpListener, shared: &Arc<Shared>) {
    let mut next_id = 0u64;
    loop {
        let accepted = listener.accept();
        if shared.stopping.load(Ordering::SeqCst) {
            return;
        }
        let stream = match accepted {
            Ok((stream, _)) => stream,
            Err(_) => {
                // Out of file descriptors or an aborted connection: try again shortly.
                thread::sleep(StdDuration::from_millis(10));
                continue;
            }
        };
        next_id += 1;
        let id = next_id;
        let Ok(registered) = stream.try_clone() else {
            continue;
        };
        lock(&shared.connections).insert(id, registered);
        let thread = {
            let shared = Arc::clone(shared);
            thread::Builder::new()
                .name(format!("hub-client-{id}"))
                .spawn(move || {
                    serve_client(id, stream, &shared);
                    lock(&shared.connections).remove(&id);
                })
        };
        let mut threads = lock(&shared.threads);
        threads.retain(|t| !t.is_finished());
        match thread {
            Ok(thread) => threads.push(thread),
            Err(_) => {
                lock(&shared.connections).remove(&id);
            }
        }
    }
}

/// One client, from the greeting to the close.
fn serve_client(id: u64, mut stream: TcpStream, shared: &Arc<Shared>) {
    if tune(&stream).is_err() {
        return;
    }
    let mut scanner = MessageScanner::new();
    let Some(channel) = handshake(&mut stream, &mut scanner, &shared.limits) else {
        let _ = stream.shutdown(Shutdown::Both);
        return;
    };
    let Ok(writer_stream) = stream.try_clone() else {
        return;
    };
    let Ok(bus_stream) = stream.try_clone() else {
        return;
    };
    let ready_at = StdInstant::now() + shared.limits.quiet_period;
    let (queue, frames) = mpsc::sync_channel(shared.limits.queue_limit);
    let writer = thread::Builder::new()
        .name(format!("hub-writer-{id}"))
        .spawn(move || write_frames(writer_stream, &frames, ready_at));
    let Ok(writer) = writer else {
        return;
    };
    // On the bus before the `< ok >`, so that a frame sent once the client has its `< ok >`
    // reaches it; the quiet period keeps it from sharing a read with the `< ok >`.
    lock(&shared.bus).clients.push(Listener {
        id,
        queue,
        stream: bus_stream,
    });
    if stream.write_all(b"< ok >").is_ok() {
        relay_from(id, &channel, &mut stream, &mut scanner, shared);
    }
    lock(&shared.bus).clients.retain(|c| c.id != id);
    let _ = stream.shutdown(Shutdown::Both);
    let _ = writer.join();
}

/// The handshake python-can 4.6.1 does, answered exactly: `< hi >`; `< open CHANNEL >` gets
/// `< ok >`; then `< rawmode >`, whose `< ok >` the caller sends once the client is on the bus.
/// The channel opened, or `None` if the client did something else (it gets an `< error ... >`
/// and is closed: it is not in rawmode yet).
fn handshake(
    stream: &mut TcpStream,
    scanner: &mut MessageScanner,
    limits: &Limits,
) -> Option<String> {
    stream
        .set_read_timeout(Some(limits.handshake_timeout))
        .ok()?;
    stream.write_all(b"< hi >").ok()?;
    let channel = match next_message(stream, scanner)? {
        Message::Open(channel) => channel,
        _ => {
            let _ = stream.write_all(b"< error expected open >");
            return None;
        }
    };
    stream.write_all(b"< ok >").ok()?;
    if next_message(stream, scanner)? != Message::Rawmode {
        let _ = stream.write_all(b"< error expected rawmode >");
        return None;
    }
    stream.set_read_timeout(None).ok()?;
    Some(channel)
}

/// The next message of the handshake (one that does not parse counts as a wrong one).
fn next_message(stream: &mut TcpStream, scanner: &mut MessageScanner) -> Option<Message> {
    let mut chunk = [0u8; 512];
    loop {
        if let Some(body) = scanner.next_message() {
            return Some(Message::parse(&body).unwrap_or(Message::Other(String::new())));
        }
        let n = stream.read(&mut chunk).ok().filter(|&n| n > 0)?;
        rearm_quickack(stream);
        scanner.push(&chunk[..n]);
    }
}

/// Reads the client's `send` messages and relays each frame to every other client until the
/// client closes. Messages other than `send`, and garbage, are skipped.
fn relay_from(
    id: u64,
    channel: &str,
    stream: &mut TcpStream,
    scanner: &mut MessageScanner,
    shared: &Shared,
) {
    let mut chunk = [0u8; 4096];
    let mut text = Vec::with_capacity(64);
    loop {
        while let Some(body) = scanner.next_message() {
            if let Ok(Message::Send(frame)) = Message::parse(&body) {
                let timestamp_us = epoch_micros(SystemTime::now());
                text.clear();
                Message::Frame {
                    frame,
                    timestamp_us,
                }
                .emit(&mut text);
                let message: Arc<[u8]> = Arc::from(&text[..]);
                let mut bus = lock(&shared.bus);
                shared.frames_relayed.fetch_add(1, Ordering::Relaxed);
                let mut dropped = Vec::new();
                for client in bus.clients.iter().filter(|c| c.id != id) {
                    match client.queue.try_send(Arc::clone(&message)) {
                        Ok(()) => {}
                        Err(TrySendError::Full(_)) => {
                            let _ = client.stream.shutdown(Shutdown::Both);
                            dropped.push(client.id);
                        }
                        Err(TrySendError::Disconnected(_)) => dropped.push(client.id),
                    }
                }
                if !dropped.is_empty() {
                    bus.clients.retain(|c| !dropped.contains(&c.id));
                    shared
                        .clients_dropped
                        .fetch_add(dropped.len() as u64, Ordering::Relaxed);
                }
                if let Some(log) = &mut bus.log {
                    if let Err(e) = log.write_frame_on(timestamp_us, channel, &frame) {
                        bus.log = None;
                        bus.log_error = Some(e.to_string());
                    }
                }
            }
        }
        match stream.read(&mut chunk) {
            Ok(0) => return,
            Ok(n) => {
                rearm_quickack(stream);
                scanner.push(&chunk[..n]);
            }
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(_) => return,
        }
    }
}

/// Writes the frames queued for one client, batching what has piled up into one write, after
/// the quiet period. Ends when the client is gone from the bus or a write fails.
fn write_frames(mut stream: TcpStream, frames: &Receiver<Arc<[u8]>>, ready_at: StdInstant) {
    let quiet = ready_at.saturating_duration_since(StdInstant::now());
    if !quiet.is_zero() {
        // The protocol's quiet period, not synchronisation: frames queue up meanwhile.
        thread::sleep(quiet);
    }
    let mut batch = Vec::with_capacity(4096);
    while let Ok(first) = frames.recv() {
        batch.clear();
        batch.extend_from_slice(&first);
        while batch.len() < 60_000 {
            match frames.try_recv() {
                Ok(next) => batch.extend_from_slice(&next),
                Err(_) => break,
            }
        }
        if stream.write_all(&batch).is_err() {
            let _ = stream.shutdown(Shutdown::Both);
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::CanFrame;
    use crate::transport::socketcand::SocketcandClient;
    use crate::transport::Transport;

    const WAIT: StdDuration = StdDuration::from_secs(5);

    fn hub() -> Hub {
        Hub::start("127.0.0.1:0", HubOptions::default()).unwrap()
    }

    /// A client that speaks the protocol byte by byte, as python-can does.
    struct Raw {
        stream: TcpStream,
        scanner: MessageScanner,
    }

    impl Raw {
        fn connect(hub: &Hub) -> Raw {
            let stream = TcpStream::connect(hub.local_addr()).unwrap();
            stream.set_read_timeout(Some(WAIT)).unwrap();
            Raw {
                stream,
                scanner: MessageScanner::new(),
            }
        }

        /// What one `recv` gets, as python-can reads each handshake reply.
        fn recv_once(&mut self) -> String {
            let mut chunk = [0u8; 4096];
            let n = self.stream.read(&mut chunk).unwrap();
            String::from_utf8(chunk[..n].to_vec()).unwrap()
        }

        fn write(&mut self, text: &str) {
            self.stream.write_all(text.as_bytes()).unwrap();
        }

        /// Connects and does python-can's handshake on `channel`, checking every reply exactly.
        fn rawmode(hub: &Hub, channel: &str) -> Raw {
            let mut raw = Raw::connect(hub);
            assert_eq!(raw.recv_once(), "< hi >");
            raw.write(&format!("< open {channel} >"));
            assert_eq!(raw.recv_once(), "< ok >");
            raw.write("< rawmode >");
            assert_eq!(raw.recv_once(), "< ok >");
            raw
        }

        /// The next message, whole (`< ... >`), with the timestamp of a frame replaced by `T`
        /// after checking that it is the wall clock with 6 decimals.
        fn next(&mut self) -> String {
            let deadline = StdInstant::now() + WAIT;
            loop {
                if let Some(body) = self.scanner.next_message() {
                    let text = format!("<{}>", String::from_utf8(body).unwrap());
                    return without_time(&text);
                }
                assert!(StdInstant::now() < deadline, "no message within {WAIT:?}");
                let mut chunk = [0u8; 4096];
                let n = self.stream.read(&mut chunk).unwrap();
                assert!(n > 0, "the hub closed the connection");
                self.scanner.push(&chunk[..n]);
            }
        }

        /// Whether the hub closed this connection (after whatever it had sent).
        fn closed_by_hub(&mut self) -> bool {
            let mut chunk = [0u8; 65536];
            loop {
                match self.stream.read(&mut chunk) {
                    Ok(0) => return true,
                    Ok(_) => continue,
                    Err(e) if e.kind() == io::ErrorKind::ConnectionReset => return true,
                    Err(_) => return false,
                }
            }
        }
    }

    fn without_time(text: &str) -> String {
        let parts: Vec<&str> = text.splitn(5, ' ').collect();
        if parts.len() < 5 || parts[1] != "frame" {
            return text.to_owned();
        }
        let (secs, micros) = parts[3].split_once('.').unwrap();
        assert_eq!(micros.len(), 6, "{text}");
        let secs: u64 = secs.parse().unwrap();
        let now = epoch_micros(SystemTime::now()) / 1_000_000;
        assert!(
            now - 10 <= secs && secs <= now,
            "{text}: not the wall clock"
        );
        format!("{} {} {} T {}", parts[0], parts[1], parts[2], parts[4])
    }

    #[test]
    fn hub_reports_the_port_it_bound() {
        let hub = hub();
        assert_eq!(hub.local_addr().ip(), std::net::Ipv4Addr::LOCALHOST);
        assert_ne!(hub.local_addr().port(), 0);
        hub.stop();
    }

    #[test]
    fn handshake_replies_come_alone_and_exactly() {
        let hub = hub();
        let _raw = Raw::rawmode(&hub, "can0");
        let deadline = StdInstant::now() + WAIT;
        while hub.clients() != 1 {
            assert!(StdInstant::now() < deadline);
            thread::yield_now();
        }
    }

    #[test]
    fn nothing_reaches_a_client_in_its_quiet_period_and_nothing_is_lost() {
        let hub = hub();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut b = Raw::connect(&hub);
        assert_eq!(b.recv_once(), "< hi >");
        b.write("< open can0 >");
        assert_eq!(b.recv_once(), "< ok >");
        // The hub starts b's quiet period after it reads the rawmode, so after this instant
        // (a bound that holds however late this thread then runs).
        let before_rawmode = StdInstant::now();
        b.write("< rawmode >");
        assert_eq!(
            b.recv_once(),
            "< ok >",
            "a frame must not share the read with the ok"
        );
        a.write("< send 123 1 aa >");
        assert_eq!(b.next(), "< frame 123 T AA >");
        let waited = before_rawmode.elapsed();
        assert!(waited >= StdDuration::from_millis(50), "{waited:?}");
    }

    #[test]
    fn frames_go_to_every_other_client_and_never_back_to_the_sender() {
        let hub = hub();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut b = Raw::rawmode(&hub, "can0");
        let mut c = Raw::rawmode(&hub, "can0");
        a.write("< send 701 1 5 >");
        assert_eq!(c.next(), "< frame 701 T 05 >");
        assert_eq!(b.next(), "< frame 701 T 05 >");
        b.write("< send 702 1 7f >");
        assert_eq!(c.next(), "< frame 702 T 7F >");
        assert_eq!(a.next(), "< frame 702 T 7F >", "a got its own frame back");
        c.write("< send 703 0  >");
        assert_eq!(a.next(), "< frame 703 T  >");
        assert_eq!(b.next(), "< frame 703 T  >");
        assert_eq!(hub.frames_relayed(), 3);
    }

    #[test]
    fn identifiers_dlc_zero_and_remote_requests_are_relayed_as_python_can_reads_them() {
        let hub = hub();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut b = Raw::rawmode(&hub, "can0");
        a.write("< send 000 0  >< send 12345678 2 a b >< send 7FF 8 1 2 3 4 5 6 7 ff >");
        a.write("< send 182 8  >< send 5 1 0 >");
        assert_eq!(b.next(), "< frame 000 T  >");
        assert_eq!(b.next(), "< frame 12345678 T 0A0B >");
        assert_eq!(b.next(), "< frame 7FF T 01020304050607FF >");
        assert_eq!(b.next(), "< frame 182 T  >");
        assert_eq!(b.next(), "< frame 005 T 00 >");
    }

    #[test]
    fn a_client_that_does_not_open_gets_an_error_and_is_closed() {
        let hub = hub();
        let mut raw = Raw::connect(&hub);
        assert_eq!(raw.recv_once(), "< hi >");
        raw.write("< rawmode >");
        assert_eq!(raw.recv_once(), "< error expected open >");
        assert!(raw.closed_by_hub());
    }

    #[test]
    fn garbage_and_a_close_mid_message_disturb_no_other_client() {
        let hub = hub();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut b = Raw::rawmode(&hub, "can0");
        let mut bad = Raw::rawmode(&hub, "can0");
        bad.write("garbage >>> <<< < send zz 1 0 >< send 123 9 0 >< bogus 1 2 ><");
        bad.stream.write_all(&[0xFF, 0xFE, b'>']).unwrap();
        bad.write("< send 100 1 1 >< send 1");
        drop(bad);
        // A half-finished handshake, too.
        let mut early = Raw::connect(&hub);
        assert_eq!(early.recv_once(), "< hi >");
        early.write("< op");
        drop(early);
        assert_eq!(a.next(), "< frame 100 T 01 >");
        assert_eq!(b.next(), "< frame 100 T 01 >");
        a.write("< send 200 2 2 3 >");
        assert_eq!(b.next(), "< frame 200 T 0203 >");
        b.write("< send 201 0  >");
        assert_eq!(a.next(), "< frame 201 T  >");
        let deadline = StdInstant::now() + WAIT;
        while hub.clients() != 2 {
            assert!(
                StdInstant::now() < deadline,
                "the bad client is still listed"
            );
            thread::yield_now();
        }
    }

    #[test]
    fn a_client_that_does_not_read_is_dropped_and_the_others_lose_nothing() {
        let options = HubOptions {
            queue_limit: 1000,
            ..HubOptions::default()
        };
        let hub = Hub::start("127.0.0.1:0", options).unwrap();
        let mut sender = Raw::rawmode(&hub, "can0");
        let mut reader = SocketcandClient::connect(hub.local_addr(), "can0", WAIT).unwrap();
        let mut stuck = Raw::rawmode(&hub, "can0");
        // Batches of 200 frames, each read before the next is sent: the reader keeps up, the
        // stuck client's socket buffers and then its queue fill.
        let mut n = 0u32;
        while hub.clients_dropped() == 0 {
            assert!(n < 400_000, "the stuck client was never dropped");
            let mut batch = String::new();
            for k in n..n + 200 {
                let [b0, b1, b2, b3] = k.to_le_bytes();
                batch.push_str(&format!("< send 181 4 {b0:x} {b1:x} {b2:x} {b3:x} >"));
            }
            sender.write(&batch);
            for k in n..n + 200 {
                let frame = reader.recv_timeout(WAIT).unwrap();
                assert_eq!(frame, CanFrame::new(0x181, &k.to_le_bytes()), "frame {k}");
            }
            n += 200;
        }
        assert_eq!(hub.clients_dropped(), 1);
        assert!(stuck.closed_by_hub());
        assert_eq!(hub.clients(), 2);
        assert_eq!(hub.frames_relayed(), u64::from(n));
    }

    /// A log that the test can read while the hub owns its writer.
    #[derive(Clone, Default)]
    struct SharedLog(Arc<Mutex<Vec<u8>>>);

    impl Write for SharedLog {
        fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
            lock(&self.0).extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn every_relayed_frame_is_logged_once_on_its_senders_channel() {
        let log = SharedLog::default();
        let options = HubOptions {
            log: Some(Box::new(log.clone())),
            ..HubOptions::default()
        };
        let hub = Hub::start("127.0.0.1:0", options).unwrap();
        let mut a = SocketcandClient::connect(hub.local_addr(), "vcan7", WAIT).unwrap();
        let mut b = Raw::rawmode(&hub, "can0");
        let mut c = Raw::rawmode(&hub, "can0");
        a.send(&CanFrame::new(0x603, &[0x2B, 0x17, 0x10, 0, 0xE8, 3, 0, 0]).unwrap())
            .unwrap();
        assert_eq!(b.next(), "< frame 603 T 2B171000E8030000 >");
        c.write("< send 583 0  >");
        assert_eq!(a.recv_timeout(WAIT).unwrap(), CanFrame::new(0x583, &[]));
        assert_eq!(b.next(), "< frame 583 T  >");
        hub.stop();
        let text = String::from_utf8(lock(&log.0).clone()).unwrap();
        let lines: Vec<&str> = text
            .lines()
            .map(|l| l.split_once(") ").unwrap().1)
            .collect();
        assert_eq!(lines, ["vcan7 603#2B171000E8030000", "can0 583#"]);
    }

    /// A log whose disk is full.
    struct FullDisk;

    impl Write for FullDisk {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::other("no space left"))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_failing_log_is_reported_and_relaying_goes_on() {
        let options = HubOptions {
            log: Some(Box::new(FullDisk)),
            ..HubOptions::default()
        };
        let hub = Hub::start("127.0.0.1:0", options).unwrap();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut b = Raw::rawmode(&hub, "can0");
        assert_eq!(hub.log_error(), None);
        a.write("< send 181 1 1 >< send 181 1 2 >");
        assert_eq!(b.next(), "< frame 181 T 01 >");
        assert_eq!(b.next(), "< frame 181 T 02 >");
        assert_eq!(hub.log_error().as_deref(), Some("no space left"));
    }

    #[test]
    fn stop_closes_every_connection_and_returns() {
        let hub = hub();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut waiting = Raw::connect(&hub);
        assert_eq!(waiting.recv_once(), "< hi >");
        let addr = hub.local_addr();
        hub.stop();
        assert!(a.closed_by_hub());
        assert!(waiting.closed_by_hub());
        assert!(TcpStream::connect(addr).is_err(), "still listening");
    }
}
