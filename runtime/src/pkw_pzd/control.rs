//! The control word (CW, master to drive) and status word (SW, drive to master): Tables 2-5 and
//! 2-7 (PROFIBUS-DP; Tables 4-5/4-7 and 5-5/5-8 are the same), where bits 0–7 hold one command
//! or state number, and the EtherNet/IP card's Tables 5-6 and 5-9 (P16.56 = 1), where each of
//! those bits means one thing. Bits 8–15 are the same in both.
//!
//! Both words are kept as the 16 bits received ([`ControlWord`], [`StatusWord`]), read and
//! changed through typed accessors, so that nothing a peer sends is lost.
//!
//! Choices where Table 5-6 is silent: its remarks give the byte of each command (no action
//! 03h, decelerate 00h, forward 01h, reverse 02h, fault reset 04h, coast 08h, jog forward 10h,
//! jog reverse 20h, stop jogging 40h). A byte with several of bits 2–6 set is read by priority
//! coast, fault reset, stop jogging, jog forward, jog reverse (the safest first); without any of
//! them bits 0–1 decide. In Table 5-9 a word with several state bits set reads as the fault if
//! bit 3 is set, else as its lowest state bit.

/// How bits 0–7 of the CW and SW are laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum WordLayout {
    /// A number (Tables 2-5, 2-7; EtherNet/IP with P16.56 = 0): PROFIBUS-DP and PROFINET.
    #[default]
    ByByte,
    /// One bit per command or state (Tables 5-6, 5-9; EtherNet/IP with P16.56 = 1).
    ByBit,
}

/// A command of CW bits 0–7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// 1: run forward.
    RunForward,
    /// 2: run in reverse.
    RunReverse,
    /// 3: jog forward.
    JogForward,
    /// 4: jog in reverse.
    JogReverse,
    /// 5: decelerate to stop.
    DecelerateToStop,
    /// 6: coast to stop (emergency stop).
    CoastToStop,
    /// 7: fault reset.
    FaultReset,
    /// 8: stop jogging.
    StopJogging,
}

impl Command {
    /// The eight commands in Table 2-5's order (numbers 1 to 8).
    pub const ALL: [Command; 8] = [
        Command::RunForward,
        Command::RunReverse,
        Command::JogForward,
        Command::JogReverse,
        Command::DecelerateToStop,
        Command::CoastToStop,
        Command::FaultReset,
        Command::StopJogging,
    ];

    /// The byte of the command in a layout.
    pub const fn byte(self, layout: WordLayout) -> u8 {
        match layout {
            WordLayout::ByByte => match self {
                Command::RunForward => 1,
                Command::RunReverse => 2,
                Command::JogForward => 3,
                Command::JogReverse => 4,
                Command::DecelerateToStop => 5,
                Command::CoastToStop => 6,
                Command::FaultReset => 7,
                Command::StopJogging => 8,
            },
            WordLayout::ByBit => match self {
                Command::DecelerateToStop => 0x00,
                Command::RunForward => 0x01,
                Command::RunReverse => 0x02,
                Command::FaultReset => 0x04,
                Command::CoastToStop => 0x08,
                Command::JogForward => 0x10,
                Command::JogReverse => 0x20,
                Command::StopJogging => 0x40,
            },
        }
    }

    /// The command of a byte in a layout; `None` for "no command" (by byte: 0 and 9–255; by
    /// bit: bits 0–1 both set with none of bits 2–6).
    pub const fn from_byte(byte: u8, layout: WordLayout) -> Option<Command> {
        match layout {
            WordLayout::ByByte => match byte {
                1 => Some(Command::RunForward),
                2 => Some(Command::RunReverse),
                3 => Some(Command::JogForward),
                4 => Some(Command::JogReverse),
                5 => Some(Command::DecelerateToStop),
                6 => Some(Command::CoastToStop),
                7 => Some(Command::FaultReset),
                8 => Some(Command::StopJogging),
                _ => None,
            },
            WordLayout::ByBit => {
                if byte & 0x08 != 0 {
                    Some(Command::CoastToStop)
                } else if byte & 0x04 != 0 {
                    Some(Command::FaultReset)
                } else if byte & 0x40 != 0 {
                    Some(Command::StopJogging)
                } else if byte & 0x10 != 0 {
                    Some(Command::JogForward)
                } else if byte & 0x20 != 0 {
                    Some(Command::JogReverse)
                } else {
                    match byte & 0x03 {
                        0 => Some(Command::DecelerateToStop),
                        1 => Some(Command::RunForward),
                        2 => Some(Command::RunReverse),
                        _ => None,
                    }
                }
            }
        }
    }
}

/// The control word: 16 bits with typed access.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ControlWord(pub u16);

