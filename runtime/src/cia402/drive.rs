//! The device-side drive: the CiA 402 state machine, its option codes, and the velocity mode (vl)
//! ramp function generator; optionally cyclic synchronous velocity (csv) too, where the target is
//! the set-point without the vl bits and the same ramp times bound the acceleration (the drive's
//! own limit; a master that generates the trajectory stays within it).
//!
//! The velocity is modelled as the ramp's output (6043h demand); the actual velocity (6044h)
//! follows the demand exactly, because a drive model with slip or load belongs to the
//! application that simulates a particular drive. The ramp is computed from elapsed time, so the
//! result does not depend on how often [`Drive::update`] is called.

use super::{controlword, mode, statusword, Command, State};
use crate::time::{Duration, Instant};

/// The ramp a drive uses to come to a stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StopRamp {
    /// Disable the drive function at once: the demand drops to zero (option code 0).
    Disable,
    /// Decelerate on the slow-down ramp (6050h).
    SlowDown,
    /// Decelerate on the quick-stop ramp (6051h).
    QuickStop,
}

/// The drive's parameters: the CiA 402 objects that shape its behaviour, with the CP301's
/// defaults (CP301 manual §8.2). [`Drive::run_on`] refreshes them from a dictionary that holds
/// them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveConfig {
    /// The speed, in the unit of 6042h, that the ramp times refer to (CP301: parameter 01-09,
    /// P.20): 604Fh is the time from 0 to this speed.
    pub max_speed: u16,
    /// 604Fh vl ramp function time, ms: acceleration from 0 to `max_speed`.
    pub ramp_time_ms: u32,
    /// 6050h vl slow down time, ms: deceleration from `max_speed` to 0.
    pub slow_down_time_ms: u32,
    /// 6051h vl quick stop time, ms.
    pub quick_stop_time_ms: u32,
    /// 605Ah quick stop option code: 0 disable; 1 slow-down ramp, 2 quick-stop ramp, then
    /// switch on disabled; 5 slow-down ramp, 6 quick-stop ramp, then stay in quick stop active.
    /// Codes 3 and 4 (current and voltage limit) stop on the quick-stop ramp as 2 does, 7 and 8
    /// as 6 does: this drive has no current or voltage limit to ramp on.
    pub quick_stop_option: i16,
    /// 605Bh shutdown option code (operation enabled → ready to switch on): 0 disable, 1 slow
    /// down first.
    pub shutdown_option: i16,
    /// 605Ch disable operation option code (operation enabled → switched on): 0 disable, 1 slow
    /// down first.
    pub disable_operation_option: i16,
    /// 605Eh fault reaction option code: 0 disable, 1 slow-down ramp, 2 quick-stop ramp.
    pub fault_reaction_option: i16,
    /// 6007h abort connection option code, applied by [`Drive::connection_lost`]: 0 nothing,
    /// 1 fault, 2 disable voltage, 3 quick stop.
    pub abort_connection_option: i16,
    /// Whether the drive runs cyclic synchronous velocity (6060h = 9) besides velocity mode.
    pub cyclic_velocity: bool,
}

impl DriveConfig {
    /// The CP301's defaults (604Fh 10 s, 6050h 10 s, 6051h 1 s, 605Ah 2, 605Bh 0, 605Ch 1) for
    /// a drive whose ramp times refer to `max_speed`; 605Eh 2 and 6007h 1 as CiA 402 proposes;
    /// velocity mode only.
    pub const fn new(max_speed: u16) -> Self {
        DriveConfig {
            max_speed,
            ramp_time_ms: 10_000,
            slow_down_time_ms: 10_000,
            quick_stop_time_ms: 1_000,
            quick_stop_option: 2,
            shutdown_option: 0,
            disable_operation_option: 1,
            fault_reaction_option: 2,
            abort_connection_option: 1,
            cyclic_velocity: false,
        }
    }

    fn ramp_for_option(option: i16) -> StopRamp {
        match option {
            0 => StopRamp::Disable,
            1 | 5 => StopRamp::SlowDown,
            _ => StopRamp::QuickStop,
        }
    }

