//! A socketcand hub: a TCP server that plays one CAN bus for all its clients, relaying every
//! frame a client sends to every other client, in one order for all, as python-can 4.6.1 expects
//! (handshake, a quiet period after rawmode, no echo), with an optional `candump -L` log.
//!
//! Blocking std threads, chosen over tokio: a hub has a handful of clients, a thread per
//! connection keeps each client's failures (garbage, a close mid-message, a reader too slow to
//! keep up) to that client's own threads, and the runtime does not depend on an async runtime.
//! Each client has a reader thread (the handshake, then its messages) and a writer thread that
//! drains the client's outbox. A client is never disconnected for being slow: its outbox is
//! bounded, and when it is full the oldest frames waiting for that client are dropped, counted,
//! reported to the hub's notices, and signalled to the client as a socketcand error frame
//! (`< error 004 ... >`, class 4: controller problems, the class SocketCAN uses for a receive
//! overflow), which python-can reads as an error frame and python `canopen` ignores.

use std::collections::{HashMap, VecDeque};
use std::io::{self, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration as StdDuration, Instant as StdInstant, SystemTime};

use super::socketcand::{rearm_quickack, tune, Message, MessageScanner};
use super::trace::{epoch_micros, TraceWriter};

/// The socketcand error class the hub sends a client for whom it dropped frames: `CAN_ERR_CRTL`
/// (controller problems), which SocketCAN raises for a receive buffer overflow.
pub const OVERFLOW_ERROR_CLASS: u32 = 0x004;

/// Something a hub wants its operator to know (`edsgen bus` prints these on standard error).
pub type Notices = Box<dyn Fn(String) + Send + Sync>;

/// How a hub treats its clients.
pub struct HubOptions {
    /// Where to write every relayed frame as a `candump -L` line, or nowhere.
    pub log: Option<Box<dyn Write + Send>>,
    /// The one channel the hub serves (`< open CHANNEL >`); any other gets
    /// `< error could not open bus >`, as socketcand answers. `can0` by default.
    pub channel: String,
    /// How long after its rawmode `< ok >` a client gets nothing: python-can 4.6.1 fails the
    /// connect when a frame lands in the same read as that `< ok >`. 50 ms by default.
    pub quiet_period: StdDuration,
    /// How many frames may wait for one client; beyond that the oldest are dropped for it.
    pub queue_limit: usize,
    /// How long a client may take for the handshake (each message of it).
    pub handshake_timeout: StdDuration,
    /// Where the hub reports frames dropped for a slow client (at most once a second per
    /// client, and a total when it leaves), or nowhere.
    pub notices: Option<Notices>,
}

impl Default for HubOptions {
    fn default() -> Self {
        HubOptions {
            log: None,
            channel: "can0".to_owned(),
            quiet_period: StdDuration::from_millis(50),
            queue_limit: 65_536,
            handshake_timeout: StdDuration::from_secs(5),
            notices: None,
        }
    }
}

impl std::fmt::Debug for HubOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HubOptions")
            .field("log", &self.log.is_some())
            .field("channel", &self.channel)
            .field("quiet_period", &self.quiet_period)
            .field("queue_limit", &self.queue_limit)
            .field("handshake_timeout", &self.handshake_timeout)
            .field("notices", &self.notices.is_some())
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
    frames_dropped: AtomicU64,
    limits: Limits,
    notices: Option<Notices>,
}

/// [`HubOptions`] but the log, which the bus owns, and the notices.
#[derive(Debug, Clone)]
struct Limits {
    channel: String,
    quiet_period: StdDuration,
    queue_limit: usize,
    handshake_timeout: StdDuration,
}

impl std::fmt::Debug for Shared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shared")
            .field("frames_relayed", &self.frames_relayed)
            .field("frames_dropped", &self.frames_dropped)
            .finish_non_exhaustive()
    }
}

