//! The device's side of one AR's AlarmCR (p-net's `pf_alarm`): the alarm protocol machines of
//! IEC 61158-6-10 for each priority, APMS/APMR (the acyclic transport, "RTA": DATA with TACK,
//! ACK, NACK, ERR, sequence numbers with a window of one, the retransmission timer) and ALPMI
//! (one alarm at a time until the controller's AlarmAck-PDU comes). Sans-IO: frames and time
//! in, frames and [`AlarmEvent`]s out; the wire format is [`super::wire::alarm`].
//!
//! The AlarmCRBlockReq of the Connect sets it up: the controller's LocalAlarmReference (our
//! AlarmDstEndpoint), the VLAN tag headers (priority 6 high, 5 low as controllers ask), the
//! retransmission timeout (RTATimeoutFactor × 100 ms) and RTARetries. A DATA PDU not
//! acknowledged after RTARetries retransmissions ends the AR (an ERR PDU to the controller,
//! PNIOStatus CF 81 FD 08), as does an ERR PDU from the controller or a DATA PDU in sequence
//! that carries neither an AlarmAck nor an AlarmNotification (ERR, FD 0B). A DATA PDU out of
//! sequence gets a NACK, a repeated one its ACK again. Frames for another endpoint, of another
//! RTA version, with a VarPartLen an ACK/NACK/ERR must not have, or not from the AR's
//! controller, are ignored. The controller's own alarm notifications are acknowledged at the
//! transport and otherwise ignored (a device has nothing to do with them).

use std::collections::VecDeque;

use edsgen_runtime::{Duration, Instant};

use super::rta::{Pending, Receipt, Transport};
use super::wire::alarm::*;
use super::wire::blocks::AlarmCrBlockReq;
use super::wire::rpc::PnioStatus;
use super::wire::Mac;

/// What happened on the AlarmCR.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AlarmEvent {
    /// The controller acknowledged the alarm sent last on its priority (AlarmAck-PDU): the
    /// AlarmAck's fields and PNIOStatus.
    Acknowledged(AlarmAck),
    /// The AlarmCR is over, and the AR with it: the PNIOStatus of the ERR PDU received or sent.
    Aborted(PnioStatus),
}

/// ErrorCode of an ERR-RTA-PDU.
pub const ERROR_CODE_RTA: u8 = 0xCF;
/// ErrorCode1: RTA error class "protocol".
pub const ERR_CLS_PROTOCOL: u8 = 0xFD;
/// ErrorCode2: an alarm was not acknowledged after the retries (AR alarm send.cnf(-)).
pub const ABORT_SEND_CNF_NEG: u8 = 0x08;
/// ErrorCode2: an alarm PDU the device cannot take (AR alarm.ind(err)).
pub const ABORT_ALARM_IND_ERROR: u8 = 0x0B;

/// One priority's machines.
#[derive(Debug, Clone)]
struct Apmx {
    high: bool,
    /// APMS/APMR: sequence numbers and the DATA PDU waiting for its ACK.
    rta: Transport,
    /// ALPMI: an alarm was sent and its AlarmAck has not come.
    awaiting_ack: bool,
    /// Alarms waiting for their turn.
    queue: VecDeque<AlarmNotification>,
    /// The next AlarmSpecifier sequence number.
    sequence: u16,
}

impl Apmx {
    fn new(high: bool) -> Apmx {
        Apmx {
            high,
            rta: Transport::default(),
            awaiting_ack: false,
            queue: VecDeque::new(),
            sequence: 0,
        }
    }
}

/// The device's AlarmCR of one AR.
#[derive(Debug, Clone)]
pub struct AlarmCr {
    device: Mac,
    controller: Mac,
    local_ref: u16,
    remote_ref: u16,
    /// The VLAN tag headers: low, high.
    tags: [u16; 2],
    timeout: Duration,
    retries: u16,
    /// Low, high.
    apmx: [Apmx; 2],
    /// AlarmCRProperties bit 0: every alarm goes with low priority.
    low_only: bool,
    outbox: VecDeque<Vec<u8>>,
    events: VecDeque<AlarmEvent>,
    closed: bool,
}