    fn ramp_time_ms(&self, ramp: StopRamp) -> u32 {
        match ramp {
            StopRamp::Disable => 0,
            StopRamp::SlowDown => self.slow_down_time_ms,
            StopRamp::QuickStop => self.quick_stop_time_ms,
        }
    }
}

/// Where a stop leads once the drive stands still.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AfterStop {
    /// The state already changed; the stop only brings the demand down.
    Nothing,
    /// Quick stop with option 1–4: on to switch on disabled.
    SwitchOnDisabled,
    /// Fault reaction: on to fault.
    Fault,
}

/// A stop in progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Stop {
    ramp: StopRamp,
    then: AfterStop,
}

/// A CiA 402 drive in velocity mode (or cyclic synchronous velocity): feed it controlwords ([`Drive::set_controlword`]), targets
/// and time ([`Drive::update`]); read its statusword and velocities.
#[derive(Debug, Clone)]
pub struct Drive {
    config: DriveConfig,
    state: State,
    /// The mode of operation in effect (6061h).
    mode: i8,
    controlword: u16,
    target: i16,
    /// The ramp output in thousandths of the velocity unit, so that slow ramps still move.
    demand_milli: i32,
    stop: Option<Stop>,
    fault_present: bool,
    warning: bool,
    updated: Instant,
}

/// How often a moving drive wants [`Drive::update`], so that 6043h/6044h read fresh.
pub const UPDATE_PERIOD: Duration = Duration::from_millis(10);

impl Drive {
    /// A drive that has just powered up: switch on disabled (transitions 0 and 1 are
    /// automatic), standing still.
    pub const fn new(config: DriveConfig, now: Instant) -> Self {
        Drive {
            config,
            state: State::SwitchOnDisabled,
            mode: mode::VELOCITY,
            controlword: 0,
            target: 0,
            demand_milli: 0,
            stop: None,
            fault_present: false,
            warning: false,
            updated: now,
        }
    }

    /// The parameters.
    pub fn config(&self) -> &DriveConfig {
        &self.config
    }

    /// The parameters, to change (a write to 604Fh …).
    pub fn config_mut(&mut self) -> &mut DriveConfig {
        &mut self.config
    }

    /// The state.
    pub fn state(&self) -> State {
        self.state
    }

    /// The mode of operation in effect (6061h modes of operation display): velocity mode
    /// until [`set_mode`](Self::set_mode) changes it.
    pub fn mode(&self) -> i8 {
        self.mode
    }

    /// Takes a mode of operation (a write to 6060h): velocity mode, or cyclic synchronous
    /// velocity if the configuration has it. Returns whether the drive now runs it; another
    /// mode leaves the one in effect.
    pub fn set_mode(&mut self, now: Instant, requested: i8) -> bool {
        let runs = requested == mode::VELOCITY
            || (requested == mode::CYCLIC_VELOCITY && self.config.cyclic_velocity);
        if runs && requested != self.mode {
            self.update(now);
            self.mode = requested;
        }
        runs
    }

    /// Whether the vl bits (4–6) of the controlword drive the ramp: in velocity mode only.
    fn vl(&self) -> bool {
        self.mode == mode::VELOCITY
    }

    /// The last controlword received.
    pub fn controlword(&self) -> u16 {
        self.controlword
    }

    /// The statusword (6041h): the state's bits, voltage enabled and remote (a VFD on a CANopen
    /// card has its DC bus up and obeys the bus), warning, target reached, internal limit.
    pub fn statusword(&self) -> u16 {
        let mut word = self.state.statusword() | statusword::VOLTAGE_ENABLED | statusword::REMOTE;
        if self.warning {
            word |= statusword::WARNING;
        }
        if self.demand_milli == self.setpoint_milli() && self.stop.is_none() {
            word |= statusword::TARGET_REACHED;
        }
        if self.target_clamped() && self.state == State::OperationEnabled {
            word |= statusword::INTERNAL_LIMIT;
        }
        word
    }

    /// 6042h vl target velocity.
    pub fn target(&self) -> i16 {
        self.target
    }

    /// Sets 6042h; the ramp moves towards it from the next [`update`](Self::update).
    pub fn set_target(&mut self, now: Instant, target: i16) {
        self.update(now);
        self.target = target;
    }

