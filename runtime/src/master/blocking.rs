//! The blocking master (feature `std`): a [`Master`] owns a [`Transport`] and runs the sans-IO
//! SDO clients, node monitor and EMCY consumer on it, one call at a time, with timeouts.
//! Typed reads and writes go through the generated [`Entry`] addresses.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt;
use std::io;
use std::time::Duration as StdDuration;

use crate::frame::CanFrame;
use crate::od::access::{Readable, Writable};
use crate::od::entry::{Entry, OdValue};
use crate::time::{Duration, Instant};
use crate::transport::driver::MonotonicClock;
use crate::transport::Transport;
use crate::wire::heartbeat::{ErrorControlRepr, NmtState};
use crate::wire::nmt::NmtCommand;
use crate::wire::sdo::Multiplexer;

use super::emcy::Emergency;
use super::identity::{ExpectedIdentity, IdentityMismatch, IDENTITY_ENTRIES};
use super::nmt::{nmt_frame, MonitorEvent, NodeMonitor, Watch, WatchError};
use super::pdo::PdoConfig;
use super::sdo_client::{Completed, Mode, SdoClient, SdoError, StartError};
use crate::wire::sdo::abort_meaning;

/// The longest the master sleeps in a transport before it looks at its timers again.
const MAX_WAIT: StdDuration = StdDuration::from_millis(20);

/// Something the master noticed while it waited for something else.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MasterEvent {
    /// A watched node booted, changed state, was lost or recovered.
    Monitor(MonitorEvent),
    /// A node sent an emergency.
    Emergency(Emergency),
    /// A node sent its boot-up message (watched or not).
    BootUp(u8),
    /// A boot-up check found an identity entry other than expected.
    IdentityMismatch(IdentityMismatch),
}

/// Why a master call failed.
#[derive(Debug)]
pub enum MasterError {
    /// The SDO transfer ended with an abort (or the client's timeout).
    Sdo {
        /// The node.
        node_id: u8,
        /// The entry.
        mux: Multiplexer,
        /// How it ended.
        error: SdoError,
    },
    /// A read value's length does not match the entry's type.
    Length {
        /// The node.
        node_id: u8,
        /// The entry.
        mux: Multiplexer,
        /// The bytes received.
        got: usize,
    },
    /// The value does not fit the entry (a 24-bit entry given a larger number).
    Value,
    /// Nothing happened within the time allowed (waiting for a boot-up).
    Timeout,
    /// A CiA 402 drive did not leave `state` in time (or stays in fault after a reset).
    DriveStuck {
        /// The node.
        node_id: u8,
        /// The state it shows.
        state: crate::cia402::State,
    },
    /// The drive does not show the mode of operation set.
    ModeNotConfirmed {
        /// The node.
        node_id: u8,
        /// The mode written to 6060h.
        wanted: i8,
        /// The mode 6061h shows.
        shown: i8,
    },
    /// The node's SDO channel is still busy (a transfer cut short by a transport error).
    Busy(u8),
    /// The node-ID is not 1..=127 (0 for a broadcast where one is allowed).
    NodeId(u8),
    /// The transport failed: the bus is gone.
    Io(io::Error),
}

impl fmt::Display for MasterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MasterError::Sdo {
                node_id,
                mux,
                error,
            } => {
                let code = error.code();
                let who = match error {
                    SdoError::Server(_) => "node aborted",
                    SdoError::Timeout => "no answer, aborted",
                    SdoError::Client(_) => "master aborted",
                };
                write!(
                    f,
                    "SDO {:04X}h:{:02X}h on node {node_id}: {who} with {:04X} {:04X}h ({})",
                    mux.index,
                    mux.sub,
                    code >> 16,
                    code & 0xFFFF,
                    abort_meaning(code).unwrap_or("unknown abort code")
                )
            }
            MasterError::Length { node_id, mux, got } => write!(
                f,
                "{:04X}h:{:02X}h on node {node_id}: {got} bytes do not match the entry's type",
                mux.index, mux.sub
            ),
            MasterError::Value => write!(f, "the value does not fit the entry"),
            MasterError::Timeout => write!(f, "timed out"),
            MasterError::DriveStuck { node_id, state } => {
                write!(f, "the drive of node {node_id} stays in {state:?}")
            }
            MasterError::ModeNotConfirmed {
                node_id,
                wanted,
                shown,
            } => write!(
                f,
                "node {node_id} shows mode of operation {shown}, not {wanted}"
            ),
            MasterError::Busy(id) => write!(f, "the SDO channel to node {id} is busy"),
            MasterError::NodeId(id) => write!(f, "node-ID {id} is not 1..=127"),
            MasterError::Io(e) => write!(f, "bus: {e}"),
        }
    }
}

