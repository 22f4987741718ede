//! NMT state changes and resets (CiA 301 §7.3.2): entering a state starts and stops the
//! services it serves; reset node and reset communication restore the dictionary and start the
//! communication afresh.

use crate::od::ObjectDictionary;
use crate::time::Instant;
use crate::wire::heartbeat::NmtState;
use crate::wire::nmt::NmtCommand;

use super::comm::CommGuard;
use super::config::SERVICE_OBJECTS;
use super::error_control::ErrorControl;
use super::timer::TimerTable;
use super::{Event, Node, NodeHooks, ResetKind, COMMUNICATION_ERRORS};

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    fn set_state(&mut self, state: NmtState, now: Instant) {
        if self.state == state {
            return;
        }
        let was = self.state;
        self.state = state;
        let leaving = was == NmtState::Operational;
        let entering = state == NmtState::Operational;
        if leaving {
            self.timers.stop_pdos();
            for rpdo in &mut self.rpdos {
                rpdo.stop();
            }
        }
        // One loop for leaving and entering operational (never both at once).
        for tpdo in &mut self.tpdos {
            if leaving {
                tpdo.stop();
            }
            if entering && tpdo.start() {
                self.tpdo_attention = true;
            }
        }
        if state == NmtState::Stopped {
            self.reset_sdo();
        }
        // Stopped stops the SYNC producer and monitoring (the producer serves only
        // pre-operational and operational); leaving stopped or initialising starts them.
        if matches!(state, NmtState::Stopped)
            || matches!(was, NmtState::Stopped | NmtState::Initialising)
        {
            self.restart_sync_producer(now);
        }
        self.events.push(Event::NmtStateChanged(state));
    }

    /// Drops the SDO transfers in progress; their downloads leave the entries as they were.
    /// Through the dictionary the channels' requests see (the one the server's code is built
    /// for, rather than a second copy of it for the bare OD).
    fn reset_sdo(&mut self) {
        let channels = self.sdo_channels();
        let mut guard = CommGuard {
            od: &mut self.od,
            hooks: &mut self.hooks,
            node_id: self.node_id,
        };
        let [first, second] = &mut self.sdo;
        first.reset(&mut guard);
        if channels > 1 {
            second.reset(&mut guard);
        }
    }

    pub(super) fn reset_communication(&mut self, now: Instant) {
        self.state = NmtState::Initialising;
        // Cleared one after the other: where the two lie side by side, one memset clears both.
        self.timers = TimerTable::OFF;
        self.error_control = ErrorControl::OFF;
        self.reset_sdo();
        #[cfg(feature = "lss")]
        {
            self.lss.load_address(&self.od);
            if self.is_unconfigured() {
                // CiA 305: no NMT slave service but LSS until the node has an ID.
                self.emcy.reset_queue(&mut self.od);
                return;
            }
        }
        self.emcy.forget_communication_errors(&COMMUNICATION_ERRORS);
        self.emcy.reset_queue(&mut self.od);
        for &index in &SERVICE_OBJECTS {
            self.configure(index, 0, now);
        }
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
        #[cfg(feature = "lss")]
        self.take_lss_node_id(kind);
        // After a reset node that cleared errors, "no error" is announced once.
        let announce_no_error = kind == ResetKind::Node && self.emcy.any_active();
        if kind == ResetKind::Node {
            self.emcy.forget_all();
        }
        self.hooks
            .restore_power_on(kind, self.node_id, &mut self.od);
        self.hooks.reset(kind, &mut self.od);
        self.events.push(Event::Reset(kind));
        self.reset_communication(now);
        if announce_no_error {
            // The master saw errors before the reset: tell it they are gone.
            self.emcy.announce_no_error();
        }
    }

    /// The node-ID an NMT reset starts with (CiA 305): reset communication takes the pending
    /// one an LSS master configured, reset node the stored one.
    #[cfg(feature = "lss")]
    fn take_lss_node_id(&mut self, kind: ResetKind) {
        let id = match kind {
            ResetKind::Node => self.lss.stored_node_id,
            ResetKind::Communication => self.lss.pending_node_id,
        };
        self.lss.pending_node_id = id;
        self.lss.attention |= id == crate::wire::lss::UNCONFIGURED_NODE_ID;
        if id != self.node_id {
            self.node_id = id;
            self.sdo[0] = super::sdo_channel::SdoChannel::new(id);
        }
    }

    /// An NMT command for this node. Out of line: the state changes and resets it reaches are
    /// rare, and kept out of [`Node::handle_frame`] they leave its SDO and PDO paths alone.
    #[inline(never)]
    pub(super) fn handle_nmt(&mut self, command: NmtCommand, now: Instant) {
        match command {
            NmtCommand::Start => self.set_state(NmtState::Operational, now),
            NmtCommand::Stop => self.set_state(NmtState::Stopped, now),
            NmtCommand::EnterPreOperational => self.set_state(NmtState::PreOperational, now),
            NmtCommand::ResetNode => self.reset(ResetKind::Node, now),
            NmtCommand::ResetCommunication => self.reset(ResetKind::Communication, now),
        }
    }
}
