//! A cyclic CiA 402 controller for masters that exchange process data every cycle (EtherCAT,
//! CANopen with SYNC-driven PDOs): each cycle it takes the statusword and the mode display
//! (6061h) and gives the controlword and the mode of operation (6060h), walking the drive with
//! [`next_command`]. It owns the fault-reset edge, the wait for the mode display, and the count
//! of cycles a transition may take; sans-IO, no_std, no allocation.

use super::{next_command, state_of};
use crate::cia402::{controlword, Command, State};

/// What a cycle's feedback says about the walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// On the way: a command is out, or the drive is moving by itself.
    Busy,
    /// The drive is in the target state and its mode display shows the requested mode.
    Reached,
    /// The drive has stayed in `state` for more cycles than the limit while the controller
    /// asked it to leave.
    Stuck {
        /// The state it stays in.
        state: State,
    },
    /// The mode display has not shown the requested mode for more cycles than the limit.
    ModeNotConfirmed {
        /// The mode requested (6060h).
        wanted: i8,
        /// The mode the drive shows (6061h).
        shown: i8,
    },
}

/// What to put in the outputs this cycle, and how the walk goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cycle {
    /// The controlword (6040h).
    pub controlword: u16,
    /// The mode of operation (6060h) to write, `None` when no mode is requested.
    pub mode: Option<i8>,
    /// How the walk goes.
    pub outcome: Outcome,
}

/// Walks a drive to a target state by cyclic process data (see the module comment).
///
/// Rules it keeps, beyond [`next_command`]:
/// - a fault reset is a rising edge of bit 7: a cycle with the bit high follows at least one
///   with it low (the first cycle counts as high, since the drive's last controlword is
///   unknown), so a reset the drive refuses is tried again every other cycle;
/// - a requested mode is written every cycle, and until the display shows it the controller
///   does not enable operation (it holds switched on); a mode change in operation enabled
///   keeps the drive enabled;
/// - with a limit, a state seen for more than `limit` cycles while the controller asks to
///   leave it, or a mode not shown for more than `limit` cycles, is reported as an
///   [`Outcome`]; the controller keeps commanding, the caller decides to give up.
///
/// ```
/// use edsgen_runtime::cia402::State;
/// use edsgen_runtime::master::cia402::{mode, Controller, Outcome};
///
/// let mut drive = Controller::new(State::OperationEnabled)
///     .with_mode(mode::CYCLIC_VELOCITY)
///     .with_limit(100);
/// // Switch on disabled, the drive still in velocity mode: shutdown, and 6060h = 9.
/// let cycle = drive.cycle(0x0240, mode::VELOCITY);
/// assert_eq!((cycle.controlword, cycle.mode), (0x06, Some(9)));
/// // Ready to switch on, mode 9 shown: switch on.
/// assert_eq!(drive.cycle(0x0221, 9).controlword, 0x07);
/// // Switched on: enable operation.
/// assert_eq!(drive.cycle(0x0223, 9).controlword, 0x0F);
/// let cycle = drive.cycle(0x0227, 9);
/// assert_eq!((cycle.controlword, cycle.outcome), (0x0F, Outcome::Reached));
/// ```
#[derive(Debug, Clone)]
pub struct Controller {
    target: State,
    mode: Option<i8>,
    operation_bits: u16,
    limit: Option<u32>,
    /// The controlword of the previous cycle.
    last: u16,
    /// The state seen in the previous cycle, and in how many cycles in a row.
    seen: Option<State>,
    seen_for: u32,
    /// Cycles in a row the display has not shown the requested mode.
    mode_pending_for: u32,
}

/// The controlword bits the controller owns: 0–3 (the state machine) and 7 (fault reset).
const STATE_BITS: u16 = 0x000F | controlword::FAULT_RESET;

impl Controller {
    /// A controller walking towards `target`: operation enabled, or switch on disabled (any
    /// other state is taken as switch on disabled, as [`next_command`] does). No mode request,
    /// no limit.
    pub const fn new(target: State) -> Self {
        Controller {
            target: Self::normalise(target),
            mode: None,
            operation_bits: 0,
            limit: None,
            // Unknown: counted as high, so that a first fault reset starts with bit 7 low.
            last: controlword::FAULT_RESET,
            seen: None,
            seen_for: 0,
            mode_pending_for: 0,
        }
    }

    /// The same, requesting mode of operation `mode` (6060h).
    pub const fn with_mode(mut self, mode: i8) -> Self {
        self.mode = Some(mode);
        self
    }

    /// The same, reporting a transition or a mode confirmation that takes more than `cycles`
    /// cycles.
    pub const fn with_limit(mut self, cycles: u32) -> Self {
        self.limit = Some(cycles);
        self
    }

    const fn normalise(target: State) -> State {
        match target {
            State::OperationEnabled => State::OperationEnabled,
            _ => State::SwitchOnDisabled,
        }
    }

