//! SYNC consumer and producer state (CiA 301 §7.2.5): the configuration from 1005h, 1006h,
//! 1007h and 1019h, the producer's counter, and when the producer's and the consumer's timers
//! (1006h, 1.5 × 1006h; their instants are in the node's timer table) are due. The node routes
//! SYNC frames and timeouts here and acts on what it is told (the SYNC's effects on PDOs, the
//! emergencies).

use super::{next_period, read_uint_or};
use crate::od::ObjectDictionary;
use crate::time::{Duration, Instant};
use crate::wire::pdo::CobIdEntry;
use crate::wire::sync::{SyncRepr, SYNC_COB_ID};

#[derive(Debug, Clone, Copy)]
pub(crate) struct Sync {
    cob_id: u16,
    producer: bool,
    period: Duration,
    window: Duration,
    overflow: u8,
    counter: u8,
    /// Producer: a SYNC to send, and its counter (a flag beside the counter rather than an
    /// `Option<SyncRepr>`, whose `None` is not zero: a new `Sync` is all zeros).
    due: bool,
    due_counter: Option<u8>,
}

impl Sync {
    /// Nothing configured: the state before reset communication reads 1005h, 1006h, 1007h and
    /// 1019h. A constant of zeros rather than a (derived) `Default`, so that power-on clears it
    /// with one memset together with the state beside it.
    pub const OFF: Sync = Sync {
        cob_id: 0,
        producer: false,
        period: Duration::ZERO,
        window: Duration::ZERO,
        overflow: 0,
        counter: 0,
        due: false,
        due_counter: None,
    };

    /// Reads 1005h, 1006h, 1007h and 1019h, and restarts the counter.
    pub fn configure<O: ObjectDictionary + ?Sized>(&mut self, od: &O) {
        let cob = CobIdEntry(read_uint_or(od, 0x1005, 0, u32::from(SYNC_COB_ID)));
        self.cob_id = cob.can_id();
        self.producer = cob.bit30() && !cob.extended();
        // An object the dictionary does not have reads as 0 (no code for it in a generated one's).
        let services = od.services();
        let read = |present: bool, index: u16| {
            if present {
                read_uint_or(od, index, 0, 0)
            } else {
                0
            }
        };
        self.period = Duration(u64::from(read(services.sync_period, 0x1006)));
        self.window = Duration(u64::from(read(services.sync_window, 0x1007)));
        self.overflow = read(services.sync_counter, 0x1019) as u8;
        self.counter = 0;
    }

    /// The CAN-ID SYNC is received (and produced) on.
    #[inline]
    pub fn cob_id(&self) -> u16 {
        self.cob_id
    }

    /// Whether a SYNC's counter matches 1019h: one when the overflow value is not 0, none when
    /// it is.
    #[inline]
    pub fn length_matches(&self, counter: Option<u8>) -> bool {
        counter.is_some() == (self.overflow != 0)
    }

    /// Whether TPDOs use their SYNC start value (1019h is not 0).
    #[inline]
    pub fn counting(&self) -> bool {
        self.overflow != 0
    }

    /// The end of the synchronous window (1007h) of a SYNC at `now`, if one is configured.
    #[inline]
    pub fn window_end(&self, now: Instant) -> Option<Instant> {
        (self.window != Duration::ZERO).then(|| now + self.window)
    }

    /// Starts (or stops) the producer for a node that `serves` SYNC (pre-operational or
    /// operational; a stopped node drops the SYNC it had to send): returns when its first SYNC
    /// is due, if it runs. (The consumer's monitoring restarts at the next SYNC.)
    pub fn restart(&mut self, now: Instant, serves: bool) -> Option<Instant> {
        let active = self.producer && self.period != Duration::ZERO && serves;
        if !active {
            self.due = false;
        }
        active.then(|| now + self.period)
    }

    /// A SYNC was consumed at `now`. Returns when a missing SYNC becomes an error (1.5 × 1006h
    /// later), if the consumer monitors SYNC (a missed-SYNC error then ends).
    pub fn consumed(&self, now: Instant) -> Option<Instant> {
        let monitoring = !self.producer && self.period != Duration::ZERO;
        monitoring.then(|| now + Duration(self.period.as_micros() * 3 / 2))
    }

    /// Whether a produced SYNC waits to be sent.
    #[inline]
    pub fn due(&self) -> bool {
        self.due
    }

    /// The SYNC the producer has to send, as (CAN-ID, counter byte, length).
    #[inline]
    pub fn poll_transmit(&mut self) -> Option<(u16, u8, u8)> {
        if !core::mem::take(&mut self.due) {
            return None;
        }
        let ([counter], len) = SyncRepr {
            counter: self.due_counter,
        }
        .emit();
        Some((self.cob_id, counter, len as u8))
    }

    /// The producer's SYNC due `at` has come (at `now`): it is queued. Returns its counter (the
    /// node consumes its own SYNC too) and when the next one is due.
    pub fn expire_producer(&mut self, at: Instant, now: Instant) -> (Option<u8>, Instant) {
        let counter = (self.overflow != 0).then(|| {
            self.counter = if self.counter >= self.overflow {
                1
            } else {
                self.counter + 1
            };
            self.counter
        });
        self.due = true;
        self.due_counter = counter;
        (counter, next_period(at, self.period, now))
    }
}