    /// 6043h vl velocity demand: the ramp's output.
    pub fn velocity_demand(&self) -> i16 {
        (self.demand_milli / 1000) as i16
    }

    /// 6044h vl velocity actual value (the demand; see the module comment).
    pub fn velocity_actual(&self) -> i16 {
        self.velocity_demand()
    }

    /// Whether a fault is present (raised and not cleared).
    pub fn fault_present(&self) -> bool {
        self.fault_present
    }

    /// Sets or clears the warning bit (7).
    pub fn set_warning(&mut self, warning: bool) {
        self.warning = warning;
    }

    /// Takes a controlword (a write to 6040h): runs the transition its command asks for in the
    /// present state, if the state machine has one; other commands are ignored, as CiA 402 says.
    pub fn set_controlword(&mut self, now: Instant, word: u16) {
        self.update(now);
        let previous = core::mem::replace(&mut self.controlword, word);
        if let Some(command) = Command::from_controlword(word, previous) {
            self.apply(command);
        }
        // The vl bits act at once (bit 4 clear zeroes the demand).
        self.update(now);
    }

    /// The application reports a fault (transition 13): the fault reaction of 605Eh runs, then
    /// the drive is in fault until the fault is cleared and reset.
    pub fn raise_fault(&mut self, now: Instant) {
        self.update(now);
        self.fault_present = true;
        if matches!(self.state, State::FaultReactionActive | State::Fault) {
            return;
        }
        let ramp = DriveConfig::ramp_for_option(self.config.fault_reaction_option);
        self.state = State::FaultReactionActive;
        self.begin_stop(ramp, AfterStop::Fault);
    }

    /// The application reports the fault's cause gone: a fault reset (bit 7 rising) now leaves
    /// the fault state (transition 15).
    pub fn clear_fault(&mut self) {
        self.fault_present = false;
    }

    /// The node lost its master (heartbeat or life guarding): acts as 6007h says.
    pub fn connection_lost(&mut self, now: Instant) {
        match self.config.abort_connection_option {
            1 => self.raise_fault(now),
            2 => {
                self.update(now);
                self.apply(Command::DisableVoltage);
            }
            3 => {
                self.update(now);
                self.apply(Command::QuickStop);
            }
            _ => {}
        }
    }

    /// When the drive next wants [`update`](Self::update): every [`UPDATE_PERIOD`] while the
    /// demand moves or a stop runs, never while it stands.
    pub fn next_update(&self) -> Option<Instant> {
        let settled = self.stop.is_none()
            && (self.demand_milli == self.setpoint_milli() || self.ramp_locked());
        (!settled).then(|| self.updated + UPDATE_PERIOD)
    }

    /// Operation enabled with the ramp function generator on but locked (bit 4 set, bit 5
    /// clear, no halt): the demand holds where it is.
    fn ramp_locked(&self) -> bool {
        let word = self.controlword;
        self.vl()
            && self.state == State::OperationEnabled
            && word & controlword::HALT == 0
            && word & controlword::VL_RAMP_ENABLE != 0
            && word & controlword::VL_RAMP_UNLOCK == 0
    }

    /// Advances the ramp to `now`, and ends a stop whose ramp reached zero.
    pub fn update(&mut self, now: Instant) {
        let elapsed_us = now.saturating_since(self.updated).as_micros();
        self.updated = now.max(self.updated);
        if let Some(stop) = self.stop {
            let time_ms = self.config.ramp_time_ms(stop.ramp);
            self.demand_milli = self.ramp_towards(0, time_ms, time_ms, elapsed_us);
            if self.demand_milli == 0 {
                self.stop = None;
                match stop.then {
                    AfterStop::Nothing => {}
                    AfterStop::SwitchOnDisabled => self.state = State::SwitchOnDisabled,
                    AfterStop::Fault => self.state = State::Fault,
                }
            }
            return;
        }
        let halting = self.controlword & controlword::HALT != 0;
        if self.vl()
            && self.state == State::OperationEnabled
            && !halting
            && self.controlword & controlword::VL_RAMP_ENABLE == 0
        {
            self.demand_milli = 0; // ramp function generator disabled: output zero
            return;
        }
        if self.ramp_locked() {
            return;
        }
        let setpoint = self.setpoint_milli();
        let accelerate_ms = if halting {
            self.config.slow_down_time_ms
        } else {
            self.config.ramp_time_ms
        };
        self.demand_milli = self.ramp_towards(
            setpoint,
            accelerate_ms,
            self.config.slow_down_time_ms,
            elapsed_us,
        );
    }

