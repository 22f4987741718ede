//! The async master (feature `std`): [`AsyncMaster`] hands SDO transfers and NMT commands to a
//! driver thread that owns the transport and runs one SDO client per node, all at once, so that
//! transfers to different nodes overlap. The same thread runs the node monitor (heartbeat
//! consumer, guarding master) on its clock, the EMCY consumer, whose events
//! [`AsyncMaster::next_event`] yields, and the LSS master ([`AsyncMaster::lss`]). Its futures need no particular executor (tokio, or any
//! other): the driver thread completes them and wakes their task.
mod channel;
mod driver;
mod lss;
mod slot;

use std::future::poll_fn;
use std::io;
use std::sync::mpsc::{self, Sender};
use std::sync::{Arc, Mutex};
use std::task::Poll;
use std::thread::{self, JoinHandle};
use std::time::Duration as StdDuration;

use crate::Transport;
use edsgen_runtime::master::nmt::{nmt_frame, Watch};
use edsgen_runtime::master::sdo_client::Mode;
#[cfg(doc)]
use edsgen_runtime::master::sdo_client::{SdoClient, DEFAULT_TIMEOUT};
use edsgen_runtime::od::access::{Readable, Writable};
use edsgen_runtime::od::entry::{Entry, OdValue};
use edsgen_runtime::time::Duration;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::wire::sdo::Multiplexer;

use super::blocking::{MasterError, MasterEvent, ReadFeed};
use channel::{Job, Transfer};
use driver::{drive, Request};
use slot::{lock, pending, EventSender, Events, Outcome};

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
        let (reply, pending) = pending();
        self.request(Request::Frame(nmt_frame(command, node_id), reply))?;
        pending.await.map(|_| ())
    }

    /// Watches `node_id` by heartbeat or guarding, from now on the driver thread's clock; its
    /// boot-up, state changes, loss and recovery come from [`next_event`](Self::next_event).
    pub async fn watch(&self, node_id: u8, watch: Watch) -> Result<(), MasterError> {
        let (reply, pending) = pending();
        self.request(Request::Watch(node_id, watch, reply))?;
        pending.await.map(|_| ())
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
        let (reply, pending) = pending();
        self.request(Request::WaitBoot(node_id, to_duration(timeout), reply))?;
        pending.await.map(|_| ())
    }

    async fn transfer(&self, node_id: u8, transfer: Transfer) -> Outcome {
        check_node(node_id)?;
        let (reply, pending) = pending();
        let job = Job {
            transfer,
            reply,
            sent: 0,
            received: Vec::new(),
            failed: None,
            retries: 0,
        };
        self.request(Request::Sdo(node_id, job))?;
        pending.await
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
