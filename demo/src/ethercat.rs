//! The EC-TX508 in the demo: an EtherCAT master's cyclic exchange with the card every 1 ms, the
//! master walking the drive by the runtime's cyclic CiA 402 [`Controller`] in cyclic synchronous
//! velocity, through the card's real images, the 21-byte outputs (RxPDO 1600h) and the 23-byte
//! inputs (TxPDO 1A00h). Two links carry the images ([`Exchange`]): by default master and device
//! hand them to each other in this process ([`InProcess`], the simulated [`EcTx508`] in the
//! cycles' own time, so every run gives the same images); with `--ethercat`, ethercrab carries
//! them in EtherCAT frames over a veth pair to `edsgen simulate --ethercat` in real time
//! ([`super::ethercat_wire`]). The trace shows both images decoded by the ESI file's names at the
//! cycles the steps look at, with the cycles in between counted, not printed.

use edsgen_runtime::cia402::{mode, State};
use edsgen_runtime::master::cia402::{Controller, Outcome};
use edsgen_runtime::Instant;

use super::{expect, Trace};
use edsgen_decode::image::ImageDecoder;
use edsgen_sim::cards::ec_tx508::ethercat::{Inputs, Outputs, RxPdo1600, TxPdo1A00};
use edsgen_sim::drives::ec_tx508::{EcTx508, ESI, ESI_PATH};

/// The speed (rpm, 60FFh) the master asks for once operation is enabled.
const SPEED: i32 = 300;
/// When (ms) the drive raises a fault, and when its cause is gone.
const FAULT_AT: u64 = 150;
const CAUSE_GONE_AT: u64 = 170;
/// When (ms) the master shuts the drive down.
const SHUT_DOWN_AT: u64 = 200;
/// How many cycles a walk may take before the step fails.
const LIMIT: u32 = 50;

/// On a wire: how far a speed may be from the ramp's value at the time of its cycle (10 ms of
/// the 3 rpm/ms ramp: a frame's outputs reach the drive a cycle later, and on a loaded machine
/// the two processes' cycles come late).
const SLACK_RPM: i32 = 30;
/// On a wire: the quick-stop ramp's length (10 ms on the drive's clock) between the frames that
/// show its start and its end: up to 5 ms shorter or 30 ms longer where the machine lets one
/// of the two processes wait; still apart from the 100 ms the ramp of 6084h would take.
const QUICK_STOP_SEEN_MS: std::ops::RangeInclusive<u64> = 5..=40;

/// What carries the images between the master and the card.
pub(super) trait Exchange {
    /// The inputs image before the first cycle.
    fn first_inputs(&self) -> [u8; Inputs::SIZE];
    /// The time of the next cycle, in ms since the first: the cycle's number in this process,
    /// the clock's on a wire.
    fn now_ms(&self) -> u64;
    /// One cycle: the outputs image to the card; the inputs image it answers with, and the
    /// cycle's time (ms, as [`Exchange::now_ms`]; on a wire, the middle of the frame's round
    /// trip).
    fn exchange(
        &mut self,
        outputs: &[u8; Outputs::SIZE],
    ) -> Result<([u8; Inputs::SIZE], u64), String>;
    /// Raises a drive fault in the card, as the drive's own monitoring would.
    fn raise_fault(&mut self) -> Result<(), String>;
    /// Removes the fault's cause: from then on the drive takes a fault reset.
    fn clear_fault(&mut self) -> Result<(), String>;
    /// Whether this is a real wire: the card takes a frame's outputs in the next frame (so a
    /// master that answers each frame's inputs sends each controlword twice) and time is the
    /// clock's, so speeds and times are checked within [`SLACK_RPM`] and
    /// [`QUICK_STOP_SEEN_MS`].
    fn wire(&self) -> bool;
}

/// The simulated card in this process, in the cycles' own time: cycle N is at N ms.
struct InProcess {
    device: EcTx508,
    ms: u64,
}

impl Exchange for InProcess {
    fn first_inputs(&self) -> [u8; Inputs::SIZE] {
        self.device.inputs()
    }