impl AlarmCr {
    /// The AlarmCR `req` asked for, between the device (`device`, its LocalAlarmReference
    /// `local_ref`) and the controller at `controller`.
    pub fn new(req: &AlarmCrBlockReq, local_ref: u16, device: Mac, controller: Mac) -> AlarmCr {
        AlarmCr {
            device,
            controller,
            local_ref,
            remote_ref: req.local_alarm_reference,
            tags: [req.tag_header_low, req.tag_header_high],
            timeout: Duration::from_millis(u64::from(req.rta_timeout_factor.max(1)) * 100),
            retries: req.rta_retries,
            apmx: [Apmx::new(false), Apmx::new(true)],
            low_only: req.properties & 1 != 0,
            outbox: VecDeque::new(),
            events: VecDeque::new(),
            closed: false,
        }
    }

    /// `true` once the AlarmCR is over (an ERR sent or received).
    pub fn closed(&self) -> bool {
        self.closed
    }

    /// Sends `alarm` on its priority at `now`, or queues it behind the alarm not acknowledged
    /// yet. The machine sets the AlarmSpecifier's sequence number (bits 0-10), and the low
    /// priority when the AlarmCRProperties ask for it only. Nothing happens once the AlarmCR is
    /// over.
    pub fn send(&mut self, now: Instant, mut alarm: AlarmNotification) {
        if self.closed {
            return;
        }
        alarm.high &= !self.low_only;
        let n = usize::from(alarm.high);
        self.apmx[n].queue.push_back(alarm);
        self.next_alarm(now, n);
    }

    /// The next frame to send.
    pub fn poll_frame(&mut self) -> Option<Vec<u8>> {
        self.outbox.pop_front()
    }

    /// The next event.
    pub fn poll_event(&mut self) -> Option<AlarmEvent> {
        self.events.pop_front()
    }

