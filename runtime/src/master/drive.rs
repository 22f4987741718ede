//! CiA 402 helpers of the blocking master (feature `std`): read a drive's state, walk it to
//! operation enabled or back with a timeout per transition, reset a fault and check it cleared,
//! set a mode of operation and wait for the drive to confirm it.

use std::time::{Duration as StdDuration, Instant as StdInstant};

use crate::transport::Transport;

use super::blocking::{Master, MasterError};
use super::cia402::{
    next_command, state_of, CONTROLWORD, MODES_OF_OPERATION, MODES_OF_OPERATION_DISPLAY, STATUSWORD,
};
use crate::cia402::{Command, State};

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

    /// Resets a fault: bit 7 low, then its rising edge; the fault must be gone within
    /// `timeout`, or the error says the drive stays in fault.
    pub fn fault_reset(&mut self, node_id: u8, timeout: StdDuration) -> Result<(), MasterError> {
        if self.drive_state(node_id)? != State::Fault {
            return Ok(());
        }
        self.drive_command(node_id, Command::DisableVoltage)?;
        self.drive_command(node_id, Command::FaultReset)?;
        self.wait_state(node_id, timeout, |s| s != State::Fault)
            .map(|_| ())
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

    fn walk_to(
        &mut self,
        node_id: u8,
        target: State,
        step_timeout: StdDuration,
    ) -> Result<(), MasterError> {
        let mut state = self.drive_state(node_id)?;
        // Each command moves one transition; no walk needs more than a handful.
        for _ in 0..8 {
            let Some(command) = next_command(state, target) else {
                if state == target {
                    return Ok(());
                }
                // Not ready or reacting to a fault: the drive moves by itself.
                state = self.wait_state(node_id, step_timeout, |s| s != state)?;
                continue;
            };
            if command == Command::FaultReset {
                self.fault_reset(node_id, step_timeout)?;
                state = self.drive_state(node_id)?;
                continue;
            }
            self.drive_command(node_id, command)?;
            let before = state;
            state = self.wait_state(node_id, step_timeout, |s| s != before)?;
        }
        Err(MasterError::DriveStuck { node_id, state })
    }

    /// Reads the statusword until `done` holds for the state, at most `timeout`.
    fn wait_state(
        &mut self,
        node_id: u8,
        timeout: StdDuration,
        done: impl Fn(State) -> bool,
    ) -> Result<State, MasterError> {
        let start = StdInstant::now();
        loop {
            let state = self.drive_state(node_id)?;
            if done(state) {
                return Ok(state);
            }
            if start.elapsed() >= timeout {
                return Err(MasterError::DriveStuck { node_id, state });
            }
            self.listen(POLL)?;
        }
    }
}
