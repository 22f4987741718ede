//! What both ends of an AlarmCR keep of the acyclic transport for each priority (APMS/APMR of
//! IEC 61158-6-10, a window of one): the sequence numbers sent and expected, and the DATA PDU
//! waiting for its transport ACK with its retransmission timer ([`Pending`]). The device's
//! machine ([`super::alarm`]) and the controller's ([`super::controller_alarm`]) share it.

use edsgen_runtime::{Duration, Instant};

use super::wire::alarm::{SEQ_FIRST, SEQ_MASK, SEQ_NONE};

/// A DATA PDU sent and not acknowledged yet.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pending {
    /// The frame, to send again as it is.
    pub frame: Vec<u8>,
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

impl Pending {
    /// `frame` sent at `now`, with `retries` retransmissions allowed.
    pub fn new(frame: Vec<u8>, now: Instant, retries: u16) -> Pending {
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
    pub fn resend(&mut self, now: Instant) -> Vec<u8> {
        self.retries_left = self.retries_left.saturating_sub(1);
        self.sent_at = now;
        self.frame.clone()
    }
}

/// One priority's transport state.
#[derive(Debug, Clone)]
pub struct Transport {
    /// SendSeqNum of the next DATA PDU.
    pub send_seq: u16,
    /// SendSeqNum of the last DATA PDU acknowledged.
    pub send_seq_o: u16,
    /// The SendSeqNum expected next.
    pub exp_seq: u16,
    /// The SendSeqNum received last in sequence (what an AckSeqNum acknowledges).
    pub exp_seq_o: u16,
    /// The DATA PDU waiting for its ACK.
    pub pending: Option<Pending>,
}

impl Default for Transport {
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

impl Transport {
    /// APMS: a transport acknowledgement (an ACK, or a DATA's AckSeqNum) of the DATA sent.
    pub fn acknowledged(&mut self, ack_seq: u16) {
        if self.pending.is_some() && ack_seq == self.send_seq {
            self.send_seq_o = self.send_seq;
            self.send_seq = self.send_seq.wrapping_add(1) & SEQ_MASK;
            self.pending = None;
        }
    }

    /// APMR: the DATA PDU `send_seq` taken in sequence.
    pub fn received(&mut self) {
        self.exp_seq_o = self.exp_seq;
        self.exp_seq = self.exp_seq.wrapping_add(1) & SEQ_MASK;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pending_pdu_waits_its_timeout_then_is_resent_until_its_retries_are_over() {
        let timeout = Duration::from_millis(100);
        let mut pending = Pending::new(vec![1, 2], Instant::from_millis(0), 1);
        assert_eq!(pending.due(Instant::from_millis(99), timeout), Due::Wait);
        assert_eq!(pending.due(Instant::from_millis(100), timeout), Due::Resend);
        assert_eq!(pending.resend(Instant::from_millis(100)), vec![1, 2]);
        assert_eq!(pending.deadline(timeout), Instant::from_millis(200));
        assert_eq!(pending.due(Instant::from_millis(150), timeout), Due::Wait);
        assert_eq!(pending.due(Instant::from_millis(200), timeout), Due::GiveUp);
    }

    #[test]
    fn an_ack_of_the_pdu_sent_moves_the_sequence_on() {
        let mut t = Transport::default();
        t.acknowledged(SEQ_FIRST);
        assert_eq!(t.send_seq, SEQ_FIRST, "nothing was pending");
        t.pending = Some(Pending::new(vec![], Instant::from_millis(0), 3));
        t.acknowledged(SEQ_FIRST.wrapping_add(1) & SEQ_MASK);
        assert!(t.pending.is_some(), "another number acknowledges nothing");
        t.acknowledged(SEQ_FIRST);
        assert_eq!((t.send_seq_o, t.pending.is_none()), (SEQ_FIRST, true));
        t.received();
        assert_eq!(t.exp_seq_o, SEQ_FIRST);
    }
}
