//! The async master (feature `std`): [`AsyncMaster`] hands SDO transfers and NMT commands to a
//! driver thread that owns the transport and runs one SDO client per node, all at once, so that
//! transfers to different nodes overlap. The same thread runs the node monitor (heartbeat
//! consumer, guarding master) on its clock and the EMCY consumer, whose events
//! [`AsyncMaster::next_event`] yields. Its futures need no particular executor (tokio, or any
//! other): the driver thread completes them and wakes their task.

use std::collections::{BTreeMap, VecDeque};
use std::future::{poll_fn, Future};
use std::io;
use std::pin::Pin;
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::{Context, Poll, Waker};
use std::thread::{self, JoinHandle};
use std::time::Duration as StdDuration;

use crate::driver::MonotonicClock;
use crate::Transport;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::od::access::{Readable, Writable};
use edsgen_runtime::od::entry::{Entry, OdValue};
use edsgen_runtime::time::{Duration, Instant};
use edsgen_runtime::wire::heartbeat::ErrorControlRepr;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::wire::sdo::Multiplexer;

use super::blocking::{Feed, MasterError, MasterEvent, ReadFeed};
use edsgen_runtime::master::emcy::Emergency;
use edsgen_runtime::master::nmt::{nmt_frame, NodeMonitor, Watch};
use edsgen_runtime::master::sdo_client::{Mode, SdoClient, SdoError, StartError, DEFAULT_TIMEOUT};

/// How long the driver thread waits for a frame before it looks for new requests again.
const POLL: StdDuration = StdDuration::from_millis(1);

/// Events kept until taken; the oldest are dropped past this.
const EVENT_QUEUE: usize = 1024;

/// What a request gives back: the value read and its size (or the size written).
type Outcome = Result<Done, MasterError>;

/// A request's success: the bytes read (an upload) and the value's size (a transfer).
#[derive(Default)]
struct Done {
    bytes: Vec<u8>,
    size: u32,
}

/// Where the driver thread leaves a transfer's outcome for its future.
#[derive(Default)]
struct Slot {
    outcome: Option<Outcome>,
    waker: Option<Waker>,
    /// The driver is gone without an outcome.
    abandoned: bool,
}

fn lock<S>(slot: &Mutex<S>) -> MutexGuard<'_, S> {
    slot.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The driver thread's end of a pending transfer.
struct Reply(Arc<Mutex<Slot>>);

impl Reply {
    fn send(self, outcome: Outcome) {
        let mut slot = lock(&self.0);
        slot.outcome = Some(outcome);
        if let Some(waker) = slot.waker.take() {
            waker.wake();
        }
    }
}

impl Drop for Reply {
    fn drop(&mut self) {
        let mut slot = lock(&self.0);
        if slot.outcome.is_none() {
            slot.abandoned = true;
            if let Some(waker) = slot.waker.take() {
                waker.wake();
            }
        }
    }
}

/// A transfer's outcome, once the driver thread has it.
struct Pending(Arc<Mutex<Slot>>);

impl Future for Pending {
    type Output = Outcome;
    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Outcome> {
        let mut slot = lock(&self.0);
        if let Some(outcome) = slot.outcome.take() {
            return Poll::Ready(outcome);
        }
        if slot.abandoned {
            return Poll::Ready(Err(MasterError::Io(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the master's driver thread stopped",
            ))));
        }
        slot.waker = Some(cx.waker().clone());
        Poll::Pending
    }
}

/// A reader a download of unannounced size takes its bytes from, on the driver thread.
type Source = ReadFeed<Box<dyn io::Read + Send>>;

enum Transfer {
    Upload(Multiplexer, Mode),
    Download(Multiplexer, Vec<u8>, Mode),
    DownloadFrom(Multiplexer, Box<Source>, Mode),
}

struct Job {
    transfer: Transfer,
    reply: Reply,
    /// Download: bytes handed to the client so far. Upload: bytes received.
    sent: usize,
    received: Vec<u8>,
    /// The source's error that ended the transfer.
    failed: Option<io::Error>,
    /// Upload: how many more times it is tried after a timeout before any byte arrived.
    retries: u8,
}

enum Request {
    Sdo(u8, Job),
    Frame(CanFrame, Reply),
    Timeout(u8, Duration),
    DefaultTimeout(Duration),
    ReadRetries(u8),
    WaitBoot(u8, Duration, Reply),
    Watch(u8, Watch, Reply),
}

