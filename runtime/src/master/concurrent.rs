//! The async master (feature `std`): [`AsyncMaster`] hands SDO transfers and NMT commands to a
//! driver thread that owns the transport and runs one SDO client per node, all at once, so that
//! transfers to different nodes overlap. Its futures need no particular executor (tokio, or any
//! other): the driver thread completes them and wakes their task.

use std::collections::{BTreeMap, VecDeque};
use std::future::Future;
use std::io;
use std::pin::Pin;
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::task::{Context, Poll, Waker};
use std::thread::{self, JoinHandle};
use std::time::Duration as StdDuration;

use crate::frame::CanFrame;
use crate::od::access::{Readable, Writable};
use crate::od::entry::{Entry, OdValue};
use crate::time::{Duration, Instant};
use crate::transport::driver::MonotonicClock;
use crate::transport::Transport;
use crate::wire::heartbeat::ErrorControlRepr;
use crate::wire::nmt::NmtCommand;
use crate::wire::sdo::Multiplexer;

use super::blocking::MasterError;
use super::nmt::nmt_frame;
use super::sdo_client::{Mode, SdoClient, StartError, DEFAULT_TIMEOUT};

/// How long the driver thread waits for a frame before it looks for new requests again.
const POLL: StdDuration = StdDuration::from_millis(1);

/// What a transfer gives back: the value read, or nothing for a write.
type Outcome = Result<Vec<u8>, MasterError>;

/// Where the driver thread leaves a transfer's outcome for its future.
#[derive(Default)]
struct Slot {
    outcome: Option<Outcome>,
    waker: Option<Waker>,
    /// The driver is gone without an outcome.
    abandoned: bool,
}

fn lock(slot: &Mutex<Slot>) -> MutexGuard<'_, Slot> {
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

enum Transfer {
    Upload(Multiplexer, Mode),
    Download(Multiplexer, Vec<u8>, Mode),
}

struct Job {
    transfer: Transfer,
    reply: Reply,
    /// Download: bytes handed to the client so far. Upload: bytes received.
    sent: usize,
    received: Vec<u8>,
}

enum Request {
    Sdo(u8, Job),
    Frame(CanFrame, Reply),
    Timeout(u8, Duration),
    WaitBoot(u8, Duration, Reply),
}

/// A wait for a node's boot-up: the node, until when, and the future to complete.
type BootWait = (u8, Instant, Reply);

/// One node's SDO channel and the transfers waiting for it.
struct Channel {
    client: SdoClient,
    current: Option<Job>,
    queue: VecDeque<Job>,
}

/// A CANopen master whose operations are futures; see the module documentation.
pub struct AsyncMaster {
    requests: Option<Sender<Request>>,
    thread: Option<JoinHandle<()>>,
}