    /// The target state.
    pub fn target(&self) -> State {
        self.target
    }

    /// Walks towards another target from the next cycle (the cycle counts start again).
    pub fn set_target(&mut self, target: State) {
        self.target = Self::normalise(target);
        self.seen = None;
    }

    /// The requested mode of operation.
    pub fn mode(&self) -> Option<i8> {
        self.mode
    }

    /// Requests another mode of operation from the next cycle.
    pub fn set_mode(&mut self, mode: i8) {
        self.mode = Some(mode);
        self.mode_pending_for = 0;
    }

    /// Sets the mode-specific controlword bits (4–6, 8, 9, and the manufacturer's 11–15: halt,
    /// the vl ramp bits, new set-point...) that go into the controlword while operation is
    /// enabled; bits 0–3 and 7 are the controller's and are ignored here.
    pub fn set_operation_bits(&mut self, bits: u16) {
        self.operation_bits = bits & !STATE_BITS;
    }

    /// One cycle: the drive's statusword (6041h) and mode display (6061h; ignored without a
    /// mode request) in, the controlword and mode of operation out.
    pub fn cycle(&mut self, statusword: u16, mode_display: i8) -> Cycle {
        let state = state_of(statusword);
        self.seen_for = match self.seen {
            Some(seen) if seen == state => self.seen_for.saturating_add(1),
            _ => 1,
        };
        self.seen = Some(state);
        let mode_pending = matches!(self.mode, Some(mode) if mode != mode_display);
        self.mode_pending_for = if mode_pending {
            self.mode_pending_for.saturating_add(1)
        } else {
            0
        };

        let command = match next_command(state, self.target) {
            // Not in a mode the drive has not confirmed (the mode's wait, not the state's).
            Some(Command::EnableOperation) if mode_pending => {
                self.seen_for = 0;
                Command::SwitchOn
            }
            // Bit 7 low first, then its rising edge.
            Some(Command::FaultReset) if self.last & controlword::FAULT_RESET != 0 => {
                Command::DisableVoltage
            }
            Some(command) => command,
            None => holding(state),
        };
        let mut word = command.controlword();
        if command == Command::EnableOperation {
            word |= self.operation_bits;
        }
        self.last = word;
        Cycle {
            controlword: word,
            mode: self.mode,
            outcome: self.outcome(state, mode_display, mode_pending),
        }
    }

    fn outcome(&self, state: State, mode_display: i8, mode_pending: bool) -> Outcome {
        let over = |cycles: u32| matches!(self.limit, Some(limit) if cycles > limit);
        match self.mode {
            Some(wanted) if mode_pending && over(self.mode_pending_for) => {
                return Outcome::ModeNotConfirmed {
                    wanted,
                    shown: mode_display,
                }
            }
            _ => {}
        }
        if state == self.target && !mode_pending {
            Outcome::Reached
        } else if state != self.target && over(self.seen_for) {
            Outcome::Stuck { state }
        } else {
            Outcome::Busy
        }
    }
}

