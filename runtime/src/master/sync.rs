//! The SYNC producer: a SYNC message (80h) every communication cycle period, with the counter
//! 1..=overflow when a synchronous counter overflow value is set (CiA 301 §7.2.5).

use crate::frame::CanFrame;
use crate::time::{Duration, Instant};
use crate::wire::sync::SyncRepr;

/// The COB-ID of SYNC.
pub const SYNC_COB_ID: u16 = 0x080;

/// Produces SYNC every `period` from its start instant.
#[derive(Debug, Clone, Copy)]
pub struct SyncProducer {
    period: Duration,
    overflow: u8,
    counter: u8,
    next: Option<Instant>,
    due: bool,
}

impl SyncProducer {
    /// A producer of SYNC every `period` without counter (overflow 0) or with a counter from 1
    /// to `overflow` (2..=240; other values mean no counter), stopped until [`start`](Self::start).
    pub const fn new(period: Duration, overflow: u8) -> Self {
        let overflow = if overflow >= 2 && overflow <= 240 {
            overflow
        } else {
            0
        };
        SyncProducer {
            period,
            overflow,
            counter: 0,
            next: None,
            due: false,
        }
    }

    /// Sends the first SYNC at `now` and every period after it.
    pub fn start(&mut self, now: Instant) {
        if self.period.as_micros() > 0 {
            self.next = Some(now);
            self.counter = 0;
        }
    }

    /// Stops producing.
    pub fn stop(&mut self) {
        self.next = None;
        self.due = false;
    }

    /// When the next SYNC is due.
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.next
    }

    /// Makes the SYNC due at `now` ready to send.
    pub fn handle_timeout(&mut self, now: Instant) {
        if let Some(at) = self.next.filter(|at| *at <= now) {
            self.due = true;
            self.next = Some(at + self.period);
        }
    }

    /// The SYNC frame, when one is due.
    pub fn poll_transmit(&mut self, _now: Instant) -> Option<CanFrame> {
        if !core::mem::take(&mut self.due) {
            return None;
        }
        let counter = (self.overflow != 0).then(|| {
            self.counter = if self.counter >= self.overflow {
                1
            } else {
                self.counter + 1
            };
            self.counter
        });
        let (data, len) = SyncRepr { counter }.emit();
        CanFrame::new(SYNC_COB_ID, &data[..len])
    }
}
