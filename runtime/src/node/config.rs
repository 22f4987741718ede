//! Configuration from the dictionary: what an accepted write to a communication object changes
//! in the running services (SDO, SYNC, guarding, PDOs) and which TPDOs a changed entry marks.

use crate::od::ObjectDictionary;
use crate::time::Instant;
use crate::wire::heartbeat::NmtState;

use super::timer::Timer;
use super::{Node, NodeHooks};

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    /// Reads the second SDO server's COB-IDs (1201h); the default server's are fixed.
    pub(super) fn configure_second_sdo(&mut self) {
        if self.services().second_sdo {
            self.sdo[1].configure(&self.od, 0x1201);
        }
    }

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

    /// Applies an accepted SDO write to the node's running state.
    pub(super) fn apply_write(&mut self, index: u16, sub: u8, now: Instant) {
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
