//! The node's timers by name ([`Timer`]) and the table that holds their instants
//! ([`TimerTable`]: one slot per timer, fixed-size, `None` while disarmed). The services say
//! when to arm a timer and what its expiry does; the node stores the instants here, finds the
//! earliest ([`Node::poll_timeout`]) and runs those due ([`Node::handle_timeout`]), in the order
//! of [`Timer::nth`].
//!
//! Three waits are not timers of the table: the EMCY inhibit time (1015h) and a TPDO's inhibit
//! time (1800h+n sub 03h) only hold a frame back (nothing runs when they end; the services
//! compute them from their last transmission), and the SDO segment timeout belongs to the
//! [`SdoServer`](crate::sdo::SdoServer), which also serves without a node. `poll_timeout`
//! reports them too.

use super::comm::CommGuard;
use super::error_control::MAX_HEARTBEAT_CONSUMERS;
use super::sdo_channel::SdoChannel;
use super::{keep_earliest, Event, Node, NodeHooks};
use super::{RPDO_TIMEOUT_CODE, SYNC_TIMEOUT_CODE};
use crate::od::ObjectDictionary;
use crate::time::Instant;
use crate::wire::heartbeat::NmtState;

/// A timer of the node, named after what runs out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Timer {
    /// The heartbeat producer's next heartbeat (1017h).
    Heartbeat,
    /// The heartbeat of watched node `k` (in 1016h order) is overdue.
    HeartbeatConsumer(usize),
    /// The NMT master stopped guarding within the life time (100Ch × 100Dh).
    #[cfg(feature = "node-guarding")]
    LifeGuard,
    /// The SYNC consumer saw no SYNC for 1.5 × 1006h.
    SyncConsumer,
    /// The SYNC producer's next SYNC (1006h).
    SyncProducer,
    /// RPDO `n` did not arrive within its event timer (1400h+n sub 05h, deadline monitoring).
    RpdoDeadline(usize),
    /// The event timer of TPDO `n` (1800h+n sub 05h).
    TpdoEvent(usize),
}

impl Timer {
    /// The `i`th timer in the order [`Node::handle_timeout`] runs them (the heartbeat
    /// producer, the consumers, life guarding, the SYNC consumer and producer, the RPDOs'
    /// deadlines, the TPDOs' event timers), `i` below [`TimerTable::LEN`]: one loop over an
    /// index, so that running a timer is one call site rather than one per kind.
    fn nth<const RPDOS: usize>(i: usize) -> Timer {
        match i {
            0 => Timer::Heartbeat,
            k if k < CONSUMERS + MAX_HEARTBEAT_CONSUMERS => Timer::HeartbeatConsumer(k - CONSUMERS),
            #[cfg(feature = "node-guarding")]
            LIFE_GUARD => Timer::LifeGuard,
            SYNC_CONSUMER => Timer::SyncConsumer,
            SYNC_PRODUCER => Timer::SyncProducer,
            n if n < SERVICE_TIMERS + RPDOS => Timer::RpdoDeadline(n - SERVICE_TIMERS),
            n => Timer::TpdoEvent(n - SERVICE_TIMERS - RPDOS),
        }
    }
}

/// The first slot of the heartbeat consumers' timers in [`TimerTable`]'s service timers.
const CONSUMERS: usize = 1;
/// How many timers the services have besides the PDOs': the heartbeat producer's, the
/// consumers', the SYNC consumer's and producer's, and life guarding's.
const SERVICE_TIMERS: usize =
    CONSUMERS + MAX_HEARTBEAT_CONSUMERS + 2 + cfg!(feature = "node-guarding") as usize;
/// Life guarding's slot, after the consumers'.
#[cfg(feature = "node-guarding")]
const LIFE_GUARD: usize = CONSUMERS + MAX_HEARTBEAT_CONSUMERS;
/// The SYNC consumer's slot, after life guarding's (if the node has it).
const SYNC_CONSUMER: usize =
    CONSUMERS + MAX_HEARTBEAT_CONSUMERS + cfg!(feature = "node-guarding") as usize;
/// The SYNC producer's slot, the last of the services'.
const SYNC_PRODUCER: usize = SYNC_CONSUMER + 1;

