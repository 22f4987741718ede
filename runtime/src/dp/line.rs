//! The receiving side of a PROFIBUS line, sans-IO, no_std and allocation-free: bytes in with the
//! time they arrived ([`LineReceiver::receive`]), whole telegrams out, under FDL's
//! synchronisation rule (IEC 61158-4-3): a receiver takes a start delimiter only after the line
//! was idle for the synchronisation time Tsyn (33 bit times), so after a telegram that does not
//! check (bad delimiter, length, FCS or end) it drops every byte until the line goes idle, and an
//! idle line ends whatever telegram was being received (a header announcing 249 bytes and then
//! silence is forgotten, not filled with the next requests).

use super::fdl::{FdlError, Telegram, MAX_TELEGRAM_LEN};
use crate::{Duration, Instant};

/// Bit times of idle line that synchronise a receiver (Tsyn).
pub const SYN_BITS: u64 = 33;

/// Tsyn at `baud` bits per second (at least one microsecond).
pub fn syn_time(baud: u32) -> Duration {
    Duration::from_micros((SYN_BITS * 1_000_000 / u64::from(baud.max(1))).max(1))
}

/// The receiver (see the module comment).
#[derive(Debug, Clone)]
pub struct LineReceiver {
    idle: Duration,
    buffer: [u8; MAX_TELEGRAM_LEN],
    len: usize,
    last_byte: Option<Instant>,
    synchronised: bool,
}

impl LineReceiver {
    /// A receiver that takes a gap of `idle` or more between bytes as an idle line (Tsyn on a
    /// UART that timestamps each byte; longer where bytes arrive in chunks).
    pub fn new(idle: Duration) -> Self {
        LineReceiver {
            idle,
            buffer: [0; MAX_TELEGRAM_LEN],
            len: 0,
            last_byte: None,
            // A line just opened counts as idle.
            synchronised: true,
        }
    }

    /// Whether the receiver takes a start delimiter now (false from a bad telegram until the
    /// line goes idle).
    pub fn is_synchronised(&self) -> bool {
        self.synchronised
    }

    /// Bytes that arrived together at `now`; `on_telegram` gets each whole telegram that
    /// checks, in order.
    pub fn receive(&mut self, now: Instant, bytes: &[u8], mut on_telegram: impl FnMut(&[u8])) {
        if bytes.is_empty() {
            return;
        }
        if self.last_byte.is_some_and(|last| now >= last + self.idle) {
            self.len = 0;
            self.synchronised = true;
        }
        self.last_byte = Some(now);
        for &byte in bytes {
            if !self.synchronised {
                continue;
            }
            self.buffer[self.len] = byte;
            self.len += 1;
            match Telegram::new_checked(&self.buffer[..self.len]) {
                Ok(telegram) if telegram.len() == self.len => {
                    self.len = 0;
                    on_telegram(&self.buffer[..telegram.len()]);
                }
                Err(FdlError::Incomplete) if self.len < MAX_TELEGRAM_LEN => {}
                // A telegram that does not check (or one shorter than what was taken, which
                // `new_checked` never returns): wait for the line to go idle.
                _ => {
                    self.len = 0;
                    self.synchronised = false;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(ms: u64) -> Instant {
        Instant::from_micros(ms * 1000)
    }

    fn received(r: &mut LineReceiver, now: Instant, bytes: &[u8]) -> [usize; 4] {
        let mut seen = [0; 4];
        let mut n = 0;
        r.receive(now, bytes, |t| {
            seen[n.min(3)] = t.len();
            n += 1;
        });
        seen
    }

    /// FDL status request to station 2 from 1: 10 02 01 49 4C 16.
    const STATUS: [u8; 6] = [0x10, 0x02, 0x01, 0x49, 0x4C, 0x16];

    #[test]
    fn a_header_then_silence_is_forgotten_when_the_line_goes_idle() {
        let mut r = LineReceiver::new(Duration::from_millis(2));
        // SD2 announcing 249 bytes, then nothing.
        assert_eq!(received(&mut r, at(0), &[0x68, 0xF9, 0xF9, 0x68]), [0; 4]);
        // Within Tsyn the bytes belong to the long telegram.
        assert_eq!(received(&mut r, at(1), &STATUS), [0; 4]);
        // After an idle line the next request is a telegram of its own.
        assert_eq!(received(&mut r, at(4), &STATUS), [6, 0, 0, 0]);
        assert_eq!(received(&mut r, at(5), &STATUS), [6, 0, 0, 0]);
    }

    #[test]
    fn after_a_bad_telegram_nothing_counts_until_the_line_goes_idle() {
        let mut r = LineReceiver::new(Duration::from_millis(2));
        // A bad FCS, then (no idle) a request: dropped, as is one inside garbage.
        let mut bytes = vec![0x10, 0x02, 0x01, 0x49, 0x4D, 0x16];
        bytes.extend_from_slice(&STATUS);
        assert_eq!(received(&mut r, at(0), &bytes), [0; 4]);
        assert!(!r.is_synchronised());
        assert_eq!(received(&mut r, at(1), &STATUS), [0; 4]);
        assert_eq!(received(&mut r, at(3), &STATUS), [6, 0, 0, 0]);
        assert!(r.is_synchronised());
    }

    #[test]
    fn telegrams_back_to_back_and_split_across_chunks() {
        let mut r = LineReceiver::new(Duration::from_millis(2));
        let mut two = STATUS.to_vec();
        two.extend_from_slice(&[0xE5]);
        assert_eq!(received(&mut r, at(0), &two), [6, 1, 0, 0]);
        assert_eq!(received(&mut r, at(10), &STATUS[..3]), [0; 4]);
        assert_eq!(received(&mut r, at(11), &STATUS[3..]), [6, 0, 0, 0]);
    }

    #[test]
    fn syn_time_is_33_bit_times() {
        assert_eq!(syn_time(19_200), Duration::from_micros(1718));
        assert_eq!(syn_time(12_000_000), Duration::from_micros(2));
        assert_eq!(syn_time(0), Duration::from_micros(33_000_000));
    }
}