    fn now_ms(&self) -> u64 {
        self.ms
    }

    fn exchange(
        &mut self,
        outputs: &[u8; Outputs::SIZE],
    ) -> Result<([u8; Inputs::SIZE], u64), String> {
        let ms = self.ms;
        self.ms += 1;
        let inputs = self
            .device
            .cycle(Instant::from_millis(ms), outputs)
            .map_err(|e| format!("{e:?}"))?;
        Ok((inputs, ms))
    }

    fn raise_fault(&mut self) -> Result<(), String> {
        let now = Instant::from_millis(self.ms);
        self.device.drive_mut().raise_fault(now);
        Ok(())
    }

    fn clear_fault(&mut self) -> Result<(), String> {
        self.device.drive_mut().clear_fault();
        Ok(())
    }

    fn wire(&self) -> bool {
        false
    }
}

/// The master and the card, joined by the two images as bytes.
struct Bench<'a> {
    controller: Controller,
    link: &'a mut dyn Exchange,
    images: ImageDecoder,
    /// The outputs image of the last cycle.
    outputs: [u8; Outputs::SIZE],
    /// The inputs image of the last cycle, which the master reads in the next.
    inputs: [u8; Inputs::SIZE],
    /// The time (ms) of the last cycle.
    last_ms: u64,
    /// The cycles run since the last one shown in the trace.
    hidden: u64,
    /// The state the inputs showed at the last cycle, and since when (ms).
    state: (Option<State>, u64),
}

/// One cycle as the master saw it: the controlword it sent, how its walk went, and the inputs
/// the device answered with.
struct Cycle {
    controlword: u16,
    outcome: Outcome,
    inputs: TxPdo1A00,
}

impl<'a> Bench<'a> {
    fn new(link: &'a mut dyn Exchange) -> Self {
        let model =
            edsgen_model::load::load_bundled(std::path::Path::new(ESI_PATH), ESI, None).device;
        Bench {
            controller: Controller::new(State::OperationEnabled)
                .with_mode(mode::CYCLIC_VELOCITY)
                .with_limit(LIMIT),
            inputs: link.first_inputs(),
            link,
            images: ImageDecoder::new(&model),
            outputs: [0; Outputs::SIZE],
            last_ms: 0,
            hidden: 0,
            state: (None, 0),
        }
    }

    /// The time (ms) of the next cycle.
    fn ms(&self) -> u64 {
        self.link.now_ms()
    }

    /// One 1 ms cycle: the master reads the last inputs and writes the outputs (60FFh only once
    /// operation is enabled), the device answers with new inputs.
    fn cycle(&mut self) -> Result<Cycle, String> {
        let error = |e| format!("{e:?}");
        let seen = Inputs::from_slice(&self.inputs).map_err(error)?.tx_pdo_1a00;
        let cycle = self
            .controller
            .cycle(seen.status_word, seen.operation_mode_display);
        let enabled = cycle.outcome == Outcome::Reached
            && self.controller.target() == State::OperationEnabled;
        self.outputs = Outputs {
            rx_pdo_1600: RxPdo1600 {
                control_word: cycle.controlword,
                operation_mode: cycle.mode.unwrap_or(0),
                target_speed: if enabled { SPEED } else { 0 },
                ..RxPdo1600::default()
            },
        }
        .to_bytes();
        (self.inputs, self.last_ms) = self.link.exchange(&self.outputs)?;
        self.hidden += 1;
        let inputs = Inputs::from_slice(&self.inputs).map_err(error)?.tx_pdo_1a00;
        let state = State::from_statusword(inputs.status_word);
        if state != self.state.0 {
            self.state = (state, self.last_ms);
        }
        Ok(Cycle {
            controlword: cycle.controlword,
            outcome: cycle.outcome,
            inputs,
        })
    }

    /// Runs cycles until the next one is at `ms` or later.
    fn run_until(&mut self, ms: u64) -> Result<(), String> {
        while self.ms() < ms {
            self.cycle()?;
        }
        Ok(())
    }

