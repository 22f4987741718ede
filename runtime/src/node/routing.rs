//! Routing: each received frame to the service that owns its COB-ID, and each service's frames
//! out in CAN priority order.

use crate::frame::CanFrame;
use crate::od::{ObjectDictionary, SdoAbort};
use crate::sdo::SdoEvent;
use crate::time::Instant;
use crate::wire::heartbeat::{ErrorControlRepr, NmtState};
use crate::wire::nmt::{NmtRepr, NMT_COB_ID};
use crate::wire::sync::SyncRepr;

use super::comm::CommGuard;
use super::emcy::{error_code, error_register};
use super::timer::Timer;
use super::{one_byte_frame, Event, Node, NodeHooks, RPDO_TIMEOUT_CODE, SYNC_TIMEOUT_CODE};

impl<O: ObjectDictionary, H: NodeHooks<O>, const RPDOS: usize, const TPDOS: usize>
    Node<O, H, RPDOS, TPDOS>
{
    /// Takes a received frame.
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let Some(id) = frame.std_id() else {
            return;
        };
        if id == NMT_COB_ID {
            if let Some(nmt) = NmtRepr::parse(frame.data()) {
                if !frame.is_remote() && nmt.addresses(self.node_id) && self.serves_nmt(nmt) {
                    self.handle_nmt(nmt.command, now);
                }
            }
            return;
        }
        // LSS costs a configured node one comparison per frame: the rest is out of line.
        #[cfg(feature = "lss")]
        if (id == crate::wire::lss::LSS_REQUEST_COB_ID || self.is_unconfigured())
            && self.lss_takes_frame(id, frame, now)
        {
            return;
        }
        if frame.is_remote() {
            self.handle_remote(id, now);
            return;
        }
        let serving = matches!(self.state, NmtState::PreOperational | NmtState::Operational);
        if serving {
            if id == self.sync.cob_id() {
                self.handle_sync_frame(frame.data(), now);
                return;
            }
            for n in 0..self.sdo_channels() {
                if self.sdo[n].accepts(id) {
                    self.handle_sdo(n, frame.data(), now);
                    return;
                }
            }
        }
        if self.state == NmtState::Operational {
            for n in 0..RPDOS {
                if self.rpdos[n].accepts(id) {
                    self.handle_rpdo(n, frame.data(), now);
                    return;
                }
            }
        }
        if let Some(node_id) = ErrorControlRepr::node_of(id) {
            if frame.dlc() == 1
                && self
                    .error_control
                    .heartbeat_received(node_id, now, self.timers.consumers())
            {
                self.end_error_control_loss();
            }
        }
    }

    /// Whether the node serves an NMT command: every one, but an unconfigured LSS node (ID 255)
    /// only the resets, which take the node-ID it was given (CiA 305).
    fn serves_nmt(&self, nmt: NmtRepr) -> bool {
        #[cfg(feature = "lss")]
        if self.is_unconfigured() {
            use crate::wire::nmt::NmtCommand;
            return matches!(
                nmt.command,
                NmtCommand::ResetNode | NmtCommand::ResetCommunication
            );
        }
        let _ = nmt;
        true
    }

    #[cfg_attr(not(feature = "node-guarding"), allow(unused_variables))]
    fn handle_remote(&mut self, id: u16, now: Instant) {
        if id == ErrorControlRepr::cob_id(self.node_id) {
            // Without node guarding the request is ignored.
            #[cfg(feature = "node-guarding")]
            self.handle_guard_request(now);
            return;
        }
        if self.state != NmtState::Operational {
            return;
        }
        for tpdo in &mut self.tpdos {
            if tpdo.remote_request(id) {
                self.tpdo_attention |= tpdo.pending();
                return;
            }
        }
    }

    /// A node-guarding RTR: queue the answer and (re)start life guarding.
    #[cfg(feature = "node-guarding")]
    fn handle_guard_request(&mut self, now: Instant) {
        let life_guarding = self.services().life_guarding;
        if let Some((life_end, recovered)) = self.error_control.guard_request(now, life_guarding) {
            self.timers.set(Timer::LifeGuard, Some(life_end));
            if recovered {
                self.end_error_control_loss();
            }
        }
    }

    /// Clears 8130h (with its error-reset emergency) once neither life guarding nor a watched
    /// heartbeat is lost.
    pub(super) fn end_error_control_loss(&mut self) {
        if !self.error_control.any_lost() {
            self.emcy.clear(&mut self.od, error_code::LIFE_GUARD);
        }
    }

    /// Inlined into its one caller: out of line (as the host build made it once the loop over
    /// the channels had a constant bound) it costs an SDO request some 16 instructions more.
    #[inline(always)]
    fn handle_sdo(&mut self, n: usize, request: &[u8], now: Instant) {
        let mut guard = CommGuard {
            od: &mut self.od,
            hooks: &mut self.hooks,
            node_id: self.node_id,
        };
        if let Some(SdoEvent::Written { index, sub }) = self.sdo[n].handle(now, request, &mut guard)
        {
            self.apply_write(index, sub, now);
            self.events.push(Event::Written { index, sub });
        }
    }

    /// Inlined into its one caller whatever the features: out of line (as the `lss` feature's
    /// code made it) it costs an RPDO some 25 instructions more.
    #[inline(always)]
    fn handle_rpdo(&mut self, n: usize, data: &[u8], now: Instant) {
        let rpdo = &mut self.rpdos[n];
        let expected = usize::from(rpdo.mapping().len);
        let deadline = self.timers.slot(Timer::RpdoDeadline(n));
        let (apply, recovered) = rpdo.receive(now, data, deadline);
        if let Some(data) = apply {
            self.apply_rpdo(n, data);
        }
        if data.len() != expected || self.length_error_raised {
            self.update_length_errors(data.len());
        }
        if recovered {
            self.end_rpdo_timeout();
        }
    }

    /// Writes a received RPDO's values into the OD, all or none. When the OD refuses one, none
    /// is written, no [`Event::RpdoReceived`] is reported, and EMCY 8200h
    /// ([`error_code::PROTOCOL`]) says which PDO and why: manufacturer bytes `n` then the abort
    /// code, little-endian. The next RPDO applied whole while no other is refused clears it.
    #[inline]
    fn apply_rpdo(&mut self, n: usize, data: &[u8]) {
        let rpdo = &mut self.rpdos[n];
        match rpdo.apply(&mut self.od, data) {
            Ok(recovered) => {
                if rpdo.feeds_tpdo() || recovered {
                    self.rpdo_applied(n, recovered);
                }
                self.events.push(Event::RpdoReceived { pdo: n as u16 });
            }
            Err(abort) => self.rpdo_refused(n, abort),
        }
    }

    /// What applying RPDO `n` changes besides its values, when it changes anything: the TPDOs
    /// that map what it wrote look for a change of state, and 8200h clears once no RPDO is
    /// refused (`recovered`: this one was). Cold, as `Mapping::unpack`'s general path: a
    /// speed-optimized build keeps it out of `apply_rpdo`'s frame, a size-optimized one inlines
    /// it at its one call.
    #[cold]
    fn rpdo_applied(&mut self, n: usize, recovered: bool) {
        if self.rpdos[n].feeds_tpdo() {
            // By index, the mapping read in place (no copy to loop over while marking).
            let mut i = 0;
            while let Some(object) = self.rpdos[n].mapping().objects().get(i) {
                self.mark_changed_at(object.position);
                i += 1;
            }
        }
        if recovered && !self.rpdos.iter().any(|r| r.refused()) {
            self.emcy.clear(&mut self.od, error_code::PROTOCOL);
        }
    }

    /// EMCY 8200h for RPDO `n`, whose values the OD refused: manufacturer bytes `n` then the
    /// abort code. Out of line, so that applying an RPDO keeps a small frame.
    #[cold]
    #[inline(never)]
    fn rpdo_refused(&mut self, n: usize, abort: SdoAbort) {
        let [a, b, c, d] = abort.code().to_le_bytes();
        let info = [n as u8, a, b, c, d];
        self.raise_communication_error(error_code::PROTOCOL, info);
    }

    /// Raises an error of the node's own communication (register bit 4) with the
    /// `manufacturer` bytes of its emergency.
    pub(super) fn raise_communication_error(&mut self, code: u16, manufacturer: [u8; 5]) {
        self.emcy.raise(
            &mut self.od,
            code,
            error_register::COMMUNICATION,
            manufacturer,
        );
    }

    /// Clears 8250h (with its error-reset emergency) once no RPDO is timed out any more.
    pub(super) fn end_rpdo_timeout(&mut self) {
        if !self.rpdos.iter().any(|r| r.timed_out()) {
            self.emcy.clear(&mut self.od, RPDO_TIMEOUT_CODE);
        }
    }

    /// Raises or clears 8210h (too short, not processed) and 8220h (too long, processed).
    fn update_length_errors(&mut self, received: usize) {
        let (mut short, mut long) = (false, false);
        for rpdo in &self.rpdos {
            let (too_short, too_long) = rpdo.length_errors();
            short |= too_short;
            long |= too_long;
        }
        let info = [received as u8, 0, 0, 0, 0];
        for (code, now_bad) in [
            (error_code::PDO_LENGTH, short),
            (error_code::PDO_LENGTH_EXCEEDED, long),
        ] {
            if now_bad {
                self.raise_communication_error(code, info);
            } else {
                // Nothing happens unless it is active.
                self.emcy.clear(&mut self.od, code);
            }
        }
        self.length_error_raised = short || long;
    }

    /// A received SYNC. Its length must match 1019h: a counter byte when the overflow value is
    /// not 0, no data when it is. Any other SYNC is not processed and raises EMCY 8240h
    /// ([`error_code::SYNC_LENGTH`], manufacturer byte 0 the length received); the next SYNC of
    /// the right length clears it.
    fn handle_sync_frame(&mut self, data: &[u8], now: Instant) {
        match SyncRepr::parse(data) {
            Some(sync) if self.sync_length_matches(sync.counter) => {
                // Nothing happens unless it is active.
                self.emcy.clear(&mut self.od, error_code::SYNC_LENGTH);
                self.handle_sync(sync.counter, now);
            }
            _ => {
                let info = [data.len() as u8, 0, 0, 0, 0];
                self.raise_communication_error(error_code::SYNC_LENGTH, info);
            }
        }
    }

    /// Whether a SYNC's counter matches 1019h (no counter without 1019h).
    #[inline(always)]
    fn sync_length_matches(&self, counter: Option<u8>) -> bool {
        if self.services().sync_counter {
            self.sync.length_matches(counter)
        } else {
            counter.is_none()
        }
    }

    /// Whether the SYNC producer has a SYNC to send (never without 1006h).
    #[inline(always)]
    fn sync_due(&self) -> bool {
        self.services().sync_period && self.sync.due()
    }

    pub(super) fn handle_sync(&mut self, counter: Option<u8>, now: Instant) {
        self.events.push(Event::Sync { counter });
        let services = self.services();
        // The services first: without their objects nothing is computed (a deadline's
        // saturating add is a call the optimizer does not drop).
        let timeout = services
            .sync_period
            .then(|| self.sync.consumed(now))
            .flatten();
        if let Some(timeout) = timeout {
            self.timers.set(Timer::SyncConsumer, Some(timeout));
            // Ends a SYNC timeout error, if one is active.
            self.emcy.clear(&mut self.od, SYNC_TIMEOUT_CODE);
        }
        if self.state != NmtState::Operational {
            return;
        }
        for n in 0..RPDOS {
            if let Some(data) = self.rpdos[n].take_buffered() {
                self.apply_rpdo(n, &data);
            }
        }
        let window_end = services
            .sync_window
            .then(|| self.sync.window_end(now))
            .flatten();
        let use_start = services.sync_counter && self.sync.counting();
        for tpdo in &mut self.tpdos {
            if tpdo.on_sync(&self.od, counter, use_start, window_end) {
                self.tpdo_attention = true;
            }
        }
    }

    /// The next frame to send, if any. Frames go out in CAN priority order of their function:
    /// boot-up first, then SYNC, EMCY, TPDOs, SDO responses, node guarding and heartbeat.
    ///
    /// Asked after every received frame, mostly with nothing to send: the services' flags are
    /// tested here, inlined (always: a host build's inliner may otherwise keep it out of line,
    /// at some 7 instructions per frame), and the frames built out of line only when one is set.
    #[inline(always)]
    pub fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        // As for received frames: one test on a configured node with nothing to say.
        #[cfg(feature = "lss")]
        if self.lss.attention {
            if let Some(frame) = self.poll_lss(now) {
                return frame;
            }
        }
        // A test, not the order frames go out in: the default SDO channel's answer, the most
        // frequent frame, is tested first.
        let sdo_answer = self.sdo[0].busy();
        let may_send = sdo_answer
            || self.boot_up_due
            || self.sync_due()
            || self.emcy.queued()
            || self.tpdo_attention
            || (self.sdo_channels() > 1 && self.sdo[1].busy())
            || self.error_control.due();
        if !may_send {
            return None;
        }
        // That answer with nothing due before it (the services whose frames go out first):
        // straight from the channel.
        if sdo_answer
            && !(self.boot_up_due || self.sync_due() || self.emcy.queued() || self.tpdo_attention)
        {
            if let Some(frame) = self.sdo[0].poll_transmit(now, &self.od) {
                return Some(frame);
            }
        }
        self.poll_transmit_due(now)
    }

    /// [`Node::poll_transmit`] once a service has a frame, or may have one (an EMCY or a TPDO
    /// held back by its inhibit time).
    #[inline(never)]
    fn poll_transmit_due(&mut self, now: Instant) -> Option<CanFrame> {
        let error_control_id = ErrorControlRepr::cob_id(self.node_id);
        // The frames of at most one byte (boot-up, SYNC, error control) are built in one place,
        // below; the others come whole from their service.
        let sync_producer = self.services().sync_period;
        let (id, byte, len) = if core::mem::take(&mut self.boot_up_due) {
            (error_control_id, ErrorControlRepr::BOOT_UP.emit(), 1)
        } else if let Some(sync) = sync_producer.then(|| self.sync.poll_transmit()).flatten() {
            sync
        } else {
            if self.state != NmtState::Stopped {
                if let Some(frame) = self.emcy.poll_transmit(now, self.services().emcy_inhibit) {
                    return Some(frame);
                }
            }
            if self.state == NmtState::Operational && self.tpdo_attention {
                if let Some(frame) = self.poll_tpdo(now) {
                    return Some(frame);
                }
            }
            let channels = self.sdo_channels();
            for channel in &mut self.sdo[..channels] {
                if let Some(frame) = channel.poll_transmit(now, &self.od) {
                    return Some(frame);
                }
            }
            (
                error_control_id,
                self.error_control.poll_transmit(self.state)?,
                1,
            )
        };
        Some(one_byte_frame(id, byte, len))
    }

    fn poll_tpdo(&mut self, now: Instant) -> Option<CanFrame> {
        for (n, tpdo) in self.tpdos.iter_mut().enumerate() {
            let event_timer = self.timers.slot(Timer::TpdoEvent(n));
            if let Some(frame) = tpdo.poll_transmit(&self.od, now, event_timer) {
                return Some(frame);
            }
        }
        // Whatever is still pending waits for an inhibit time; poll_timeout reports when.
        self.tpdo_attention = self.tpdos.iter().any(|t| t.pending());
        None
    }
}
