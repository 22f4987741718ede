//! EMCY producer state (CiA 301 §7.2.7): the active errors behind the error register (1001h),
//! the pre-defined error field (1003h), and the queue of emergencies waiting for the inhibit time
//! (1015h).

use super::{read_uint, read_uint_or};
use crate::frame::CanFrame;
use crate::od::ObjectDictionary;
use crate::time::{Duration, Instant};
use crate::wire::emcy::{EmcyRepr, EMCY_BASE};
use crate::wire::pdo::CobIdEntry;

/// Bits of the error register (1001h, CiA 301 §7.5.2.2).
pub mod error_register {
    /// Generic error.
    pub const GENERIC: u8 = 0x01;
    /// Current.
    pub const CURRENT: u8 = 0x02;
    /// Voltage.
    pub const VOLTAGE: u8 = 0x04;
    /// Temperature.
    pub const TEMPERATURE: u8 = 0x08;
    /// Communication error (overrun, error state, life guard, heartbeat, PDO length).
    pub const COMMUNICATION: u8 = 0x10;
    /// Device-profile specific.
    pub const DEVICE_PROFILE: u8 = 0x20;
    /// Manufacturer specific.
    pub const MANUFACTURER: u8 = 0x80;
}

/// Emergency error codes the node raises itself (CiA 301 table 26), and the reset code.
pub mod error_code {
    /// Error reset or no error: the emergency that clears one.
    pub const NO_ERROR: u16 = 0x0000;
    /// Communication, generic: SYNC missing for 1.5 × 1006h (this runtime's choice of code for
    /// the SYNC consumer's timeout, as CANopenNode's).
    pub const COMMUNICATION: u16 = 0x8100;
    /// Life guard error or heartbeat error: the NMT master stopped guarding (100Ch × 100Dh;
    /// manufacturer bytes 0), or a node watched by the heartbeat consumer (1016h) missed its
    /// heartbeat (manufacturer byte 0 its node-ID). Cleared when neither is lost any more.
    pub const LIFE_GUARD: u16 = 0x8130;
    /// Protocol error, generic: an RPDO was not applied because the dictionary refused one of
    /// its mapped values (this runtime's choice; the manufacturer bytes say which PDO and why).
    pub const PROTOCOL: u16 = 0x8200;
    /// PDO not processed due to a length error (shorter than its mapping).
    pub const PDO_LENGTH: u16 = 0x8210;
    /// PDO length exceeded (longer than its mapping; processed).
    pub const PDO_LENGTH_EXCEEDED: u16 = 0x8220;
    /// Unexpected SYNC data length (a counter where 1019h is 0, or none where it is not).
    pub const SYNC_LENGTH: u16 = 0x8240;
    /// RPDO timeout: a monitored RPDO missed its event timer (1400h+n sub 05h).
    pub const RPDO_TIMEOUT: u16 = 0x8250;
}

/// The most errors active at once, and the most emergencies waiting for the inhibit time.
pub const MAX_ACTIVE_ERRORS: usize = 8;
const QUEUE: usize = 4;

/// Writes 1001h (an OD without it, or refusing the value, keeps the node's own register). Not
/// inlined: raising, clearing and both resets share it.
#[inline(never)]
fn write_error_register<O: ObjectDictionary + ?Sized>(od: &mut O, register: u8) {
    let _ = od.write(0x1001, 0, &[register]);
}

#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Emcy {
    cob_id: u16,
    enabled: bool,
    inhibit: Duration,
    last_sent: Option<Instant>,
    /// A ring: `queued` emergencies from `first` on, in the order raised.
    queue: [EmcyRepr; QUEUE],
    first: usize,
    queued: usize,
    /// Emergencies dropped because the queue was full.
    dropped: u32,
    /// The active errors' codes and register bits: two arrays rather than one of (code,
    /// register) pairs, whose padding byte made clearing them a store per field.
    active_codes: [u16; MAX_ACTIVE_ERRORS],
    active_registers: [u8; MAX_ACTIVE_ERRORS],
    active_count: usize,
    /// Sub-indices of 1003h beyond 0.
    history_len: u8,
}

impl Emcy {
    /// Reads 1014h, 1015h and the size of 1003h (reset communication or an SDO write).
    pub fn configure<O: ObjectDictionary + ?Sized>(&mut self, od: &O, node_id: u8) {
        let default = u32::from(EMCY_BASE) + u32::from(node_id);
        let cob = CobIdEntry(read_uint_or(od, 0x1014, 0, default));
        self.cob_id = cob.can_id();
        self.enabled = cob.valid() && !cob.extended();
        self.inhibit = if od.services().emcy_inhibit {
            Duration::from_micros(u64::from(read_uint_or(od, 0x1015, 0, 0)) * 100)
        } else {
            Duration::ZERO
        };
        self.history_len = if od.services().error_history {
            crate::od::descriptors(od)
                .filter(|(_, e)| e.index() == 0x1003 && e.sub() > 0)
                .count()
                .min(254) as u8
        } else {
            0
        };
    }

    /// The error register: every active error's bits, and the generic bit (bit 0) whenever
    /// any error is active (CiA 301 §7.5.2.2: it is set for every error).
    #[inline]
    pub fn register(&self) -> u8 {
        let bits = self.active_registers[..self.active_count]
            .iter()
            .fold(0, |acc, register| acc | register);
        if self.active_count > 0 {
            bits | error_register::GENERIC
        } else {
            bits
        }
    }

    #[inline]
    pub fn is_active(&self, code: u16) -> bool {
        self.active_codes[..self.active_count].contains(&code)
    }

    #[inline]
    pub fn any_active(&self) -> bool {
        self.active_count > 0
    }

