//! Error-control state (CiA 301 §7.2.8.3.2): the heartbeat producer (1017h), the heartbeat
//! consumers (1016h), and node guarding with its toggle bit and life time (100Ch × 100Dh; with
//! the `node-guarding` feature). Their instants are in the node's timer table: this module says
//! when to arm them and what their expiry does.

use super::events::EventQueue;
use super::{next_period, read_uint_or, Event};
use crate::od::ObjectDictionary;
use crate::time::{Duration, Instant};
use crate::wire::heartbeat::{ErrorControlRepr, NmtState};

/// The most remote nodes whose heartbeat one node watches; 1016h entries beyond are not served.
pub const MAX_HEARTBEAT_CONSUMERS: usize = 8;

/// A watched node; a slot that watches none has node-ID 0, which no heartbeat carries.
#[derive(Debug, Clone, Copy)]
struct Consumer {
    node_id: u8,
    /// The consumer heartbeat time (1016h, ms) as read: 16 bits, not a 64-bit `Duration`.
    period_ms: u16,
    /// The heartbeat timed out and has not arrived since (EMCY 8130h is active for it).
    lost: bool,
}

impl Consumer {
    /// An empty slot.
    const NONE: Consumer = Consumer {
        node_id: 0,
        period_ms: 0,
        lost: false,
    };
}

/// Node guarding and life guarding.
#[cfg(feature = "node-guarding")]
#[derive(Debug, Clone, Copy)]
struct Guarding {
    guard_time: Duration,
    life_time_factor: u8,
    toggle: bool,
    answer_due: bool,
    /// Life guarding ran out and no guard request came since (EMCY 8130h).
    life_lost: bool,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct ErrorControl {
    producer_period: Duration,
    heartbeat_due: bool,
    #[cfg(feature = "node-guarding")]
    guarding: Guarding,
    /// The watched nodes in 1016h order, then empty slots.
    consumers: [Consumer; MAX_HEARTBEAT_CONSUMERS],
}

impl ErrorControl {
    /// Nothing configured, nothing monitored: the state before reset communication reads
    /// 1016h, 1017h, 100Ch and 100Dh. A constant of zeros and `None`s rather than a (derived)
    /// `Default`, so that power-on and reset communication clear it in place with one memset.
    pub const OFF: ErrorControl = ErrorControl {
        producer_period: Duration::ZERO,
        heartbeat_due: false,
        #[cfg(feature = "node-guarding")]
        guarding: Guarding {
            guard_time: Duration::ZERO,
            life_time_factor: 0,
            toggle: false,
            answer_due: false,
            life_lost: false,
        },
        consumers: [Consumer::NONE; MAX_HEARTBEAT_CONSUMERS],
    };

    /// Reads 1017h; a change takes effect at once. Returns when the first heartbeat is due
    /// (one period from `now`), if the producer runs.
    pub fn configure_producer<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        now: Instant,
    ) -> Option<Instant> {
        let ms = read_uint_or(od, 0x1017, 0, 0);
        self.producer_period = Duration::from_millis(u64::from(ms));
        self.heartbeat_due = false;
        (ms != 0).then(|| now + self.producer_period)
    }

    /// Reads 100Ch and 100Dh. Returns whether life guarding is configured (else its timer
    /// stops).
    #[cfg(feature = "node-guarding")]
    pub fn configure_guarding<O: ObjectDictionary + ?Sized>(&mut self, od: &O) -> bool {
        if !od.services().life_guarding {
            return false;
        }
        let guard_ms = read_uint_or(od, 0x100C, 0, 0);
        self.guarding.guard_time = Duration::from_millis(u64::from(guard_ms));
        self.guarding.life_time_factor = read_uint_or(od, 0x100D, 0, 0) as u8;
        self.life_time().is_some()
    }

