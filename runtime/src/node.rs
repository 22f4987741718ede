//! The device side of CiA 301: a sans-IO [`Node`] that serves an object dictionary.
//!
//! A node owns the OD and its node-ID. It takes received frames with a timestamp
//! ([`Node::handle_frame`]) and offers frames to send ([`Node::poll_transmit`]), its next deadline
//! ([`Node::poll_timeout`], then [`Node::handle_timeout`]) and application events
//! ([`Node::poll_event`]). It implements the NMT slave, the SDO server (1200h and, if the OD has
//! it, 1201h; block transfer with the `sdo-block` feature), heartbeat producer and consumer, node
//! guarding (with the `node-guarding` feature), SYNC consumer and producer, the EMCY
//! producer with 1001h/1003h, TPDOs and RPDOs of every transmission type with dynamic mapping,
//! RPDO deadline monitoring (event timer, EMCY 8250h), and store/restore (1010h/1011h) through
//! [`NodeHooks`]. No allocation, no clock reads.
//!
//! Services by NMT state (CiA 301 table 80): pre-operational serves SDO, SYNC, EMCY and error
//! control; operational adds PDOs; stopped serves only NMT and error control (heartbeat, node
//! guarding, heartbeat consumer).
//!
//! The node routes frames to one module per service, each owning its state: `error_control`
//! (heartbeat producer and consumers, node guarding), `sync`, `emcy`, `pdo` (RPDOs and TPDOs),
//! `sdo_channel` (the SDO server channels), `comm` (the CiA 301 checks on writes to
//! communication objects) and `events` (the application's event queue). The node holds the
//! instants of the services' timers in one table of named timers (`timer`), with one place that
//! finds the earliest and one that runs those due; the services say when to arm them and what
//! their expiry does.
//!
//! Choices CiA 301 leaves open, documented where they are made: an NMT reset restores the
//! dictionary's defaults of its area ([`NodeHooks::restore_power_on`]); a SYNC whose length
//! does not match 1019h is not processed (EMCY 8240h); an RPDO the dictionary refuses a value
//! of is not applied at all (EMCY 8200h with the PDO number and the abort code); writing 0 to
//! 1003h:00 clears the recorded codes too (their sub-indices read 0).

mod comm;
mod emcy;
mod error_control;
mod events;
mod pdo;
mod sdo_channel;
mod sync;
mod timer;

pub use self::comm::{LOAD_SIGNATURE, SAVE_SIGNATURE};
pub use self::emcy::{error_code, error_register, MAX_ACTIVE_ERRORS};
pub use self::error_control::MAX_HEARTBEAT_CONSUMERS;
pub use self::pdo::MAX_MAPPED;
pub use crate::wire::heartbeat::NmtState;

use self::comm::CommGuard;
use self::emcy::{Emcy, Raised};
use self::error_control::ErrorControl;
use self::events::EventQueue;
use self::pdo::{Rpdo, Tpdo};
use self::sdo_channel::SdoChannel;
use self::sync::Sync;
use self::timer::{Timer, TimerTable};
use crate::frame::CanFrame;
use crate::od::{ObjectDictionary, SdoAbort};
use crate::sdo::SdoEvent;
use crate::time::{Duration, Instant};
use crate::wire::heartbeat::ErrorControlRepr;
use crate::wire::nmt::{NmtCommand, NmtRepr, NMT_COB_ID};
use crate::wire::sync::SyncRepr;

pub use self::events::EVENT_QUEUE;
pub use self::sdo_channel::SDO_TIMEOUT;

/// The emergency code of a SYNC consumer that misses SYNC for 1.5 × 1006h
/// ([`error_code::COMMUNICATION`]).
pub const SYNC_TIMEOUT_CODE: u16 = error_code::COMMUNICATION;
/// The emergency code of an RPDO that did not arrive within its event timer
/// ([`error_code::RPDO_TIMEOUT`]).
pub const RPDO_TIMEOUT_CODE: u16 = error_code::RPDO_TIMEOUT;

/// The errors the communication layer raises itself: a reset communication forgets them, as it
/// starts its monitoring afresh.
const COMMUNICATION_ERRORS: [u16; 7] = [
    error_code::COMMUNICATION,
    error_code::LIFE_GUARD,
    error_code::PROTOCOL,
    error_code::PDO_LENGTH,
    error_code::PDO_LENGTH_EXCEEDED,
    error_code::SYNC_LENGTH,
    error_code::RPDO_TIMEOUT,
];