/// Bits 8–15 of the control word (the same in both layouts).
pub mod cw_bit {
    /// 8: enable writing (through PKW1–PKW4).
    pub const ENABLE_WRITE: u16 = 1 << 8;
    /// 9–10: motor group (0 motor 1, 1 motor 2).
    pub const MOTOR_GROUP: u16 = 0b11 << 9;
    /// 11: enable switching between torque and speed control.
    pub const CONTROL_MODE_SWITCH: u16 = 1 << 11;
    /// 12: reset the power consumption to zero.
    pub const RESET_POWER_CONSUMPTION: u16 = 1 << 12;
    /// 13: pre-excitation.
    pub const PRE_EXCITATION: u16 = 1 << 13;
    /// 14: DC braking.
    pub const DC_BRAKING: u16 = 1 << 14;
    /// 15: heartbeat reference.
    pub const HEARTBEAT: u16 = 1 << 15;
}

impl ControlWord {
    /// A control word carrying only `command`.
    pub const fn new(command: Command, layout: WordLayout) -> Self {
        ControlWord(command.byte(layout) as u16)
    }

    /// The command of bits 0–7.
    pub const fn command(self, layout: WordLayout) -> Option<Command> {
        Command::from_byte(self.0 as u8, layout)
    }

    /// The word with bits 0–7 set to `command`.
    pub const fn with_command(self, command: Command, layout: WordLayout) -> Self {
        ControlWord(self.0 & 0xFF00 | command.byte(layout) as u16)
    }

    /// Whether bit `mask` (one of [`cw_bit`]) is set.
    pub const fn has(self, mask: u16) -> bool {
        self.0 & mask != 0
    }

    /// The word with the bits of `mask` (one of [`cw_bit`]) set or cleared.
    pub const fn with(self, mask: u16, on: bool) -> Self {
        ControlWord(if on { self.0 | mask } else { self.0 & !mask })
    }

    /// Bit 8: PKW writes enabled.
    pub const fn write_enabled(self) -> bool {
        self.has(cw_bit::ENABLE_WRITE)
    }

    /// Bits 9–10: the motor group (0 motor 1, 1 motor 2).
    pub const fn motor_group(self) -> u8 {
        ((self.0 & cw_bit::MOTOR_GROUP) >> 9) as u8
    }
}

/// A running state of SW bits 0–7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RunState {
    /// 1: running forward.
    Forward,
    /// 2: running in reverse.
    Reverse,
    /// 3: stopped.
    Stopped,
    /// 4: faulted.
    Fault,
    /// 5: POFF (power off: bus voltage low).
    PowerOff,
    /// 6: pre-excitation.
    PreExcitation,
}

impl RunState {
    /// The state's number in Table 2-7 (1 to 6).
    pub const fn number(self) -> u8 {
        match self {
            RunState::Forward => 1,
            RunState::Reverse => 2,
            RunState::Stopped => 3,
            RunState::Fault => 4,
            RunState::PowerOff => 5,
            RunState::PreExcitation => 6,
        }
    }

    /// The state of Table 2-7's number.
    pub const fn from_number(number: u8) -> Option<RunState> {
        match number {
            1 => Some(RunState::Forward),
            2 => Some(RunState::Reverse),
            3 => Some(RunState::Stopped),
            4 => Some(RunState::Fault),
            5 => Some(RunState::PowerOff),
            6 => Some(RunState::PreExcitation),
            _ => None,
        }
    }

    /// The byte of the state in a layout (by bit: bit number − 1 set).
    pub const fn byte(self, layout: WordLayout) -> u8 {
        match layout {
            WordLayout::ByByte => self.number(),
            WordLayout::ByBit => 1 << (self.number() - 1),
        }
    }

    /// The state of a byte in a layout (see the module comment for several bits).
    pub const fn from_byte(byte: u8, layout: WordLayout) -> Option<RunState> {
        match layout {
            WordLayout::ByByte => RunState::from_number(byte),
            WordLayout::ByBit => {
                if byte & 0x08 != 0 {
                    Some(RunState::Fault)
                } else if byte & 0x3F == 0 {
                    None
                } else {
                    RunState::from_number((byte & 0x3F).trailing_zeros() as u8 + 1)
                }
            }
        }
    }
}

/// SW bits 13–14: where run and stop commands come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RunStopMode {
    /// 0: the keypad.
    Keypad,
    /// 1: the terminals.
    Terminal,
    /// 2: communication.
    Communication,
    /// 3: reserved.
    Reserved,
}

/// Bits 8–15 of the status word (the same in both layouts).
pub mod sw_bit {
    /// 8: bus voltage established, ready to run.
    pub const READY: u16 = 1 << 8;
    /// 9–10: motor group feedback.
    pub const MOTOR_GROUP: u16 = 0b11 << 9;
    /// 11: synchronous motor (0 asynchronous).
    pub const SYNCHRONOUS_MOTOR: u16 = 1 << 11;
    /// 12: overload pre-alarm.
    pub const OVERLOAD_PRE_ALARM: u16 = 1 << 12;
    /// 13–14: run/stop mode ([`RunStopMode`](super::RunStopMode)).
    pub const RUN_STOP_MODE: u16 = 0b11 << 13;
    /// 15: heartbeat feedback.
    pub const HEARTBEAT: u16 = 1 << 15;
}

/// The status word: 16 bits with typed access.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct StatusWord(pub u16);

impl StatusWord {
    /// A status word of `state`, nothing else set.
    pub const fn new(state: RunState, layout: WordLayout) -> Self {
        StatusWord(state.byte(layout) as u16)
    }