impl Shared {
    fn notice(&self, text: String) {
        if let Some(notices) = &self.notices {
            notices(text);
        }
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

/// A client in rawmode and its outbox.
struct Listener {
    id: u64,
    /// Its address, for notices.
    peer: String,
    outbox: Arc<Outbox>,
}

/// The messages waiting for one client: at most `limit` frames, the oldest dropped (and
/// counted) to make room, so a slow client costs bounded memory and never slows the bus.
struct Outbox {
    state: Mutex<OutboxState>,
    ready: Condvar,
    limit: usize,
}

#[derive(Default)]
struct OutboxState {
    messages: VecDeque<Arc<[u8]>>,
    /// The client left: the writer stops.
    closed: bool,
    /// Frames dropped since the client was last told (by an error frame).
    untold: u64,
    /// Frames dropped for this client in all.
    dropped: u64,
    /// Frames dropped since the last notice, and when that was.
    unnoticed: u64,
    noticed_at: Option<StdInstant>,
}

/// How often at most a hub reports the frames it drops for one client.
const NOTICE_INTERVAL: StdDuration = StdDuration::from_secs(1);

impl Outbox {
    fn new(limit: usize) -> Self {
        Outbox {
            state: Mutex::new(OutboxState::default()),
            ready: Condvar::new(),
            limit: limit.max(1),
        }
    }

    /// Queues `message`, dropping the oldest one if the outbox is full. Whether one was
    /// dropped, and when a notice is due (the first drop, then at most once a second), the
    /// frames dropped since the last notice and in all.
    fn push(&self, message: Arc<[u8]>) -> (bool, Option<(u64, u64)>) {
        let mut state = lock(&self.state);
        let dropped = state.messages.len() >= self.limit;
        let mut notice = None;
        if dropped {
            state.messages.pop_front();
            state.untold += 1;
            state.dropped += 1;
            state.unnoticed += 1;
            if state
                .noticed_at
                .is_none_or(|at| at.elapsed() >= NOTICE_INTERVAL)
            {
                notice = Some((std::mem::take(&mut state.unnoticed), state.dropped));
                state.noticed_at = Some(StdInstant::now());
            }
        }
        state.messages.push_back(message);
        drop(state);
        self.ready.notify_one();
        (dropped, notice)
    }

    fn close(&self) {
        lock(&self.state).closed = true;
        self.ready.notify_one();
    }

    /// Waits for messages and appends up to about `max` bytes of them to `batch`, preceded by an
    /// error frame if frames were dropped since the last batch (how many comes back); `None`
    /// once closed.
    fn take(&self, batch: &mut Vec<u8>, max: usize) -> Option<u64> {
        let mut state = lock(&self.state);
        while state.messages.is_empty() && !state.closed {
            state = self
                .ready
                .wait(state)
                .unwrap_or_else(|poisoned| poisoned.into_inner());
        }
        if state.closed {
            return None;
        }
        let untold = std::mem::take(&mut state.untold);
        if untold > 0 {
            Message::Error {
                class: OVERFLOW_ERROR_CLASS,
                timestamp_us: epoch_micros(SystemTime::now()),
            }
            .emit(batch);
        }
        while let Some(message) = state.messages.pop_front() {
            batch.extend_from_slice(&message);
            if batch.len() >= max {
                break;
            }
        }
        Some(untold)
    }

    fn dropped(&self) -> u64 {
        lock(&self.state).dropped
    }
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
        let log = options
            .log
            .map(|output| TraceWriter::new(output, &options.channel));
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
            frames_dropped: AtomicU64::new(0),
            limits: Limits {
                channel: options.channel,
                quiet_period: options.quiet_period,
                queue_limit: options.queue_limit,
                handshake_timeout: options.handshake_timeout,
            },
            notices: options.notices,
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

    /// How many frames the hub dropped, over all clients, because a client did not read them
    /// in time (each counted once per client that missed it).
    pub fn frames_dropped(&self) -> u64 {
        self.shared.frames_dropped.load(Ordering::Relaxed)
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
    let peer = stream
        .peer_addr()
        .map_or_else(|_| "?".to_owned(), |a| a.to_string());
    let mut scanner = MessageScanner::new();
    if handshake(&mut stream, &mut scanner, &shared.limits).is_none() {
        let _ = stream.shutdown(Shutdown::Both);
        return;
    }
    let Ok(writer_stream) = stream.try_clone() else {
        return;
    };
    let ready_at = StdInstant::now() + shared.limits.quiet_period;
    let outbox = Arc::new(Outbox::new(shared.limits.queue_limit));
    let writer = {
        let outbox = Arc::clone(&outbox);
        thread::Builder::new()
            .name(format!("hub-writer-{id}"))
            .spawn(move || write_frames(writer_stream, &outbox, ready_at))
    };
    let Ok(writer) = writer else {
        return;
    };
    // On the bus before the `< ok >`, so that a frame sent once the client has its `< ok >`
    // reaches it; the quiet period keeps it from sharing a read with the `< ok >`.
    lock(&shared.bus).clients.push(Listener {
        id,
        peer: peer.clone(),
        outbox: Arc::clone(&outbox),
    });
    if stream.write_all(b"< ok >").is_ok() {
        relay_from(id, &mut stream, &mut scanner, &outbox, shared);
    }
    lock(&shared.bus).clients.retain(|c| c.id != id);
    outbox.close();
    let _ = stream.shutdown(Shutdown::Both);
    let _ = writer.join();
    let dropped = outbox.dropped();
    if dropped > 0 {
        shared.notice(format!(
            "client {id} ({peer}) left; {dropped} frame(s) were dropped for it in all"
        ));
    }
}

/// The handshake python-can 4.6.1 does, answered exactly: `< hi >`; `< open CHANNEL >` gets
/// `< ok >` (`< error could not open bus >` for a channel the hub does not serve, as socketcand
/// answers); then `< rawmode >`, whose `< ok >` the caller sends once the client is on the bus.
/// `None` if the client did something else (it gets an `< error ... >` and is closed).
fn handshake(stream: &mut TcpStream, scanner: &mut MessageScanner, limits: &Limits) -> Option<()> {
    stream
        .set_read_timeout(Some(limits.handshake_timeout))
        .ok()?;
    stream.write_all(b"< hi >").ok()?;
    match next_message(stream, scanner)? {
        Message::Open(channel) if channel == limits.channel => {}
        Message::Open(_) => {
            let _ = stream.write_all(b"< error could not open bus >");
            return None;
        }
        _ => {
            let _ = stream.write_all(b"< error expected open >");
            return None;
        }
    }
    stream.write_all(b"< ok >").ok()?;
    if next_message(stream, scanner)? != Message::Rawmode {
        let _ = stream.write_all(b"< error expected rawmode >");
        return None;
    }
    stream.set_read_timeout(None).ok()?;
    Some(())
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

/// What the hub answers a rawmode client's message that is not a frame to relay, as socketcand
/// does: `< echo >` comes back, an unknown command or a malformed `send` gets an error.
fn answer(body: &[u8]) -> Option<&'static [u8]> {
    match Message::parse(body) {
        Ok(Message::Send(_)) => None,
        Ok(Message::Other(words)) if words == "echo" => Some(b"< echo >"),
        Err(_) if body.trim_ascii().starts_with(b"send") => {
            Some(b"< error syntax error in send command >")
        }
        _ => Some(b"< error unknown command >"),
    }
}

/// Reads the client's messages and relays each frame to every other client until the client
/// closes; other messages get their [`answer`].
fn relay_from(
    id: u64,
    stream: &mut TcpStream,
    scanner: &mut MessageScanner,
    outbox: &Outbox,
    shared: &Shared,
) {
    let mut chunk = [0u8; 4096];
    let mut text = Vec::with_capacity(64);
    let mut notices = Vec::new();
    loop {
        while let Some(body) = scanner.next_message() {
            let Ok(Message::Send(frame)) = Message::parse(&body) else {
                if let Some(reply) = answer(&body) {
                    outbox.push(Arc::from(reply));
                }
                continue;
            };
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
            for client in bus.clients.iter().filter(|c| c.id != id) {
                let (dropped, notice) = client.outbox.push(Arc::clone(&message));
                if dropped {
                    shared.frames_dropped.fetch_add(1, Ordering::Relaxed);
                }
                if let Some((since, total)) = notice {
                    notices.push(format!(
                        "client {} ({}) reads too slowly: dropped its {since} oldest frame(s) \
                         ({total} in all)",
                        client.id, client.peer
                    ));
                }
            }
            if let Some(log) = &mut bus.log {
                if let Err(e) = log.write_frame(timestamp_us, &frame) {
                    bus.log = None;
                    bus.log_error = Some(e.to_string());
                }
            }
            drop(bus);
            for notice in notices.drain(..) {
                shared.notice(notice);
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

/// Writes the messages queued for one client, batching what has piled up into one write, after
/// the quiet period. Ends when the client leaves or a write fails.
fn write_frames(mut stream: TcpStream, outbox: &Outbox, ready_at: StdInstant) {
    let quiet = ready_at.saturating_duration_since(StdInstant::now());
    if !quiet.is_zero() {
        // The protocol's quiet period, not synchronisation: frames queue up meanwhile.
        thread::sleep(quiet);
    }
    let mut batch = Vec::with_capacity(65_536);
    loop {
        batch.clear();
        if outbox.take(&mut batch, 60_000).is_none() {
            return;
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
    use crate::socketcand::SocketcandClient;
    use crate::Transport;
    use edsgen_runtime::frame::CanFrame;

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
    fn a_channel_the_hub_does_not_serve_gets_the_socketcand_error_and_is_closed() {
        let hub = hub();
        let mut raw = Raw::connect(&hub);
        assert_eq!(raw.recv_once(), "< hi >");
        raw.write("< open can1 >");
        assert_eq!(raw.recv_once(), "< error could not open bus >");
        assert!(raw.closed_by_hub());
    }

    #[test]
    fn unknown_commands_and_malformed_sends_get_errors_and_echo_comes_back() {
        let hub = hub();
        let mut a = Raw::rawmode(&hub, "can0");
        let mut b = Raw::rawmode(&hub, "can0");
        a.write("< bogus 1 2 >< send zz 1 0 >< send 123 2 1 >< echo >< send 123 1 1 >");
        assert_eq!(a.next(), "< error unknown command >");
        assert_eq!(a.next(), "< error syntax error in send command >");
        assert_eq!(a.next(), "< error syntax error in send command >");
        assert_eq!(a.next(), "< echo >");
        assert_eq!(b.next(), "< frame 123 T 01 >");
        assert_eq!(hub.frames_relayed(), 1);
    }

    #[test]
    fn a_full_outbox_drops_its_oldest_frames_and_the_next_batch_says_so() {
        let outbox = Outbox::new(2);
        assert_eq!(outbox.push(Arc::from(&b"< a >"[..])), (false, None));
        assert_eq!(outbox.push(Arc::from(&b"< b >"[..])), (false, None));
        // The first drop is noticed at once, the next within a second is not.
        assert_eq!(outbox.push(Arc::from(&b"< c >"[..])), (true, Some((1, 1))));
        assert_eq!(outbox.push(Arc::from(&b"< d >"[..])), (true, None));
        let mut batch = Vec::new();
        assert_eq!(outbox.take(&mut batch, 1000), Some(2));
        let text = String::from_utf8(batch).unwrap();
        let (error, rest) = text.split_at(text.find(">").unwrap() + 1);
        assert!(error.starts_with("< error 004 "), "{text}");
        assert_eq!(rest, "< c >< d >");
        assert_eq!(outbox.dropped(), 2);
        outbox.push(Arc::from(&b"< e >"[..]));
        let mut batch = Vec::new();
        assert_eq!(outbox.take(&mut batch, 1000), Some(0));
        assert_eq!(batch, b"< e >");
        outbox.close();
        assert_eq!(outbox.take(&mut batch, 1000), None);
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
    fn every_relayed_frame_is_logged_once_on_the_hubs_channel() {
        let log = SharedLog::default();
        let options = HubOptions {
            log: Some(Box::new(log.clone())),
            channel: "vcan7".into(),
            ..HubOptions::default()
        };
        let hub = Hub::start("127.0.0.1:0", options).unwrap();
        let mut a = SocketcandClient::connect(hub.local_addr(), "vcan7", WAIT).unwrap();
        let mut b = Raw::rawmode(&hub, "vcan7");
        let mut c = Raw::rawmode(&hub, "vcan7");
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
        assert_eq!(lines, ["vcan7 603#2B171000E8030000", "vcan7 583#"]);
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