    /// Runs cycles until the device's inputs show `state`, at most [`LIMIT`]: the controlwords
    /// the master sent on the way.
    fn walk_to(&mut self, state: State) -> Result<Vec<u16>, String> {
        let mut words = Vec::new();
        for _ in 0..LIMIT {
            let cycle = self.cycle()?;
            words.push(cycle.controlword);
            if let Outcome::Stuck { .. } | Outcome::ModeNotConfirmed { .. } = cycle.outcome {
                return Err(format!("{:?} after {}", cycle.outcome, hex_words(&words)));
            }
            if State::from_statusword(cycle.inputs.status_word) == Some(state) {
                return Ok(words);
            }
        }
        Err(format!("not {state:?} after {}", hex_words(&words)))
    }

    /// The last cycle's images, decoded, after a count of the cycles not shown.
    fn show(&mut self, trace: &mut Trace) {
        let hidden = self.hidden.saturating_sub(1);
        if hidden > 0 {
            trace.line(None, format!("… {hidden} cycle(s) not shown"));
        }
        self.hidden = 0;
        let ms = self.last_ms;
        let at = format!("{}.{:06}", ms / 1000, (ms % 1000) * 1000);
        let outputs = self.images.outputs(&self.outputs);
        let inputs = self.images.inputs(&self.inputs);
        trace.line(None, format!("{at}  SM2  OUTPUTS    {outputs}"));
        trace.line(None, format!("{at}  SM3  INPUTS     {inputs}"));
    }

    /// The inputs of the last cycle.
    fn inputs(&self) -> Result<TxPdo1A00, String> {
        Ok(Inputs::from_slice(&self.inputs)
            .map_err(|e| format!("{e:?}"))?
            .tx_pdo_1a00)
    }

    /// Expects the controlwords `words` to be `expected`: exactly in this process; on a wire,
    /// each may come more than once in a row (see [`Exchange::wire`]).
    fn expect_words(&self, words: &[u16], expected: &[u16]) -> Result<String, String> {
        let mut seen = words.to_vec();
        if self.link.wire() {
            seen.dedup();
        }
        if seen == expected {
            Ok(hex_words(words))
        } else {
            Err(format!(
                "got {}, expected {}",
                hex_words(words),
                hex_words(expected)
            ))
        }
    }
}

/// Controlwords as `06h, 07h, 0Fh`.
fn hex_words(words: &[u16]) -> String {
    let words: Vec<String> = words.iter().map(|w| format!("{w:02X}h")).collect();
    words.join(", ")
}

/// The EC-TX508's section of the demo, in this process whatever the CANopen link.
pub(super) fn run(trace: &mut Trace) {
    trace.heading(
        "EC-TX508 (EtherCAT, simulated in this process): CiA 402 cyclic synchronous velocity, \
         1 ms cycle",
    );
    let mut link = InProcess {
        device: EcTx508::new(Instant::from_millis(0)),
        ms: 0,
    };
    if let Err(problem) = workflow(trace, &mut link) {
        trace.step("EC-TX508 workflow", Err(problem));
    }
}

/// In `--bus` mode: the bus is CANopen, there is no EtherCAT network to drive.
pub(super) fn not_run(trace: &mut Trace) {
    trace.heading("EC-TX508 (EtherCAT)");
    trace.step(
        "EC-TX508 over EtherCAT",
        Ok("not run: --bus is a CANopen bus, with no EtherCAT network".into()),
    );
}