/// The events the driver thread noticed, for [`AsyncMaster::next_event`].
#[derive(Default)]
struct Events {
    queue: VecDeque<MasterEvent>,
    waker: Option<Waker>,
    /// The driver thread has stopped: no event follows the queued ones.
    stopped: bool,
}

/// The driver thread's end of the events.
struct EventSender(Arc<Mutex<Events>>);

impl EventSender {
    fn send(&self, event: MasterEvent) {
        let mut events = lock(&self.0);
        if events.queue.len() == EVENT_QUEUE {
            events.queue.pop_front();
        }
        events.queue.push_back(event);
        if let Some(waker) = events.waker.take() {
            waker.wake();
        }
    }
}

impl Drop for EventSender {
    fn drop(&mut self) {
        let mut events = lock(&self.0);
        events.stopped = true;
        if let Some(waker) = events.waker.take() {
            waker.wake();
        }
    }
}

/// A wait for a node's boot-up: the node, until when, and the future to complete.
type BootWait = (u8, Instant, Reply);

/// One node's SDO channel and the transfers waiting for it.
struct Channel {
    client: SdoClient,
    /// The timeout was set for this node ([`AsyncMaster::set_timeout`]), not by default.
    own_timeout: bool,
    current: Option<Job>,
    queue: VecDeque<Job>,
}

/// A CANopen master whose operations are futures; see the module documentation.
pub struct AsyncMaster {
    requests: Option<Sender<Request>>,
    events: Arc<Mutex<Events>>,
    thread: Option<JoinHandle<()>>,
}