impl std::error::Error for MasterError {}

impl From<io::Error> for MasterError {
    fn from(e: io::Error) -> Self {
        MasterError::Io(e)
    }
}

/// A CANopen master on one bus, driven by the calling thread.
pub struct Master<T> {
    transport: T,
    clock: MonotonicClock,
    default_timeout: Duration,
    read_retries: u8,
    clients: BTreeMap<u8, SdoClient>,
    /// The nodes whose SDO timeout was set for them, which the default leaves alone.
    own_timeouts: BTreeSet<u8>,
    monitor: Box<NodeMonitor<127>>,
    events: VecDeque<MasterEvent>,
    /// The last error-control state each node reported (watched or not).
    seen: BTreeMap<u8, NmtState>,
}

impl<T: Transport> Master<T> {
    /// A master on `transport`, with the SDO client's default timeout.
    pub fn new(transport: T) -> Self {
        Master {
            transport,
            clock: MonotonicClock::new(),
            default_timeout: super::sdo_client::DEFAULT_TIMEOUT,
            read_retries: 1,
            clients: BTreeMap::new(),
            own_timeouts: BTreeSet::new(),
            monitor: Box::new(NodeMonitor::new()),
            events: VecDeque::new(),
            seen: BTreeMap::new(),
        }
    }

    /// The transport, for frames the master does not speak (PDOs).
    pub fn transport_mut(&mut self) -> &mut T {
        &mut self.transport
    }

    /// The SDO timeout of nodes without one of their own.
    pub fn set_default_timeout(&mut self, timeout: StdDuration) {
        self.default_timeout = to_duration(timeout);
        for (node_id, client) in self.clients.iter_mut() {
            if !self.own_timeouts.contains(node_id) {
                client.set_timeout(self.default_timeout);
            }
        }
    }

    /// How many times a read that timed out before any byte arrived is tried again (1 by
    /// default). Writes are never repeated: the node may have applied one it did not confirm.
    pub fn set_read_retries(&mut self, retries: u8) {
        self.read_retries = retries;
    }

    /// The SDO timeout for `node_id`, which [`set_default_timeout`](Self::set_default_timeout)
    /// then leaves alone.
    pub fn set_timeout(&mut self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        self.client(node_id)?.set_timeout(to_duration(timeout));
        self.own_timeouts.insert(node_id);
        Ok(())
    }

    /// Reads `entry` of `node_id`, typed (an address of any device's generated module).
    pub fn read<V: OdValue, D, A: Readable>(
        &mut self,
        node_id: u8,
        entry: Entry<V, D, A>,
    ) -> Result<V, MasterError> {
        let mux = Multiplexer::new(entry.index, entry.sub);
        let bytes = self.upload(node_id, mux, Mode::Normal)?;
        entry.decode(&bytes).ok_or(MasterError::Length {
            node_id,
            mux,
            got: bytes.len(),
        })
    }

    /// Writes `value` to `entry` of `node_id`.
    pub fn write<V: OdValue, D, A: Writable>(
        &mut self,
        node_id: u8,
        entry: Entry<V, D, A>,
        value: V,
    ) -> Result<(), MasterError> {
        let now = self.clock.now();
        let client = self.client(node_id)?;
        match client.write(now, entry, &value) {
            Ok(()) => {}
            Err(StartError::Value) => return Err(MasterError::Value),
            Err(StartError::Busy) => return Err(MasterError::Busy(node_id)),
        }
        self.finish(node_id, &mut [].as_slice(), &mut Vec::new())
            .map(|_| ())
    }

    /// Reads the value of (index, sub) as bytes, by `mode`.
    pub fn upload(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
    ) -> Result<Vec<u8>, MasterError> {
        let mut value = Vec::new();
        self.upload_to(node_id, mux, mode, &mut value)?;
        Ok(value)
    }

