//! CiA 402 (drives and motion control), the parts both sides share and the device's drive.
//!
//! This module owns the meaning of the two words a CiA 402 master and drive exchange: the
//! controlword (6040h) decoded into a [`Command`], and the statusword (6041h) encoded from and
//! decoded into a [`State`]. [`Drive`] is the device side: the drive state machine with its
//! option codes and the velocity mode (vl) ramp, sans-IO like the rest of the runtime (it takes
//! controlwords and instants, and gives statuswords and velocities); [`Drive::run_on`] runs it
//! against the CiA 402 objects of any object dictionary.

mod drive;
mod objects;

pub use self::drive::{Drive, DriveConfig, StopRamp, UPDATE_PERIOD};

/// The states of the CiA 402 drive state machine (CiA 402-2 figure "state machine").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum State {
    /// Initialising after power-on; left by itself (transition 1).
    NotReadyToSwitchOn,
    /// High voltage may be off; the drive function is disabled.
    SwitchOnDisabled,
    /// Waiting for "switch on".
    ReadyToSwitchOn,
    /// Power applied, the drive function disabled.
    SwitchedOn,
    /// The drive follows its set-point.
    OperationEnabled,
    /// The quick-stop function is running (or, with option codes 5–8, done and holding).
    QuickStopActive,
    /// The fault reaction is running.
    FaultReactionActive,
    /// A fault is active; the drive function is disabled.
    Fault,
}

/// Statusword (6041h) bits.
pub mod statusword {
    /// Bit 0: ready to switch on.
    pub const READY_TO_SWITCH_ON: u16 = 1 << 0;
    /// Bit 1: switched on.
    pub const SWITCHED_ON: u16 = 1 << 1;
    /// Bit 2: operation enabled.
    pub const OPERATION_ENABLED: u16 = 1 << 2;
    /// Bit 3: fault.
    pub const FAULT: u16 = 1 << 3;
    /// Bit 4: voltage enabled (high voltage applied).
    pub const VOLTAGE_ENABLED: u16 = 1 << 4;
    /// Bit 5: quick stop, active low (0 while a quick stop runs or holds).
    pub const QUICK_STOP: u16 = 1 << 5;
    /// Bit 6: switch on disabled.
    pub const SWITCH_ON_DISABLED: u16 = 1 << 6;
    /// Bit 7: warning.
    pub const WARNING: u16 = 1 << 7;
    /// Bit 9: remote (the drive obeys the controlword).
    pub const REMOTE: u16 = 1 << 9;
    /// Bit 10: target reached (vl: the demand equals the target, or the drive stopped on halt).
    pub const TARGET_REACHED: u16 = 1 << 10;
    /// Bit 11: internal limit active (vl: the target was clamped to the maximum speed).
    pub const INTERNAL_LIMIT: u16 = 1 << 11;
    /// The bits that encode the state (bits 0–3, 5 and 6).
    pub const STATE_MASK: u16 = 0x006F;
}

/// Controlword (6040h) bits.
pub mod controlword {
    /// Bit 0: switch on.
    pub const SWITCH_ON: u16 = 1 << 0;
    /// Bit 1: enable voltage.
    pub const ENABLE_VOLTAGE: u16 = 1 << 1;
    /// Bit 2: quick stop, active low.
    pub const QUICK_STOP: u16 = 1 << 2;
    /// Bit 3: enable operation.
    pub const ENABLE_OPERATION: u16 = 1 << 3;
    /// Bit 4, velocity mode: enable the ramp function generator (0: demand forced to zero).
    pub const VL_RAMP_ENABLE: u16 = 1 << 4;
    /// Bit 5, velocity mode: unlock the ramp (0: the demand is held where it is).
    pub const VL_RAMP_UNLOCK: u16 = 1 << 5;
    /// Bit 6, velocity mode: use the reference (0: the ramp runs towards zero).
    pub const VL_REFERENCE: u16 = 1 << 6;
    /// Bit 7: fault reset, on its rising edge.
    pub const FAULT_RESET: u16 = 1 << 7;
    /// Bit 8: halt.
    pub const HALT: u16 = 1 << 8;
}

