//! A receive PDO: its configuration from 1400h–15FFh, reception (synchronous ones buffered until
//! SYNC), deadline monitoring and the length checks.

use crate::od::{ObjectDictionary, SdoAbort};
use crate::time::Instant;

use super::arm_timer;
use super::mapping::Mapping;
use super::params::PdoParams;

/// A receive PDO.
/// Word-aligned (its widest field has 2 bytes) so that [`Rpdo::load`]'s clear is a word-wise
/// memclr: a byte-wise one would bring 208 B of `__aeabi_memclr` into a firmware image (see
/// [`Mapping`]'s `Default`).
#[derive(Debug, Clone, Copy)]
#[repr(align(4))]
pub(crate) struct Rpdo {
    /// Its configuration (deadline monitoring: the event timer, 1400h+n sub 05h, ms; 0 = off:
    /// the PDO must arrive again within this time of its last reception).
    params: PdoParams,
    /// Data received for a synchronous RPDO, applied at the next SYNC.
    buffered: Option<[u8; 8]>,
    /// Some TPDO maps an object this PDO writes (change-of-state detection must look).
    feeds_tpdo: bool,
    /// The last frame was shorter / longer than the mapping.
    too_short: bool,
    too_long: bool,
    /// The last frame was not applied: the OD refused one of its values (EMCY 8200h).
    refused: bool,
    /// The deadline passed and the PDO has not arrived since (EMCY 8250h is active for it).
    timed_out: bool,
}

impl Rpdo {
    /// A PDO that does not exist (yet): nothing configured, nothing received. A constant of
    /// zeros and `None`s rather than a (derived) `Default`, so that power-on and [`Rpdo::load`]
    /// clear it with one word-aligned memset instead of building a copy to move.
    pub const OFF: Rpdo = Rpdo {
        params: PdoParams::OFF,
        buffered: None,
        feeds_tpdo: false,
        too_short: false,
        too_long: false,
        refused: false,
        timed_out: false,
    };

    /// Reads the configuration of RPDO `n` (1400h + n, 1600h + n) into this PDO, in place, and
    /// forgets its running state. Returns why the mapping was refused if the COB-ID is valid
    /// (the PDO is then not served).
    pub fn load<O: ObjectDictionary + ?Sized>(&mut self, od: &O, n: u16) -> Option<SdoAbort> {
        *self = Rpdo::OFF;
        self.params.load(od, 0x1400 + n)
    }

    #[inline]
    fn synchronous(&self) -> bool {
        self.params.transmission <= 240
    }

    /// Whether a frame on `id` is this PDO.
    #[inline]
    pub fn accepts(&self, id: u16) -> bool {
        self.params.enabled && id == self.params.cob_id
    }

    /// The checked mapping.
    #[inline]
    pub fn mapping(&self) -> &Mapping {
        &self.params.mapping
    }

    /// Whether a TPDO maps an object this PDO writes (so that a reception looks for changes
    /// of state).
    #[inline]
    pub fn feeds_tpdo(&self) -> bool {
        self.feeds_tpdo
    }

    /// Notes whether a TPDO maps an object this PDO writes.
    #[inline]
    pub fn set_feeds_tpdo(&mut self, feeds: bool) {
        self.feeds_tpdo = feeds;
    }

    /// The last frame was shorter / longer than the mapping (EMCY 8210h / 8220h).
    #[inline]
    pub fn length_errors(&self) -> (bool, bool) {
        (self.too_short, self.too_long)
    }

    /// The deadline passed and the PDO has not arrived since (EMCY 8250h).
    #[inline]
    pub fn timed_out(&self) -> bool {
        self.timed_out
    }

    /// The last frame was not applied: the OD refused one of its values (EMCY 8200h).
    #[inline]
    pub fn refused(&self) -> bool {
        self.refused
    }

    /// A frame received at `now`. A frame shorter than the mapping is not processed (and is no
    /// reception for the deadline monitoring); a synchronous PDO's data waits for the next
    /// SYNC; an event-driven one is handed back to be applied. Also returns whether a timeout
    /// of the PDO ended. `deadline` is the PDO's slot in the node's timer table. Inlined into
    /// its one caller, the node's frame routing, whatever else that inlines.
    #[inline(always)]
    pub fn receive<'d>(
        &mut self,
        now: Instant,
        data: &'d [u8],
        deadline: &mut Option<Instant>,
    ) -> (Option<&'d [u8]>, bool) {
        let expected = usize::from(self.params.mapping.len);
        self.too_short = data.len() < expected;
        self.too_long = data.len() > expected;
        if self.too_short {
            return (None, false);
        }
        // CiA 301, 1400h+n sub 05h: a non-zero event timer of an RPDO is its deadline; the
        // monitoring is activated with the next reception of the RPDO (after entering
        // operational or configuring the event timer) and restarts with each one. Without an
        // event timer the slot stays empty ([`Rpdo::reload`]).
        if self.params.event_timer_ms != 0 {
            arm_timer(deadline, now, self.params.event_timer_ms);
        }
        let recovered = core::mem::take(&mut self.timed_out);
        if self.synchronous() {
            let mut buffer = [0u8; 8];
            buffer[..expected].copy_from_slice(&data[..expected]);
            self.buffered = Some(buffer);
            (None, recovered)
        } else {
            (Some(data), recovered)
        }
    }

    /// The data of a synchronous PDO received before this SYNC, to apply now.
    #[inline]
    pub fn take_buffered(&mut self) -> Option<[u8; 8]> {
        self.buffered.take()
    }

    /// Writes received data into the OD, all or none ([`Mapping::unpack`]), and notes whether
    /// it was refused. `Ok(true)` when it was applied after a refusal.
    pub fn apply<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        data: &[u8],
    ) -> Result<bool, SdoAbort> {
        match self.params.mapping.unpack(od, data) {
            Ok(()) => Ok(core::mem::take(&mut self.refused)),
            Err(abort) => {
                self.refused = true;
                Err(abort)
            }
        }
    }

    /// Leaving operational: buffered data is dropped (the node stops the deadline).
    pub fn stop(&mut self) {
        self.buffered = None;
    }

    /// Re-reads RPDO `n` after an SDO write to its parameters. A valid PDO keeps its deadline
    /// monitoring across other changes (its transmission type); a new event timer
    /// (`event_timer_written`) stops it, as does disabling the PDO: CiA 301 activates the
    /// monitoring with the next reception after the event timer is configured. `deadline` is
    /// the PDO's slot in the node's timer table. Returns whether a timeout ended.
    pub fn reload<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        n: u16,
        event_timer_written: bool,
        deadline: &mut Option<Instant>,
    ) -> bool {
        let timed_out = self.timed_out;
        self.load(od, n);
        let keeps_monitoring = self.params.enabled && !event_timer_written;
        if keeps_monitoring {
            self.timed_out = timed_out;
        }
        // Without an event timer, the slot stays empty (a reception arms none).
        if !keeps_monitoring || self.params.event_timer_ms == 0 {
            *deadline = None;
        }
        timed_out && !self.timed_out
    }

    /// The deadline passed: the PDO is timed out until it arrives again.
    pub fn expire(&mut self) {
        self.timed_out = true;
    }
}