/// When each [`Timer`] runs out: `None` while it is disarmed. The PDO timers run in
/// operational only (the node disarms them when it leaves).
#[derive(Debug, Clone, Copy)]
pub(crate) struct TimerTable<const RPDOS: usize, const TPDOS: usize> {
    /// The heartbeat producer's, the consumers' (in 1016h order), the SYNC consumer's and
    /// producer's, and life guarding's: one array, so that finding the earliest is one loop.
    services: [Option<Instant>; SERVICE_TIMERS],
    rpdo_deadlines: [Option<Instant>; RPDOS],
    tpdo_events: [Option<Instant>; TPDOS],
}

impl<const RPDOS: usize, const TPDOS: usize> TimerTable<RPDOS, TPDOS> {
    /// How many timers the table holds.
    const LEN: usize = SERVICE_TIMERS + RPDOS + TPDOS;

    /// Every timer disarmed.
    pub const OFF: Self = TimerTable {
        services: [None; SERVICE_TIMERS],
        rpdo_deadlines: [None; RPDOS],
        tpdo_events: [None; TPDOS],
    };

    /// The slot of `timer`. Always inlined: every caller names the kind of timer, and what is
    /// left of the match is the index into one array.
    #[inline(always)]
    pub fn slot(&mut self, timer: Timer) -> &mut Option<Instant> {
        let service = match timer {
            Timer::RpdoDeadline(n) => return &mut self.rpdo_deadlines[n],
            Timer::TpdoEvent(n) => return &mut self.tpdo_events[n],
            Timer::Heartbeat => 0,
            Timer::HeartbeatConsumer(k) => CONSUMERS + k,
            #[cfg(feature = "node-guarding")]
            Timer::LifeGuard => LIFE_GUARD,
            Timer::SyncConsumer => SYNC_CONSUMER,
            Timer::SyncProducer => SYNC_PRODUCER,
        };
        &mut self.services[service]
    }

    /// The slot of [`Timer::nth`]`(i)`.
    fn nth_slot(&mut self, i: usize) -> &mut Option<Instant> {
        if i < SERVICE_TIMERS {
            &mut self.services[i]
        } else if i < SERVICE_TIMERS + RPDOS {
            &mut self.rpdo_deadlines[i - SERVICE_TIMERS]
        } else {
            &mut self.tpdo_events[i - SERVICE_TIMERS - RPDOS]
        }
    }

    /// The instant of [`Timer::nth`]`(i)`.
    fn nth(&self, i: usize) -> &Option<Instant> {
        if i < SERVICE_TIMERS {
            &self.services[i]
        } else if i < SERVICE_TIMERS + RPDOS {
            &self.rpdo_deadlines[i - SERVICE_TIMERS]
        } else {
            &self.tpdo_events[i - SERVICE_TIMERS - RPDOS]
        }
    }

    /// The heartbeat consumers' slots, in 1016h order (see `ErrorControl::configure_consumers`).
    pub fn consumers(&mut self) -> &mut [Option<Instant>] {
        &mut self.services[CONSUMERS..CONSUMERS + MAX_HEARTBEAT_CONSUMERS]
    }

    /// Arms `timer` to run out `at`, or disarms it (`None`).
    pub fn set(&mut self, timer: Timer, at: Option<Instant>) {
        *self.slot(timer) = at;
    }

    /// Disarms the PDO timers (leaving operational).
    pub fn stop_pdos(&mut self) {
        self.rpdo_deadlines = [None; RPDOS];
        self.tpdo_events = [None; TPDOS];
    }