impl AsyncMaster {
    /// Starts the driver thread on `transport`.
    pub fn spawn<T: Transport + Send + 'static>(transport: T) -> io::Result<AsyncMaster> {
        let (requests, incoming) = mpsc::channel();
        let events = Arc::new(Mutex::new(Events::default()));
        let sender = EventSender(Arc::clone(&events));
        let thread = thread::Builder::new()
            .name("edsgen-master".into())
            .spawn(move || drive(transport, incoming, sender))?;
        Ok(AsyncMaster {
            requests: Some(requests),
            events,
            thread: Some(thread),
        })
    }

    /// Sets the SDO timeout of `node_id` (from its next transfer on), which
    /// [`set_default_timeout`](Self::set_default_timeout) then leaves alone.
    pub fn set_timeout(&self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        check_node(node_id)?;
        self.request(Request::Timeout(node_id, to_duration(timeout)))
    }

    /// Sets the SDO timeout of the nodes without one of their own (the SDO client's
    /// [`DEFAULT_TIMEOUT`] until then).
    pub fn set_default_timeout(&self, timeout: StdDuration) -> Result<(), MasterError> {
        self.request(Request::DefaultTimeout(to_duration(timeout)))
    }

    /// How many times a read that timed out before any byte arrived is tried again (1 by
    /// default), as by the blocking master. Writes are never repeated: the node may have
    /// applied one it did not confirm.
    pub fn set_read_retries(&self, retries: u8) -> Result<(), MasterError> {
        self.request(Request::ReadRetries(retries))
    }

    /// Reads `entry` of `node_id`, typed (an address of any device's generated module).
    pub async fn read<V: OdValue, D, A: Readable>(
        &self,
        node_id: u8,
        entry: Entry<V, D, A>,
    ) -> Result<V, MasterError> {
        let mux = Multiplexer::new(entry.index, entry.sub);
        let bytes = self.upload(node_id, mux, Mode::Normal).await?;
        entry.decode(&bytes).ok_or(MasterError::Length {
            node_id,
            mux,
            got: bytes.len(),
        })
    }

    /// Writes `value` to `entry` of `node_id`.
    pub async fn write<V: OdValue, D, A: Writable>(
        &self,
        node_id: u8,
        entry: Entry<V, D, A>,
        value: V,
    ) -> Result<(), MasterError> {
        let mut buf = [0u8; 256];
        let len = entry.encode(&value, &mut buf).ok_or(MasterError::Value)?;
        let mux = Multiplexer::new(entry.index, entry.sub);
        self.download(node_id, mux, buf[..len].to_vec(), Mode::Normal)
            .await
    }

    /// Reads (index, sub) of `node_id` as bytes.
    pub async fn upload(
        &self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
    ) -> Result<Vec<u8>, MasterError> {
        let done = self.transfer(node_id, Transfer::Upload(mux, mode)).await?;
        Ok(done.bytes)
    }

    /// Writes `data` to (index, sub) of `node_id`.
    pub async fn download(
        &self,
        node_id: u8,
        mux: Multiplexer,
        data: Vec<u8>,
        mode: Mode,
    ) -> Result<(), MasterError> {
        self.transfer(node_id, Transfer::Download(mux, data, mode))
            .await
            .map(|_| ())
    }

    /// Writes to (index, sub) a value read from `source` until its end, of a length not known
    /// up front: the size is not indicated (see [`SdoClient::download_unsized`]). Returns the
    /// value's length. `source` is read on the driver thread, a window at a time, so it should
    /// not block for long (a file or a buffer; not a socket that may stay silent). Its error
    /// aborts the transfer (0800 0000) and is returned as [`MasterError::Io`].
    pub async fn download_from(
        &self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
        source: impl io::Read + Send + 'static,
    ) -> Result<u32, MasterError> {
        let source: Box<dyn io::Read + Send> = Box::new(source);
        let transfer = Transfer::DownloadFrom(mux, Box::new(ReadFeed::new(source)), mode);
        Ok(self.transfer(node_id, transfer).await?.size)
    }

    /// Sends an NMT command to `node_id` (0: all nodes); done once the frame is on the bus.
    pub async fn nmt(&self, command: NmtCommand, node_id: u8) -> Result<(), MasterError> {
        if node_id > 127 {
            return Err(MasterError::NodeId(node_id));
        }
        let slot = Arc::new(Mutex::new(Slot::default()));
        let reply = Reply(Arc::clone(&slot));
        self.request(Request::Frame(nmt_frame(command, node_id), reply))?;
        Pending(slot).await.map(|_| ())
    }

    /// Watches `node_id` by heartbeat or guarding, from now on the driver thread's clock; its
    /// boot-up, state changes, loss and recovery come from [`next_event`](Self::next_event).
    pub async fn watch(&self, node_id: u8, watch: Watch) -> Result<(), MasterError> {
        let slot = Arc::new(Mutex::new(Slot::default()));
        let reply = Reply(Arc::clone(&slot));
        self.request(Request::Watch(node_id, watch, reply))?;
        Pending(slot).await.map(|_| ())
    }

    /// Waits for the next event noticed, oldest first: a watched node's boot-up, state change,
    /// loss or recovery, any node's emergency or boot-up message. `None` once the driver thread
    /// has stopped and every event is taken. The last 1024 events are kept until taken. One
    /// task at a time should wait for events (the last to poll is the one woken).
    pub async fn next_event(&self) -> Option<MasterEvent> {
        poll_fn(|cx| {
            let mut events = lock(&self.events);
            if let Some(event) = events.queue.pop_front() {
                return Poll::Ready(Some(event));
            }
            if events.stopped {
                return Poll::Ready(None);
            }
            events.waker = Some(cx.waker().clone());
            Poll::Pending
        })
        .await
    }

    /// The next event noticed, if there is one, without waiting.
    pub fn poll_event(&self) -> Option<MasterEvent> {
        lock(&self.events).queue.pop_front()
    }

    /// Waits until `node_id` sends its boot-up message, at most `timeout`. A boot-up received
    /// since the last wait for that node counts.
    pub async fn wait_for_boot(
        &self,
        node_id: u8,
        timeout: StdDuration,
    ) -> Result<(), MasterError> {
        check_node(node_id)?;
        let slot = Arc::new(Mutex::new(Slot::default()));
        let reply = Reply(Arc::clone(&slot));
        self.request(Request::WaitBoot(node_id, to_duration(timeout), reply))?;
        Pending(slot).await.map(|_| ())
    }

    async fn transfer(&self, node_id: u8, transfer: Transfer) -> Outcome {
        check_node(node_id)?;
        let slot = Arc::new(Mutex::new(Slot::default()));
        let job = Job {
            transfer,
            reply: Reply(Arc::clone(&slot)),
            sent: 0,
            received: Vec::new(),
            failed: None,
            retries: 0,
        };
        self.request(Request::Sdo(node_id, job))?;
        Pending(slot).await
    }

    fn request(&self, request: Request) -> Result<(), MasterError> {
        let gone = || io::Error::new(io::ErrorKind::BrokenPipe, "the driver thread stopped");
        let requests = self.requests.as_ref().ok_or_else(gone)?;
        requests.send(request).map_err(|_| MasterError::Io(gone()))
    }
}