    /// The running state of bits 0–7.
    pub const fn state(self, layout: WordLayout) -> Option<RunState> {
        RunState::from_byte(self.0 as u8, layout)
    }

    /// Whether bit `mask` (one of [`sw_bit`]) is set.
    pub const fn has(self, mask: u16) -> bool {
        self.0 & mask != 0
    }

    /// The word with the bits of `mask` (one of [`sw_bit`]) set or cleared.
    pub const fn with(self, mask: u16, on: bool) -> Self {
        StatusWord(if on { self.0 | mask } else { self.0 & !mask })
    }

    /// Bit 8: ready to run.
    pub const fn ready(self) -> bool {
        self.has(sw_bit::READY)
    }

    /// Bits 9–10: the motor group.
    pub const fn motor_group(self) -> u8 {
        ((self.0 & sw_bit::MOTOR_GROUP) >> 9) as u8
    }

    /// Bits 13–14: the run/stop mode.
    pub const fn run_stop_mode(self) -> RunStopMode {
        match (self.0 & sw_bit::RUN_STOP_MODE) >> 13 {
            0 => RunStopMode::Keypad,
            1 => RunStopMode::Terminal,
            2 => RunStopMode::Communication,
            _ => RunStopMode::Reserved,
        }
    }

    /// The word with bits 13–14 set to `mode`.
    pub const fn with_run_stop_mode(self, mode: RunStopMode) -> Self {
        let bits = match mode {
            RunStopMode::Keypad => 0,
            RunStopMode::Terminal => 1,
            RunStopMode::Communication => 2,
            RunStopMode::Reserved => 3,
        };
        StatusWord(self.0 & !sw_bit::RUN_STOP_MODE | bits << 13)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_by_byte_are_table_2_5() {
        for (n, command) in Command::ALL.iter().enumerate() {
            let word = ControlWord::new(*command, WordLayout::ByByte);
            assert_eq!(word.0, n as u16 + 1);
            assert_eq!(word.command(WordLayout::ByByte), Some(*command));
        }
        assert_eq!(ControlWord(0).command(WordLayout::ByByte), None);
        assert_eq!(ControlWord(9).command(WordLayout::ByByte), None);
        // Bit 8 set beside a run command: 0101h.
        let word = ControlWord::new(Command::RunForward, WordLayout::ByByte)
            .with(cw_bit::ENABLE_WRITE, true);
        assert_eq!(word.0, 0x0101);
        assert!(word.write_enabled());
        assert_eq!(
            word.with_command(Command::FaultReset, WordLayout::ByByte).0,
            0x0107
        );
        assert_eq!(ControlWord(0x0400).motor_group(), 2);
    }

    #[test]
    fn commands_by_bit_are_table_5_6() {
        let bytes = [
            (Command::DecelerateToStop, 0x00),
            (Command::RunForward, 0x01),
            (Command::RunReverse, 0x02),
            (Command::FaultReset, 0x04),
            (Command::CoastToStop, 0x08),
            (Command::JogForward, 0x10),
            (Command::JogReverse, 0x20),
            (Command::StopJogging, 0x40),
        ];
        for (command, byte) in bytes {
            assert_eq!(command.byte(WordLayout::ByBit), byte);
            assert_eq!(Command::from_byte(byte, WordLayout::ByBit), Some(command));
        }
        assert_eq!(Command::from_byte(0x03, WordLayout::ByBit), None);
        // Coast wins over everything else.
        assert_eq!(
            Command::from_byte(0x0D, WordLayout::ByBit),
            Some(Command::CoastToStop)
        );
    }

    #[test]
    fn states_in_both_layouts_are_tables_2_7_and_5_9() {
        let states = [
            RunState::Forward,
            RunState::Reverse,
            RunState::Stopped,
            RunState::Fault,
            RunState::PowerOff,
            RunState::PreExcitation,
        ];
        for (n, state) in states.iter().enumerate() {
            let by_byte = StatusWord::new(*state, WordLayout::ByByte);
            assert_eq!(by_byte.0, n as u16 + 1);
            assert_eq!(by_byte.state(WordLayout::ByByte), Some(*state));
            let by_bit = StatusWord::new(*state, WordLayout::ByBit);
            assert_eq!(by_bit.0, 1 << n);
            assert_eq!(by_bit.state(WordLayout::ByBit), Some(*state));
        }
        assert_eq!(StatusWord(0).state(WordLayout::ByBit), None);
        assert_eq!(
            StatusWord(0x0C).state(WordLayout::ByBit),
            Some(RunState::Fault)
        );
        // Stopped, ready, communication control: 4103h.
        let word = StatusWord::new(RunState::Stopped, WordLayout::ByByte)
            .with(sw_bit::READY, true)
            .with_run_stop_mode(RunStopMode::Communication);
        assert_eq!(word.0, 0x4103);
        assert!(word.ready());
        assert_eq!(word.run_stop_mode(), RunStopMode::Communication);
        assert_eq!(StatusWord(0x6000).run_stop_mode(), RunStopMode::Reserved);
        assert_eq!(StatusWord(0x0200).motor_group(), 1);
    }
}
