//! CiA 402 for masters: the addresses of the drive objects every CiA 402 device has, the next
//! controlword command on the way to a target state, and [`Controller`], which walks a drive by
//! cyclic process data with it. The controlword and statusword codings are the ones the device
//! side uses ([`crate::cia402`]).

mod cyclic;

use crate::cia402::{Command, State};
use crate::od::entry::Entry;

pub use self::cyclic::{Controller, Cycle, Outcome};
pub use crate::cia402::mode;

/// Controlword (6040h).
pub const CONTROLWORD: Entry<u16> = Entry::new(0x6040, 0);
/// Statusword (6041h).
pub const STATUSWORD: Entry<u16> = Entry::new(0x6041, 0);
/// Modes of operation (6060h).
pub const MODES_OF_OPERATION: Entry<i8> = Entry::new(0x6060, 0);
/// Modes of operation display (6061h).
pub const MODES_OF_OPERATION_DISPLAY: Entry<i8> = Entry::new(0x6061, 0);

/// The state a master reads from a statusword: a pattern that codes no state reads as not
/// ready to switch on, the state a drive cannot be commanded from.
pub const fn state_of(statusword: u16) -> State {
    match State::from_statusword(statusword) {
        Some(state) => state,
        None => State::NotReadyToSwitchOn,
    }
}

/// The command that moves a drive in `state` one transition closer to `target` (operation
/// enabled or switch on disabled; a fault is reset first); `None` when it is there, or must get
/// there by itself (not ready to switch on, fault reaction active).
pub const fn next_command(state: State, target: State) -> Option<Command> {
    use State as S;
    let enable = matches!(target, S::OperationEnabled);
    match state {
        S::NotReadyToSwitchOn | S::FaultReactionActive => None,
        S::Fault => Some(Command::FaultReset),
        S::OperationEnabled if enable => None,
        S::SwitchOnDisabled if !enable => None,
        S::SwitchOnDisabled => Some(Command::Shutdown),
        S::ReadyToSwitchOn if enable => Some(Command::SwitchOn),
        S::SwitchedOn if enable => Some(Command::EnableOperation),
        _ => Some(Command::DisableVoltage),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cia402::{Drive, DriveConfig};
    use crate::Instant;

    #[test]
    fn next_commands_walk_a_drive_to_operation_enabled_and_back() {
        let now = Instant::from_millis(0);
        let mut drive = Drive::new(DriveConfig::new(1500), now);
        let mut walked = [None; 4];
        for step in walked.iter_mut() {
            *step = next_command(drive.state(), State::OperationEnabled);
            if let Some(command) = step {
                drive.set_controlword(now, command.controlword());
            }
        }
        assert_eq!(
            walked,
            [
                Some(Command::Shutdown),
                Some(Command::SwitchOn),
                Some(Command::EnableOperation),
                None
            ]
        );
        assert_eq!(state_of(drive.statusword()), State::OperationEnabled);
        drive.raise_fault(now);
        drive.update(now);
        assert_eq!(
            next_command(drive.state(), State::OperationEnabled),
            Some(Command::FaultReset)
        );
        drive.clear_fault();
        drive.set_controlword(now, Command::FaultReset.controlword());
        assert_eq!(drive.state(), State::SwitchOnDisabled);
        assert_eq!(next_command(drive.state(), State::SwitchOnDisabled), None);
        // A pattern that codes no state.
        assert_eq!(state_of(0x0061), State::NotReadyToSwitchOn);
    }
}
