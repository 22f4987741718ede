//! What both ends of an AlarmCR keep of the acyclic transport for each priority (APMS/APMR of
//! IEC 61158-6-10, a window of one): the sequence numbers sent and expected ([`Transport`]),
//! the DATA PDU waiting for its transport ACK with its retransmission timer ([`Pending`]), and
//! what a received DATA PDU is to the receiver ([`Receipt`]). No clock reads and no heap: the
//! frame kept for retransmission is the caller's type (a `Vec<u8>` on a host, an index into a
//! frame pool on firmware).

use super::wire::alarm::{RtaHeader, PDU_DATA, RTA_VERSION, SEQ_FIRST, SEQ_MASK, SEQ_NONE};
use super::wire::alarm::{TACK, WINDOW_1};
use crate::{Duration, Instant};

/// A DATA PDU sent and not acknowledged yet.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pending<F> {
    /// The frame, to send again as it is.
    pub frame: F,
    /// When it was last sent.
    pub sent_at: Instant,
    /// Retransmissions left (RTARetries at first).
    pub retries_left: u16,
}

/// What a [`Pending`] DATA PDU asks for at a time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Due {
    /// Its timeout passed and retries are left: send it again.
    Resend,
    /// Its timeout passed after the last retry: the AlarmCR is over.
    GiveUp,
    /// Its timeout has not passed.
    Wait,
}

impl<F: Clone> Pending<F> {
    /// `frame` sent at `now`, with `retries` retransmissions allowed.
    pub fn new(frame: F, now: Instant, retries: u16) -> Pending<F> {
        Pending {
            frame,
            sent_at: now,
            retries_left: retries,
        }
    }

    /// When its timeout (`timeout` after the last send) passes.
    pub fn deadline(&self, timeout: Duration) -> Instant {
        self.sent_at + timeout
    }

    /// What is due at `now` with the retransmission timeout `timeout`.
    pub fn due(&self, now: Instant, timeout: Duration) -> Due {
        if now < self.deadline(timeout) {
            Due::Wait
        } else if self.retries_left == 0 {
            Due::GiveUp
        } else {
            Due::Resend
        }
    }

    /// Counts one retransmission at `now`: the frame to send again.
    pub fn resend(&mut self, now: Instant) -> F {
        self.retries_left = self.retries_left.saturating_sub(1);
        self.sent_at = now;
        self.frame.clone()
    }
}

/// What a DATA PDU asking for a transport ACK is to the receiving side (APMR).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Receipt {
    /// The one taken last, again (its ACK was lost): its AckSeqNum is taken; answer with an ACK.
    Repeated,
    /// Neither the one expected nor the last: answer with a NACK.
    OutOfSequence,
    /// The one expected: the receiver judges its content, then takes it ([`Transport::take`])
    /// and answers with an ACK, or ends the AlarmCR.
    InSequence,
}

/// One priority's transport state.
#[derive(Debug, Clone)]
pub struct Transport<F> {
    /// SendSeqNum of the next DATA PDU.
    pub send_seq: u16,
    /// SendSeqNum of the last DATA PDU acknowledged.
    pub send_seq_o: u16,
    /// The SendSeqNum expected next.
    pub exp_seq: u16,
    /// The SendSeqNum received last in sequence (what an AckSeqNum acknowledges).
    pub exp_seq_o: u16,
    /// The DATA PDU waiting for its ACK.
    pub pending: Option<Pending<F>>,
}

impl<F> Default for Transport<F> {
    fn default() -> Self {
        Transport {
            send_seq: SEQ_FIRST,
            send_seq_o: SEQ_NONE,
            exp_seq: SEQ_FIRST,
            exp_seq_o: SEQ_NONE,
            pending: None,
        }
    }
}

impl<F: Clone> Transport<F> {
    /// APMS: a transport acknowledgement (an ACK, or a DATA's AckSeqNum) of the DATA sent.
    pub fn acknowledged(&mut self, ack_seq: u16) {
        if self.pending.is_some() && ack_seq == self.send_seq {
            self.send_seq_o = self.send_seq;
            self.send_seq = self.send_seq.wrapping_add(1) & SEQ_MASK;
            self.pending = None;
        }
    }

    /// APMR: the DATA PDU `exp_seq` taken in sequence.
    pub fn received(&mut self) {
        self.exp_seq_o = self.exp_seq;
        self.exp_seq = self.exp_seq.wrapping_add(1) & SEQ_MASK;
    }

    /// APMR: a DATA PDU with header `h` that asks for a transport ACK. A repetition's
    /// AckSeqNum is taken at once; one in sequence waits for [`Transport::take`].
    pub fn receive(&mut self, h: &RtaHeader) -> Receipt {
        if h.send_seq == self.exp_seq_o {
            self.acknowledged(h.ack_seq);
            Receipt::Repeated
        } else if h.send_seq != self.exp_seq {
            Receipt::OutOfSequence
        } else {
            Receipt::InSequence
        }
    }

    /// APMR: the DATA PDU in sequence with header `h` taken: its AckSeqNum acknowledges what
    /// was sent, and the next one is expected.
    pub fn take(&mut self, h: &RtaHeader) {
        self.acknowledged(h.ack_seq);
        self.received();
    }

    /// The header of an ACK or NACK (`pdu_type`) from `src` to `dst` (AlarmEndpoints).
    pub fn transport_header(&self, (dst, src): (u16, u16), pdu_type: u8) -> RtaHeader {
        RtaHeader {
            dst,
            src,
            pdu_type,
            version: RTA_VERSION,
            add_flags: WINDOW_1,
            send_seq: self.send_seq_o,
            ack_seq: self.exp_seq_o,
        }
    }

