//! CiA 402 for masters: controlword commands, the drive state a statusword shows, the next
//! command on the way to a target state, and [`DriveModel`], the device's state machine, for
//! simulated drives in tests and examples.

use crate::entry::Entry;

/// Controlword (6040h).
pub const CONTROLWORD: Entry<u16> = Entry::new(0x6040, 0);
/// Statusword (6041h).
pub const STATUSWORD: Entry<u16> = Entry::new(0x6041, 0);
/// Modes of operation (6060h).
pub const MODES_OF_OPERATION: Entry<i8> = Entry::new(0x6060, 0);
/// Modes of operation display (6061h).
pub const MODES_OF_OPERATION_DISPLAY: Entry<i8> = Entry::new(0x6061, 0);

/// Modes of operation (6060h values).
pub mod mode {
    /// Profile position mode.
    pub const PROFILE_POSITION: i8 = 1;
    /// Velocity mode (vl).
    pub const VELOCITY: i8 = 2;
    /// Profile velocity mode.
    pub const PROFILE_VELOCITY: i8 = 3;
    /// Profile torque mode.
    pub const PROFILE_TORQUE: i8 = 4;
    /// Homing mode.
    pub const HOMING: i8 = 6;
}

/// The states of the CiA 402 power drive state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DriveState {
    /// Not ready to switch on.
    NotReadyToSwitchOn,
    /// Switch on disabled.
    SwitchOnDisabled,
    /// Ready to switch on.
    ReadyToSwitchOn,
    /// Switched on.
    SwitchedOn,
    /// Operation enabled.
    OperationEnabled,
    /// Quick stop active.
    QuickStopActive,
    /// Fault reaction active.
    FaultReactionActive,
    /// Fault.
    Fault,
}

impl DriveState {
    /// The state a statusword shows (bits 0–3, 5 and 6).
    pub const fn from_statusword(statusword: u16) -> Self {
        match (statusword & 0x4F, statusword & 0x6F) {
            (0x00, _) => DriveState::NotReadyToSwitchOn,
            (0x40, _) => DriveState::SwitchOnDisabled,
            (0x0F, _) => DriveState::FaultReactionActive,
            (0x08, _) => DriveState::Fault,
            (_, 0x21) => DriveState::ReadyToSwitchOn,
            (_, 0x23) => DriveState::SwitchedOn,
            (_, 0x27) => DriveState::OperationEnabled,
            (_, 0x07) => DriveState::QuickStopActive,
            // Undefined combinations read as the state the drive cannot be commanded from.
            _ => DriveState::NotReadyToSwitchOn,
        }
    }

    /// The statusword bits a drive in this state shows (bits 0–3, 5, 6; bit 4 voltage enabled
    /// with the power stage on).
    pub const fn statusword(self) -> u16 {
        match self {
            DriveState::NotReadyToSwitchOn => 0x0000,
            DriveState::SwitchOnDisabled => 0x0040,
            DriveState::ReadyToSwitchOn => 0x0021,
            DriveState::SwitchedOn => 0x0033,
            DriveState::OperationEnabled => 0x0037,
            DriveState::QuickStopActive => 0x0017,
            DriveState::FaultReactionActive => 0x000F,
            DriveState::Fault => 0x0008,
        }
    }

    /// The command that moves a drive in this state one transition closer to `target`
    /// (operation enabled or switch on disabled; a fault is reset first); `None` when it is
    /// there, or must get there by itself (not ready to switch on, fault reaction active).
    pub const fn next_command(self, target: DriveState) -> Option<Command> {
        use DriveState as S;
        let enable = matches!(target, S::OperationEnabled);
        match self {
            S::NotReadyToSwitchOn | S::FaultReactionActive => None,
            S::Fault => Some(Command::FaultReset),
            S::OperationEnabled if enable => None,
            S::SwitchOnDisabled if !enable => None,
            S::SwitchOnDisabled => Some(Command::Shutdown),
            S::ReadyToSwitchOn if enable => Some(Command::SwitchOn),
            S::SwitchedOn if enable => Some(Command::EnableOperation),
            S::QuickStopActive if enable => Some(Command::DisableVoltage),
            _ => Some(Command::DisableVoltage),
        }
    }
}

