//! The async master's LSS calls (CiA 305): [`AsyncMaster::lss`] and
//! [`AsyncMaster::lss_scan_all`] hand services to the driver thread, whose one [`LssMaster`]
//! ([`LssChannel`]) runs them one after the other beside the SDO clients.

use std::collections::VecDeque;
use std::future::Future;
use std::io;
use std::time::Duration as StdDuration;

use crate::Transport;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::master::lss::{
    LssMaster, LssOutcome, LssService, DEFAULT_TIMEOUT, FASTSCAN_TIMEOUT,
};
use edsgen_runtime::time::{Duration, Instant};
use edsgen_runtime::wire::lss::{LssAddress, LssMode};

use super::super::blocking::MasterError;
use super::driver::Request;
use super::slot::{pending, Reply};
use super::{to_duration, AsyncMaster};

/// An LSS service for the driver thread: the service, how long each of its probes waits for
/// silence, and the future to complete.
pub(super) struct LssJob {
    service: LssService,
    probe_timeout: Duration,
    reply: Reply<LssOutcome>,
}

impl AsyncMaster {
    /// Runs one LSS service with the default timeouts ([`DEFAULT_TIMEOUT`],
    /// [`FASTSCAN_TIMEOUT`]). Services run one after the other, in the order called; frames
    /// other than LSS answers that arrive meanwhile go to the master's other services as usual.
    pub async fn lss(&self, service: LssService) -> Result<LssOutcome, MasterError> {
        self.lss_probing(service, FASTSCAN_TIMEOUT).await
    }

    /// Fastscan, again and again: the address of every non-configured slave, one after the
    /// other, each probe waiting `probe_timeout` for silence. `found` is called with each as it
    /// is found, while that slave is in configuration (and the only one there); its future
    /// gives `true` if it gave the slave a node-ID, which the master then switches back to
    /// waiting (where an unconfigured slave takes the ID), or `false` to leave it in
    /// configuration, out of the next scans, until the end, when the master switches every
    /// slave back to waiting. Stops when no slave answers, or after 127. The LSS services of
    /// other tasks would run between the scan's: one task at a time should use LSS.
    pub async fn lss_scan_all<F, Found>(
        &self,
        probe_timeout: StdDuration,
        mut found: F,
    ) -> Result<Vec<LssAddress>, MasterError>
    where
        F: FnMut(LssAddress) -> Found,
        Found: Future<Output = Result<bool, MasterError>>,
    {
        let probe_timeout = to_duration(probe_timeout);
        let mut addresses = Vec::new();
        let mut left_in_configuration = false;
        let waiting = LssService::SwitchGlobal(LssMode::Waiting);
        while addresses.len() < 127 {
            let LssOutcome::Scanned(Some(address)) = self
                .lss_probing(LssService::Fastscan, probe_timeout)
                .await?
            else {
                break;
            };
            addresses.push(address);
            match found(address).await {
                Ok(true) => {
                    self.lss(waiting).await?;
                }
                Ok(false) => left_in_configuration = true,
                Err(e) => {
                    self.lss(waiting).await?;
                    return Err(e);
                }
            }
        }
        if left_in_configuration {
            self.lss(waiting).await?;
        }
        Ok(addresses)
    }

    async fn lss_probing(
        &self,
        service: LssService,
        probe_timeout: Duration,
    ) -> Result<LssOutcome, MasterError> {
        let (reply, pending) = pending();
        self.request(Request::Lss(LssJob {
            service,
            probe_timeout,
            reply,
        }))?;
        pending.await
    }
}

/// The driver thread's LSS master and the services waiting for it.
#[derive(Default)]
pub(super) struct LssChannel {
    master: LssMaster,
    current: Option<Reply<LssOutcome>>,
    queue: VecDeque<LssJob>,
}

impl LssChannel {
    pub(super) fn push(&mut self, job: LssJob) {
        self.queue.push_back(job);
    }

    /// Whether a service runs or waits.
    pub(super) fn is_busy(&self) -> bool {
        self.current.is_some() || !self.queue.is_empty()
    }

    /// When the LSS master next needs to run.
    pub(super) fn poll_timeout(&self) -> Option<Instant> {
        self.master.poll_timeout()
    }

    pub(super) fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        self.master.handle_frame(now, frame);
    }

    /// Starts the next service if none runs, runs the timeout if due, sends the master's frames
    /// and completes the service's future when it ends.
    pub(super) fn run<T: Transport>(&mut self, now: Instant, transport: &mut T) -> io::Result<()> {
        self.complete();
        if self.current.is_none() {
            if let Some(job) = self.queue.pop_front() {
                self.master.set_timeouts(DEFAULT_TIMEOUT, job.probe_timeout);
                match self.master.start(job.service) {
                    Ok(()) => self.current = Some(job.reply),
                    Err(e) => job.reply.send(Err(MasterError::Lss(e))),
                }
            }
        }
        if self.master.poll_timeout().is_some_and(|at| at <= now) {
            self.master.handle_timeout(now);
        }
        while let Some(frame) = self.master.poll_transmit(now) {
            transport.send(&frame)?;
        }
        self.complete();
        Ok(())
    }

    fn complete(&mut self) {
        if let Some(result) = self.master.poll_result() {
            if let Some(reply) = self.current.take() {
                reply.send(result.map_err(MasterError::Lss));
            }
        }
    }
}
