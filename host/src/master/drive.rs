//! CiA 402 helpers of the blocking master (feature `std`): read a drive's state, walk it to
//! operation enabled or back with a timeout per transition, reset a fault and check it cleared,
//! set a mode of operation and wait for the drive to confirm it. The walks run the cyclic
//! [`Controller`] over SDO, one statusword read per cycle.

use std::time::{Duration as StdDuration, Instant as StdInstant};

use crate::Transport;

use super::blocking::{Master, MasterError};
use edsgen_runtime::cia402::{Command, State};
use edsgen_runtime::master::cia402::{
    state_of, Controller, Outcome, CONTROLWORD, MODES_OF_OPERATION, MODES_OF_OPERATION_DISPLAY,
    STATUSWORD,
};

/// How often a helper reads the statusword while it waits for a transition.
const POLL: StdDuration = StdDuration::from_millis(5);

impl<T: Transport> Master<T> {
    /// The drive state node `node_id` shows in its statusword.
    pub fn drive_state(&mut self, node_id: u8) -> Result<State, MasterError> {
        Ok(state_of(self.read(node_id, STATUSWORD)?))
    }

    /// Sends a controlword command.
    pub fn drive_command(&mut self, node_id: u8, command: Command) -> Result<(), MasterError> {
        self.write(node_id, CONTROLWORD, command.controlword())
    }

    /// Walks the drive to operation enabled (resetting a fault on the way), each transition
    /// within `step_timeout`.
    pub fn enable_operation(
        &mut self,
        node_id: u8,
        step_timeout: StdDuration,
    ) -> Result<(), MasterError> {
        self.walk_to(node_id, State::OperationEnabled, step_timeout)
    }

    /// Walks the drive back to switch on disabled (power stage off).
    pub fn disable_drive(
        &mut self,
        node_id: u8,
        step_timeout: StdDuration,
    ) -> Result<(), MasterError> {
        self.walk_to(node_id, State::SwitchOnDisabled, step_timeout)
    }

    /// Resets a fault: bit 7 low, then its rising edge (again while the drive stays in fault);
    /// the fault must be gone within `timeout`, or the error says the drive stays in fault.
    pub fn fault_reset(&mut self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        if self.drive_state(node_id)? != State::Fault {
            return Ok(());
        }
        self.walk_to(node_id, State::SwitchOnDisabled, timeout)
    }

    /// Sets the mode of operation (6060h) and waits until the display (6061h) shows it.
    pub fn set_mode(
        &mut self,
        node_id: u8,
        mode: i8,
        timeout: StdDuration,
    ) -> Result<(), MasterError> {
        self.write(node_id, MODES_OF_OPERATION, mode)?;
        let start = StdInstant::now();
        loop {
            let shown = self.read(node_id, MODES_OF_OPERATION_DISPLAY)?;
            if shown == mode {
                return Ok(());
            }
            if start.elapsed() >= timeout {
                return Err(MasterError::ModeNotConfirmed {
                    node_id,
                    wanted: mode,
                    shown,
                });
            }
            self.listen(POLL)?;
        }
    }

    /// Walks the drive with the cyclic [`Controller`], a statusword read per cycle and a
    /// controlword written when it changes; a state the drive stays in for `step_timeout` is
    /// an error.
    fn walk_to(
        &mut self,
        node_id: u8,
        target: State,
        step_timeout: StdDuration,
    ) -> Result<(), MasterError> {
        let mut controller = Controller::new(target);
        let mut written = None;
        let mut seen: Option<(State, StdInstant)> = None;
        loop {
            let statusword = self.read(node_id, STATUSWORD)?;
            let state = state_of(statusword);
            let cycle = controller.cycle(statusword, 0);
            if cycle.outcome == Outcome::Reached {
                return Ok(());
            }
            let unchanged = match seen {
                Some((seen, since)) if seen == state => {
                    if since.elapsed() >= step_timeout {
                        return Err(MasterError::DriveStuck { node_id, state });
                    }
                    true
                }
                _ => {
                    seen = Some((state, StdInstant::now()));
                    false
                }
            };
            if written != Some(cycle.controlword) {
                self.write(node_id, CONTROLWORD, cycle.controlword)?;
                written = Some(cycle.controlword);
            }
            // A confirmed write has usually moved the drive already: read again at once, and
            // wait only while it stays.
            if unchanged {
                self.listen(POLL)?;
            }
        }
    }
}