    /// Where the ramp is heading now, in thousandths.
    fn setpoint_milli(&self) -> i32 {
        let vl_bits = controlword::VL_RAMP_ENABLE | controlword::VL_REFERENCE;
        let follows = self.state == State::OperationEnabled
            && self.controlword & controlword::HALT == 0
            && (!self.vl() || self.controlword & vl_bits == vl_bits);
        if !follows {
            return 0;
        }
        let limit = i32::from(self.config.max_speed.min(i16::MAX as u16));
        i32::from(self.target).clamp(-limit, limit) * 1000
    }

    fn target_clamped(&self) -> bool {
        i32::from(self.target).unsigned_abs() > u32::from(self.config.max_speed)
    }

    /// The demand after `elapsed_us` of ramping towards `setpoint`: away from zero at the rate
    /// of `accelerate_ms`, towards zero at the rate of `decelerate_ms` (both times from 0 to
    /// `max_speed`; 0 ms jumps). Crossing zero decelerates first, then accelerates.
    fn ramp_towards(
        &self,
        setpoint: i32,
        accelerate_ms: u32,
        decelerate_ms: u32,
        elapsed_us: u64,
    ) -> i32 {
        let mut demand = self.demand_milli;
        let mut budget_us = elapsed_us;
        // At most two segments: down to zero, then up on the other side.
        for _ in 0..2 {
            if demand == setpoint {
                break;
            }
            let towards_zero = demand != 0
                && (setpoint.signum() != demand.signum() || setpoint.abs() < demand.abs());
            let (goal, time_ms) = if towards_zero {
                (
                    if setpoint.signum() == demand.signum() {
                        setpoint
                    } else {
                        0
                    },
                    decelerate_ms,
                )
            } else {
                (setpoint, accelerate_ms)
            };
            let distance = u64::from(goal.abs_diff(demand));
            // Thousandths per microsecond: max_speed × 1000 / (time_ms × 1000).
            let reach = if time_ms == 0 {
                distance
            } else {
                u64::from(self.config.max_speed) * budget_us / u64::from(time_ms)
            };
            if reach >= distance {
                demand = goal;
                if time_ms != 0 {
                    // The time that segment took, from its distance.
                    let used =
                        distance * u64::from(time_ms) / u64::from(self.config.max_speed.max(1));
                    budget_us = budget_us.saturating_sub(used);
                }
            } else {
                let step = reach as i32;
                demand += if goal > demand { step } else { -step };
                break;
            }
        }
        demand
    }

    fn begin_stop(&mut self, ramp: StopRamp, then: AfterStop) {
        self.stop = Some(Stop { ramp, then });
        if ramp == StopRamp::Disable || self.demand_milli == 0 {
            self.demand_milli = 0;
            self.stop = None;
            match then {
                AfterStop::Nothing => {}
                AfterStop::SwitchOnDisabled => self.state = State::SwitchOnDisabled,
                AfterStop::Fault => self.state = State::Fault,
            }
        }
    }