impl Drop for AsyncMaster {
    /// Stops the driver thread after the transfers in progress.
    fn drop(&mut self) {
        self.requests.take();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn to_duration(d: StdDuration) -> Duration {
    Duration::from_micros(d.as_micros().min(u128::from(u64::MAX)) as u64)
}

fn check_node(node_id: u8) -> Result<(), MasterError> {
    if (1..=127).contains(&node_id) {
        Ok(())
    } else {
        Err(MasterError::NodeId(node_id))
    }
}

/// The driver thread: requests in, transfers run side by side, outcomes out, until the
/// [`AsyncMaster`] is dropped and nothing is pending, or the transport fails.
fn drive<T: Transport>(mut transport: T, requests: Receiver<Request>, events: EventSender) {
    let clock = MonotonicClock::new();
    let mut monitor: Box<NodeMonitor<127>> = Box::default();
    let mut default_timeout = DEFAULT_TIMEOUT;
    let mut read_retries = 1;
    let mut channels: BTreeMap<u8, Channel> = BTreeMap::new();
    let mut boot_waits: Vec<BootWait> = Vec::new();
    let mut booted: Vec<u8> = Vec::new();
    let mut open = true;
    loop {
        while open {
            match requests.try_recv() {
                Ok(Request::Sdo(node_id, mut job)) => {
                    if let Transfer::Upload(..) = job.transfer {
                        job.retries = read_retries;
                    }
                    let channel = channel(&mut channels, node_id, default_timeout);
                    channel.queue.push_back(job)
                }
                Ok(Request::Timeout(node_id, timeout)) => {
                    let channel = channel(&mut channels, node_id, default_timeout);
                    channel.client.set_timeout(timeout);
                    channel.own_timeout = true;
                }
                Ok(Request::DefaultTimeout(timeout)) => {
                    default_timeout = timeout;
                    for channel in channels.values_mut().filter(|c| !c.own_timeout) {
                        channel.client.set_timeout(timeout);
                    }
                }
                Ok(Request::ReadRetries(retries)) => read_retries = retries,
                Ok(Request::WaitBoot(node_id, timeout, reply)) => {
                    if let Some(i) = booted.iter().position(|&id| id == node_id) {
                        booted.remove(i);
                        reply.send(Ok(Done::default()));
                    } else {
                        boot_waits.push((node_id, clock.now() + timeout, reply));
                    }
                }
                Ok(Request::Frame(frame, reply)) => match transport.send(&frame) {
                    Ok(()) => reply.send(Ok(Done::default())),
                    Err(e) => return reply.send(Err(MasterError::Io(e))),
                },
                Ok(Request::Watch(node_id, watch, reply)) => {
                    let watched = monitor.watch(clock.now(), node_id, watch);
                    reply.send(match watched {
                        Ok(()) => Ok(Done::default()),
                        Err(_) => Err(MasterError::NodeId(node_id)),
                    });
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => open = false,
            }
        }
        let now = clock.now();
        let mut deadline: Option<Instant> = None;
        let mut busy = false;
        for channel in channels.values_mut() {
            if run_channel(channel, now, &mut transport).is_err() {
                // The bus is gone: every pending future learns it from its dropped reply.
                return;
            }
            busy |= channel.current.is_some() || !channel.queue.is_empty();
            deadline = match (deadline, channel.client.poll_timeout()) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
        let (overdue, waiting): (Vec<BootWait>, Vec<BootWait>) =
            boot_waits.drain(..).partition(|(_, at, _)| *at <= now);
        boot_waits = waiting;
        for (_, _, reply) in overdue {
            reply.send(Err(MasterError::Timeout));
        }
        for (_, at, _) in &boot_waits {
            deadline = Some(deadline.map_or(*at, |d| d.min(*at)));
        }
        if monitor.poll_timeout().is_some_and(|at| at <= now) {
            monitor.handle_timeout(now);
        }
        while let Some(frame) = monitor.poll_transmit(now) {
            if transport.send(&frame).is_err() {
                return;
            }
        }
        while let Some(event) = monitor.poll_event() {
            events.send(MasterEvent::Monitor(event));
        }
        if let Some(at) = monitor.poll_timeout() {
            deadline = Some(deadline.map_or(at, |d| d.min(at)));
        }
        if !open && !busy {
            return;
        }
        let wait = match deadline {
            Some(at) => POLL.min(StdDuration::from_micros((at - now).as_micros())),
            None => POLL,
        };
        match transport.recv_timeout(wait) {
            Ok(Some(frame)) => {
                monitor.handle_frame(clock.now(), &frame);
                while let Some(event) = monitor.poll_event() {
                    events.send(MasterEvent::Monitor(event));
                }
                if let Some(emergency) = Emergency::from_frame(&frame) {
                    events.send(MasterEvent::Emergency(emergency));
                }
                let server = frame
                    .std_id()
                    .filter(|id| (0x581..=0x5FF).contains(id))
                    .map(|id| (id - 0x580) as u8);
                if let Some(channel) = server.and_then(|id| channels.get_mut(&id)) {
                    channel.client.handle_frame(clock.now(), &frame);
                }
                if let Some(node_id) = boot_up(&frame) {
                    events.send(MasterEvent::BootUp(node_id));
                    match boot_waits.iter().position(|(id, _, _)| *id == node_id) {
                        Some(i) => boot_waits.remove(i).2.send(Ok(Done::default())),
                        None if !booted.contains(&node_id) => booted.push(node_id),
                        None => {}
                    }
                }
            }
            Ok(None) => {}
            Err(_) => return,
        }
    }
}

/// The node whose boot-up message `frame` is.
fn boot_up(frame: &CanFrame) -> Option<u8> {
    let id = frame.std_id().filter(|id| (0x701..=0x77F).contains(id))?;
    let message = ErrorControlRepr::parse(frame.data()).filter(|_| !frame.is_remote())?;
    (message == ErrorControlRepr::BOOT_UP).then_some((id - 0x700) as u8)
}

fn channel(channels: &mut BTreeMap<u8, Channel>, node_id: u8, timeout: Duration) -> &mut Channel {
    channels.entry(node_id).or_insert_with(|| {
        let mut client = SdoClient::new(node_id);
        client.set_timeout(timeout);
        Channel {
            client,
            own_timeout: false,
            current: None,
            queue: VecDeque::new(),
        }
    })
}

/// Starts the next transfer of an idle channel, moves data in and out of a busy one, sends its
/// frames and completes its future when it ends.
fn run_channel<T: Transport>(
    channel: &mut Channel,
    now: Instant,
    transport: &mut T,
) -> io::Result<()> {
    complete(channel);
    if channel.current.is_none() {
        if let Some(job) = channel.queue.pop_front() {
            let client = &mut channel.client;
            let started = match &job.transfer {
                Transfer::Upload(mux, mode) => client.upload(now, *mux, *mode),
                Transfer::Download(mux, data, mode) => u32::try_from(data.len())
                    .map_err(|_| StartError::Value)
                    .and_then(|size| client.download(now, *mux, size, *mode)),
                Transfer::DownloadFrom(mux, _, mode) => client.download_unsized(now, *mux, *mode),
            };
            match started {
                Ok(()) => channel.current = Some(job),
                Err(StartError::Value) => job.reply.send(Err(MasterError::Value)),
                Err(StartError::Busy) => job.reply.send(Err(MasterError::Busy(client.node_id()))),
            }
        }
    }
    let client = &mut channel.client;
    if client.poll_timeout().is_some_and(|at| at <= now) {
        client.handle_timeout(now);
    }
    if let Some(job) = channel.current.as_mut() {
        match &mut job.transfer {
            Transfer::Download(_, data, _) => job.sent += client.write_data(&data[job.sent..]),
            Transfer::DownloadFrom(_, source, _) => {
                if let Err(e) = source.feed(client) {
                    job.failed = Some(e);
                    client.abort(edsgen_runtime::od::SdoAbort::General.code());
                }
            }
            Transfer::Upload(..) => {}
        }
        drain(client, &mut job.received);
    }
    while let Some(frame) = client.poll_transmit(now) {
        transport.send(&frame)?;
    }
    complete(channel);
    Ok(())
}

/// Completes the channel's transfer if it has ended (or queues a read that timed out before any
/// byte arrived again, if it has retries left).
fn complete(channel: &mut Channel) {
    let client = &mut channel.client;
    let Some(result) = client.poll_result() else {
        return;
    };
    if let Some(mut job) = channel.current.take() {
        drain(client, &mut job.received);
        if result == Err(SdoError::Timeout) && job.retries > 0 && job.received.is_empty() {
            job.retries -= 1;
            channel.queue.push_front(job);
            return;
        }
        let (node_id, mux) = (client.node_id(), client.mux());
        let outcome = match (result, job.failed.take()) {
            (_, Some(e)) => Err(MasterError::Io(e)),
            (Ok(done), None) => Ok(Done {
                bytes: core::mem::take(&mut job.received),
                size: done.size,
            }),
            (Err(error), None) => Err(MasterError::Sdo {
                node_id,
                mux,
                error,
            }),
        };
        job.reply.send(outcome);
    }
}

fn drain(client: &mut SdoClient, into: &mut Vec<u8>) {
    let mut chunk = [0u8; 256];
    loop {
        let n = client.read_data(&mut chunk);
        if n == 0 {
            return;
        }
        into.extend_from_slice(&chunk[..n]);
    }
}
