//! A simple variable-frequency drive behind a communication card: a parameter table with ranges
//! and access rules, an output frequency that follows its reference on the acceleration and
//! deceleration ramps, DC-bus voltage, output voltage and current that move plausibly with it,
//! and faults that a test injects.
//!
//! The electrical model is deliberately small: V/f control with the rated voltage at the rated
//! frequency, a DC bus that sags a little under load, a current of a no-load part plus a part
//! proportional to speed, and more while the drive accelerates. It makes the values a master reads
//! move the way a real drive's do, not match any particular motor.

use edsgen_runtime::{Duration, Instant};

/// Who may change a parameter, and when (the manuals' "modify" column).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Modify {
    /// At any time.
    Always,
    /// Only while the drive is stopped.
    Stopped,
    /// Never from outside (a monitored value or a fault record).
    ReadOnly,
}

/// One parameter: its address in the card's encoding, default, range and access rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParameterSpec {
    /// The address the card's protocol uses (Goodrive350: group in the high byte, number in the
    /// low byte, so P15.13 is 0F0Dh).
    pub address: u16,
    /// The value at power-on.
    pub default: u16,
    /// The lowest value a write may set.
    pub min: u16,
    /// The highest value a write may set.
    pub max: u16,
    /// Who may change it.
    pub modify: Modify,
}

/// Why a parameter write was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterError {
    /// No parameter has this address.
    NoSuchParameter,
    /// The parameter is read-only.
    ReadOnly,
    /// The value is outside the parameter's range.
    OutOfRange,
    /// The parameter may be changed only while the drive is stopped.
    WhileRunning,
}

/// The parameter table: specifications sorted by address, and the present values.
#[derive(Debug, Clone)]
pub struct Parameters {
    specs: &'static [ParameterSpec],
    values: Vec<u16>,
}

impl Parameters {
    /// A table at its defaults. `specs` must be sorted by address (checked by the cards' tests).
    pub fn new(specs: &'static [ParameterSpec]) -> Self {
        Parameters {
            specs,
            values: specs.iter().map(|spec| spec.default).collect(),
        }
    }

    fn position(&self, address: u16) -> Option<usize> {
        self.specs
            .binary_search_by_key(&address, |spec| spec.address)
            .ok()
    }

    /// The value of a parameter, `None` if there is none at `address`.
    pub fn get(&self, address: u16) -> Option<u16> {
        self.position(address).map(|i| self.values[i])
    }

    /// A write from the bus, checked against the parameter's range and access rule.
    pub fn set(&mut self, address: u16, value: u16, running: bool) -> Result<(), ParameterError> {
        let i = self
            .position(address)
            .ok_or(ParameterError::NoSuchParameter)?;
        let spec = self.specs[i];
        match spec.modify {
            Modify::ReadOnly => return Err(ParameterError::ReadOnly),
            Modify::Stopped if running => return Err(ParameterError::WhileRunning),
            _ => {}
        }
        if !(spec.min..=spec.max).contains(&value) {
            return Err(ParameterError::OutOfRange);
        }
        self.values[i] = value;
        Ok(())
    }

    /// Sets a value the drive itself keeps (a fault record), bypassing the checks. Ignored for an
    /// address with no parameter.
    pub fn record(&mut self, address: u16, value: u16) {
        if let Some(i) = self.position(address) {
            self.values[i] = value;
        }
    }
}

/// The drive's rated data and ramps, in the units the cards use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ratings {
    /// Maximum output frequency in 0.01 Hz: the ramp times refer to it.
    pub max_frequency: u32,
    /// Rated motor voltage in V, reached at the rated frequency (V/f).
    pub rated_voltage: u32,
    /// Rated frequency in 0.01 Hz.
    pub rated_frequency: u32,
    /// DC-bus voltage at rest, in 0.1 V (a 380 V supply rectified: about 540 V).
    pub bus_voltage: u32,
    /// Motor pole pairs (for the speed in rpm).
    pub pole_pairs: u32,
}