/// Controlword commands (bits 0–3 and 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// Shutdown: to ready to switch on.
    Shutdown,
    /// Switch on: to switched on.
    SwitchOn,
    /// Switch on and enable operation.
    EnableOperation,
    /// Disable voltage: to switch on disabled.
    DisableVoltage,
    /// Quick stop.
    QuickStop,
    /// Disable operation: back to switched on.
    DisableOperation,
    /// Fault reset (acts on the rising edge of bit 7).
    FaultReset,
}

impl Command {
    /// The controlword of this command (bits 4–6 and 8 zero).
    pub const fn controlword(self) -> u16 {
        match self {
            Command::Shutdown => 0x0006,
            Command::SwitchOn => 0x0007,
            Command::EnableOperation => 0x000F,
            Command::DisableVoltage => 0x0000,
            Command::QuickStop => 0x0002,
            Command::DisableOperation => 0x0007,
            Command::FaultReset => 0x0080,
        }
    }
}

/// The device side of the state machine, for simulated drives: the state a controlword leads
/// to, transitions as CiA 402 numbers them (2–12, 15), with a fault that a reset clears unless
/// it persists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveModel {
    /// The state.
    pub state: DriveState,
    /// Whether a fault stays after a fault reset (its cause is still there).
    pub fault_persists: bool,
    last_controlword: u16,
}

impl Default for DriveModel {
    fn default() -> Self {
        DriveModel::new()
    }
}

impl DriveModel {
    /// A drive that has finished its self-test: switch on disabled.
    pub const fn new() -> Self {
        DriveModel {
            state: DriveState::SwitchOnDisabled,
            fault_persists: false,
            last_controlword: 0,
        }
    }

    /// A fault: the drive goes to fault (through fault reaction, which this model skips).
    pub fn fault(&mut self) {
        self.state = DriveState::Fault;
    }

    /// Applies a controlword; returns the new state.
    pub fn apply(&mut self, controlword: u16) -> DriveState {
        use DriveState as S;
        let rising_reset = controlword & 0x80 != 0 && self.last_controlword & 0x80 == 0;
        self.last_controlword = controlword;
        let (enable_voltage, quick_stop_off, switch_on, enable_operation) = (
            controlword & 0x02 != 0,
            controlword & 0x04 != 0,
            controlword & 0x01 != 0,
            controlword & 0x08 != 0,
        );
        let shutdown = enable_voltage && quick_stop_off && !switch_on;
        let on = enable_voltage && quick_stop_off && switch_on;
        let quick_stop = enable_voltage && !quick_stop_off;
        self.state = match self.state {
            S::Fault if rising_reset && !self.fault_persists => S::SwitchOnDisabled,
            S::Fault | S::NotReadyToSwitchOn | S::FaultReactionActive => self.state,
            _ if !enable_voltage => S::SwitchOnDisabled,
            S::SwitchOnDisabled if shutdown => S::ReadyToSwitchOn,
            S::ReadyToSwitchOn if on && enable_operation => S::OperationEnabled,
            S::ReadyToSwitchOn if on => S::SwitchedOn,
            S::SwitchedOn if shutdown => S::ReadyToSwitchOn,
            S::SwitchedOn if on && enable_operation => S::OperationEnabled,
            S::OperationEnabled if quick_stop => S::QuickStopActive,
            S::OperationEnabled if shutdown => S::ReadyToSwitchOn,
            S::OperationEnabled if on && !enable_operation => S::SwitchedOn,
            S::ReadyToSwitchOn | S::SwitchedOn if quick_stop => S::SwitchOnDisabled,
            other => other,
        };
        self.state
    }
}

/// A device node with a [`DriveModel`] behind its 6040h/6041h (feature `std`): a simulated
/// CiA 402 drive for testing masters on the virtual bus or a transport. After every frame and
/// timer it applies a new controlword, shows the state in the statusword, copies 6060h to 6061h
/// and, in velocity mode (vl), the target velocity 6042h to the demand and actual values
/// 6043h/6044h while operation is enabled (0 otherwise).
#[cfg(feature = "std")]
pub struct SimulatedDrive<O, H = ()> {
    /// The node serving the drive's dictionary.
    pub node: crate::node::Node<O, H>,
    /// The drive's state machine.
    pub model: DriveModel,
    last_controlword: Option<u16>,
}

