//! The EC-TX508 in the demo: an EtherCAT master's cyclic exchange with the simulated card
//! ([`EcTx508`]) every 1 ms, the master walking the drive by the runtime's cyclic CiA 402
//! [`Controller`] in cyclic synchronous velocity. There is no EtherCAT network: master and
//! device hand each other the card's real images in this process, the 21-byte outputs (RxPDO
//! 1600h) and the 23-byte inputs (TxPDO 1A00h), byte for byte what a master would put in its
//! frame. The trace shows both images decoded by the ESI file's names at the cycles the steps
//! look at, with the cycles in between counted, not printed.

use edsgen_runtime::cia402::{mode, State};
use edsgen_runtime::master::cia402::{Controller, Outcome};
use edsgen_runtime::Instant;

use super::{expect, Trace};
use crate::cards::ec_tx508::ethercat::{Inputs, Outputs, RxPdo1600, TxPdo1A00};
use crate::decode::image::ImageDecoder;
use crate::drives::ec_tx508::{EcTx508, ESI, ESI_PATH};

/// The speed (rpm, 60FFh) the master asks for once operation is enabled.
const SPEED: i32 = 300;
/// When (ms) the drive raises a fault, and when its cause is gone.
const FAULT_AT: u64 = 150;
const CAUSE_GONE_AT: u64 = 170;
/// When (ms) the master shuts the drive down.
const SHUT_DOWN_AT: u64 = 200;
/// How many cycles a walk may take before the step fails.
const LIMIT: u32 = 50;

/// The master and the device, joined by the two images as bytes.
struct Bench {
    controller: Controller,
    device: EcTx508,
    images: ImageDecoder,
    /// The outputs image of the last cycle.
    outputs: [u8; Outputs::LEN],
    /// The inputs image of the last cycle, which the master reads in the next.
    inputs: [u8; Inputs::LEN],
    /// The next cycle's number, which is its time in ms.
    ms: u64,
    /// The cycles run since the last one shown in the trace.
    hidden: u64,
}

/// One cycle as the master saw it: the controlword it sent, how its walk went, and the inputs
/// the device answered with.
struct Cycle {
    controlword: u16,
    outcome: Outcome,
    inputs: TxPdo1A00,
}

impl Bench {
    fn new() -> Self {
        let device = EcTx508::new(Instant::from_millis(0));
        let model = edsgen_codegen::read::read_bytes(std::path::Path::new(ESI_PATH), ESI).device;
        Bench {
            controller: Controller::new(State::OperationEnabled)
                .with_mode(mode::CYCLIC_VELOCITY)
                .with_limit(LIMIT),
            inputs: device.inputs(),
            device,
            images: ImageDecoder::new(&model),
            outputs: [0; Outputs::LEN],
            ms: 0,
            hidden: 0,
        }
    }

    /// One 1 ms cycle: the master reads the last inputs and writes the outputs (60FFh only once
    /// operation is enabled), the device answers with new inputs.
    fn cycle(&mut self) -> Result<Cycle, String> {
        let error = |e| format!("{e:?}");
        let seen = Inputs::decode(&self.inputs).map_err(error)?.tx_pdo_1a00;
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
        .encode();
        let now = Instant::from_millis(self.ms);
        self.inputs = self.device.cycle(now, &self.outputs).map_err(error)?;
        self.ms += 1;
        self.hidden += 1;
        Ok(Cycle {
            controlword: cycle.controlword,
            outcome: cycle.outcome,
            inputs: Inputs::decode(&self.inputs).map_err(error)?.tx_pdo_1a00,
        })
    }