impl AsyncMaster {
    /// Starts the driver thread on `transport`.
    pub fn spawn<T: Transport + Send + 'static>(transport: T) -> io::Result<AsyncMaster> {
        let (requests, incoming) = mpsc::channel();
        let thread = thread::Builder::new()
            .name("edsgen-master".into())
            .spawn(move || drive(transport, incoming))?;
        Ok(AsyncMaster {
            requests: Some(requests),
            thread: Some(thread),
        })
    }

    /// Sets the SDO timeout of `node_id` (from its next transfer on).
    pub fn set_timeout(&self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        check_node(node_id)?;
        let micros = timeout.as_micros().min(u128::from(u64::MAX)) as u64;
        self.request(Request::Timeout(node_id, Duration::from_micros(micros)))
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
        self.transfer(node_id, Transfer::Upload(mux, mode)).await
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

    /// Waits until `node_id` sends its boot-up message, at most `timeout`. A boot-up received
    /// since the last wait for that node counts.
    pub async fn wait_for_boot(
        &self,
        node_id: u8,
        timeout: StdDuration,
    ) -> Result<(), MasterError> {
        check_node(node_id)?;
        let micros = timeout.as_micros().min(u128::from(u64::MAX)) as u64;
        let slot = Arc::new(Mutex::new(Slot::default()));
        let reply = Reply(Arc::clone(&slot));
        self.request(Request::WaitBoot(
            node_id,
            Duration::from_micros(micros),
            reply,
        ))?;
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

fn check_node(node_id: u8) -> Result<(), MasterError> {
    if (1..=127).contains(&node_id) {
        Ok(())
    } else {
        Err(MasterError::NodeId(node_id))
    }
}

/// The driver thread: requests in, transfers run side by side, outcomes out, until the
/// [`AsyncMaster`] is dropped and nothing is pending, or the transport fails.
fn drive<T: Transport>(mut transport: T, requests: Receiver<Request>) {
    let clock = MonotonicClock::new();
    let mut channels: BTreeMap<u8, Channel> = BTreeMap::new();
    let mut boot_waits: Vec<BootWait> = Vec::new();
    let mut booted: Vec<u8> = Vec::new();
    let mut open = true;
    loop {
        while open {
            match requests.try_recv() {
                Ok(Request::Sdo(node_id, job)) => {
                    channel(&mut channels, node_id).queue.push_back(job)
                }
                Ok(Request::Timeout(node_id, timeout)) => {
                    channel(&mut channels, node_id).client.set_timeout(timeout)
                }
                Ok(Request::WaitBoot(node_id, timeout, reply)) => {
                    if let Some(i) = booted.iter().position(|&id| id == node_id) {
                        booted.remove(i);
                        reply.send(Ok(Vec::new()));
                    } else {
                        boot_waits.push((node_id, clock.now() + timeout, reply));
                    }
                }
                Ok(Request::Frame(frame, reply)) => match transport.send(&frame) {
                    Ok(()) => reply.send(Ok(Vec::new())),
                    Err(e) => return reply.send(Err(MasterError::Io(e))),
                },
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
        if !open && !busy {
            return;
        }
        let wait = match deadline {
            Some(at) => POLL.min(StdDuration::from_micros((at - now).as_micros())),
            None => POLL,
        };
        match transport.recv_timeout(wait) {
            Ok(Some(frame)) => {
                let server = frame
                    .std_id()
                    .filter(|id| (0x581..=0x5FF).contains(id))
                    .map(|id| (id - 0x580) as u8);
                if let Some(channel) = server.and_then(|id| channels.get_mut(&id)) {
                    channel.client.handle_frame(clock.now(), &frame);
                }
                if let Some(node_id) = boot_up(&frame) {
                    match boot_waits.iter().position(|(id, _, _)| *id == node_id) {
                        Some(i) => boot_waits.remove(i).2.send(Ok(Vec::new())),
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

fn channel(channels: &mut BTreeMap<u8, Channel>, node_id: u8) -> &mut Channel {
    channels.entry(node_id).or_insert_with(|| {
        let mut client = SdoClient::new(node_id);
        client.set_timeout(DEFAULT_TIMEOUT);
        Channel {
            client,
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
        if let Transfer::Download(_, data, _) = &job.transfer {
            job.sent += client.write_data(&data[job.sent..]);
        }
        drain(client, &mut job.received);
    }
    while let Some(frame) = client.poll_transmit(now) {
        transport.send(&frame)?;
    }
    complete(channel);
    Ok(())
}

/// Completes the channel's transfer if it has ended.
fn complete(channel: &mut Channel) {
    let client = &mut channel.client;
    let Some(result) = client.poll_result() else {
        return;
    };
    if let Some(mut job) = channel.current.take() {
        drain(client, &mut job.received);
        let (node_id, mux) = (client.node_id(), client.mux());
        let outcome = result
            .map(|_| core::mem::take(&mut job.received))
            .map_err(|error| MasterError::Sdo {
                node_id,
                mux,
                error,
            });
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