    /// Reads 1016h. Monitoring of a consumer whose entry did not change continues (its timer
    /// moves to its new place in `timers`, and its loss stays); a removed consumer's loss ends.
    /// `timers` are the consumers' slots of the node's timer table, in 1016h order: all
    /// [`MAX_HEARTBEAT_CONSUMERS`] of them (a slice of another length changes nothing), taken as
    /// one array so that they are set aside and cleared whole.
    pub fn configure_consumers<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &O,
        timers: &mut [Option<Instant>],
    ) {
        let Ok(timers) = <&mut [_; MAX_HEARTBEAT_CONSUMERS]>::try_from(timers) else {
            return;
        };
        let previous = self.consumers;
        let previous_timers = *timers;
        self.consumers.fill(Consumer::NONE);
        timers.fill(None);
        let count = read_uint_or(od, 0x1016, 0, 0).min(127) as u8;
        let mut served = 0;
        for sub in 1..count + 1 {
            let value = read_uint_or(od, 0x1016, sub, 0);
            let consumer = Consumer {
                node_id: (value >> 16) as u8,
                period_ms: value as u16,
                lost: false,
            };
            if consumer.node_id == 0 || consumer.node_id > 127 || consumer.period_ms == 0 {
                continue;
            }
            if served == MAX_HEARTBEAT_CONSUMERS {
                break;
            }
            self.consumers[served] = consumer;
            // A watched node whose entry is the same keeps its loss and its timer (an empty
            // slot matches none: the new entry's node-ID is not 0).
            for k in 0..MAX_HEARTBEAT_CONSUMERS {
                let old = previous[k];
                if old.node_id == consumer.node_id && old.period_ms == consumer.period_ms {
                    self.consumers[served] = old;
                    timers[served] = previous_timers[k];
                    break;
                }
            }
            served += 1;
        }
    }

    /// The life time (guard time × life time factor), if guarding is configured and the
    /// heartbeat producer is off (CiA 301: heartbeat takes precedence).
    #[cfg(feature = "node-guarding")]
    fn life_time(&self) -> Option<Duration> {
        let life = self.guarding.guard_time.as_micros() * u64::from(self.guarding.life_time_factor);
        (life != 0 && self.producer_period == Duration::ZERO).then_some(Duration(life))
    }

    /// Restarts a watched node's timer (its slot in `timers`, as for
    /// [`configure_consumers`](Self::configure_consumers)) when its heartbeat (or boot-up)
    /// arrives. Returns whether its loss ended.
    pub fn heartbeat_received(
        &mut self,
        node_id: u8,
        now: Instant,
        timers: &mut [Option<Instant>],
    ) -> bool {
        let mut recovered = false;
        for (consumer, timer) in self.consumers.iter_mut().zip(timers) {
            if consumer.node_id == node_id {
                *timer = Some(now + Duration::from_millis(u64::from(consumer.period_ms)));
                recovered |= core::mem::take(&mut consumer.lost);
            }
        }
        recovered
    }

    /// Whether a watched heartbeat or life guarding is lost: EMCY 8130h, which CiA 301 uses
    /// for both, stays active until none is.
    pub fn any_lost(&self) -> bool {
        #[cfg(feature = "node-guarding")]
        if self.guarding.life_lost {
            return true;
        }
        self.consumers.iter().any(|c| c.lost)
    }

    /// A node-guarding request at `now`: the answer is queued. If life guarding is configured
    /// (and the dictionary has its objects: `life_guarding`, a constant for a generated one)
    /// it (re)starts: returns when it runs out, and whether it had been lost (its error ends).
    #[cfg(feature = "node-guarding")]
    pub fn guard_request(&mut self, now: Instant, life_guarding: bool) -> Option<(Instant, bool)> {
        self.guarding.answer_due = true;
        if !life_guarding {
            return None;
        }
        let life = self.life_time()?;
        Some((now + life, core::mem::take(&mut self.guarding.life_lost)))
    }

    /// Whether an error-control frame is due (a heartbeat, or the answer to a guard request).
    #[inline]
    pub fn due(&self) -> bool {
        #[cfg(feature = "node-guarding")]
        if self.guarding.answer_due {
            return true;
        }
        self.heartbeat_due
    }

    /// The error-control byte to send for a node in `state`, if one is due: the answer to a
    /// guard request (with the toggle bit, which then alternates), else a heartbeat.
    #[inline]
    pub fn poll_transmit(&mut self, state: NmtState) -> Option<u8> {
        let repr = ErrorControlRepr {
            state,
            toggle: false,
        };
        #[cfg(feature = "node-guarding")]
        if core::mem::take(&mut self.guarding.answer_due) {
            let toggle = self.guarding.toggle;
            self.guarding.toggle = !toggle;
            return Some(ErrorControlRepr { toggle, ..repr }.emit());
        }
        core::mem::take(&mut self.heartbeat_due).then(|| repr.emit())
    }

    /// The heartbeat due `at` has come (at `now`): it is queued. Returns when the next one is
    /// due.
    pub fn expire_heartbeat(&mut self, at: Instant, now: Instant) -> Instant {
        self.heartbeat_due = true;
        next_period(at, self.producer_period, now)
    }

    /// Watched node `k` missed its heartbeat ([`Event::HeartbeatLost`]); its monitoring waits
    /// for the next heartbeat. Returns the node's ID (the node raises its emergency).
    pub fn expire_consumer(&mut self, k: usize, events: &mut EventQueue) -> u8 {
        let consumer = &mut self.consumers[k];
        consumer.lost = true;
        events.push(Event::HeartbeatLost {
            node_id: consumer.node_id,
        });
        consumer.node_id
    }

    /// The master stopped guarding ([`Event::LifeGuardingLost`]); the node raises its
    /// emergency.
    #[cfg(feature = "node-guarding")]
    pub fn expire_life_guard(&mut self, events: &mut EventQueue) {
        self.guarding.life_lost = true;
        events.push(Event::LifeGuardingLost);
    }
}