    /// The transition `command` asks for in the present state (CiA 402-2 table "transitions").
    fn apply(&mut self, command: Command) {
        use Command::*;
        use State::*;
        let option_ramp = DriveConfig::ramp_for_option;
        match (self.state, command) {
            // 2: shutdown.
            (SwitchOnDisabled, Shutdown) => self.state = ReadyToSwitchOn,
            // 3, and 3 + 4 when operation is enabled in the same word.
            (ReadyToSwitchOn, SwitchOn) => self.state = SwitchedOn,
            (ReadyToSwitchOn, EnableOperation) | (SwitchedOn, EnableOperation) => {
                self.state = OperationEnabled
            }
            // 6: shutdown from switched on.
            (SwitchedOn, Shutdown) => self.state = ReadyToSwitchOn,
            // 5: disable operation, stopping as 605Ch says.
            (OperationEnabled, SwitchOn) => {
                self.state = SwitchedOn;
                self.begin_stop(
                    option_ramp(self.config.disable_operation_option),
                    AfterStop::Nothing,
                );
            }
            // 8: shutdown from operation enabled, stopping as 605Bh says.
            (OperationEnabled, Shutdown) => {
                self.state = ReadyToSwitchOn;
                self.begin_stop(option_ramp(self.config.shutdown_option), AfterStop::Nothing);
            }
            // 11: quick stop, as 605Ah says.
            (OperationEnabled, QuickStop) => {
                self.state = QuickStopActive;
                let option = self.config.quick_stop_option;
                let then = if (5..=8).contains(&option) {
                    AfterStop::Nothing
                } else {
                    AfterStop::SwitchOnDisabled
                };
                self.begin_stop(option_ramp(option), then);
            }
            // 16: back to operation from a holding quick stop (option codes 5–8 only).
            (QuickStopActive, EnableOperation)
                if (5..=8).contains(&self.config.quick_stop_option) =>
            {
                self.stop = None;
                self.state = OperationEnabled;
            }
            // 7, 10: disable voltage or quick stop where nothing moves.
            (ReadyToSwitchOn | SwitchedOn, DisableVoltage | QuickStop) => {
                self.state = SwitchOnDisabled
            }
            // 9, 12: disable voltage: the drive function stops at once.
            (OperationEnabled | QuickStopActive, DisableVoltage) => {
                self.state = SwitchOnDisabled;
                self.stop = None;
                self.demand_milli = 0;
            }
            // 15: fault reset, once the fault is gone.
            (Fault, FaultReset) if !self.fault_present => self.state = SwitchOnDisabled,
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(ms: u64) -> Instant {
        Instant::from_millis(ms)
    }

    /// A CP301-like drive whose ramp times refer to 3000 rpm: 604Fh 5 s up, 6050h 10 s down,
    /// 6051h 1 s quick stop; so 600 rpm/s up, 300 rpm/s down, 3000 rpm/s quick stop.
    fn drive() -> Drive {
        let mut config = DriveConfig::new(3000);
        config.ramp_time_ms = 5_000;
        Drive::new(config, at(0))
    }

    /// Brings the drive to operation enabled with the vl bits set (CP301 §5.3: 06h, 07h, 0Fh,
    /// 7Fh) at `ms`.
    fn enable(drive: &mut Drive, ms: u64) {
        for word in [0x06, 0x07, 0x0F, 0x7F] {
            drive.set_controlword(at(ms), word);
        }
    }

    #[test]
    fn cp301_velocity_sequence_ramps_up_and_reverses() {
        let mut drive = drive();
        assert_eq!(drive.statusword(), 0x0650); // switch on disabled, voltage, remote, at rest
        drive.set_target(at(0), 1500);
        drive.set_controlword(at(0), 0x06);
        assert_eq!(drive.statusword(), 0x0631);
        drive.set_controlword(at(0), 0x07);
        assert_eq!(drive.statusword(), 0x0633);
        drive.set_controlword(at(0), 0x0F);
        assert_eq!(drive.state(), State::OperationEnabled);
        assert_eq!(drive.statusword(), 0x0637); // bits 4–6 clear: nothing to reach
        drive.set_controlword(at(0), 0x7F);
        assert_eq!(drive.statusword(), 0x0237); // now heading for 1500 rpm
        assert_eq!(drive.next_update(), Some(at(10)));

        drive.update(at(1_000));
        assert_eq!(drive.velocity_demand(), 600);
        drive.update(at(2_500));
        assert_eq!(drive.velocity_demand(), 1500);
        assert_eq!(drive.velocity_actual(), 1500);
        assert_eq!(drive.statusword(), 0x0637);
        assert_eq!(drive.next_update(), None);

        // -1500 reverses: 5 s down on the slow-down ramp, then 2.5 s up on the other side.
        drive.set_target(at(3_000), -1500);
        drive.update(at(5_500));
        assert_eq!(drive.velocity_demand(), 750);
        drive.update(at(8_000));
        assert_eq!(drive.velocity_demand(), 0);
        drive.update(at(9_000));
        assert_eq!(drive.velocity_demand(), -600);
        drive.update(at(10_500));
        assert_eq!(drive.velocity_demand(), -1500);
    }

    #[test]
    fn a_reversal_within_one_update_ramps_through_zero() {
        let mut drive = drive();
        drive.set_target(at(0), 300);
        enable(&mut drive, 0);
        drive.update(at(500));
        assert_eq!(drive.velocity_demand(), 300);
        // 1 s down (300 rpm at 300 rpm/s), then 0.5 s up at 600 rpm/s: -300.
        drive.set_target(at(500), -1500);
        drive.update(at(2_000));
        assert_eq!(drive.velocity_demand(), -300);
    }

    #[test]
    fn vl_bits_enable_lock_and_reference_the_ramp() {
        let mut drive = drive();
        drive.set_target(at(0), 1500);
        enable(&mut drive, 0);
        drive.update(at(1_000));
        assert_eq!(drive.velocity_demand(), 600);
        // Bit 5 clear: the ramp is locked, the demand holds, no update needed.
        drive.set_controlword(at(1_000), 0x5F);
        drive.update(at(2_000));
        assert_eq!(drive.velocity_demand(), 600);
        assert_eq!(drive.next_update(), None);
        // Bit 6 clear: the ramp runs towards zero on the slow-down ramp.
        drive.set_controlword(at(2_000), 0x3F);
        drive.update(at(3_000));
        assert_eq!(drive.velocity_demand(), 300);
        // Bit 4 clear: the output is zero at once.
        drive.set_controlword(at(3_000), 0x6F);
        assert_eq!(drive.velocity_demand(), 0);
    }

    #[test]
    fn halt_stops_on_the_slow_down_ramp_and_reports_target_reached() {
        let mut drive = drive();
        drive.set_target(at(0), 600);
        enable(&mut drive, 0);
        drive.update(at(1_000));
        drive.set_controlword(at(1_000), 0x17F);
        drive.update(at(2_000));
        assert_eq!(drive.velocity_demand(), 300);
        assert_eq!(drive.statusword() & statusword::TARGET_REACHED, 0);
        drive.update(at(3_000));
        assert_eq!(drive.velocity_demand(), 0);
        assert_eq!(drive.statusword(), 0x0637);
    }

    #[test]
    fn quick_stop_option_2_ramps_down_then_disables() {
        let mut drive = drive();
        drive.set_target(at(0), 1500);
        enable(&mut drive, 0);
        drive.update(at(2_500));
        drive.set_controlword(at(2_500), 0x7B); // bit 2 clear: quick stop
        assert_eq!(drive.state(), State::QuickStopActive);
        assert_eq!(drive.statusword(), 0x0217);
        drive.update(at(2_750)); // 3000 rpm/s on 6051h
        assert_eq!(drive.velocity_demand(), 750);
        drive.update(at(3_000));
        assert_eq!(drive.velocity_demand(), 0);
        assert_eq!(drive.state(), State::SwitchOnDisabled);
        // Not reversible: enable operation is ignored in switch on disabled.
        drive.set_controlword(at(3_000), 0x7F);
        assert_eq!(drive.state(), State::SwitchOnDisabled);
    }

    #[test]
    fn quick_stop_option_6_holds_and_returns_to_operation() {
        let mut drive = drive();
        drive.config_mut().quick_stop_option = 6;
        drive.set_target(at(0), 1500);
        enable(&mut drive, 0);
        drive.update(at(2_500));
        drive.set_controlword(at(2_500), 0x7B);
        drive.update(at(4_000));
        assert_eq!(drive.velocity_demand(), 0);
        assert_eq!(drive.state(), State::QuickStopActive);
        drive.set_controlword(at(4_000), 0x7F);
        assert_eq!(drive.state(), State::OperationEnabled);
        drive.update(at(5_000));
        assert_eq!(drive.velocity_demand(), 600);
    }

    #[test]
    fn shutdown_and_disable_operation_follow_their_option_codes() {
        // 605Bh = 0: shutdown drops the drive function at once.
        let mut drive = drive();
        drive.set_target(at(0), 1500);
        enable(&mut drive, 0);
        drive.update(at(2_500));
        drive.set_controlword(at(2_500), 0x06);
        assert_eq!(drive.state(), State::ReadyToSwitchOn);
        assert_eq!(drive.velocity_demand(), 0);

        // 605Ch = 1: disable operation slows down on 6050h first.
        let mut drive = self::drive();
        drive.set_target(at(0), 1500);
        enable(&mut drive, 0);
        drive.update(at(2_500));
        drive.set_controlword(at(2_500), 0x07);
        assert_eq!(drive.state(), State::SwitchedOn);
        drive.update(at(3_500));
        assert_eq!(drive.velocity_demand(), 1200);
        drive.update(at(7_500));
        assert_eq!(drive.velocity_demand(), 0);
        assert_eq!(drive.next_update(), None);
    }

    #[test]
    fn a_fault_reacts_then_resets_only_once_cleared() {
        let mut drive = drive();
        drive.set_target(at(0), 1500);
        enable(&mut drive, 0);
        drive.update(at(2_500));
        drive.raise_fault(at(2_500)); // 605Eh = 2: quick-stop ramp
        assert_eq!(drive.state(), State::FaultReactionActive);
        assert_eq!(drive.statusword(), 0x021F);
        drive.update(at(3_000));
        assert_eq!(drive.state(), State::Fault);
        assert_eq!(drive.statusword(), 0x0618);
        // Reset while the fault is still present: stays in fault.
        drive.set_controlword(at(3_000), 0x80);
        assert_eq!(drive.state(), State::Fault);
        drive.clear_fault();
        // Bit 7 is still set: no new edge.
        drive.set_controlword(at(3_000), 0x80);
        assert_eq!(drive.state(), State::Fault);
        drive.set_controlword(at(3_000), 0x00);
        drive.set_controlword(at(3_000), 0x80);
        assert_eq!(drive.state(), State::SwitchOnDisabled);
    }

    #[test]
    fn connection_loss_acts_as_6007h_says() {
        for (option, state) in [
            (0, State::OperationEnabled),
            (1, State::FaultReactionActive),
            (2, State::SwitchOnDisabled),
            (3, State::QuickStopActive),
        ] {
            let mut drive = drive();
            drive.config_mut().abort_connection_option = option;
            drive.set_target(at(0), 1500);
            enable(&mut drive, 0);
            drive.update(at(2_500));
            drive.connection_lost(at(2_500));
            assert_eq!(drive.state(), state, "6007h = {option}");
        }
    }

    #[test]
    fn cyclic_velocity_follows_the_target_without_the_vl_bits_when_configured() {
        let mut drive = drive();
        assert!(!drive.set_mode(at(0), mode::CYCLIC_VELOCITY));
        assert_eq!(drive.mode(), mode::VELOCITY);
        drive.config_mut().cyclic_velocity = true;
        assert!(drive.set_mode(at(0), mode::CYCLIC_VELOCITY));
        assert!(!drive.set_mode(at(0), mode::CYCLIC_POSITION));
        assert_eq!(drive.mode(), mode::CYCLIC_VELOCITY);
        drive.set_target(at(0), 1500);
        for word in [0x06, 0x07, 0x0F] {
            drive.set_controlword(at(0), word);
        }
        drive.update(at(1_000));
        assert_eq!(drive.velocity_demand(), 600);
        // Halt (bit 8) stops on the slow-down ramp as in vl.
        drive.set_controlword(at(1_000), 0x10F);
        drive.update(at(2_000));
        assert_eq!(drive.velocity_demand(), 300);
        // Back to vl: bits 4–6 clear zero the demand.
        assert!(drive.set_mode(at(2_000), mode::VELOCITY));
        drive.set_controlword(at(2_000), 0x0F);
        assert_eq!(drive.velocity_demand(), 0);
    }

    #[test]
    fn a_target_beyond_the_maximum_speed_is_clamped_and_flagged() {
        let mut drive = drive();
        drive.set_target(at(0), 4000);
        enable(&mut drive, 0);
        drive.update(at(10_000));
        assert_eq!(drive.velocity_demand(), 3000);
        assert_eq!(drive.statusword(), 0x0E37);
    }
}
