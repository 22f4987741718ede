//! Configuration from the dictionary: what reading a communication object changes in the
//! running services (SDO, SYNC, EMCY, error control, PDOs), in one place that reset
//! communication and an accepted SDO write both use, and which TPDOs a changed entry marks.

use crate::od::ObjectDictionary;
use crate::time::Instant;
use crate::wire::heartbeat::NmtState;

use super::timer::Timer;
use super::{Node, NodeHooks};

/// The communication objects (besides the PDOs') that reset communication reads through
/// [`Node::configure`], one of each service's: the SYNC (1005h, 1006h, 1007h, 1019h), the EMCY
/// (1014h, 1015h), the heartbeat consumers (1016h), the heartbeat producer and node guarding
/// (1017h, 100Ch, 100Dh), the second SDO server (1201h).
pub(super) static SERVICE_OBJECTS: [u16; 5] = [0x1005, 0x1014, 0x1016, 0x1017, 0x1201];

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    pub(super) fn restart_sync_producer(&mut self, now: Instant) {
        let serves = matches!(self.state, NmtState::PreOperational | NmtState::Operational);
        // Without 1006h no SYNC is ever produced, and the consumer does not monitor.
        let first = if self.services().sync_period {
            self.sync.restart(now, serves)
        } else {
            None
        };
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

    /// Applies an accepted SDO write to the node's running state: the service the object
    /// configures reads it again, and the TPDOs that map it look for a change.
    pub(super) fn apply_write(&mut self, index: u16, sub: u8, now: Instant) {
        self.configure(index, sub, now);
        self.mark_changed(index, sub);
    }

    /// Reads communication object `index` (`sub` written) into the service it configures. A
    /// running service keeps what the new value does not change (a heartbeat consumer whose
    /// entry is the same, a PDO's deadline monitoring and timing history). Out of line: reset
    /// communication calls it for each of [`SERVICE_OBJECTS`], after clearing the services.
    #[inline(never)]
    pub(super) fn configure(&mut self, index: u16, sub: u8, now: Instant) {
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
            // The default server's COB-IDs are fixed.
            0x1201 if self.services().second_sdo => self.sdo[1].configure(&self.od, 0x1201),
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
    }

    /// Notes which RPDOs write objects that a TPDO maps, so that a received PDO looks for
    /// changes of state only when it can cause one.
    pub(super) fn link_pdos(&mut self) {
        for rpdo in &mut self.rpdos {
            let feeds = rpdo
                .mapping()
                .objects()
                .iter()
                .any(|object| self.tpdos.iter().any(|tpdo| tpdo.maps(object.position)));
            rpdo.set_feeds_tpdo(feeds);
        }
    }

    /// An OD entry changed: TPDOs that map it compare before their next transmission.
    pub(super) fn mark_changed(&mut self, index: u16, sub: u8) {
        if let Ok(position) = self.od.locate(index, sub) {
            // Positions beyond 16 bits are never mapped.
            self.mark_changed_at(position as u16);
        }
    }

    /// [`Node::mark_changed`] of the entry at `position` in the OD's table.
    pub(super) fn mark_changed_at(&mut self, position: u16) {
        for tpdo in &mut self.tpdos {
            if tpdo.maps(position) {
                tpdo.mark_changed();
                self.tpdo_attention = true;
            }
        }
    }
}