#[cfg(feature = "std")]
impl<O: crate::ObjectDictionary, H: crate::node::NodeHooks<O>> SimulatedDrive<O, H> {
    /// The drive of `node`, switch on disabled.
    pub fn new(node: crate::node::Node<O, H>) -> Self {
        let mut drive = SimulatedDrive {
            node,
            model: DriveModel::new(),
            last_controlword: None,
        };
        drive.update();
        drive
    }

    fn read<T: crate::OdValue>(&self, entry: Entry<T>) -> Option<T> {
        let mut buf = [0u8; 8];
        let len = self
            .node
            .od()
            .read(entry.index, entry.sub, 0, &mut buf)
            .ok()?;
        entry.decode(&buf[..len])
    }

    fn write<T: crate::OdValue>(&mut self, entry: Entry<T>, value: T) {
        let mut buf = [0u8; 8];
        if let Some(len) = entry.encode(&value, &mut buf) {
            // Entries the dictionary lacks are simply not simulated.
            let _ = self
                .node
                .od_mut()
                .write(entry.index, entry.sub, &buf[..len]);
        }
    }

    /// Runs the model on the dictionary's current controlword.
    pub fn update(&mut self) {
        let controlword = self.read(CONTROLWORD).unwrap_or(0);
        if self.last_controlword != Some(controlword) {
            self.last_controlword = Some(controlword);
            self.model.apply(controlword);
        }
        // Bit 9: remote (the drive follows the controlword).
        self.write(STATUSWORD, self.model.state.statusword() | 0x0200);
        if let Some(mode) = self.read(MODES_OF_OPERATION) {
            self.write(MODES_OF_OPERATION_DISPLAY, mode);
        }
        let target: Entry<i16> = Entry::new(0x6042, 0);
        let velocity = match self.model.state {
            DriveState::OperationEnabled => self.read(target).unwrap_or(0),
            _ => 0,
        };
        self.write(Entry::<i16>::new(0x6043, 0), velocity);
        self.write(Entry::<i16>::new(0x6044, 0), velocity);
    }
}

#[cfg(feature = "std")]
impl<O: crate::ObjectDictionary, H: crate::node::NodeHooks<O>> crate::vbus::BusDevice
    for SimulatedDrive<O, H>
{
    fn handle_frame(&mut self, now: crate::Instant, frame: &crate::CanFrame) {
        self.node.handle_frame(now, frame);
        self.update();
    }
    fn poll_transmit(&mut self, now: crate::Instant) -> Option<crate::CanFrame> {
        self.node.poll_transmit(now)
    }
    fn poll_timeout(&self) -> Option<crate::Instant> {
        self.node.poll_timeout()
    }
    fn handle_timeout(&mut self, now: crate::Instant) {
        self.node.handle_timeout(now);
        self.update();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_state_reads_back_from_its_statusword() {
        use DriveState as S;
        for state in [
            S::NotReadyToSwitchOn,
            S::SwitchOnDisabled,
            S::ReadyToSwitchOn,
            S::SwitchedOn,
            S::OperationEnabled,
            S::QuickStopActive,
            S::FaultReactionActive,
            S::Fault,
        ] {
            // Manufacturer bits (8, 14, 15) and warning (7) do not change the state.
            assert_eq!(
                DriveState::from_statusword(state.statusword() | 0xC180),
                state
            );
        }
        // A typical CP301 statusword in operation: 0x0637.
        assert_eq!(DriveState::from_statusword(0x0637), S::OperationEnabled);
    }

    #[test]
    fn next_commands_walk_the_model_to_operation_enabled_and_back() {
        let mut drive = DriveModel::new();
        let mut walked = [None; 4];
        for step in walked.iter_mut() {
            *step = drive.state.next_command(DriveState::OperationEnabled);
            if let Some(command) = step {
                drive.apply(command.controlword());
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
        assert_eq!(drive.state, DriveState::OperationEnabled);
        drive.fault();
        assert_eq!(
            drive.state.next_command(DriveState::OperationEnabled),
            Some(Command::FaultReset)
        );
        drive.apply(Command::FaultReset.controlword());
        assert_eq!(drive.state, DriveState::SwitchOnDisabled);
        drive.apply(Command::Shutdown.controlword());
        drive.apply(Command::QuickStop.controlword());
        assert_eq!(drive.state, DriveState::SwitchOnDisabled);
    }
}
