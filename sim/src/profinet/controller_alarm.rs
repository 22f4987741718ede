//! The IO controller's side of one AR's AlarmCR: it takes the device's alarms (DATA PDUs in
//! sequence get their transport ACK, a repeated one its ACK again), reports each
//! AlarmNotification, and acknowledges it with an AlarmAck-PDU (PNIOStatus zero) in a DATA PDU
//! of its own, sent again every RTA timeout until the device's ACK comes, RTARetries times.
//! An ERR PDU from the device, or an AlarmAck never acknowledged, ends it. Sans-IO: frames and
//! time in, frames and [`ControllerAlarmEvent`]s out; the wire format is [`super::wire::alarm`].

use std::collections::VecDeque;

use edsgen_runtime::{Duration, Instant};

use super::rta::{Pending, Receipt, Transport};
use super::wire::alarm::*;
use super::wire::blocks::AlarmCrBlockReq;
use super::wire::rpc::PnioStatus;
use super::wire::Mac;

/// What happened on the controller's AlarmCR.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ControllerAlarmEvent {
    /// The device sent an alarm; its AlarmAck is on its way.
    Alarm(AlarmNotification),
    /// The AlarmCR (and the AR) is over: the ERR PDU's PNIOStatus, or none when the device
    /// never acknowledged an AlarmAck.
    Aborted(Option<PnioStatus>),
}

/// One priority's transport and the AlarmAcks waiting.
#[derive(Debug, Clone, Default)]
struct Priority {
    /// APMS/APMR: sequence numbers and the DATA PDU waiting for its ACK.
    rta: Transport,
    /// AlarmAcks waiting for the one before to be acknowledged.
    queue: VecDeque<AlarmAck>,
}

/// The controller's AlarmCR of one AR.
#[derive(Debug, Clone)]
pub struct ControllerAlarms {
    controller: Mac,
    device: Mac,
    local_ref: u16,
    remote_ref: u16,
    /// The VLAN tag headers: low, high.
    tags: [u16; 2],
    timeout: Duration,
    retries: u16,
    /// Low, high.
    priorities: [Priority; 2],
    outbox: VecDeque<Vec<u8>>,
    events: VecDeque<ControllerAlarmEvent>,
    closed: bool,
}

impl ControllerAlarms {
    /// The AlarmCR the controller (`controller`) asked for with `req`, with the device at
    /// `device` whose LocalAlarmReference is `device_ref`.
    pub fn new(req: &AlarmCrBlockReq, device_ref: u16, controller: Mac, device: Mac) -> Self {
        ControllerAlarms {
            controller,
            device,
            local_ref: req.local_alarm_reference,
            remote_ref: device_ref,
            tags: [req.tag_header_low, req.tag_header_high],
            timeout: Duration::from_millis(u64::from(req.rta_timeout_factor.max(1)) * 100),
            retries: req.rta_retries,
            priorities: [Priority::default(), Priority::default()],
            outbox: VecDeque::new(),
            events: VecDeque::new(),
            closed: false,
        }
    }

    /// The next frame to send.
    pub fn poll_frame(&mut self) -> Option<Vec<u8>> {
        self.outbox.pop_front()
    }

    /// The next event.
    pub fn poll_event(&mut self) -> Option<ControllerAlarmEvent> {
        self.events.pop_front()
    }

    /// When an AlarmAck is due to be sent again (or its retries are over).
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.priorities
            .iter()
            .filter_map(|p| p.rta.poll_timeout(self.timeout))
            .min()
    }

    /// Time passed to `now`: an unacknowledged AlarmAck sent again, or the AlarmCR over after
    /// the last retry.
    pub fn handle_timeout(&mut self, now: Instant) {
        for n in 0..2 {
            match self.priorities[n].rta.handle_timeout(now, self.timeout) {
                Ok(resend) => self.outbox.extend(resend),
                Err(()) => {
                    self.close(None);
                    return;
                }
            }
        }
    }

    /// A received Ethernet frame at `now`: `true` when it was an alarm frame of this AlarmCR's
    /// device to the controller.
    pub fn handle_frame(&mut self, now: Instant, frame: &[u8]) -> bool {
        let Some(rta) = RtaFrame::parse(frame) else {
            return false;
        };
        if rta.eth.src != self.device || rta.eth.dst != self.controller {
            return false;
        }
        let h = rta.header;
        if self.closed || h.dst != self.local_ref || h.src != self.remote_ref {
            return true;
        }
        let n = usize::from(rta.high());
        match h.pdu_type {
            PDU_ACK => {
                self.priorities[n].rta.acknowledged(h.ack_seq);
                self.next_ack(now, n);
            }
            PDU_ERR => {
                let status = <[u8; 4]>::try_from(rta.var_part).ok().map(PnioStatus);
                self.close(status);
            }
            PDU_DATA => self.data(now, n, &h, rta.var_part),
            _ => {}
        }
        true
    }

    fn data(&mut self, now: Instant, n: usize, h: &RtaHeader, var_part: &[u8]) {
        let rta = &mut self.priorities[n].rta;
        match rta.receive(h) {
            Receipt::Repeated => return self.transport(n, PDU_ACK),
            Receipt::OutOfSequence => return self.transport(n, PDU_NACK),
            Receipt::InSequence => rta.take(h),
        }
        self.transport(n, PDU_ACK);
        if let Some(alarm) = AlarmNotification::parse(var_part) {
            self.priorities[n].queue.push_back(AlarmAck {
                high: alarm.high,
                source: alarm.source,
                status: PnioStatus::OK,
            });
            self.events.push_back(ControllerAlarmEvent::Alarm(alarm));
        }
        self.next_ack(now, n);
    }

    /// Sends the next AlarmAck of priority `n` when none is waiting for its ACK.
    fn next_ack(&mut self, now: Instant, n: usize) {
        let p = &mut self.priorities[n];
        if p.rta.pending.is_some() {
            return;
        }
        let Some(ack) = p.queue.pop_front() else {
            return;
        };
        let mut var_part = Vec::new();
        append_ack(&mut var_part, &ack);
        let header = p.rta.data_header((self.remote_ref, self.local_ref));
        let frame = self.frame(n, &header, &var_part);
        self.priorities[n].rta.pending = Some(Pending::new(frame.clone(), now, self.retries));
        self.outbox.push_back(frame);
    }

    fn transport(&mut self, n: usize, pdu_type: u8) {
        let header = self.priorities[n]
            .rta
            .transport_header((self.remote_ref, self.local_ref), pdu_type);
        let frame = self.frame(n, &header, &[]);
        self.outbox.push_back(frame);
    }

    fn close(&mut self, status: Option<PnioStatus>) {
        if self.closed {
            return;
        }
        self.closed = true;
        for p in &mut self.priorities {
            p.rta.pending = None;
            p.queue.clear();
        }
        self.events.push_back(ControllerAlarmEvent::Aborted(status));
    }

    fn frame(&self, n: usize, header: &RtaHeader, var_part: &[u8]) -> Vec<u8> {
        let frame_id = if n == 1 { FRAME_ID_HIGH } else { FRAME_ID_LOW };
        emit_frame(
            self.device,
            self.controller,
            self.tags[n],
            frame_id,
            header,
            var_part,
        )
    }
}
