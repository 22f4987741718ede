//! The DP slave on profirust's in-process simulated bus (`profirust::phy::SimulatorPhy`), in bus
//! time, for deterministic tests and the demo: a thin driver around the sans-IO [`DpSlave`], as
//! [`serial`](super::serial) is for a real line. It reads the bytes on the bus and answers a
//! complete telegram 11 bit times (the minimum Tsdr) after it ended; the simulator refuses an
//! earlier answer.

use edsgen_runtime::dp::fdl::{self, FdlError, MAX_TELEGRAM_LEN};
use edsgen_runtime::dp::{DpApplication, DpSlave};
use edsgen_runtime::Instant;
use profirust::phy::{ProfibusPhy, SimulatorPhy};
use profirust::Baudrate;

/// A slave station on a [`SimulatorPhy`] (a `duplicate` of the master's).
pub struct SlaveStation<A: DpApplication> {
    phy: SimulatorPhy,
    baud: Baudrate,
    /// The slave, for a test or the demo to look at between polls.
    pub slave: DpSlave<A>,
    /// An answer waiting for its Tsdr: when it may go, its bytes and length.
    answer: Option<(profirust::time::Instant, [u8; MAX_TELEGRAM_LEN], usize)>,
}

impl<A: DpApplication> SlaveStation<A> {
    /// `slave` on `phy`, a bus running at `baud`.
    pub fn new(phy: SimulatorPhy, baud: Baudrate, slave: DpSlave<A>) -> Self {
        SlaveStation {
            phy,
            baud,
            slave,
            answer: None,
        }
    }

    /// Runs the slave at bus time `now`: its watchdog, a pending answer once its Tsdr has
    /// passed, or the next complete telegram on the bus.
    pub fn poll(&mut self, now: profirust::time::Instant) {
        let at = Instant::from_micros(u64::try_from(now.total_micros()).unwrap_or(0));
        self.slave.handle_timeout(at);
        if self.phy.poll_transmission(now) {
            return;
        }
        if let Some((due, bytes, len)) = self.answer.take() {
            if now >= due {
                self.phy.transmit_data(now, |buf| {
                    buf[..len].copy_from_slice(&bytes[..len]);
                    (len, ())
                });
            } else {
                self.answer = Some((due, bytes, len));
            }
            return;
        }
        let slave = &mut self.slave;
        self.phy
            .receive_data(now, |pending| match fdl::parse(pending) {
                Ok((_, used)) => {
                    slave.handle(at, &pending[..used]);
                    (used, ())
                }
                Err(FdlError::Incomplete) => (0, ()),
                Err(_) => (1, ()),
            });
        let mut bytes = [0u8; MAX_TELEGRAM_LEN];
        if let Some(len) = self.slave.poll_transmit(at, &mut bytes) {
            self.answer = Some((now + self.baud.bits_to_time(11), bytes, len));
        }
    }
}