    /// Whether an emergency waits to be sent (perhaps for its inhibit time).
    #[inline]
    pub fn queued(&self) -> bool {
        self.queued > 0
    }

    fn enqueue(&mut self, repr: EmcyRepr) {
        if self.queued < QUEUE {
            self.queue[(self.first + self.queued) % QUEUE] = repr;
            self.queued += 1;
        } else {
            self.dropped = self.dropped.saturating_add(1);
        }
    }

    /// Records an error, updates 1001h and 1003h, and queues its emergency. `false` (and
    /// nothing sent) if the code is already active or the table of active errors is full.
    pub fn raise<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        code: u16,
        register: u8,
        manufacturer: [u8; 5],
    ) -> bool {
        self.change(od, code, Some(register), manufacturer)
    }

    /// Clears an active error; queues the error-reset emergency (code 0000h). `false` if the
    /// code was not active.
    pub fn clear<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O, code: u16) -> bool {
        self.change(od, code, None, [0; 5])
    }

    /// Raises `code` with its `raise` register bits, or clears it (`None`): one search of the
    /// active errors, then 1001h, 1003h (a raise) and the emergency, in one routine for both.
    /// `false` if nothing changed (raising an active code or one too many, clearing an
    /// inactive one).
    #[inline(never)]
    fn change<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        code: u16,
        raise: Option<u8>,
        manufacturer: [u8; 5],
    ) -> bool {
        let count = self.active_count;
        let found = self.active_codes[..count]
            .iter()
            .position(|&active| active == code);
        match (found, raise) {
            (None, Some(register)) if count < MAX_ACTIVE_ERRORS => {
                self.active_codes[count] = code;
                self.active_registers[count] = register;
                self.active_count += 1;
            }
            (Some(pos), None) => {
                // The last active error takes its place: their order does not matter.
                self.active_count -= 1;
                self.active_codes[pos] = self.active_codes[count - 1];
                self.active_registers[pos] = self.active_registers[count - 1];
            }
            _ => return false,
        }
        let register = self.register();
        write_error_register(od, register);
        let code = if raise.is_some() {
            self.push_history(od, u32::from(code));
            code
        } else {
            error_code::NO_ERROR
        };
        self.enqueue(EmcyRepr {
            code,
            register,
            manufacturer,
        });
        true
    }

    /// Forgets errors the communication layer raised itself (a reset communication starts its
    /// monitoring afresh), without an emergency; 1001h is rewritten by [`Emcy::reset_queue`].
    pub fn forget_communication_errors(&mut self, codes: &[u16]) {
        let mut kept = 0;
        for i in 0..self.active_count {
            if !codes.contains(&self.active_codes[i]) {
                self.active_codes[kept] = self.active_codes[i];
                self.active_registers[kept] = self.active_registers[i];
                kept += 1;
            }
        }
        self.active_count = kept;
    }

    /// Forgets every active error (reset node), without an emergency; the reset communication
    /// that follows drops the queue and rewrites 1001h ([`Emcy::reset_queue`]).
    pub fn forget_all(&mut self) {
        self.active_count = 0;
    }

    /// Drops queued emergencies and the inhibit timer (reset communication); the active errors
    /// stay, and 1001h is rewritten from them.
    pub fn reset_queue<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O) {
        self.queued = 0;
        // Never set without 1015h.
        if od.services().emcy_inhibit {
            self.last_sent = None;
        }
        write_error_register(od, self.register());
    }

    /// Queues the "no error" emergency (code 0000h, register 0).
    pub fn announce_no_error(&mut self) {
        self.enqueue(EmcyRepr::default());
    }

    fn push_history<O: ObjectDictionary + ?Sized>(&mut self, od: &mut O, value: u32) {
        if !od.services().error_history || self.history_len == 0 {
            return;
        }
        let count = (read_uint_or(od, 0x1003, 0, 0) as u8).min(self.history_len);
        let kept = count.min(self.history_len - 1);
        for sub in (1..kept + 1).rev() {
            if let Some(older) = read_uint(od, 0x1003, sub) {
                let _ = od.write(0x1003, sub + 1, &older.to_le_bytes());
            }
        }
        let _ = od.write(0x1003, 1, &value.to_le_bytes());
        let _ = od.write(0x1003, 0, &[kept + 1]);
    }

    /// When the next emergency may go out, if one is waiting. `inhibit_time`: the dictionary
    /// has 1015h (a constant for a generated one); without it an emergency never waits.
    #[inline]
    pub fn ready_at(&self, inhibit_time: bool) -> Option<Instant> {
        if self.queued == 0 || !self.enabled {
            return None;
        }
        Some(match self.last_sent {
            Some(sent) if inhibit_time => sent + self.inhibit,
            _ => Instant::from_micros(0),
        })
    }

    /// Emergencies dropped because more were raised than the inhibit time let out.
    #[inline]
    pub fn dropped(&self) -> u32 {
        self.dropped
    }

    /// The next emergency frame, if one is waiting and the inhibit time has passed
    /// (`inhibit_time` as for [`Emcy::ready_at`]).
    #[inline]
    pub fn poll_transmit(&mut self, now: Instant, inhibit_time: bool) -> Option<CanFrame> {
        let repr = self.poll(now, inhibit_time)?;
        Some(CanFrame::from_parts(self.cob_id, repr.emit(), 8))
    }

    /// The next emergency, if one is waiting and the inhibit time has passed.
    #[inline]
    fn poll(&mut self, now: Instant, inhibit_time: bool) -> Option<EmcyRepr> {
        if self.ready_at(inhibit_time)? > now {
            return None;
        }
        let repr = self.queue[self.first];
        self.first = (self.first + 1) % QUEUE;
        self.queued -= 1;
        if inhibit_time {
            self.last_sent = Some(now);
        }
        Some(repr)
    }
}