/// The steps, on either link: csv, operation enabled, the ramp, a fault and its reset,
/// operation enabled again, the shutdown.
pub(super) fn workflow(trace: &mut Trace, link: &mut dyn Exchange) -> Result<(), String> {
    let wire = link.wire();
    let mut bench = Bench::new(link);

    // 6061h shows 9 once the drive has taken 6060h (in this process from the first cycle).
    let mut words = Vec::new();
    let mut shown = 0;
    for _ in 0..LIMIT {
        let cycle = bench.cycle()?;
        words.push(cycle.controlword);
        shown = cycle.inputs.operation_mode_display;
        if shown == mode::CYCLIC_VELOCITY {
            break;
        }
    }
    bench.show(trace);
    trace.step(
        "6060h = 9: mode 9 (csv) confirmed by 6061h",
        expect(shown, mode::CYCLIC_VELOCITY),
    );
    words.extend(bench.walk_to(State::OperationEnabled)?);
    bench.show(trace);
    trace.step(
        "operation enabled by 06h, 07h, 0Fh",
        bench.expect_words(&words, &[0x06, 0x07, 0x0F]),
    );

    // 60FFh = 300 from the next cycle: 3 rpm per ms (604Fh: 1 s to 3000 rpm).
    // On a wire the ramp is measured from the first cycle that shows motion (the drive takes a
    // frame's outputs in the next frame, which may come late).
    let from = bench.ms();
    let mut moving = None;
    while bench.ms() < from + 51 {
        let speed = bench.cycle()?.inputs.actual_speed;
        if moving.is_none() && speed > 0 {
            moving = Some((bench.last_ms, speed));
        }
    }
    bench.show(trace);
    let (start, speed_then) = moving.filter(|_| wire).unwrap_or((from, 0));
    let on_ramp = (speed_then + 3 * (bench.last_ms - start) as i32).min(SPEED);
    let speed = bench.inputs()?.actual_speed;
    trace.step(
        "60FFh = 300: 606Ch 50 ms later, on the ramp of 3 rpm per ms",
        if wire {
            within(speed, on_ramp, SLACK_RPM)
        } else {
            expect(speed, on_ramp)
        },
    );
    bench.run_until(from + 101)?;
    let reached = |i: &TxPdo1A00| (i.actual_speed, i.status_word & 0x0400 != 0) == (SPEED, true);
    // On a wire, the ramp's last cycles may come a little later.
    while wire && !reached(&bench.inputs()?) && bench.ms() < from + 101 + 50 {
        bench.cycle()?;
    }
    bench.show(trace);
    let inputs = bench.inputs()?;
    trace.step(
        "606Ch follows the target on its ramp to 300 rpm, 6041h bit 10 target reached",
        expect(
            (inputs.actual_speed, inputs.status_word & 0x0400 != 0),
            (SPEED, true),
        ),
    );

    // A fault: the quick-stop ramp (6051h 100 ms from 3000 rpm, 605Eh 2), then fault; the ramp
    // from the first cycle that shows the fault reaction to the first that shows the fault.
    bench.run_until(FAULT_AT)?;
    bench.link.raise_fault()?;
    let mut reaction_at = None;
    for _ in 0..LIMIT {
        bench.cycle()?;
        match bench.state {
            (Some(State::FaultReactionActive), at) => reaction_at = Some(at),
            (Some(State::Fault), _) => break,
            _ => {}
        }
    }
    bench.show(trace);
    let inputs = bench.inputs()?;
    let took = match (reaction_at, bench.state) {
        (Some(from), (Some(State::Fault), to)) => to - from,
        _ => {
            return Err(format!(
                "no fault reaction, then fault: {:?}",
                bench.state.0
            ))
        }
    };
    let seen = (took, inputs.actual_speed, inputs.status_word & 0x0008 != 0);
    trace.step(
        "a drive fault: the quick-stop ramp to 0 rpm in 10 ms, then fault (6041h bit 3)",
        if wire && QUICK_STOP_SEEN_MS.contains(&took) {
            expect((seen.1, seen.2), (0, true)).map(|_| format!("{seen:?}"))
        } else {
            expect(seen, (10, 0, true))
        },
    );
    // The cause stays until CAUSE_GONE_AT, and at least 10 ms and 4 cycles after the fault
    // shows (on a wire, the fault may show later, cycles may come late): the resets before are
    // refused.
    let cause_gone_at = CAUSE_GONE_AT.max(bench.last_ms + 10);
    let mut words = Vec::new();
    while bench.ms() < cause_gone_at || words.len() < 4 {
        words.push(bench.cycle()?.controlword);
    }
    let refused = words.len();
    bench.link.clear_fault()?;
    words.extend(bench.walk_to(State::SwitchOnDisabled)?);
    bench.show(trace);
    let name = "a fault reset by a rising edge of bit 7, every other cycle until the cause is gone";
    if wire {
        trace.step(name, resets(&words, refused));
    } else {
        let refused_then_reset = [
            0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80,
        ];
        trace.step(name, bench.expect_words(&words, &refused_then_reset));
    }
    let words = bench.walk_to(State::OperationEnabled)?;
    bench.show(trace);
    trace.step(
        "operation enabled again by 06h, 07h, 0Fh",
        bench.expect_words(&words, &[0x06, 0x07, 0x0F]),
    );

    bench.run_until(SHUT_DOWN_AT)?;
    bench.show(trace);
    bench.controller.set_target(State::SwitchOnDisabled);
    let words = bench.walk_to(State::SwitchOnDisabled)?;
    bench.show(trace);
    let speed = bench.inputs()?.actual_speed;
    trace.step(
        "shut down by 00h (disable voltage): switch on disabled, 606Ch 0",
        bench
            .expect_words(&words, &[0x00])
            .and_then(|words| expect(speed, 0).map(|speed| format!("{words}, 606Ch {speed}"))),
    );
    Ok(())
}