    /// Reads the value of (index, sub) into `sink` as it arrives (a domain of any length);
    /// returns its length.
    pub fn upload_to(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
        sink: &mut impl io::Write,
    ) -> Result<u32, MasterError> {
        let mut sink = CountingSink {
            inner: sink,
            count: 0,
        };
        let mut retries = self.read_retries;
        loop {
            let now = self.clock.now();
            if self.client(node_id)?.upload(now, mux, mode).is_err() {
                return Err(MasterError::Busy(node_id));
            }
            match self.finish(node_id, &mut [].as_slice(), &mut sink) {
                Err(MasterError::Sdo {
                    error: SdoError::Timeout,
                    ..
                }) if retries > 0 && sink.count == 0 => retries -= 1,
                result => return result.map(|done| done.size),
            }
        }
    }

    /// Writes `data` to (index, sub) by `mode`.
    pub fn download(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        data: &[u8],
        mode: Mode,
    ) -> Result<(), MasterError> {
        let now = self.clock.now();
        let size = u32::try_from(data.len()).map_err(|_| MasterError::Value)?;
        if self
            .client(node_id)?
            .download(now, mux, size, mode)
            .is_err()
        {
            return Err(MasterError::Busy(node_id));
        }
        self.finish(node_id, &mut &data[..], &mut io::sink())
            .map(|_| ())
    }

    /// Writes to (index, sub) by `mode` a value read from `source` until its end, of a length
    /// not known up front (a file, a generated image): the size is not indicated (see
    /// [`SdoClient::download_unsized`]). Returns the value's length. An error of `source`
    /// aborts the transfer (0800 0000) and is returned as [`MasterError::Io`].
    pub fn download_from(
        &mut self,
        node_id: u8,
        mux: Multiplexer,
        mode: Mode,
        source: &mut impl io::Read,
    ) -> Result<u32, MasterError> {
        let now = self.clock.now();
        if self
            .client(node_id)?
            .download_unsized(now, mux, mode)
            .is_err()
        {
            return Err(MasterError::Busy(node_id));
        }
        let mut source = ReadFeed::new(source);
        self.finish(node_id, &mut source, &mut io::sink())
            .map(|done| done.size)
    }

    /// Sends an NMT command to `node_id` (0: all nodes).
    pub fn nmt(&mut self, command: NmtCommand, node_id: u8) -> Result<(), MasterError> {
        if node_id > 127 {
            return Err(MasterError::NodeId(node_id));
        }
        self.transport.send(&nmt_frame(command, node_id))?;
        Ok(())
    }

    /// Watches `node_id` by heartbeat or guarding; its events come from
    /// [`poll_event`](Self::poll_event).
    pub fn watch(&mut self, node_id: u8, watch: Watch) -> Result<(), MasterError> {
        let now = self.clock.now();
        self.monitor
            .watch(now, node_id, watch)
            .map_err(|e| match e {
                WatchError::Full | WatchError::Invalid => MasterError::NodeId(node_id),
            })
    }