/// Which parameters an NMT reset re-initialises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ResetKind {
    /// Reset node: application and communication parameters (and power-on).
    Node,
    /// Reset communication: communication parameters (1000h–1FFFh) only.
    Communication,
}

impl ResetKind {
    /// The indices it re-initialises: every one for reset node, the communication area
    /// (1000h–1FFFh) for reset communication.
    pub const fn indices(self) -> core::ops::RangeInclusive<u16> {
        match self {
            ResetKind::Node => 0x0000..=0xFFFF,
            ResetKind::Communication => 0x1000..=0x1FFF,
        }
    }
}

/// What the application learns from the node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Event {
    /// The NMT state changed (after a reset: to pre-operational, following [`Event::Reset`]).
    NmtStateChanged(NmtState),
    /// An NMT reset ran; [`NodeHooks::reset`] has re-initialised the OD.
    Reset(ResetKind),
    /// An SDO client wrote an entry.
    Written {
        /// OD index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
    /// A receive PDO wrote its mapped entries (`pdo` n is the one at 1400h + n).
    RpdoReceived {
        /// The PDO's number, from 0.
        pdo: u16,
    },
    /// A receive PDO with deadline monitoring (event timer, 1400h+n sub 05h) did not arrive
    /// within that time of its last reception; EMCY 8250h is raised with it, and cleared when
    /// the PDO arrives again. Reported once per timeout.
    RpdoTimeout {
        /// The PDO's number, from 0.
        pdo: u16,
    },
    /// A SYNC was received (or produced by this node).
    Sync {
        /// The SYNC counter, if the message carries one.
        counter: Option<u8>,
    },
    /// A node watched by the heartbeat consumer (1016h) missed its heartbeat; EMCY 8130h is
    /// raised with it (manufacturer byte 0 the node-ID), and cleared once every lost node beats
    /// again (or is no longer watched) and life guarding is not lost.
    HeartbeatLost {
        /// The silent node.
        node_id: u8,
    },
    /// The NMT master stopped guarding this node within the life time (100Ch × 100Dh); EMCY
    /// 8130h is raised with it, and cleared by the next guard request unless a watched
    /// heartbeat is lost too.
    LifeGuardingLost,
    /// A PDO whose COB-ID is valid in the OD is not served, because its mapping (1600h+n or
    /// 1A00h+n) was refused: reported when the node reads its configuration (power-on, reset
    /// communication).
    PdoMappingRejected {
        /// Transmit (1A00h+n) or receive (1600h+n).
        transmit: bool,
        /// The PDO's number n, from 0.
        pdo: u16,
        /// Why: 0604 0041 (an object cannot be mapped) or 0604 0042 (too long).
        reason: SdoAbort,
    },
}

/// What the application provides to the node: re-initialisation on reset, and the persistence
/// behind store (1010h) and restore (1011h). Every method has a default (NMT resets restore the
/// dictionary's defaults, the rest does nothing or refuses), so `()` is a valid hook for a node
/// without persistence.
pub trait NodeHooks<O: ?Sized> {
    /// Sets the parameters that `kind` re-initialises to their power-on values (stored ones, or
    /// defaults after a restore). Called at power-on with [`ResetKind::Node`], and on NMT resets
    /// after [`restore_power_on`](Self::restore_power_on) has set the dictionary's defaults.
    fn reset(&mut self, kind: ResetKind, od: &mut O) {
        let _ = (kind, od);
    }

    /// Sets what an NMT reset of `kind` re-initialises to the dictionary's defaults, before
    /// [`reset`](Self::reset) runs: by default
    /// [`ObjectDictionary::restore_defaults`] over [`ResetKind::indices`]. Not called at
    /// power-on, where the node takes the dictionary as the application built it. Override it
    /// to keep values across resets, or to load stored ones instead.
    fn restore_power_on(&mut self, kind: ResetKind, node_id: u8, od: &mut O)
    where
        O: ObjectDictionary,
    {
        od.restore_defaults(kind.indices(), node_id);
    }

    /// Stores parameters after "save" was written to 1010h:`sub` (1 all, 2 communication,
    /// 3 application, 4+ manufacturer). An error becomes the SDO abort.
    fn save(&mut self, sub: u8, od: &O) -> Result<(), SdoAbort> {
        let _ = (sub, od);
        Err(SdoAbort::CannotStore)
    }

