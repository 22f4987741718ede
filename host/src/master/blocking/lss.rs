//! The blocking master's LSS calls (CiA 305): each runs one [`LssService`] of the sans-IO
//! [`LssMaster`] to its end; frames other than LSS answers that arrive meanwhile go to the
//! master's other services as usual.

use std::time::Duration as StdDuration;

use crate::Transport;
use edsgen_runtime::master::lss::{LssMaster, LssOutcome, LssService};
use edsgen_runtime::wire::lss::{LssAddress, LssMode};

use super::{to_duration, Master, MasterError, MAX_WAIT};

impl<T: Transport> Master<T> {
    /// Runs one LSS service with the default timeouts
    /// ([`DEFAULT_TIMEOUT`](edsgen_runtime::master::lss::DEFAULT_TIMEOUT),
    /// [`FASTSCAN_TIMEOUT`](edsgen_runtime::master::lss::FASTSCAN_TIMEOUT)).
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
    /// other. `found` is called with each as it is found, while that slave is in configuration
    /// (and the only one there): it returns `true` if it gave the slave a node-ID, which the
    /// master then switches back to waiting (where an unconfigured slave takes the ID), or
    /// `false` to leave it in configuration, out of the next scans, until the end, when the
    /// master switches every slave back to waiting. Stops when no slave answers, or after 127.
    pub fn lss_scan_all(
        &mut self,
        probe_timeout: StdDuration,
        mut found: impl FnMut(&mut Self, LssAddress) -> Result<bool, MasterError>,
    ) -> Result<Vec<LssAddress>, MasterError> {
        let mut lss = LssMaster::new();
        lss.set_timeouts(
            edsgen_runtime::master::lss::DEFAULT_TIMEOUT,
            to_duration(probe_timeout),
        );
        let mut addresses = Vec::new();
        let mut left_in_configuration = false;
        let waiting = LssService::SwitchGlobal(LssMode::Waiting);
        while addresses.len() < 127 {
            let LssOutcome::Scanned(Some(address)) =
                self.lss_with(&mut lss, LssService::Fastscan)?
            else {
                break;
            };
            addresses.push(address);
            match found(self, address) {
                Ok(true) => {
                    self.lss(waiting)?;
                }
                Ok(false) => left_in_configuration = true,
                Err(e) => {
                    self.lss(waiting)?;
                    return Err(e);
                }
            }
        }
        if left_in_configuration {
            self.lss(waiting)?;
        }
        Ok(addresses)
    }
}
