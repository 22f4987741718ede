//! The blocking master's NMT and monitoring: commands, watching nodes, waiting for boot-up,
//! identity checks, booting a node, scanning the bus and listening for events.

use std::io;
use std::time::Duration as StdDuration;

use crate::Transport;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::master::identity::{ExpectedIdentity, IdentityMismatch, IDENTITY_ENTRIES};
use edsgen_runtime::master::nmt::{nmt_frame, Watch, WatchError};
use edsgen_runtime::master::sdo_client::{Mode, SdoError};
use edsgen_runtime::wire::heartbeat::{ErrorControlRepr, NmtState};
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::wire::sdo::Multiplexer;

use super::{to_duration, Master, MasterError, MasterEvent};

impl<T: Transport> Master<T> {
    /// Sends an NMT command to `node_id` (0: all nodes).
    pub fn nmt(&mut self, command: NmtCommand, node_id: u8) -> Result<(), MasterError> {
        if node_id > 127 {
            return Err(MasterError::NodeId(node_id));
        }
        self.transport.send(&nmt_frame(command, node_id))?;
        Ok(())
    }

    /// Watches `node_id` by heartbeat or guarding; its events come from
    /// [`poll_event`](Self::poll_event).
    pub fn watch(&mut self, node_id: u8, watch: Watch) -> Result<(), MasterError> {
        let now = self.clock.now();
        self.monitor
            .watch(now, node_id, watch)
            .map_err(|e| match e {
                WatchError::Full | WatchError::Invalid => MasterError::NodeId(node_id),
            })
    }

    /// Waits until `node_id` sends its boot-up message, at most `timeout`. A boot-up received
    /// earlier and not yet taken as an event counts.
    pub fn wait_for_boot(&mut self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        let is_boot = |e: &MasterEvent| *e == MasterEvent::BootUp(node_id);
        let deadline = self.clock.now() + to_duration(timeout);
        loop {
            if let Some(i) = self.events.iter().position(is_boot) {
                self.events.remove(i);
                return Ok(());
            }
            let now = self.clock.now();
            if now >= deadline {
                return Err(MasterError::Timeout);
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
    }

    /// The boot-up check: reads 1000h and 1018h:1–4 where `expected` names a value and
    /// returns each difference (also queued as a [`MasterEvent::IdentityMismatch`]). A read
    /// that fails with an abort is a mismatch; a transport error is an error.
    pub fn check_identity(
        &mut self,
        node_id: u8,
        expected: &ExpectedIdentity,
    ) -> Result<Vec<IdentityMismatch>, MasterError> {
        let mut mismatches = Vec::new();
        for (entry, expected) in IDENTITY_ENTRIES.into_iter().zip(expected.expected()) {
            let Some(expected) = expected else {
                continue;
            };
            let (actual, abort) = match self.read(node_id, entry) {
                Ok(value) if value == expected => continue,
                Ok(value) => (Some(value), None),
                Err(MasterError::Sdo { error, .. }) => (None, Some(error.code())),
                Err(MasterError::Length { .. }) => (None, None),
                Err(e) => return Err(e),
            };
            let mismatch = IdentityMismatch {
                node_id,
                entry,
                expected,
                actual,
                abort,
            };
            self.events
                .push_back(MasterEvent::IdentityMismatch(mismatch));
            mismatches.push(mismatch);
        }
        Ok(mismatches)
    }

    /// Boots a node as a CiA 302 master would, in spirit: waits for its boot-up (at most
    /// `timeout`), checks its identity, downloads `configuration` (a DCF's values, see
    /// [`download_configuration`](Self::download_configuration)) and starts it. A node whose
    /// identity differs is neither configured nor started: the mismatches are returned (and
    /// queued as events); an empty list means the node runs.
    pub fn boot_node<V: AsRef<[u8]>>(
        &mut self,
        node_id: u8,
        expected: &ExpectedIdentity,
        configuration: &[(Multiplexer, V)],
        timeout: StdDuration,
    ) -> Result<Vec<IdentityMismatch>, MasterError> {
        self.wait_for_boot(node_id, timeout)?;
        let mismatches = self.check_identity(node_id, expected)?;
        if mismatches.is_empty() {
            self.download_configuration(node_id, configuration)?;
            self.nmt(NmtCommand::Start, node_id)?;
        }
        Ok(mismatches)
    }

    /// Finds the nodes on the bus: an SDO upload of 1000h to every node-ID 1..=127 at once (one
    /// channel each), and the node-IDs that answered within `timeout` (with a value or an
    /// abort), in order. Node-IDs that stay silent are not sent an abort.
    pub fn scan(&mut self, timeout: StdDuration) -> Result<Vec<u8>, MasterError> {
        let now = self.clock.now();
        for node_id in 1..=127 {
            let client = self.client(node_id)?;
            if client
                .upload(now, Multiplexer::new(0x1000, 0), Mode::Normal)
                .is_err()
            {
                return Err(MasterError::Busy(node_id));
            }
        }
        let deadline = now + to_duration(timeout);
        let mut found = Vec::new();
        loop {
            let now = self.clock.now();
            for (&node_id, client) in self.clients.iter_mut() {
                match client.poll_result() {
                    Some(Ok(_)) | Some(Err(SdoError::Server(_))) => found.push(node_id),
                    _ => {}
                }
            }
            if now >= deadline || self.clients.values().all(|c| !c.is_busy()) {
                break;
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
        for client in self.clients.values_mut() {
            client.cancel();
        }
        found.sort_unstable();
        Ok(found)
    }

    /// The NMT state `node_id` reports: the last heartbeat seen, else the answer to a guarding
    /// RTR within `timeout` (`None` if the node does not answer one).
    pub fn query_state(
        &mut self,
        node_id: u8,
        timeout: StdDuration,
    ) -> Result<Option<NmtState>, MasterError> {
        if let Some(state) = self.last_state(node_id) {
            return Ok(Some(state));
        }
        let id = ErrorControlRepr::cob_id(node_id);
        self.transport.send(&CanFrame::remote(id, 1))?;
        let deadline = self.clock.now() + to_duration(timeout);
        loop {
            let now = self.clock.now();
            if let Some(state) = self.last_state(node_id) {
                return Ok(Some(state));
            }
            if now >= deadline {
                return Ok(None);
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
    }

    /// Listens for `duration`, collecting events.
    pub fn listen(&mut self, duration: StdDuration) -> Result<(), MasterError> {
        let deadline = self.clock.now() + to_duration(duration);
        loop {
            let now = self.clock.now();
            if now >= deadline {
                return Ok(());
            }
            self.step(now, Some(deadline), &mut [].as_slice(), &mut io::sink())?;
        }
    }
}