    /// Restores default parameters after "load" was written to 1011h:`sub`; they take effect at
    /// the next reset. An error becomes the SDO abort.
    fn restore_defaults(&mut self, sub: u8) -> Result<(), SdoAbort> {
        let _ = sub;
        Err(SdoAbort::CannotStore)
    }
}

impl<O: ?Sized> NodeHooks<O> for () {}

/// Why a node could not be created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InvalidNodeId(pub u8);

/// Lowers `next` to `at` if `at` is earlier (or `next` is `None`). Not inlined, and `at` by
/// reference: [`Node::poll_timeout`] calls it once per timer, and one copy keeps that small in
/// flash.
#[inline(never)]
pub(crate) fn keep_earliest(next: &mut Option<Instant>, at: &Option<Instant>) {
    if let Some(at) = *at {
        if next.is_none_or(|next| at < next) {
            *next = Some(at);
        }
    }
}

/// The next time of a periodic timer that was due `at`: one `period` later, or one period from
/// `now` if that is already past (the caller was late by a period or more). Not inlined: the
/// heartbeat producer and the SYNC producer share one copy.
#[inline(never)]
fn next_period(at: Instant, period: Duration, now: Instant) -> Instant {
    let next = at + period;
    if next <= now {
        now + period
    } else {
        next
    }
}

/// A frame of at most one data byte (boot-up, heartbeat, node guarding, SYNC). The payload is
/// built as one integer rather than byte by byte, so that the frames `poll_transmit` returns
/// from its different branches join as whole words (smaller code on a 32-bit target).
fn one_byte_frame(id: u16, byte: u8, len: u8) -> CanFrame {
    CanFrame::from_parts(id, u64::from(byte).to_le_bytes(), len)
}

/// Reads an unsigned value of up to 4 bytes, zero-extended, or `default` if the OD does not have
/// it. Not inlined: the node reads some twenty configuration values this way.
#[inline(never)]
pub(crate) fn read_uint_or<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    sub: u8,
    default: u32,
) -> u32 {
    read_uint(od, index, sub).unwrap_or(default)
}

/// Reads an unsigned value of up to 4 bytes, zero-extended.
pub(crate) fn read_uint<O: ObjectDictionary + ?Sized>(od: &O, index: u16, sub: u8) -> Option<u32> {
    let mut bytes = [0u8; 4];
    od.read(index, sub, 0, &mut bytes).ok()?;
    Some(u32::from_le_bytes(bytes))
}

/// A CANopen device serving the object dictionary `O`, with `RPDOS` receive and `TPDOS`
/// transmit PDOs (1400h.. and 1800h.., as far as the OD has them).
pub struct Node<O, H = (), const RPDOS: usize = 4, const TPDOS: usize = 4> {
    od: O,
    hooks: H,
    node_id: u8,
    state: NmtState,
    boot_up_due: bool,
    sdo: [SdoChannel; 2],
    error_control: ErrorControl,
    sync: Sync,
    emcy: Emcy,
    rpdos: [Rpdo; RPDOS],
    tpdos: [Tpdo; TPDOS],
    events: EventQueue,
    timers: TimerTable<RPDOS, TPDOS>,
    /// After a reset node that cleared errors, announce "no error" once.
    announce_no_error: bool,
    /// Some RPDO's last frame had the wrong length (8210h/8220h raised): the next frame of
    /// the right length looks whether they clear.
    length_error_raised: bool,
    /// Some TPDO may have something to send or a change to look for (a fast path for
    /// [`Node::poll_transmit`]).
    tpdo_attention: bool,
}

impl<O: ObjectDictionary> Node<O> {
    /// A node with 4 RPDOs and 4 TPDOs and no persistence hooks. See [`Node::with_capacity`].
    pub fn new(od: O, node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        Node::with_capacity(od, (), node_id, now)
    }
}