/// The command that keeps a drive where it is, for a state the controller does not move it
/// from (or cannot: not ready to switch on, fault reaction active).
const fn holding(state: State) -> Command {
    match state {
        State::OperationEnabled => Command::EnableOperation,
        State::SwitchedOn => Command::SwitchOn,
        State::ReadyToSwitchOn => Command::Shutdown,
        _ => Command::DisableVoltage,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cia402::mode;

    /// Statuswords as a drive with voltage and remote reports them.
    fn status(state: State) -> u16 {
        state.statusword() | 0x0210
    }

    #[test]
    fn walks_to_operation_enabled_and_holds_it() {
        let mut controller = Controller::new(State::OperationEnabled);
        let mut words = [0u16; 5];
        let states = [
            State::NotReadyToSwitchOn,
            State::SwitchOnDisabled,
            State::ReadyToSwitchOn,
            State::SwitchedOn,
            State::OperationEnabled,
        ];
        for (word, state) in words.iter_mut().zip(states) {
            let cycle = controller.cycle(status(state), 0);
            *word = cycle.controlword;
            assert_eq!(cycle.mode, None);
            let reached = state == State::OperationEnabled;
            assert_eq!(cycle.outcome == Outcome::Reached, reached, "{state:?}");
        }
        assert_eq!(words, [0x00, 0x06, 0x07, 0x0F, 0x0F]);
    }

    #[test]
    fn operation_bits_go_with_enable_operation_only() {
        let mut controller = Controller::new(State::OperationEnabled);
        controller.set_operation_bits(0x01F0 | 0x008F);
        assert_eq!(
            controller.cycle(status(State::SwitchedOn), 0).controlword,
            0x0F | 0x170
        );
        // Bit 7 was low in that word: the reset edge at once, without the operation bits.
        assert_eq!(controller.cycle(status(State::Fault), 0).controlword, 0x80);
        assert_eq!(
            controller
                .cycle(status(State::SwitchOnDisabled), 0)
                .controlword,
            0x06
        );
    }

    #[test]
    fn a_fault_reset_is_a_rising_edge_tried_again_every_other_cycle() {
        let mut controller = Controller::new(State::OperationEnabled).with_limit(3);
        let words: [(u16, Outcome); 5] = core::array::from_fn(|_| {
            let cycle = controller.cycle(status(State::Fault), 0);
            (cycle.controlword, cycle.outcome)
        });
        let stuck = Outcome::Stuck {
            state: State::Fault,
        };
        assert_eq!(
            words,
            [
                (0x00, Outcome::Busy),
                (0x80, Outcome::Busy),
                (0x00, Outcome::Busy),
                (0x80, stuck),
                (0x00, stuck)
            ]
        );
        // The reset took: on to operation enabled.
        let cycle = controller.cycle(status(State::SwitchOnDisabled), 0);
        assert_eq!((cycle.controlword, cycle.outcome), (0x06, Outcome::Busy));
    }

    #[test]
    fn a_first_fault_reset_after_a_low_bit_7_is_at_once() {
        let mut controller = Controller::new(State::OperationEnabled);
        assert_eq!(
            controller
                .cycle(status(State::OperationEnabled), 0)
                .controlword,
            0x0F
        );
        assert_eq!(
            controller
                .cycle(status(State::FaultReactionActive), 0)
                .controlword,
            0x00
        );
        assert_eq!(controller.cycle(status(State::Fault), 0).controlword, 0x80);
    }

    #[test]
    fn the_mode_request_holds_switched_on_until_the_display_confirms_it() {
        let mut controller = Controller::new(State::OperationEnabled)
            .with_mode(mode::CYCLIC_VELOCITY)
            .with_limit(2);
        let run = |controller: &mut Controller, state, shown| {
            let cycle = controller.cycle(status(state), shown);
            assert_eq!(cycle.mode, Some(9));
            (cycle.controlword, cycle.outcome)
        };
        assert_eq!(
            run(&mut controller, State::SwitchedOn, mode::VELOCITY),
            (0x07, Outcome::Busy)
        );
        assert_eq!(
            run(&mut controller, State::SwitchedOn, mode::VELOCITY),
            (0x07, Outcome::Busy)
        );
        assert_eq!(
            run(&mut controller, State::SwitchedOn, mode::VELOCITY),
            (
                0x07,
                Outcome::ModeNotConfirmed {
                    wanted: 9,
                    shown: 2
                }
            )
        );
        assert_eq!(
            run(&mut controller, State::SwitchedOn, 9),
            (0x0F, Outcome::Busy)
        );
        assert_eq!(
            run(&mut controller, State::OperationEnabled, 9),
            (0x0F, Outcome::Reached)
        );
        // A mode change while enabled keeps the drive enabled until it shows.
        controller.set_mode(mode::CYCLIC_POSITION);
        let cycle = controller.cycle(status(State::OperationEnabled), 9);
        assert_eq!(
            (cycle.controlword, cycle.mode, cycle.outcome),
            (0x0F, Some(8), Outcome::Busy)
        );
        let cycle = controller.cycle(status(State::OperationEnabled), 8);
        assert_eq!(cycle.outcome, Outcome::Reached);
    }

    #[test]
    fn disabling_walks_down_and_holds_switch_on_disabled() {
        let mut controller = Controller::new(State::OperationEnabled);
        assert_eq!(
            controller.cycle(status(State::OperationEnabled), 0).outcome,
            Outcome::Reached
        );
        controller.set_target(State::SwitchedOn); // taken as switch on disabled
        assert_eq!(controller.target(), State::SwitchOnDisabled);
        let cycle = controller.cycle(status(State::OperationEnabled), 0);
        assert_eq!((cycle.controlword, cycle.outcome), (0x00, Outcome::Busy));
        let cycle = controller.cycle(status(State::SwitchOnDisabled), 0);
        assert_eq!((cycle.controlword, cycle.outcome), (0x00, Outcome::Reached));
    }

    #[test]
    fn a_transition_within_the_limit_is_not_stuck() {
        let mut controller = Controller::new(State::OperationEnabled).with_limit(2);
        let sod = status(State::SwitchOnDisabled);
        assert_eq!(controller.cycle(sod, 0).outcome, Outcome::Busy);
        assert_eq!(controller.cycle(sod, 0).outcome, Outcome::Busy);
        assert_eq!(
            controller.cycle(sod, 0).outcome,
            Outcome::Stuck {
                state: State::SwitchOnDisabled
            }
        );
        let rtso = status(State::ReadyToSwitchOn);
        assert_eq!(controller.cycle(rtso, 0).outcome, Outcome::Busy);
        // A pattern that codes no state reads as not ready to switch on.
        assert_eq!(controller.cycle(0x0061, 0).controlword, 0x00);
    }
}
