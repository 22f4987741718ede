//! The node's timers by name ([`Timer`]), each kept by the service it belongs to: the one place
//! that finds the earliest ([`Node::poll_timeout`]) and the one dispatch that runs those due
//! ([`Node::handle_timeout`]), in the order of [`Timer::each`].

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
    /// The EMCY inhibit time (1015h) lets the next queued emergency out.
    EmcyInhibit,
    /// RPDO `n` did not arrive within its event timer (1400h+n sub 05h, deadline monitoring).
    RpdoDeadline(usize),
    /// The event timer of TPDO `n` (1800h+n sub 05h).
    TpdoEvent(usize),
    /// The inhibit time of TPDO `n`'s waiting frame (1800h+n sub 03h).
    TpdoInhibit(usize),
    /// The segment timeout of SDO server channel `n` ([`super::SDO_TIMEOUT`]).
    SdoTimeout(usize),
}

/// How many timers of each kind run: the node's [`Node::running_timers`].
#[derive(Debug, Clone, Copy)]
struct Running {
    /// Heartbeat consumers configured (1016h).
    consumers: usize,
    /// Whether emergencies may be sent (every NMT state but stopped).
    emcy: bool,
    /// RPDOs and TPDOs with timers (all of them in operational, none otherwise).
    rpdos: usize,
    tpdos: usize,
    sdo_channels: usize,
}

impl Timer {
    /// Calls `f` with every timer that runs, in the order [`Node::handle_timeout`] runs them.
    /// `f` is a `dyn` closure so that one copy of the walk serves both
    /// [`Node::poll_timeout`] and [`Node::handle_timeout`] (some 170 B less flash than two).
    fn each(running: Running, f: &mut dyn FnMut(Timer)) {
        f(Timer::Heartbeat);
        for k in 0..running.consumers {
            f(Timer::HeartbeatConsumer(k));
        }
        #[cfg(feature = "node-guarding")]
        f(Timer::LifeGuard);
        f(Timer::SyncConsumer);
        f(Timer::SyncProducer);
        if running.emcy {
            f(Timer::EmcyInhibit);
        }
        for n in 0..running.rpdos {
            f(Timer::RpdoDeadline(n));
        }
        for n in 0..running.tpdos {
            f(Timer::TpdoEvent(n));
            f(Timer::TpdoInhibit(n));
        }
        for n in 0..running.sdo_channels {
            f(Timer::SdoTimeout(n));
        }
    }
}

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    /// The timers that run in the node's NMT state and configuration: PDO timers in
    /// operational only, the EMCY inhibit time in every state but stopped.
    fn running_timers(&self) -> Running {
        let pdos = match self.state {
            NmtState::Operational => (RPDOS, TPDOS),
            _ => (0, 0),
        };
        Running {
            consumers: self.error_control.consumer_count(),
            emcy: self.state != NmtState::Stopped,
            rpdos: pdos.0,
            tpdos: pdos.1,
            sdo_channels: self.sdo.len(),
        }
    }

    /// The next instant at which [`handle_timeout`](Self::handle_timeout) has work, or at which a
    /// frame held back by an inhibit time may go out through [`poll_transmit`](Self::poll_transmit).
    pub fn poll_timeout(&self) -> Option<Instant> {
        let mut next = None;
        Timer::each(self.running_timers(), &mut |timer| {
            keep_earliest(&mut next, &self.deadline(timer));
        });
        next
    }

    /// Runs every timer due at `now`: heartbeat production and consumption, life guarding,
    /// SYNC production and monitoring, TPDO event timers, RPDO deadlines and SDO timeouts.
    pub fn handle_timeout(&mut self, now: Instant) {
        Timer::each(self.running_timers(), &mut |timer| {
            if self.deadline(timer).is_some_and(|at| at <= now) {
                self.expire(timer, now);
            }
        });
    }

    /// When `timer` runs out, as the service that owns it says; `None` if it does not run.
    fn deadline(&self, timer: Timer) -> Option<Instant> {
        match timer {
            Timer::Heartbeat => self.error_control.heartbeat_deadline(),
            Timer::HeartbeatConsumer(k) => self.error_control.consumer_deadline(k),
            #[cfg(feature = "node-guarding")]
            Timer::LifeGuard => self.error_control.life_deadline(),
            Timer::SyncConsumer => self.sync.consumer_deadline(),
            Timer::SyncProducer => self.sync.producer_deadline(),
            Timer::EmcyInhibit => self.emcy.ready_at(),
            Timer::RpdoDeadline(n) => self.rpdos.get(n)?.next_deadline(),
            Timer::TpdoEvent(n) => self.tpdos.get(n)?.event_deadline(),
            Timer::TpdoInhibit(n) => self.tpdos.get(n)?.inhibit_end(),
            Timer::SdoTimeout(n) => self.sdo.get(n)?.next_deadline(),
        }
    }

    /// Runs `timer`, which is due at `now`.
    fn expire(&mut self, timer: Timer, now: Instant) {
        match timer {
            Timer::Heartbeat => self.error_control.expire_heartbeat(now),
            Timer::HeartbeatConsumer(k) => {
                let node_id = self.error_control.expire_consumer(k, &mut self.events);
                // Already active when another node or life guarding was lost first: one
                // emergency for all.
                self.raise_communication_error(
                    super::error_code::LIFE_GUARD,
                    [node_id, 0, 0, 0, 0],
                );
            }
            #[cfg(feature = "node-guarding")]
            Timer::LifeGuard => {
                self.error_control.expire_life_guard(&mut self.events);
                self.raise_communication_error(super::error_code::LIFE_GUARD, [0; 5]);
            }
            Timer::SyncConsumer => {
                self.sync.expire_consumer();
                self.raise_communication_error(SYNC_TIMEOUT_CODE, [0; 5]);
            }
            Timer::SyncProducer => {
                let counter = self.sync.expire_producer(now);
                self.handle_sync(counter, now);
            }
            // The frames they held back go out through poll_transmit.
            Timer::EmcyInhibit | Timer::TpdoInhibit(_) => {}
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
            Timer::SdoTimeout(n) => self.sdo[n].expire(now),
        }
    }
}