impl<O: ObjectDictionary, H: NodeHooks<O>> Node<O, H> {
    /// A node with 4 RPDOs and 4 TPDOs and the application's hooks. See [`Node::with_capacity`].
    pub fn with_hooks(od: O, hooks: H, node_id: u8, now: Instant) -> Result<Self, InvalidNodeId> {
        Node::with_capacity(od, hooks, node_id, now)
    }
}

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    /// Powers the node on at `now`, with room for `RPDOS` receive and `TPDOS` transmit PDOs
    /// (`Node::<Od, Hooks, 8, 8>::with_capacity(od, hooks, 3, now)`): the hooks load power-on
    /// values ([`ResetKind::Node`]), the node reads its communication parameters, queues the
    /// boot-up message and enters pre-operational. `node_id` must be 1..=127.
    #[inline(never)]
    pub fn with_capacity(
        od: O,
        hooks: H,
        node_id: u8,
        now: Instant,
    ) -> Result<Self, InvalidNodeId> {
        if !matches!(node_id, 1..=127) {
            return Err(InvalidNodeId(node_id));
        }
        let mut node = Node {
            od,
            hooks,
            node_id,
            state: NmtState::Initialising,
            boot_up_due: false,
            // The second channel is read from 1201h by reset communication below.
            sdo: [SdoChannel::new(node_id), SdoChannel::new(node_id)],
            error_control: ErrorControl::OFF,
            sync: Sync::default(),
            emcy: Emcy::default(),
            rpdos: const { [Rpdo::OFF; RPDOS] },
            tpdos: const { [Tpdo::OFF; TPDOS] },
            events: EventQueue::new(),
            timers: TimerTable::OFF,
            announce_no_error: false,
            length_error_raised: false,
            tpdo_attention: false,
        };
        node.hooks.reset(ResetKind::Node, &mut node.od);
        node.reset_communication(now);
        Ok(node)
    }

    /// The node-ID.
    pub fn node_id(&self) -> u8 {
        self.node_id
    }

    /// The NMT state.
    pub fn nmt_state(&self) -> NmtState {
        self.state
    }

    /// The object dictionary.
    pub fn od(&self) -> &O {
        &self.od
    }

    /// The object dictionary, for the application to update. Event-driven and acyclic TPDOs
    /// compare their mapped values before the next transmission (change-of-state detection).
    /// Writes to communication objects here bypass the CiA 301 checks and are applied at the
    /// next reset communication.
    pub fn od_mut(&mut self) -> &mut O {
        for tpdo in &mut self.tpdos {
            tpdo.mark_changed();
            self.tpdo_attention = true;
        }
        &mut self.od
    }

    /// The hooks.
    pub fn hooks(&self) -> &H {
        &self.hooks
    }

    /// The hooks, mutably.
    pub fn hooks_mut(&mut self) -> &mut H {
        &mut self.hooks
    }

    /// Events dropped because the application did not poll them in time.
    pub fn events_lost(&self) -> u32 {
        self.events.lost()
    }

    /// Emergencies dropped because more were raised than the inhibit time let out.
    pub fn emergencies_dropped(&self) -> u32 {
        self.emcy.dropped()
    }

    /// The error register (1001h) as the node computes it from the active errors.
    pub fn error_register(&self) -> u8 {
        self.emcy.register()
    }

    /// Raises an error: sets its `register` bits (see [`error_register`]) in 1001h, records
    /// `code` in 1003h and queues an emergency with the `manufacturer` bytes. Returns `false`
    /// (and sends nothing) if `code` is already active or [`MAX_ACTIVE_ERRORS`] are.
    pub fn raise_error(&mut self, code: u16, register: u8, manufacturer: [u8; 5]) -> bool {
        self.emcy.raise(&mut self.od, code, register, manufacturer) == Raised::New
    }

    /// Clears an active error and queues the error-reset emergency (code 0000h with the
    /// remaining error register: all zeros once nothing is active). `false` if it was not active.
    pub fn clear_error(&mut self, code: u16) -> bool {
        self.emcy.clear(&mut self.od, code)
    }

    /// Whether an error code is active.
    pub fn error_active(&self, code: u16) -> bool {
        self.emcy.is_active(code)
    }

    /// An application event for TPDO `n` (1800h + n): an event-driven PDO (254/255) is sent as
    /// soon as its inhibit time allows, an acyclic synchronous one (0) at the next SYNC.
    /// `false` if the PDO does not exist, is not valid, or has another transmission type.
    pub fn trigger_tpdo(&mut self, n: usize) -> bool {
        let Some(tpdo) = self.tpdos.get_mut(n) else {
            return false;
        };
        if !tpdo.trigger() {
            return false;
        }
        self.tpdo_attention |= tpdo.pending();
        true
    }

    /// The next application event.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.events.pop()
    }

    fn set_state(&mut self, state: NmtState, now: Instant) {
        if self.state == state {
            return;
        }
        let was = self.state;
        self.state = state;
        if was == NmtState::Operational {
            self.timers.stop_pdos();
            for tpdo in &mut self.tpdos {
                tpdo.stop();
            }
            for rpdo in &mut self.rpdos {
                rpdo.stop();
            }
        }
        match state {
            NmtState::Operational => {
                for tpdo in &mut self.tpdos {
                    if tpdo.start() {
                        self.tpdo_attention = true;
                    }
                }
            }
            NmtState::Stopped => {
                for channel in &mut self.sdo {
                    channel.reset();
                }
                self.sync.stop();
                self.timers.set(Timer::SyncProducer, None);
                self.timers.set(Timer::SyncConsumer, None);
            }
            _ => {}
        }
        if was == NmtState::Stopped || was == NmtState::Initialising {
            self.restart_sync_producer(now);
        }
        self.events.push(Event::NmtStateChanged(state));
    }

    fn reset_communication(&mut self, now: Instant) {
        self.state = NmtState::Initialising;
        self.timers = TimerTable::OFF;
        for channel in &mut self.sdo {
            channel.reset();
        }
        self.emcy.forget_communication_errors(&COMMUNICATION_ERRORS);
        self.emcy.reset_queue(&mut self.od);
        self.emcy.configure(&self.od, self.node_id);
        self.configure_second_sdo();
        self.error_control = ErrorControl::OFF;
        let heartbeat = self.error_control.configure_producer(&self.od, now);
        self.timers.set(Timer::Heartbeat, heartbeat);
        #[cfg(feature = "node-guarding")]
        self.error_control.configure_guarding(&self.od);
        self.error_control
            .configure_consumers(&self.od, self.timers.consumers());
        self.sync.configure(&self.od);
        for n in 0..RPDOS {
            if let Some(reason) = self.rpdos[n].load(&self.od, n as u16) {
                self.events.push(Event::PdoMappingRejected {
                    transmit: false,
                    pdo: n as u16,
                    reason,
                });
            }
        }
        for n in 0..TPDOS {
            if let Some(reason) = self.tpdos[n].load(&self.od, n as u16) {
                self.events.push(Event::PdoMappingRejected {
                    transmit: true,
                    pdo: n as u16,
                    reason,
                });
            }
        }
        self.link_pdos();
        // 8210h and 8220h were forgotten with the other communication errors above.
        self.length_error_raised = false;
        self.boot_up_due = true;
        self.set_state(NmtState::PreOperational, now);
    }

    fn reset(&mut self, kind: ResetKind, now: Instant) {
        if kind == ResetKind::Node {
            if self.emcy.any_active() {
                self.announce_no_error = true;
            }
            self.emcy.clear_all(&mut self.od);
        }
        self.hooks
            .restore_power_on(kind, self.node_id, &mut self.od);
        self.hooks.reset(kind, &mut self.od);
        self.events.push(Event::Reset(kind));
        self.reset_communication(now);
        if core::mem::take(&mut self.announce_no_error) {
            // The master saw errors before the reset: tell it they are gone.
            self.emcy.announce_no_error();
        }
    }

    /// Reads the second SDO server's COB-IDs (1201h); the default server's are fixed.
    fn configure_second_sdo(&mut self) {
        self.sdo[1].configure(&self.od, 0x1201);
    }

    fn restart_sync_producer(&mut self, now: Instant) {
        let serves = matches!(self.state, NmtState::PreOperational | NmtState::Operational);
        let first = self.sync.restart(now, serves);
        self.timers.set(Timer::SyncProducer, first);
        self.timers.set(Timer::SyncConsumer, None);
    }

    /// Reads 100Ch and 100Dh; life guarding stops if they (or the heartbeat producer) turn it
    /// off.
    #[cfg(feature = "node-guarding")]
    fn configure_guarding(&mut self) {
        if !self.error_control.configure_guarding(&self.od) {
            self.timers.set(Timer::LifeGuard, None);
        }
    }

    /// Applies an accepted SDO write to the node's running state.
    fn apply_write(&mut self, index: u16, sub: u8, now: Instant) {
        match index {
            0x1005 | 0x1006 | 0x1007 | 0x1019 => {
                self.sync.configure(&self.od);
                self.restart_sync_producer(now);
            }
            #[cfg(feature = "node-guarding")]
            0x100C | 0x100D => self.configure_guarding(),
            0x1014 | 0x1015 => self.emcy.configure(&self.od, self.node_id),
            0x1016 => {
                let was_lost = self.error_control.any_lost();
                self.error_control
                    .configure_consumers(&self.od, self.timers.consumers());
                if was_lost {
                    // A lost node may no longer be watched.
                    self.end_error_control_loss();
                }
            }
            0x1017 => {
                let heartbeat = self.error_control.configure_producer(&self.od, now);
                self.timers.set(Timer::Heartbeat, heartbeat);
                #[cfg(feature = "node-guarding")]
                self.configure_guarding();
            }
            0x1201 => self.configure_second_sdo(),
            0x1400..=0x17FF => {
                let n = usize::from((index - 0x1400) & 0x1FF);
                if n < RPDOS {
                    let event_timer_written = index == 0x1400 + n as u16 && sub == 5;
                    let deadline = self.timers.slot(Timer::RpdoDeadline(n));
                    if self.rpdos[n].reload(&self.od, n as u16, event_timer_written, deadline) {
                        self.end_rpdo_timeout();
                    }
                }
            }
            0x1800..=0x1BFF => {
                let n = usize::from((index - 0x1800) & 0x1FF);
                if n < TPDOS {
                    let operational = self.state == NmtState::Operational;
                    let event_timer = self.timers.slot(Timer::TpdoEvent(n));
                    if self.tpdos[n].reload(&self.od, n as u16, now, operational, event_timer) {
                        self.tpdo_attention = true;
                    }
                }
            }
            _ => {}
        }
        if matches!(index, 0x1400..=0x1BFF) {
            self.link_pdos();
        }
        self.mark_changed(index, sub);
    }

    /// Notes which RPDOs write objects that a TPDO maps, so that a received PDO looks for
    /// changes of state only when it can cause one.
    fn link_pdos(&mut self) {
        for rpdo in &mut self.rpdos {
            let feeds = rpdo.mapping().objects().iter().any(|object| {
                self.tpdos
                    .iter()
                    .any(|tpdo| tpdo.maps(object.index, object.sub))
            });
            rpdo.set_feeds_tpdo(feeds);
        }
    }

    /// An OD entry changed: TPDOs that map it compare before their next transmission.
    fn mark_changed(&mut self, index: u16, sub: u8) {
        for tpdo in &mut self.tpdos {
            if tpdo.maps(index, sub) {
                tpdo.mark_changed();
                self.tpdo_attention = true;
            }
        }
    }

    /// Takes a received frame.
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let Some(id) = frame.std_id() else {
            return;
        };
        if id == NMT_COB_ID {
            if let Some(nmt) = NmtRepr::parse(frame.data()) {
                if !frame.is_remote() && nmt.addresses(self.node_id) {
                    self.handle_nmt(nmt.command, now);
                }
            }
            return;
        }
        if frame.is_remote() {
            self.handle_remote(id, now);
            return;
        }
        let serving = matches!(self.state, NmtState::PreOperational | NmtState::Operational);
        if serving {
            if id == self.sync.cob_id() {
                self.handle_sync_frame(frame.data(), now);
                return;
            }
            for n in 0..self.sdo.len() {
                if self.sdo[n].accepts(id) {
                    self.handle_sdo(n, frame.data(), now);
                    return;
                }
            }
        }
        if self.state == NmtState::Operational {
            for n in 0..RPDOS {
                if self.rpdos[n].accepts(id) {
                    self.handle_rpdo(n, frame.data(), now);
                    return;
                }
            }
        }
        if let Some(node_id) = ErrorControlRepr::node_of(id) {
            if frame.dlc() == 1
                && self
                    .error_control
                    .heartbeat_received(node_id, now, self.timers.consumers())
            {
                self.end_error_control_loss();
            }
        }
    }

    fn handle_nmt(&mut self, command: NmtCommand, now: Instant) {
        match command {
            NmtCommand::Start => self.set_state(NmtState::Operational, now),
            NmtCommand::Stop => self.set_state(NmtState::Stopped, now),
            NmtCommand::EnterPreOperational => self.set_state(NmtState::PreOperational, now),
            NmtCommand::ResetNode => self.reset(ResetKind::Node, now),
            NmtCommand::ResetCommunication => self.reset(ResetKind::Communication, now),
        }
    }

    #[cfg_attr(not(feature = "node-guarding"), allow(unused_variables))]
    fn handle_remote(&mut self, id: u16, now: Instant) {
        if id == ErrorControlRepr::cob_id(self.node_id) {
            // Without node guarding the request is ignored.
            #[cfg(feature = "node-guarding")]
            self.handle_guard_request(now);
            return;
        }
        if self.state != NmtState::Operational {
            return;
        }
        for tpdo in &mut self.tpdos {
            if tpdo.remote_request(id) {
                self.tpdo_attention |= tpdo.pending();
                return;
            }
        }
    }

    /// A node-guarding RTR: queue the answer and (re)start life guarding.
    #[cfg(feature = "node-guarding")]
    fn handle_guard_request(&mut self, now: Instant) {
        if let Some((life_end, recovered)) = self.error_control.guard_request(now) {
            self.timers.set(Timer::LifeGuard, Some(life_end));
            if recovered {
                self.end_error_control_loss();
            }
        }
    }

    /// Clears 8130h (with its error-reset emergency) once neither life guarding nor a watched
    /// heartbeat is lost.
    fn end_error_control_loss(&mut self) {
        if !self.error_control.any_lost() {
            self.emcy.clear(&mut self.od, error_code::LIFE_GUARD);
        }
    }

    fn handle_sdo(&mut self, n: usize, request: &[u8], now: Instant) {
        let mut guard = CommGuard {
            od: &mut self.od,
            hooks: &mut self.hooks,
            node_id: self.node_id,
        };
        if let Some(SdoEvent::Written { index, sub }) = self.sdo[n].handle(now, request, &mut guard)
        {
            self.apply_write(index, sub, now);
            self.events.push(Event::Written { index, sub });
        }
    }

    fn handle_rpdo(&mut self, n: usize, data: &[u8], now: Instant) {
        let rpdo = &mut self.rpdos[n];
        let expected = usize::from(rpdo.mapping().len);
        let deadline = self.timers.slot(Timer::RpdoDeadline(n));
        let (apply, recovered) = rpdo.receive(now, data, deadline);
        if let Some(data) = apply {
            self.apply_rpdo(n, data);
        }
        if data.len() != expected || self.length_error_raised {
            self.update_length_errors(data.len());
        }
        if recovered {
            self.end_rpdo_timeout();
        }
    }

    /// Writes a received RPDO's values into the OD, all or none. When the OD refuses one, none
    /// is written, no [`Event::RpdoReceived`] is reported, and EMCY 8200h
    /// ([`error_code::PROTOCOL`]) says which PDO and why: manufacturer bytes `n` then the abort
    /// code, little-endian. The next RPDO applied whole while no other is refused clears it.
    fn apply_rpdo(&mut self, n: usize, data: &[u8]) {
        let rpdo = &mut self.rpdos[n];
        match rpdo.apply(&mut self.od, data) {
            Ok(recovered) => {
                if rpdo.feeds_tpdo() {
                    let mapping = *rpdo.mapping();
                    for object in mapping.objects() {
                        self.mark_changed(object.index, object.sub);
                    }
                }
                self.events.push(Event::RpdoReceived { pdo: n as u16 });
                if recovered && !self.rpdos.iter().any(|r| r.refused()) {
                    self.emcy.clear(&mut self.od, error_code::PROTOCOL);
                }
            }
            Err(abort) => {
                let [a, b, c, d] = abort.code().to_le_bytes();
                let info = [n as u8, a, b, c, d];
                self.raise_communication_error(error_code::PROTOCOL, info);
            }
        }
    }

    /// Raises an error of the node's own communication (register bit 4) with the
    /// `manufacturer` bytes of its emergency.
    fn raise_communication_error(&mut self, code: u16, manufacturer: [u8; 5]) {
        self.emcy.raise(
            &mut self.od,
            code,
            error_register::COMMUNICATION,
            manufacturer,
        );
    }

    /// Clears 8250h (with its error-reset emergency) once no RPDO is timed out any more.
    fn end_rpdo_timeout(&mut self) {
        if !self.rpdos.iter().any(|r| r.timed_out()) {
            self.emcy.clear(&mut self.od, RPDO_TIMEOUT_CODE);
        }
    }

    /// Raises or clears 8210h (too short, not processed) and 8220h (too long, processed).
    fn update_length_errors(&mut self, received: usize) {
        let (mut short, mut long) = (false, false);
        for rpdo in &self.rpdos {
            let (too_short, too_long) = rpdo.length_errors();
            short |= too_short;
            long |= too_long;
        }
        let info = [received as u8, 0, 0, 0, 0];
        for (code, now_bad) in [
            (error_code::PDO_LENGTH, short),
            (error_code::PDO_LENGTH_EXCEEDED, long),
        ] {
            if now_bad {
                self.raise_communication_error(code, info);
            } else {
                // Nothing happens unless it is active.
                self.emcy.clear(&mut self.od, code);
            }
        }
        self.length_error_raised = short || long;
    }

    /// A received SYNC. Its length must match 1019h: a counter byte when the overflow value is
    /// not 0, no data when it is. Any other SYNC is not processed and raises EMCY 8240h
    /// ([`error_code::SYNC_LENGTH`], manufacturer byte 0 the length received); the next SYNC of
    /// the right length clears it.
    fn handle_sync_frame(&mut self, data: &[u8], now: Instant) {
        match SyncRepr::parse(data) {
            Some(sync) if self.sync.length_matches(sync.counter) => {
                // Nothing happens unless it is active.
                self.emcy.clear(&mut self.od, error_code::SYNC_LENGTH);
                self.handle_sync(sync.counter, now);
            }
            _ => {
                let info = [data.len() as u8, 0, 0, 0, 0];
                self.raise_communication_error(error_code::SYNC_LENGTH, info);
            }
        }
    }

    fn handle_sync(&mut self, counter: Option<u8>, now: Instant) {
        self.events.push(Event::Sync { counter });
        if let Some(timeout) = self.sync.consumed(now) {
            self.timers.set(Timer::SyncConsumer, Some(timeout));
            // Ends a SYNC timeout error, if one is active.
            self.emcy.clear(&mut self.od, SYNC_TIMEOUT_CODE);
        }
        if self.state != NmtState::Operational {
            return;
        }
        for n in 0..RPDOS {
            if let Some(data) = self.rpdos[n].take_buffered() {
                self.apply_rpdo(n, &data);
            }
        }
        let window_end = self.sync.window_end(now);
        let use_start = self.sync.counting();
        for tpdo in &mut self.tpdos {
            if tpdo.on_sync(&self.od, counter, use_start, window_end) {
                self.tpdo_attention = true;
            }
        }
    }

    /// The next frame to send, if any. Frames go out in CAN priority order of their function:
    /// boot-up first, then SYNC, EMCY, TPDOs, SDO responses, node guarding and heartbeat.
    pub fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        let error_control_id = ErrorControlRepr::cob_id(self.node_id);
        if core::mem::take(&mut self.boot_up_due) {
            return Some(one_byte_frame(
                error_control_id,
                ErrorControlRepr::BOOT_UP.emit(),
                1,
            ));
        }
        if let Some((id, counter, len)) = self.sync.poll_transmit() {
            return Some(one_byte_frame(id, counter, len));
        }
        if self.state != NmtState::Stopped {
            if let Some(frame) = self.emcy.poll_transmit(now) {
                return Some(frame);
            }
        }
        if self.state == NmtState::Operational && self.tpdo_attention {
            if let Some(frame) = self.poll_tpdo(now) {
                return Some(frame);
            }
        }
        for channel in &mut self.sdo {
            if let Some(frame) = channel.poll_transmit(now, &self.od) {
                return Some(frame);
            }
        }
        let byte = self.error_control.poll_transmit(self.state)?;
        Some(one_byte_frame(error_control_id, byte, 1))
    }

    fn poll_tpdo(&mut self, now: Instant) -> Option<CanFrame> {
        for (n, tpdo) in self.tpdos.iter_mut().enumerate() {
            let event_timer = self.timers.slot(Timer::TpdoEvent(n));
            if let Some(frame) = tpdo.poll_transmit(&self.od, now, event_timer) {
                return Some(frame);
            }
        }
        // Whatever is still pending waits for an inhibit time; poll_timeout reports when.
        self.tpdo_attention = self.tpdos.iter().any(|t| t.pending());
        None
    }
}
