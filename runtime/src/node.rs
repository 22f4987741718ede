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
//! [`NodeHooks`]. No allocation, no clock reads. A service whose objects the dictionary lacks
//! costs no code: the node asks [`ObjectDictionary::services`], a constant for a generated
//! dictionary, before each (error history, SYNC producer and monitoring, synchronous window and
//! counter, EMCY inhibit time, life guarding, the second SDO server). With the `lss` feature it
//! is an LSS slave (CiA 305, `lss`): it may start without a node-ID (255) and be given one over
//! the bus.
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
//! their expiry does. The node's own parts: `routing` (received frames to their service, frames
//! out in priority order), `nmt` (state changes and resets) and `config` (what a write to a
//! communication object changes in the running services).
//!
//! Choices CiA 301 leaves open, documented where they are made: an NMT reset restores the
//! dictionary's defaults of its area ([`NodeHooks::restore_power_on`]); a SYNC whose length
//! does not match 1019h is not processed (EMCY 8240h); an RPDO the dictionary refuses a value
//! of is not applied at all (EMCY 8200h with the PDO number and the abort code); writing 0 to
//! 1003h:00 clears the recorded codes too (their sub-indices read 0).

mod comm;
mod config;
mod emcy;
mod error_control;
mod events;
#[cfg(feature = "lss")]
mod lss;
mod nmt;
mod pdo;
mod routing;
mod sdo_channel;
mod sync;
mod timer;

pub use self::comm::{LOAD_SIGNATURE, SAVE_SIGNATURE};
pub use self::emcy::{error_code, error_register, MAX_ACTIVE_ERRORS};
pub use self::error_control::MAX_HEARTBEAT_CONSUMERS;
#[cfg(feature = "lss")]
pub use self::lss::BitTiming;
pub use self::pdo::MAX_MAPPED;
pub use crate::wire::heartbeat::NmtState;

use self::emcy::Emcy;
use self::error_control::ErrorControl;
use self::events::EventQueue;
use self::pdo::{Rpdo, Tpdo};
use self::sdo_channel::SdoChannel;
use self::sync::Sync;
use self::timer::TimerTable;
use crate::frame::CanFrame;
use crate::od::{ObjectDictionary, SdoAbort, Services};
use crate::time::{Duration, Instant};

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
    /// An LSS master activated the configured bit timing (CiA 305): the application switches
    /// the controller to it one switch delay after this event; the node sends nothing until a
    /// second switch delay has passed.
    #[cfg(feature = "lss")]
    BitTimingActivated {
        /// The bit timing to switch to.
        timing: BitTiming,
        /// The switch delay, in milliseconds.
        switch_delay_ms: u16,
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

    /// Stores the LSS configuration (CiA 305 store configuration): the node-ID a power-on or
    /// reset node starts with, and the bit timing, if one was configured. The same persistence
    /// as [`save`](Self::save) keeps them (the dictionary does not hold them). By default
    /// storing is not supported (LSS error 1).
    #[cfg(feature = "lss")]
    fn store_lss(
        &mut self,
        node_id: u8,
        bit_timing: Option<BitTiming>,
    ) -> Result<(), crate::wire::lss::LssError> {
        let _ = (node_id, bit_timing);
        Err(crate::wire::lss::LssError::StoreNotSupported)
    }

    /// Whether the device offers a bit timing (configure bit timing answers error 1
    /// otherwise). By default the entries of table 0 that have a bit rate
    /// ([`BitTiming::table0_kbit`]); override it to offer a manufacturer table (128..=255).
    #[cfg(feature = "lss")]
    fn bit_timing_supported(&self, timing: BitTiming) -> bool {
        timing.table0_kbit().is_some()
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
/// `now` if that is already past (the caller was late by a period or more). The heartbeat
/// producer and the SYNC producer share it; the compiler keeps one copy out of line when a
/// dictionary has both (a SYNC producer needs 1006h), and inlines it into the heartbeat's
/// expiry when it does not.
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
    /// Some RPDO's last frame had the wrong length (8210h/8220h raised): the next frame of
    /// the right length looks whether they clear.
    length_error_raised: bool,
    /// Some TPDO may have something to send or a change to look for (a fast path for
    /// [`Node::poll_transmit`]).
    tpdo_attention: bool,
    #[cfg(feature = "lss")]
    lss: self::lss::LssSlave,
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
    /// boot-up message and enters pre-operational. `node_id` must be 1..=127, or with the `lss`
    /// feature 255: the node is unconfigured, serves LSS only and waits for an LSS master to
    /// give it a node-ID (CiA 305).
    #[inline(never)]
    pub fn with_capacity(
        od: O,
        hooks: H,
        node_id: u8,
        now: Instant,
    ) -> Result<Self, InvalidNodeId> {
        let unconfigured = cfg!(feature = "lss") && node_id == 0xFF;
        if !matches!(node_id, 1..=127) && !unconfigured {
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
            sync: Sync::OFF,
            emcy: Emcy::default(),
            rpdos: const { [Rpdo::OFF; RPDOS] },
            tpdos: const { [Tpdo::OFF; TPDOS] },
            events: EventQueue::new(),
            timers: TimerTable::OFF,
            length_error_raised: false,
            tpdo_attention: false,
            #[cfg(feature = "lss")]
            lss: self::lss::LssSlave::new(node_id),
        };
        node.hooks.reset(ResetKind::Node, &mut node.od);
        node.reset_communication(now);
        Ok(node)
    }

    /// The optional services the dictionary has the objects of: a constant for a generated
    /// dictionary, so that the node's tests of it leave no code for the others.
    #[inline(always)]
    fn services(&self) -> Services {
        self.od.services()
    }

    /// The SDO server channels the dictionary has: the default one (1200h), and the second if
    /// it has 1201h.
    #[inline(always)]
    fn sdo_channels(&self) -> usize {
        if self.services().second_sdo {
            2
        } else {
            1
        }
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
        self.emcy.raise(&mut self.od, code, register, manufacturer)
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
}