impl State {
    /// The state a statusword reports (CiA 402-2 table "state coding"), or `None` for a pattern
    /// that codes no state.
    pub const fn from_statusword(word: u16) -> Option<State> {
        use statusword::*;
        // Bits 0–3 and 6 name most states; bit 5 tells the two that share 0111b apart.
        let low = word & (READY_TO_SWITCH_ON | SWITCHED_ON | OPERATION_ENABLED | FAULT);
        let disabled = word & SWITCH_ON_DISABLED != 0;
        let quick_stop = word & QUICK_STOP != 0;
        Some(match (low, disabled, quick_stop) {
            (0b0000, false, _) => State::NotReadyToSwitchOn,
            (0b0000, true, _) => State::SwitchOnDisabled,
            (0b0001, false, true) => State::ReadyToSwitchOn,
            (0b0011, false, true) => State::SwitchedOn,
            (0b0111, false, true) => State::OperationEnabled,
            (0b0111, false, false) => State::QuickStopActive,
            (0b1111, false, _) => State::FaultReactionActive,
            (0b1000, false, _) => State::Fault,
            _ => return None,
        })
    }

    /// The state bits of the statusword in this state (bits 0–3, 5 and 6; the others clear).
    pub const fn statusword(self) -> u16 {
        use statusword::*;
        match self {
            State::NotReadyToSwitchOn => 0,
            State::SwitchOnDisabled => SWITCH_ON_DISABLED,
            State::ReadyToSwitchOn => QUICK_STOP | READY_TO_SWITCH_ON,
            State::SwitchedOn => QUICK_STOP | SWITCHED_ON | READY_TO_SWITCH_ON,
            State::OperationEnabled => {
                QUICK_STOP | OPERATION_ENABLED | SWITCHED_ON | READY_TO_SWITCH_ON
            }
            State::QuickStopActive => OPERATION_ENABLED | SWITCHED_ON | READY_TO_SWITCH_ON,
            State::FaultReactionActive => {
                FAULT | OPERATION_ENABLED | SWITCHED_ON | READY_TO_SWITCH_ON
            }
            State::Fault => FAULT,
        }
    }
}

/// A device-control command, as bits 0–3 and 7 of the controlword code it (CiA 402-2 table
/// "command coding").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// xxxx x110: transitions 2, 6, 8.
    Shutdown,
    /// 0111: transition 3 (and 5 from operation enabled, where it is "disable operation").
    SwitchOn,
    /// 1111: transitions 4 and 16 (and 3 + 4 from ready to switch on).
    EnableOperation,
    /// xxxx xx0x: transitions 7, 9, 10, 12.
    DisableVoltage,
    /// xxxx x01x: transitions 7, 10, 11.
    QuickStop,
    /// Bit 7 rising: transition 15.
    FaultReset,
}

impl Command {
    /// The command a controlword codes, given the previous controlword (fault reset acts on the
    /// rising edge of bit 7). `None` for the patterns that code no command (xxxx 1110 is
    /// shutdown; 0xxx x111 with bit 3 clear or set is switch on or enable operation, so every
    /// pattern codes one: `None` only while bit 7 stays set).
    pub const fn from_controlword(word: u16, previous: u16) -> Option<Command> {
        use controlword::*;
        if word & FAULT_RESET != 0 {
            return if previous & FAULT_RESET == 0 {
                Some(Command::FaultReset)
            } else {
                None
            };
        }
        Some(if word & ENABLE_VOLTAGE == 0 {
            Command::DisableVoltage
        } else if word & QUICK_STOP == 0 {
            Command::QuickStop
        } else if word & SWITCH_ON == 0 {
            Command::Shutdown
        } else if word & ENABLE_OPERATION == 0 {
            Command::SwitchOn
        } else {
            Command::EnableOperation
        })
    }

    /// The controlword's bits 0–3 and 7 for this command (the others clear): what a master
    /// writes.
    pub const fn controlword(self) -> u16 {
        use controlword::*;
        match self {
            Command::Shutdown => QUICK_STOP | ENABLE_VOLTAGE,
            Command::SwitchOn => QUICK_STOP | ENABLE_VOLTAGE | SWITCH_ON,
            Command::EnableOperation => ENABLE_OPERATION | QUICK_STOP | ENABLE_VOLTAGE | SWITCH_ON,
            Command::DisableVoltage => 0,
            Command::QuickStop => ENABLE_VOLTAGE,
            Command::FaultReset => FAULT_RESET,
        }
    }
}

