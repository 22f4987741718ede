//! The blocking master (feature `std`): a [`Master`] owns a [`Transport`] and runs the sans-IO
//! SDO clients, node monitor and EMCY consumer on it, one call at a time, with timeouts.
//! Typed reads and writes go through the generated [`Entry`](edsgen_runtime::Entry) addresses.
//!
//! This module holds the master, its errors and its event loop; `sdo`, `nmt` and `pdo` hold its
//! SDO transfers, its NMT and monitoring calls and its PDO calls.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt;
use std::io;
use std::time::Duration as StdDuration;

use crate::driver::MonotonicClock;
use crate::Transport;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::time::{Duration, Instant};
use edsgen_runtime::wire::heartbeat::{ErrorControlRepr, NmtState};
use edsgen_runtime::wire::sdo::Multiplexer;

use edsgen_runtime::master::emcy::Emergency;
use edsgen_runtime::master::identity::IdentityMismatch;
use edsgen_runtime::master::nmt::{MonitorEvent, NodeMonitor};
use edsgen_runtime::master::sdo_client::{Completed, SdoClient, SdoError, Transfer};
use edsgen_runtime::wire::sdo::abort_meaning;

mod lss;
mod nmt;
mod pdo;
mod sdo;

use sdo::drain;
pub(super) use sdo::{Feed, ReadFeed};

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
        state: edsgen_runtime::cia402::State,
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
    /// An LSS service failed (no answer, or the slave refused).
    Lss(edsgen_runtime::master::lss::LssMasterError),
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
            MasterError::Lss(e) => write!(f, "LSS: {e}"),
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
    /// How the last transfer that completed went on the wire.
    last_transfer: Option<Transfer>,
}

impl<T: Transport> Master<T> {
    /// A master on `transport`, with the SDO client's default timeout.
    pub fn new(transport: T) -> Self {
        Master {
            transport,
            clock: MonotonicClock::new(),
            default_timeout: edsgen_runtime::master::sdo_client::DEFAULT_TIMEOUT,
            read_retries: 1,
            clients: BTreeMap::new(),
            own_timeouts: BTreeSet::new(),
            monitor: Box::new(NodeMonitor::new()),
            events: VecDeque::new(),
            seen: BTreeMap::new(),
            last_transfer: None,
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

    /// The next event noticed, oldest first.
    pub fn poll_event(&mut self) -> Option<MasterEvent> {
        self.events.pop_front()
    }

    /// How the last SDO transfer that completed went on the wire (a block upload the server
    /// answered segmented says [`Transfer::Segmented`]).
    pub fn last_transfer(&self) -> Option<Transfer> {
        self.last_transfer
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
                client.abort(edsgen_runtime::od::SdoAbort::General.code());
                if let Some(frame) = client.poll_transmit(now) {
                    let _ = self.transport.send(&frame);
                }
                return Err(e);
            }
            let client = self.client(node_id)?;
            if let Some(result) = client.poll_result() {
                drain(client, sink)?;
                if let Ok(completed) = &result {
                    self.last_transfer = Some(completed.transfer);
                }
                let client = self.client(node_id)?;
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

fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

fn to_duration(d: StdDuration) -> Duration {
    Duration::from_micros(d.as_micros().min(u128::from(u64::MAX)) as u64)
}
