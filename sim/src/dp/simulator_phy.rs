//! The DP slave on profirust's in-process simulated bus (`profirust::phy::SimulatorPhy`), in bus
//! time, for deterministic tests and the demo: a thin driver around the sans-IO [`DpSlave`], as
//! [`serial`](super::serial) is for a real line. It reads the bytes on the bus and answers a
//! complete telegram 11 bit times (the minimum Tsdr) after it ended; the simulator refuses an
//! earlier answer.

use edsgen_runtime::Instant;
use profirust::phy::{ProfibusPhy, SimulatorPhy};
use profirust::Baudrate;

use super::fdl::{self, FdlError};
use super::slave::{DpApplication, DpSlave};

/// A slave station on a [`SimulatorPhy`] (a `duplicate` of the master's).
pub struct SlaveStation<A: DpApplication> {
    phy: SimulatorPhy,
    baud: Baudrate,
    /// The slave, for a test or the demo to look at between polls.
    pub slave: DpSlave<A>,
    answer: Option<(profirust::time::Instant, Vec<u8>)>,
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
        if let Some((due, bytes)) = self.answer.take() {
            if now >= due {
                self.phy.transmit_data(now, |buf| {
                    buf[..bytes.len()].copy_from_slice(&bytes);
                    (bytes.len(), ())
                });
            } else {
                self.answer = Some((due, bytes));
            }
            return;
        }
        let slave = &mut self.slave;
        let answer = self
            .phy
            .receive_data(now, |pending| match fdl::parse(pending) {
                Ok((_, used)) => (used, slave.handle(at, &pending[..used])),
                Err(FdlError::Incomplete) => (0, None),
                Err(_) => (1, None),
            });
        if let Some(bytes) = answer {
            self.answer = Some((now + self.baud.bits_to_time(11), bytes));
        }
    }
}