/// Expects `actual` within `slack` of `expected`.
fn within(actual: i32, expected: i32, slack: i32) -> Result<String, String> {
    if actual.abs_diff(expected) <= slack.unsigned_abs() {
        Ok(format!("{actual} (the ramp's {expected} ± {slack})"))
    } else {
        Err(format!("got {actual}, expected {expected} ± {slack}"))
    }
}

/// On a wire: the fault resets as the master sent them, `refused` of them before the cause was
/// gone. Expects 80h and 00h in turn from 80h (a rising edge every other cycle), an edge
/// refused (the first, taken by the drive before the cause was gone: two cycles passed), and
/// the reset by one of the first two edges from the last cycle before the cause was gone (the
/// drive takes a frame's outputs in the next frame), seen within the two cycles that takes.
fn resets(words: &[u16], refused: usize) -> Result<String, String> {
    let alternating = words
        .iter()
        .enumerate()
        .all(|(n, w)| *w == if n % 2 == 0 { 0x80 } else { 0x00 });
    let edges: Vec<usize> = (refused.saturating_sub(1)..words.len())
        .filter(|&n| words[n] == 0x80)
        .take(2)
        .collect();
    let in_time = edges.last().is_some_and(|&edge| words.len() <= edge + 3);
    let seen = format!("{} ({refused} before the cause was gone)", hex_words(words));
    if alternating && refused >= 2 && in_time {
        Ok(seen)
    } else {
        Err(seen)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wire_resets_alternate_from_80h_and_reset_soon_after_the_cause_goes() {
        let ok = |words: &[u16], refused| resets(words, refused).is_ok();
        // Two refused before the cause went; the edge after it taken, seen a cycle later.
        assert_eq!(
            resets(&[0x80, 0x00, 0x80, 0x00], 2),
            Ok("80h, 00h, 80h, 00h (2 before the cause was gone)".into())
        );
        // The edge sent in the last cycle before the cause went, taken in the next frame.
        assert!(ok(&[0x80, 0x00, 0x80, 0x00, 0x80, 0x00], 5));
        // No edge surely refused, or not alternating, or the reset seen too late.
        assert!(!ok(&[0x80, 0x00], 1));
        assert!(!ok(&[0x80, 0x80, 0x00], 2));
        assert!(!ok(&[0x00, 0x80, 0x00], 2));
        assert!(!ok(&[0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80, 0x00], 3));
        assert!(!ok(&[0x80, 0x00, 0x80, 0x00, 0x80, 0x00], 6));
    }

    #[test]
    fn a_speed_within_slack_of_the_ramp_says_both() {
        assert_eq!(within(141, 150, 30), Ok("141 (the ramp's 150 ± 30)".into()));
        assert_eq!(
            within(119, 150, 30),
            Err("got 119, expected 150 ± 30".into())
        );
    }
}