    /// Waits until `node_id` sends its boot-up message, at most `timeout`. A boot-up received
    /// earlier and not yet taken as an event counts.
    pub fn wait_for_boot(&mut self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        let is_boot = |e: &MasterEvent| *e == MasterEvent::BootUp(node_id);
        let deadline = self.clock.now() + to_duration(timeout);
        loop {
            if let Some(i) = self.events.iter().position(is_boot) {
                self.events.remove(i);
                return Ok(());
            }
            let now = self.clock.now();
            if now >= deadline {
                return Err(MasterError::Timeout);
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
    }

    /// The boot-up check: reads 1000h and 1018h:1–4 where `expected` names a value and
    /// returns each difference (also queued as a [`MasterEvent::IdentityMismatch`]). A read
    /// that fails with an abort is a mismatch; a transport error is an error.
    pub fn check_identity(
        &mut self,
        node_id: u8,
        expected: &ExpectedIdentity,
    ) -> Result<Vec<IdentityMismatch>, MasterError> {
        let mut mismatches = Vec::new();
        for (entry, expected) in IDENTITY_ENTRIES.into_iter().zip(expected.expected()) {
            let Some(expected) = expected else {
                continue;
            };
            let (actual, abort) = match self.read(node_id, entry) {
                Ok(value) if value == expected => continue,
                Ok(value) => (Some(value), None),
                Err(MasterError::Sdo { error, .. }) => (None, Some(error.code())),
                Err(MasterError::Length { .. }) => (None, None),
                Err(e) => return Err(e),
            };
            let mismatch = IdentityMismatch {
                node_id,
                entry,
                expected,
                actual,
                abort,
            };
            self.events
                .push_back(MasterEvent::IdentityMismatch(mismatch));
            mismatches.push(mismatch);
        }
        Ok(mismatches)
    }

    /// Boots a node as a CiA 302 master would, in spirit: waits for its boot-up (at most
    /// `timeout`), checks its identity, downloads `configuration` (a DCF's values, see
    /// [`download_configuration`](Self::download_configuration)) and starts it. A node whose
    /// identity differs is neither configured nor started: the mismatches are returned (and
    /// queued as events); an empty list means the node runs.
    pub fn boot_node<V: AsRef<[u8]>>(
        &mut self,
        node_id: u8,
        expected: &ExpectedIdentity,
        configuration: &[(Multiplexer, V)],
        timeout: StdDuration,
    ) -> Result<Vec<IdentityMismatch>, MasterError> {
        self.wait_for_boot(node_id, timeout)?;
        let mismatches = self.check_identity(node_id, expected)?;
        if mismatches.is_empty() {
            self.download_configuration(node_id, configuration)?;
            self.nmt(NmtCommand::Start, node_id)?;
        }
        Ok(mismatches)
    }

    /// Finds the nodes on the bus: an SDO upload of 1000h to every node-ID 1..=127 at once (one
    /// channel each), and the node-IDs that answered within `timeout` (with a value or an
    /// abort), in order. Node-IDs that stay silent are not sent an abort.
    pub fn scan(&mut self, timeout: StdDuration) -> Result<Vec<u8>, MasterError> {
        let now = self.clock.now();
        for node_id in 1..=127 {
            let client = self.client(node_id)?;
            if client
                .upload(now, Multiplexer::new(0x1000, 0), Mode::Normal)
                .is_err()
            {
                return Err(MasterError::Busy(node_id));
            }
        }
        let deadline = now + to_duration(timeout);
        let mut found = Vec::new();
        loop {
            let now = self.clock.now();
            for (&node_id, client) in self.clients.iter_mut() {
                match client.poll_result() {
                    Some(Ok(_)) | Some(Err(SdoError::Server(_))) => found.push(node_id),
                    _ => {}
                }
            }
            if now >= deadline || self.clients.values().all(|c| !c.is_busy()) {
                break;
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
        for client in self.clients.values_mut() {
            client.cancel();
        }
        found.sort_unstable();
        Ok(found)
    }

    /// The NMT state `node_id` reports: the last heartbeat seen, else the answer to a guarding
    /// RTR within `timeout` (`None` if the node does not answer one).
    pub fn query_state(
        &mut self,
        node_id: u8,
        timeout: StdDuration,
    ) -> Result<Option<NmtState>, MasterError> {
        if let Some(state) = self.last_state(node_id) {
            return Ok(Some(state));
        }
        let id = ErrorControlRepr::cob_id(node_id);
        self.transport.send(&CanFrame::remote(id, 1))?;
        let deadline = self.clock.now() + to_duration(timeout);
        loop {
            let now = self.clock.now();
            if let Some(state) = self.last_state(node_id) {
                return Ok(Some(state));
            }
            if now >= deadline {
                return Ok(None);
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
    }

    /// Configures a PDO of `node_id` by SDO in CiA 301's safe order (see
    /// [`PdoConfig::writes`]); the first write the node refuses is the error. For the PDO a
    /// generated struct describes: `PdoConfig::of::<cp301::pdo::Tpdo1>(cob_id, 254, Some(20))`.
    pub fn configure_pdo(&mut self, node_id: u8, config: &PdoConfig) -> Result<(), MasterError> {
        for (mux, value, len) in config.writes() {
            let bytes = value.to_le_bytes();
            self.download(node_id, mux, &bytes[..usize::from(len)], Mode::Normal)?;
        }
        Ok(())
    }

    /// Downloads a configuration (a DCF's ParameterValues) in the safe order of
    /// [`download_order`](super::dcf::download_order); the first write the node refuses is the
    /// error (naming the entry).
    pub fn download_configuration<V: AsRef<[u8]>>(
        &mut self,
        node_id: u8,
        entries: &[(Multiplexer, V)],
    ) -> Result<(), MasterError> {
        for (mux, value) in super::dcf::download_order(entries) {
            value.with_bytes(|bytes| self.download(node_id, mux, bytes, Mode::Normal))?;
        }
        Ok(())
    }

    /// Sends a PDO: `payload` (a generated struct's `encode()`) on `cob_id` (its `cob_id(node)`:
    /// an 11-bit identifier as `u16`, or a 29-bit one as `u32` above 7FFh).
    pub fn send_pdo(&mut self, cob_id: impl Into<u32>, payload: &[u8]) -> Result<(), MasterError> {
        let cob_id = cob_id.into();
        let frame = match u16::try_from(cob_id) {
            Ok(id) if id <= 0x7FF => CanFrame::new(id, payload),
            _ => CanFrame::new_extended(cob_id, payload),
        };
        self.transport.send(&frame.ok_or(MasterError::Value)?)?;
        Ok(())
    }

    /// Waits at most `timeout` for a frame `accept` takes (a PDO decoded by a
    /// [`pdo_dispatch!`](crate::pdo_dispatch) enum), handling everything else as usual.
    pub fn receive<R>(
        &mut self,
        timeout: StdDuration,
        mut accept: impl FnMut(&CanFrame) -> Option<R>,
    ) -> Result<Option<R>, MasterError> {
        let deadline = self.clock.now() + to_duration(timeout);
        loop {
            let now = self.clock.now();
            if now >= deadline {
                return Ok(None);
            }
            let wait = StdDuration::from_micros((deadline - now).as_micros()).min(MAX_WAIT);
            if let Some(frame) = self.transport.recv_timeout(wait)? {
                self.dispatch(&frame);
                if let Some(taken) = accept(&frame) {
                    return Ok(Some(taken));
                }
            }
        }
    }

    /// Listens for `duration`, collecting events.
    pub fn listen(&mut self, duration: StdDuration) -> Result<(), MasterError> {
        let deadline = self.clock.now() + to_duration(duration);
        loop {
            let now = self.clock.now();
            if now >= deadline {
                return Ok(());
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
    }

    /// The next event noticed, oldest first.
    pub fn poll_event(&mut self) -> Option<MasterEvent> {
        self.events.pop_front()
    }

    /// The last state `node_id` reported by heartbeat, boot-up or guarding answer.
    pub fn last_state(&self, node_id: u8) -> Option<NmtState> {
        self.seen.get(&node_id).copied()
    }

    fn client(&mut self, node_id: u8) -> Result<&mut SdoClient, MasterError> {
        if !(1..=127).contains(&node_id) {
            return Err(MasterError::NodeId(node_id));
        }
        let timeout = self.default_timeout;
        Ok(self.clients.entry(node_id).or_insert_with(|| {
            let mut client = SdoClient::new(node_id);
            client.set_timeout(timeout);
            client
        }))
    }

    /// Runs the transfer on `node_id`'s channel to its end, feeding it from `source` and
    /// draining it into `sink`.
    fn finish(
        &mut self,
        node_id: u8,
        source: &mut impl Feed,
        sink: &mut impl io::Write,
    ) -> Result<Completed, MasterError> {
        loop {
            let now = self.clock.now();
            if let Err(e) = self.step(now, None, source, sink) {
                // The bus or the source is gone: free the channel for a later call, and tell
                // the node if the bus is still there.
                let client = self.client(node_id)?;
                client.abort(crate::od::SdoAbort::General.code());
                if let Some(frame) = client.poll_transmit(now) {
                    let _ = self.transport.send(&frame);
                }
                return Err(e);
            }
            let client = self.client(node_id)?;
            if let Some(result) = client.poll_result() {
                drain(client, sink)?;
                return result.map_err(|error| MasterError::Sdo {
                    node_id,
                    mux: client.mux(),
                    error,
                });
            }
        }
    }

    /// One round: timers, data in and out of the busy channel, frames out, then one wait for
    /// a frame (until the next deadline, `until`, or [`MAX_WAIT`]).
    fn step(
        &mut self,
        now: Instant,
        until: Option<Instant>,
        source: &mut impl Feed,
        sink: &mut impl io::Write,
    ) -> Result<(), MasterError> {
        let mut deadline = until;
        for client in self.clients.values_mut() {
            if client.poll_timeout().is_some_and(|at| at <= now) {
                client.handle_timeout(now);
            }
            if client.is_busy() {
                source.feed(client)?;
                drain(client, sink)?;
            }
            while let Some(frame) = client.poll_transmit(now) {
                self.transport.send(&frame)?;
            }
            deadline = earliest(deadline, client.poll_timeout());
        }
        if self.monitor.poll_timeout().is_some_and(|at| at <= now) {
            self.monitor.handle_timeout(now);
        }
        while let Some(frame) = self.monitor.poll_transmit(now) {
            self.transport.send(&frame)?;
        }
        while let Some(event) = self.monitor.poll_event() {
            self.events.push_back(MasterEvent::Monitor(event));
        }
        deadline = earliest(deadline, self.monitor.poll_timeout());
        let wait = match deadline {
            Some(at) => MAX_WAIT.min(StdDuration::from_micros((at - now).as_micros())),
            None => MAX_WAIT,
        };
        if let Some(frame) = self.transport.recv_timeout(wait)? {
            self.dispatch(&frame);
        }
        Ok(())
    }

    fn dispatch(&mut self, frame: &CanFrame) {
        let now = self.clock.now();
        if let Some(id) = frame.std_id().filter(|id| (0x581..=0x5FF).contains(id)) {
            if let Some(client) = self.clients.get_mut(&((id - 0x580) as u8)) {
                client.handle_frame(now, frame);
            }
        }
        self.monitor.handle_frame(now, frame);
        if let Some(emergency) = Emergency::from_frame(frame) {
            self.events.push_back(MasterEvent::Emergency(emergency));
        }
        let error_control = frame
            .std_id()
            .filter(|id| (0x701..=0x77F).contains(id) && !frame.is_remote())
            .zip(ErrorControlRepr::parse(frame.data()));
        if let Some((id, message)) = error_control {
            let node_id = (id - 0x700) as u8;
            if message == ErrorControlRepr::BOOT_UP {
                self.events.push_back(MasterEvent::BootUp(node_id));
                self.seen.insert(node_id, NmtState::PreOperational);
            } else {
                self.seen.insert(node_id, message.state);
            }
        }
    }
}

/// Where a download's bytes come from.
pub(super) trait Feed {
    /// Gives `client` as many bytes as its window takes now (and ends a value of unannounced
    /// size at the source's end).
    fn feed(&mut self, client: &mut SdoClient) -> io::Result<()>;
}

/// A value in memory, of known size.
impl Feed for &[u8] {
    fn feed(&mut self, client: &mut SdoClient) -> io::Result<()> {
        let taken = client.write_data(self);
        *self = &self[taken..];
        Ok(())
    }
}

/// A value read from a reader until its end, of unannounced size.
pub(super) struct ReadFeed<R> {
    reader: R,
    chunk: [u8; 256],
    /// The chunk's bytes not yet taken by the client.
    start: usize,
    end: usize,
    done: bool,
}

impl<R: io::Read> ReadFeed<R> {
    pub(super) fn new(reader: R) -> Self {
        ReadFeed {
            reader,
            chunk: [0; 256],
            start: 0,
            end: 0,
            done: false,
        }
    }
}

impl<R: io::Read> Feed for ReadFeed<R> {
    fn feed(&mut self, client: &mut SdoClient) -> io::Result<()> {
        loop {
            if self.start == self.end && !self.done {
                let n = loop {
                    match self.reader.read(&mut self.chunk) {
                        Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                        result => break result?,
                    }
                };
                (self.start, self.end) = (0, n);
                self.done = n == 0;
            }
            if self.done {
                client.end_data();
                return Ok(());
            }
            let taken = client.write_data(&self.chunk[self.start..self.end]);
            self.start += taken;
            if taken == 0 {
                return Ok(()); // the window is full
            }
        }
    }
}

/// A sink that counts what it was given, so that a read is repeated only if nothing of it
/// reached the caller.
struct CountingSink<'a, W> {
    inner: &'a mut W,
    count: usize,
}

impl<W: io::Write> io::Write for CountingSink<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.count += n;
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

fn drain(client: &mut SdoClient, sink: &mut impl io::Write) -> io::Result<()> {
    let mut chunk = [0u8; 256];
    loop {
        let n = client.read_data(&mut chunk);
        if n == 0 {
            return Ok(());
        }
        sink.write_all(&chunk[..n])?;
    }
}

fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

fn to_duration(d: StdDuration) -> Duration {
    Duration::from_micros(d.as_micros().min(u128::from(u64::MAX)) as u64)
}