    /// The header of the next DATA PDU from `src` to `dst`, asking for a transport ACK.
    pub fn data_header(&self, (dst, src): (u16, u16)) -> RtaHeader {
        RtaHeader {
            dst,
            src,
            pdu_type: PDU_DATA,
            version: RTA_VERSION,
            add_flags: WINDOW_1 | TACK,
            send_seq: self.send_seq,
            ack_seq: self.exp_seq_o,
        }
    }

    /// When the pending DATA PDU is due to be sent again (or its retries are over).
    pub fn poll_timeout(&self, timeout: Duration) -> Option<Instant> {
        self.pending.as_ref().map(|p| p.deadline(timeout))
    }

    /// Time passed to `now`: the frame to send again when its timeout passed with retries
    /// left (`Ok(Some)`), `Err(())` when it passed after the last retry (the AlarmCR is over).
    #[allow(clippy::result_unit_err)]
    pub fn handle_timeout(&mut self, now: Instant, timeout: Duration) -> Result<Option<F>, ()> {
        let Some(pending) = self.pending.as_mut() else {
            return Ok(None);
        };
        match pending.due(now, timeout) {
            Due::Wait => Ok(None),
            Due::GiveUp => Err(()),
            Due::Resend => Ok(Some(pending.resend(now))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::wire::alarm::{PDU_ACK, PDU_NACK};
    use super::*;

    fn data(send_seq: u16, ack_seq: u16) -> RtaHeader {
        RtaHeader {
            dst: 1,
            src: 2,
            pdu_type: PDU_DATA,
            version: RTA_VERSION,
            add_flags: WINDOW_1 | TACK,
            send_seq,
            ack_seq,
        }
    }

    #[test]
    fn a_pending_pdu_waits_its_timeout_then_is_resent_until_its_retries_are_over() {
        let timeout = Duration::from_millis(100);
        let mut pending = Pending::new([1, 2], Instant::from_millis(0), 1);
        assert_eq!(pending.due(Instant::from_millis(99), timeout), Due::Wait);
        assert_eq!(pending.due(Instant::from_millis(100), timeout), Due::Resend);
        assert_eq!(pending.resend(Instant::from_millis(100)), [1, 2]);
        assert_eq!(pending.deadline(timeout), Instant::from_millis(200));
        assert_eq!(pending.due(Instant::from_millis(150), timeout), Due::Wait);
        assert_eq!(pending.due(Instant::from_millis(200), timeout), Due::GiveUp);
    }

    #[test]
    fn the_transports_timeout_resends_then_gives_up() {
        let timeout = Duration::from_millis(100);
        let mut t = Transport::default();
        assert_eq!(
            t.handle_timeout(Instant::from_millis(500), timeout),
            Ok(None)
        );
        t.pending = Some(Pending::new(7u8, Instant::from_millis(0), 1));
        assert_eq!(t.poll_timeout(timeout), Some(Instant::from_millis(100)));
        assert_eq!(
            t.handle_timeout(Instant::from_millis(99), timeout),
            Ok(None)
        );
        assert_eq!(
            t.handle_timeout(Instant::from_millis(100), timeout),
            Ok(Some(7))
        );
        assert_eq!(
            t.handle_timeout(Instant::from_millis(200), timeout),
            Err(())
        );
    }

    #[test]
    fn an_ack_of_the_pdu_sent_moves_the_sequence_on() {
        let mut t = Transport::default();
        t.acknowledged(SEQ_FIRST);
        assert_eq!(t.send_seq, SEQ_FIRST, "nothing was pending");
        t.pending = Some(Pending::new([0u8; 0], Instant::from_millis(0), 3));
        t.acknowledged(SEQ_FIRST.wrapping_add(1) & SEQ_MASK);
        assert!(t.pending.is_some(), "another number acknowledges nothing");
        t.acknowledged(SEQ_FIRST);
        assert_eq!((t.send_seq_o, t.pending.is_none()), (SEQ_FIRST, true));
        t.received();
        assert_eq!(t.exp_seq_o, SEQ_FIRST);
    }

    #[test]
    fn a_data_pdu_is_in_sequence_repeated_or_out_of_sequence() {
        let mut t: Transport<()> = Transport::default();
        assert_eq!(t.receive(&data(1, SEQ_NONE)), Receipt::OutOfSequence);
        let first = data(SEQ_FIRST, SEQ_NONE);
        assert_eq!(t.receive(&first), Receipt::InSequence);
        assert_eq!(t.exp_seq, SEQ_FIRST, "nothing taken before take");
        t.take(&first);
        assert_eq!((t.exp_seq_o, t.exp_seq), (SEQ_FIRST, 0));
        t.pending = Some(Pending::new((), Instant::from_millis(0), 1));
        assert_eq!(t.receive(&data(SEQ_FIRST, SEQ_FIRST)), Receipt::Repeated);
        assert!(t.pending.is_none(), "a repetition's AckSeqNum is taken");
        let ack = t.transport_header((1, 2), PDU_ACK);
        assert_eq!(
            (ack.send_seq, ack.ack_seq, ack.add_flags),
            (SEQ_FIRST, SEQ_FIRST, 1)
        );
        let nack = t.transport_header((1, 2), PDU_NACK);
        assert_eq!((nack.pdu_type, nack.dst, nack.src), (PDU_NACK, 1, 2));
        let next = t.data_header((1, 2));
        assert_eq!(
            (next.send_seq, next.ack_seq, next.add_flags),
            (0, SEQ_FIRST, 0x11)
        );
    }
}