/// Where the output is heading.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Run {
    /// Stopped, or stopping on the deceleration ramp.
    Stop,
    /// Running forward at the reference.
    Forward,
    /// Running in reverse at the reference.
    Reverse,
}

/// The drive's motion and electrical state.
#[derive(Debug, Clone)]
pub struct Vfd {
    ratings: Ratings,
    /// Output frequency in 0.01 Hz, negative in reverse.
    output: i32,
    /// Reference frequency in 0.01 Hz.
    reference: u32,
    run: Run,
    /// Acceleration and deceleration times in 0.1 s, from 0 to the maximum frequency and back.
    ramp_times: (u16, u16),
    fault: Option<u16>,
    fault_cause_present: bool,
    updated: Instant,
}

/// How often a moving drive wants [`Vfd::update`].
pub const UPDATE_PERIOD: Duration = Duration::from_millis(10);

impl Vfd {
    /// A drive at rest with these ratings.
    pub fn new(ratings: Ratings, now: Instant) -> Self {
        Vfd {
            ratings,
            output: 0,
            reference: 0,
            run: Run::Stop,
            ramp_times: (100, 100),
            fault: None,
            fault_cause_present: false,
            updated: now,
        }
    }

    /// The command: stop, forward or reverse.
    pub fn run(&self) -> Run {
        self.run
    }

    /// Sets the acceleration and deceleration times in 0.1 s (from 0 to the maximum frequency
    /// and back; 0 jumps) from `now` on.
    pub fn set_ramp_times(&mut self, now: Instant, accel: u16, decel: u16) {
        self.update(now);
        self.ramp_times = (accel, decel);
    }

    /// Commands forward, reverse or stop (on the deceleration ramp) at `now`. Ignored while
    /// faulted.
    pub fn command(&mut self, now: Instant, run: Run) {
        self.update(now);
        if self.fault.is_none() {
            self.run = run;
        }
    }

    /// Cuts the output at once (coast to stop).
    pub fn coast(&mut self) {
        self.run = Run::Stop;
        self.output = 0;
    }

    /// Sets the reference frequency in 0.01 Hz at `now`, clamped to the maximum frequency.
    pub fn set_reference(&mut self, now: Instant, reference: u32) {
        self.update(now);
        self.reference = reference.min(self.ratings.max_frequency);
    }

    /// The reference frequency in 0.01 Hz.
    pub fn reference(&self) -> u32 {
        self.reference
    }

    /// Whether the output is live (running, or still ramping down).
    pub fn running(&self) -> bool {
        self.run != Run::Stop || self.output != 0
    }

    /// Whether the output is moving away from zero towards its set-point.
    pub fn accelerating(&self) -> bool {
        let setpoint = self.setpoint();
        let same_side = self.output == 0 || setpoint.signum() == self.output.signum();
        same_side && setpoint.abs() > self.output.abs()
    }

    /// Whether the output is moving towards zero (stopping, or on the way to a lower speed or
    /// the other direction).
    pub fn decelerating(&self) -> bool {
        self.output != self.setpoint() && !self.accelerating()
    }

    /// The output frequency in 0.01 Hz, negative in reverse.
    pub fn output_frequency(&self) -> i32 {
        self.output
    }

    /// The output voltage in V (V/f up to the rated voltage).
    pub fn output_voltage(&self) -> u32 {
        let f = self.output.unsigned_abs().min(self.ratings.rated_frequency);
        self.ratings.rated_voltage * f / self.ratings.rated_frequency.max(1)
    }

    /// The output current in 0.1 A: nothing at rest, 2.0 A magnetising, up to 8.0 A at the
    /// maximum frequency, 4.0 A more while accelerating.
    pub fn output_current(&self) -> u32 {
        if self.output == 0 {
            return 0;
        }
        let speed = self.output.unsigned_abs() * 60 / self.ratings.max_frequency.max(1);
        20 + speed + if self.accelerating() { 40 } else { 0 }
    }

    /// The DC-bus voltage in 0.1 V: sags by up to 3 V with the current.
    pub fn bus_voltage(&self) -> u32 {
        self.ratings.bus_voltage - self.output_current() * 3 / 10
    }