    /// The earliest armed instant.
    fn earliest(&self) -> Option<Instant> {
        let mut next = None;
        // One loop over the index, as `Node::handle_timeout` runs them.
        for i in 0..Self::LEN {
            keep_earliest(&mut next, self.nth(i));
        }
        next
    }
}

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    /// The next instant at which [`handle_timeout`](Self::handle_timeout) has work, or at which a
    /// frame held back by an inhibit time may go out through [`poll_transmit`](Self::poll_transmit).
    pub fn poll_timeout(&self) -> Option<Instant> {
        let mut next = self.timers.earliest();
        if self.state != NmtState::Stopped {
            keep_earliest(&mut next, &self.emcy.ready_at(self.services().emcy_inhibit));
        }
        if self.state == NmtState::Operational {
            for tpdo in &self.tpdos {
                keep_earliest(&mut next, &tpdo.inhibit_end());
            }
        }
        // The default SDO channel, then the second if the dictionary has it: no loop for one.
        keep_earliest(&mut next, &self.sdo[0].next_deadline());
        if self.sdo_channels() > 1 {
            keep_earliest(&mut next, &self.sdo[1].next_deadline());
        }
        next
    }

    /// Runs every timer due at `now`: heartbeat production and consumption, life guarding,
    /// SYNC production and monitoring, RPDO deadlines, TPDO event timers, then SDO timeouts.
    pub fn handle_timeout(&mut self, now: Instant) {
        for i in 0..TimerTable::<RPDOS, TPDOS>::LEN {
            let slot = self.timers.nth_slot(i);
            if let Some(at) = slot.filter(|&at| at <= now) {
                *slot = None;
                self.expire(Timer::nth::<RPDOS>(i), at, now);
            }
        }
        let channels = self.sdo_channels();
        let mut guard = CommGuard {
            od: &mut self.od,
            hooks: &mut self.hooks,
            node_id: self.node_id,
        };
        let mut expire = |channel: &mut SdoChannel| {
            if channel.next_deadline().is_some_and(|at| at <= now) {
                channel.expire(now, &mut guard);
            }
        };
        // As in poll_timeout: no loop for one channel.
        let [first, second] = &mut self.sdo;
        expire(first);
        if channels > 1 {
            expire(second);
        }
    }

    /// Runs `timer`, which was due `at` and is disarmed now (`now`); re-arms it if it repeats.
    fn expire(&mut self, timer: Timer, at: Instant, now: Instant) {
        match timer {
            Timer::Heartbeat => {
                let next = self.error_control.expire_heartbeat(at, now);
                self.timers.set(timer, Some(next));
            }
            Timer::HeartbeatConsumer(k) => {
                let node_id = self.error_control.expire_consumer(k, &mut self.events);
                // Already active when another node or life guarding was lost first: one
                // emergency for all.
                self.raise_communication_error(
                    super::error_code::LIFE_GUARD,
                    [node_id, 0, 0, 0, 0],
                );
            }
            // Never armed without 100Ch and 100Dh.
            #[cfg(feature = "node-guarding")]
            Timer::LifeGuard if !self.services().life_guarding => {}
            #[cfg(feature = "node-guarding")]
            Timer::LifeGuard => {
                self.error_control.expire_life_guard(&mut self.events);
                self.raise_communication_error(super::error_code::LIFE_GUARD, [0; 5]);
            }
            // Never armed without 1006h (the node then builds no SYNC producer or monitoring).
            Timer::SyncConsumer | Timer::SyncProducer if !self.services().sync_period => {}
            Timer::SyncConsumer => {
                // Monitoring waits for the next SYNC.
                self.raise_communication_error(SYNC_TIMEOUT_CODE, [0; 5]);
            }
            Timer::SyncProducer => {
                let (counter, next) = self.sync.expire_producer(at, now);
                self.timers.set(timer, Some(next));
                self.handle_sync(counter, now);
            }
            Timer::RpdoDeadline(n) => {
                self.rpdos[n].expire();
                self.events.push(Event::RpdoTimeout { pdo: n as u16 });
                // Already active when another RPDO timed out first: one emergency for both.
                self.raise_communication_error(RPDO_TIMEOUT_CODE, [0; 5]);
            }
            Timer::TpdoEvent(n) => {
                self.tpdos[n].expire_event();
                self.tpdo_attention = true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(ms: u64) -> Option<Instant> {
        Some(Instant::from_millis(ms))
    }

    #[test]
    fn the_table_keeps_one_instant_per_timer_and_finds_the_earliest() {
        let mut table = TimerTable::<2, 3>::OFF;
        assert_eq!(table.earliest(), None);
        table.set(Timer::Heartbeat, at(500));
        table.set(Timer::HeartbeatConsumer(7), at(400));
        table.set(Timer::SyncProducer, at(300));
        table.set(Timer::TpdoEvent(2), at(200));
        assert_eq!(table.earliest(), at(200));
        assert_eq!(table.consumers()[7], at(400));
        assert_eq!(*table.slot(Timer::SyncConsumer), None);
        table.set(Timer::RpdoDeadline(1), at(100));
        assert_eq!(table.earliest(), at(100));
        table.stop_pdos();
        assert_eq!(table.earliest(), at(300));
        table.set(Timer::SyncProducer, None);
        assert_eq!(table.earliest(), at(400));
    }
}