    /// When a DATA frame is due to be sent again (or its retries are over).
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.apmx
            .iter()
            .filter_map(|a| a.rta.poll_timeout(self.timeout))
            .min()
    }

    /// Time passed to `now`: unacknowledged DATA sent again, or the AR aborted after the last
    /// retry.
    pub fn handle_timeout(&mut self, now: Instant) {
        for n in 0..2 {
            match self.apmx[n].rta.handle_timeout(now, self.timeout) {
                Ok(resend) => self.outbox.extend(resend),
                Err(()) => {
                    self.abort(ABORT_SEND_CNF_NEG);
                    return;
                }
            }
        }
    }

    /// A received Ethernet frame at `now`: `true` when it was an alarm frame (FrameID 0xFC01
    /// or 0xFE01) of this AlarmCR's controller to the device, whatever became of it.
    pub fn handle_frame(&mut self, now: Instant, frame: &[u8]) -> bool {
        let Some(rta) = RtaFrame::parse(frame) else {
            return false;
        };
        if rta.eth.src != self.controller || rta.eth.dst != self.device {
            return false;
        }
        let h = rta.header;
        if self.closed
            || h.version != RTA_VERSION
            || h.dst != self.local_ref
            || h.src != self.remote_ref
        {
            return true;
        }
        let n = usize::from(rta.high());
        match h.pdu_type {
            PDU_ACK if rta.var_part.is_empty() => {
                self.apmx[n].rta.acknowledged(h.ack_seq);
                // An AlarmAck may have come before this ACK: the next alarm's turn.
                self.next_alarm(now, n);
            }
            PDU_ERR => {
                if let Ok(status) = <[u8; 4]>::try_from(rta.var_part) {
                    self.close(PnioStatus(status));
                }
            }
            PDU_DATA if h.add_flags & TACK != 0 => self.data(now, n, &h, rta.var_part),
            // NACK: the DATA is sent again when its timer expires; anything else is ignored.
            _ => {}
        }
        true
    }

    /// APMR: a DATA PDU asking for a transport ACK.
    fn data(&mut self, now: Instant, n: usize, h: &RtaHeader, var_part: &[u8]) {
        let apmx = &mut self.apmx[n];
        match apmx.rta.receive(h) {
            Receipt::Repeated => return self.transport(n, PDU_ACK),
            Receipt::OutOfSequence => return self.transport(n, PDU_NACK),
            Receipt::InSequence => {}
        }
        let ack = AlarmAck::parse(var_part).filter(|a| a.high == apmx.high);
        let notification = AlarmNotification::parse(var_part).filter(|a| a.high == apmx.high);
        if ack.is_none() && notification.is_none() {
            self.abort(ABORT_ALARM_IND_ERROR);
            return;
        }
        apmx.rta.take(h);
        self.transport(n, PDU_ACK);
        let apmx = &mut self.apmx[n];
        if let Some(ack) = ack {
            if apmx.awaiting_ack {
                apmx.awaiting_ack = false;
                self.events.push_back(AlarmEvent::Acknowledged(ack));
                self.next_alarm(now, n);
            }
        }
    }

    /// ALPMI: sends the next queued alarm when none is outstanding.
    fn next_alarm(&mut self, now: Instant, n: usize) {
        let apmx = &mut self.apmx[n];
        if apmx.awaiting_ack || apmx.rta.pending.is_some() {
            return;
        }
        let Some(mut alarm) = apmx.queue.pop_front() else {
            return;
        };
        alarm.source.specifier = (alarm.source.specifier & !SPEC_SEQUENCE) | apmx.sequence;
        apmx.sequence = (apmx.sequence + 1) & SPEC_SEQUENCE;
        let mut var_part = Vec::new();
        alarm.emit(&mut var_part);
        let header = apmx.rta.data_header((self.remote_ref, self.local_ref));
        let frame = self.frame(n, &header, &var_part);
        let apmx = &mut self.apmx[n];
        apmx.rta.pending = Some(Pending::new(frame.clone(), now, self.retries));
        apmx.awaiting_ack = true;
        self.outbox.push_back(frame);
    }

    /// Queues an ACK or NACK of priority `n`.
    fn transport(&mut self, n: usize, pdu_type: u8) {
        let header = self.apmx[n]
            .rta
            .transport_header((self.remote_ref, self.local_ref), pdu_type);
        let frame = self.frame(n, &header, &[]);
        self.outbox.push_back(frame);
    }

    /// Ends the AlarmCR from the device's side: an ERR PDU (low priority) with ErrorCode2
    /// `code2`, and [`AlarmEvent::Aborted`].
    pub fn abort(&mut self, code2: u8) {
        if self.closed {
            return;
        }
        let status = PnioStatus::new(
            ERROR_CODE_RTA,
            PnioStatus::DECODE_PNIO,
            ERR_CLS_PROTOCOL,
            code2,
        );
        let header = RtaHeader {
            dst: self.remote_ref,
            src: self.local_ref,
            pdu_type: PDU_ERR,
            version: RTA_VERSION,
            add_flags: WINDOW_1,
            send_seq: self.apmx[0].rta.send_seq,
            ack_seq: self.apmx[0].rta.exp_seq_o,
        };
        let frame = self.frame(0, &header, &status.0);
        self.outbox.push_back(frame);
        self.close(status);
    }

    fn close(&mut self, status: PnioStatus) {
        self.closed = true;
        for apmx in &mut self.apmx {
            apmx.rta.pending = None;
            apmx.queue.clear();
        }
        self.events.push_back(AlarmEvent::Aborted(status));
    }

    fn frame(&self, n: usize, header: &RtaHeader, var_part: &[u8]) -> Vec<u8> {
        let frame_id = if n == 1 { FRAME_ID_HIGH } else { FRAME_ID_LOW };
        emit_frame(
            self.controller,
            self.device,
            self.tags[n],
            frame_id,
            header,
            var_part,
        )
    }
}

#[cfg(test)]
mod tests;