    /// The motor speed in rpm (synchronous speed: 60 × f / pole pairs), negative in reverse.
    pub fn speed_rpm(&self) -> i32 {
        self.output * 60 / 100 / self.ratings.pole_pairs.max(1) as i32
    }

    /// The active fault's code, if any.
    pub fn fault(&self) -> Option<u16> {
        self.fault
    }

    /// A fault trips the drive at `now`: the output is cut (coast) and the drive refuses to run
    /// until the cause is gone and the fault is reset.
    pub fn trip(&mut self, now: Instant, code: u16) {
        self.update(now);
        self.fault = Some(code);
        self.fault_cause_present = true;
        self.coast();
    }

    /// The fault's cause has gone (a test says so); a reset now clears the fault.
    pub fn cause_removed(&mut self) {
        self.fault_cause_present = false;
    }

    /// Resets the fault if its cause has gone; returns the code cleared.
    pub fn reset_fault(&mut self) -> Option<u16> {
        if self.fault_cause_present {
            return None;
        }
        self.fault.take()
    }

    /// When the drive next wants [`update`](Self::update): while the output moves.
    pub fn next_update(&self) -> Option<Instant> {
        (self.output != self.setpoint()).then(|| self.updated + UPDATE_PERIOD)
    }

    fn setpoint(&self) -> i32 {
        match self.run {
            Run::Stop => 0,
            Run::Forward => self.reference as i32,
            Run::Reverse => -(self.reference as i32),
        }
    }

    /// Moves the output towards its set-point on the ramps, up to `now`. Through zero it
    /// decelerates first.
    pub fn update(&mut self, now: Instant) {
        let (accel, decel) = self.ramp_times;
        let elapsed = now.saturating_since(self.updated).as_micros();
        let setpoint = self.setpoint();
        let away_from_zero = setpoint.signum() == self.output.signum() || self.output == 0;
        let time = if self.accelerating() { accel } else { decel };
        let goal = if away_from_zero { setpoint } else { 0 };
        // 0.01 Hz per µs: max_frequency / (time × 100 000 µs).
        let step = if time == 0 {
            u64::MAX
        } else {
            u64::from(self.ratings.max_frequency) * elapsed / (u64::from(time) * 100_000)
        };
        let distance = goal.abs_diff(self.output);
        if step >= u64::from(distance) {
            self.output = goal;
            self.updated = now.max(self.updated);
        } else {
            self.output += if goal > self.output {
                step as i32
            } else {
                -(step as i32)
            };
            // Only the time the whole 0.01 Hz steps took is spent: the rest carries over, so a
            // drive updated every few microseconds ramps as fast as one updated every second.
            let spent = match self.ratings.max_frequency {
                0 => elapsed,
                max => step * u64::from(time) * 100_000 / u64::from(max),
            };
            self.updated = self.updated + Duration::from_micros(spent);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive() -> Vfd {
        let ratings = Ratings {
            max_frequency: 5000,
            rated_voltage: 380,
            rated_frequency: 5000,
            bus_voltage: 5400,
            pole_pairs: 2,
        };
        let mut vfd = Vfd::new(ratings, Instant::from_micros(0));
        vfd.set_ramp_times(Instant::from_micros(0), 100, 100);
        vfd.set_reference(Instant::from_micros(0), 5000);
        vfd.command(Instant::from_micros(0), Run::Forward);
        vfd
    }

    /// 50.00 Hz in 10.0 s: after 1 s the output is 5.00 Hz, whether the drive was updated once or
    /// every 150 µs (a step of 0.0075 Hz each, which rounds to nothing on its own).
    #[test]
    fn frequent_updates_ramp_as_fast_as_rare_ones() {
        let mut rare = drive();
        rare.update(Instant::from_micros(1_000_000));
        let mut frequent = drive();
        for n in 1..=6_666u64 {
            frequent.update(Instant::from_micros(n * 150));
        }
        frequent.update(Instant::from_micros(1_000_000));
        assert_eq!(rare.output_frequency(), 500);
        assert_eq!(frequent.output_frequency(), 500);
    }
}
