//! The blocking master's LSS calls (CiA 305): each runs one [`LssService`] of the sans-IO
//! [`LssMaster`] to its end; frames other than LSS answers that arrive meanwhile go to the
//! master's other services as usual.

use std::time::Duration as StdDuration;

use crate::master::lss::{LssMaster, LssOutcome, LssService};
use crate::transport::Transport;
use crate::wire::lss::{LssAddress, LssMode};

use super::{to_duration, Master, MasterError, MAX_WAIT};

impl<T: Transport> Master<T> {
    /// Runs one LSS service with the default timeouts
    /// ([`DEFAULT_TIMEOUT`](crate::master::lss::DEFAULT_TIMEOUT),
    /// [`FASTSCAN_TIMEOUT`](crate::master::lss::FASTSCAN_TIMEOUT)).
    pub fn lss(&mut self, service: LssService) -> Result<LssOutcome, MasterError> {
        self.lss_with(&mut LssMaster::new(), service)
    }

    /// Runs one LSS service on `lss` (whose timeouts apply).
    pub fn lss_with(
        &mut self,
        lss: &mut LssMaster,
        service: LssService,
    ) -> Result<LssOutcome, MasterError> {
        lss.start(service).map_err(MasterError::Lss)?;
        loop {
            let now = self.clock.now();
            if lss.poll_timeout().is_some_and(|at| at <= now) {
                lss.handle_timeout(now);
            }
            while let Some(frame) = lss.poll_transmit(now) {
                self.transport.send(&frame)?;
            }
            if let Some(result) = lss.poll_result() {
                return result.map_err(MasterError::Lss);
            }
            let wait = match lss.poll_timeout() {
                Some(at) => MAX_WAIT.min(StdDuration::from_micros(
                    at.saturating_since(now).as_micros(),
                )),
                None => MAX_WAIT,
            };
            if let Some(frame) = self.transport.recv_timeout(wait)? {
                lss.handle_frame(self.clock.now(), &frame);
                self.dispatch(&frame);
            }
        }
    }

    /// Fastscan, again and again: the address of every non-configured slave, one after the
    /// other. `assign` is called with each as it is found (the slave is in configuration
    /// then) and must take it out of the scan, by giving it a node-ID; the master switches
    /// it back to waiting afterwards. Stops when no slave answers, or after 127.
    pub fn lss_scan_all(
        &mut self,
        probe_timeout: StdDuration,
        mut assign: impl FnMut(&mut Self, LssAddress) -> Result<(), MasterError>,
    ) -> Result<Vec<LssAddress>, MasterError> {
        let mut lss = LssMaster::new();
        lss.set_timeouts(
            crate::master::lss::DEFAULT_TIMEOUT,
            to_duration(probe_timeout),
        );
        let mut found = Vec::new();
        while found.len() < 127 {
            match self.lss_with(&mut lss, LssService::Fastscan)? {
                LssOutcome::Scanned(Some(address)) => {
                    found.push(address);
                    let assigned = assign(self, address);
                    self.lss(LssService::SwitchGlobal(LssMode::Waiting))?;
                    assigned?;
                }
                _ => break,
            }
        }
        Ok(found)
    }
}