    /// Runs cycles up to (not including) the one at `ms`.
    fn run_until(&mut self, ms: u64) -> Result<(), String> {
        while self.ms < ms {
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
        let ms = self.ms.saturating_sub(1);
        let at = format!("{}.{:06}", ms / 1000, (ms % 1000) * 1000);
        let outputs = self.images.outputs(&self.outputs);
        let inputs = self.images.inputs(&self.inputs);
        trace.line(None, format!("{at}  SM2  OUTPUTS    {outputs}"));
        trace.line(None, format!("{at}  SM3  INPUTS     {inputs}"));
    }

    /// The inputs of the last cycle.
    fn inputs(&self) -> Result<TxPdo1A00, String> {
        Ok(Inputs::decode(&self.inputs)
            .map_err(|e| format!("{e:?}"))?
            .tx_pdo_1a00)
    }
}

/// Controlwords as `06h, 07h, 0Fh`.
fn hex_words(words: &[u16]) -> String {
    let words: Vec<String> = words.iter().map(|w| format!("{w:02X}h")).collect();
    words.join(", ")
}

/// Expects the controlwords `words` to be `expected`.
fn expect_words(words: &[u16], expected: &[u16]) -> Result<String, String> {
    if words == expected {
        Ok(hex_words(words))
    } else {
        Err(format!(
            "got {}, expected {}",
            hex_words(words),
            hex_words(expected)
        ))
    }
}

/// The EC-TX508's section of the demo, in this process whatever the CANopen link.
pub(super) fn run(trace: &mut Trace) {
    trace.heading(
        "EC-TX508 (EtherCAT, simulated in this process): CiA 402 cyclic synchronous velocity, \
         1 ms cycle",
    );
    if let Err(problem) = workflow(trace) {
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

fn workflow(trace: &mut Trace) -> Result<(), String> {
    let mut bench = Bench::new();

    let first = bench.cycle()?;
    bench.show(trace);
    trace.step(
        "6060h = 9: mode 9 (csv) confirmed by 6061h",
        expect(first.inputs.operation_mode_display, mode::CYCLIC_VELOCITY),
    );
    let mut words = vec![first.controlword];
    words.extend(bench.walk_to(State::OperationEnabled)?);
    bench.show(trace);
    trace.step(
        "operation enabled by 06h, 07h, 0Fh",
        expect_words(&words, &[0x06, 0x07, 0x0F]),
    );

    // 60FFh = 300 from the next cycle: 3 rpm per ms (604Fh: 1 s to 3000 rpm).
    let from = bench.ms;
    bench.run_until(from + 51)?;
    bench.show(trace);
    trace.step(
        "60FFh = 300: 606Ch 50 ms later, on the ramp of 3 rpm per ms",
        expect(bench.inputs()?.actual_speed, 150),
    );
    bench.run_until(from + 101)?;
    bench.show(trace);
    let inputs = bench.inputs()?;
    trace.step(
        "606Ch follows the target on its ramp to 300 rpm, 6041h bit 10 target reached",
        expect(
            (inputs.actual_speed, inputs.status_word & 0x0400 != 0),
            (SPEED, true),
        ),
    );

    // A fault: the quick-stop ramp (6051h 100 ms from 3000 rpm, 605Eh 2), then fault.
    bench.run_until(FAULT_AT)?;
    bench
        .device
        .drive_mut()
        .raise_fault(Instant::from_millis(FAULT_AT));
    bench.walk_to(State::Fault)?;
    bench.show(trace);
    let inputs = bench.inputs()?;
    trace.step(
        "a drive fault: the quick-stop ramp to 0 rpm in 10 ms, then fault (6041h bit 3)",
        expect(
            (
                bench.ms - 1 - FAULT_AT,
                inputs.actual_speed,
                inputs.status_word & 0x0008 != 0,
            ),
            (10, 0, true),
        ),
    );
    // The cause stays until CAUSE_GONE_AT: the resets before it are refused.
    let mut words = Vec::new();
    while bench.ms < CAUSE_GONE_AT {
        words.push(bench.cycle()?.controlword);
    }
    bench.device.drive_mut().clear_fault();
    words.extend(bench.walk_to(State::SwitchOnDisabled)?);
    bench.show(trace);
    let refused_then_reset = [
        0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80, 0x00, 0x80,
    ];
    trace.step(
        "a fault reset by a rising edge of bit 7, every other cycle until the cause is gone",
        expect_words(&words, &refused_then_reset),
    );
    let words = bench.walk_to(State::OperationEnabled)?;
    bench.show(trace);
    trace.step(
        "operation enabled again by 06h, 07h, 0Fh",
        expect_words(&words, &[0x06, 0x07, 0x0F]),
    );

    bench.run_until(SHUT_DOWN_AT)?;
    bench.show(trace);
    bench.controller.set_target(State::SwitchOnDisabled);
    let words = bench.walk_to(State::SwitchOnDisabled)?;
    bench.show(trace);
    let speed = bench.inputs()?.actual_speed;
    trace.step(
        "shut down by 00h (disable voltage): switch on disabled, 606Ch 0",
        expect_words(&words, &[0x00])
            .and_then(|words| expect(speed, 0).map(|speed| format!("{words}, 606Ch {speed}"))),
    );
    Ok(())
}