/// Modes of operation (6060h/6061h) this runtime's drive knows by name.
pub mod mode {
    /// Profile position.
    pub const PROFILE_POSITION: i8 = 1;
    /// Velocity (vl).
    pub const VELOCITY: i8 = 2;
    /// Profile velocity.
    pub const PROFILE_VELOCITY: i8 = 3;
    /// Profile torque.
    pub const PROFILE_TORQUE: i8 = 4;
    /// Homing.
    pub const HOMING: i8 = 6;
    /// Cyclic synchronous position.
    pub const CYCLIC_POSITION: i8 = 8;
    /// Cyclic synchronous velocity.
    pub const CYCLIC_VELOCITY: i8 = 9;
    /// Cyclic synchronous torque.
    pub const CYCLIC_TORQUE: i8 = 10;
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [State; 8] = [
        State::NotReadyToSwitchOn,
        State::SwitchOnDisabled,
        State::ReadyToSwitchOn,
        State::SwitchedOn,
        State::OperationEnabled,
        State::QuickStopActive,
        State::FaultReactionActive,
        State::Fault,
    ];

    #[test]
    fn every_state_round_trips_through_its_statusword() {
        for state in ALL {
            assert_eq!(State::from_statusword(state.statusword()), Some(state));
            // Bits outside the state mask (voltage, warning, remote, target reached) do not
            // change the state.
            assert_eq!(
                State::from_statusword(state.statusword() | 0x0E90),
                Some(state)
            );
        }
    }

    #[test]
    fn statuswords_of_the_cp301_table() {
        // CP301 manual §8.2.4, the state column with the x bits clear.
        assert_eq!(State::SwitchOnDisabled.statusword(), 0b0100_0000);
        assert_eq!(State::ReadyToSwitchOn.statusword(), 0b0010_0001);
        assert_eq!(State::SwitchedOn.statusword(), 0b0010_0011);
        assert_eq!(State::OperationEnabled.statusword(), 0b0010_0111);
        assert_eq!(State::QuickStopActive.statusword(), 0b0000_0111);
        assert_eq!(State::FaultReactionActive.statusword(), 0b0000_1111);
        assert_eq!(State::Fault.statusword(), 0b0000_1000);
        assert_eq!(State::from_statusword(0b0110_0001), None);
    }

    #[test]
    fn controlwords_of_the_cp301_command_table() {
        // CP301 manual §8.2.3: 06h shutdown, 07h switch on, 0Fh enable operation, 7Fh enable
        // operation with the vl bits, 02h quick stop, 00h disable voltage, 80h fault reset.
        assert_eq!(Command::from_controlword(0x06, 0), Some(Command::Shutdown));
        assert_eq!(Command::from_controlword(0x0E, 0), Some(Command::Shutdown));
        assert_eq!(Command::from_controlword(0x07, 0), Some(Command::SwitchOn));
        assert_eq!(
            Command::from_controlword(0x0F, 0),
            Some(Command::EnableOperation)
        );
        assert_eq!(
            Command::from_controlword(0x7F, 0),
            Some(Command::EnableOperation)
        );
        assert_eq!(Command::from_controlword(0x02, 0), Some(Command::QuickStop));
        assert_eq!(
            Command::from_controlword(0x0D, 0),
            Some(Command::DisableVoltage)
        );
        assert_eq!(
            Command::from_controlword(0x80, 0x00),
            Some(Command::FaultReset)
        );
        assert_eq!(Command::from_controlword(0x80, 0x80), None);
        for command in [
            Command::Shutdown,
            Command::SwitchOn,
            Command::EnableOperation,
            Command::DisableVoltage,
            Command::QuickStop,
            Command::FaultReset,
        ] {
            assert_eq!(
                Command::from_controlword(command.controlword(), 0),
                Some(command)
            );
        }
    }
}
