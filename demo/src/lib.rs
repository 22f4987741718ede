//! `edsgen demo`: the bundled cards at work. The six description files (five EDS, the EC-TX508's
//! ESI) are validated; then a master built from the generated bindings brings a CP301 (node 2)
//! and a Goodrive350 (node 3) through their manuals' workflows, every frame decoded by name; then
//! an EtherCAT master walks a simulated EC-TX508 through CiA 402 cyclic synchronous velocity,
//! exchanging the card's real process images every 1 ms cycle (`ethercat`), the images decoded
//! by name at the cycles the steps look at; then a class-1 EtherNet/IP scanner drives the
//! Goodrive350's EtherNet/IP card through PKW and PZD (`enip`), a PROFINET controller finds,
//! names and drives the Goodrive350's PROFINET card by DCP, RPC and RT frames (`profinet`),
//! and profirust's DP master brings the Goodrive350's PROFIBUS-DP card to data exchange on its
//! simulated bus and walks the manual's PKW examples and CW/SW commands (`dp`).
//! Each step checks what the manual (or CiA 402) says should happen; the demo passes only if
//! every step does.
//!
//! Two links for the CANopen drives, one set of workflows (`Link`): by default the drives are
//! simulated in this process on the in-memory bus (`memory`), in the bus's own time, so the
//! manuals' ramps of several seconds run in no time and every run gives the same frames; with
//! `--bus HOST:PORT` edsgen's blocking master drives whatever answers at those node-IDs on a
//! socketcand bus (`remote`), in real time (`edsgen simulate --card cp301@2 --card
//! goodrive350`, or real drives); a fault cannot be injected there, and that step says so. The
//! EC-TX508 runs in the first mode only, in its own 1 ms cycles; a socketcand bus has no
//! EtherCAT network, and with `--bus` its one step says it was not run.
//!
//! Over a real wire ([`Wires`], root): the EC-TX508 on a veth pair to `edsgen simulate
//! --ethercat` in a network namespace, driven by ethercrab (`ethercat_wire`), and the
//! EtherNet/IP card between two namespaces, TCP 44818 and UDP 2222 (`enip_wire`), and the
//! PROFINET card between two namespaces, DCP and RT_CLASS_1 frames and UDP 34964
//! (`profinet_wire`); the same steps, checked within the slack real time needs
//! ([`crate::netns`] makes and removes the namespaces; `two_namespaces` starts the simulator
//! and the demo's client role in them).

#![forbid(unsafe_code)]

mod dp;
mod dp_line;
mod enip;
mod enip_wire;
mod ethercat;
mod ethercat_wire;
mod machine;
mod memory;
mod profinet;
mod profinet_wire;
mod pty;
mod remote;
mod two_namespaces;

#[cfg(feature = "ethercrab")]
pub mod ecat;
pub mod netns;

use std::path::Path;
use std::time::Duration as StdDuration;

use edsgen_model::diag::Severity;
use edsgen_model::load;
use edsgen_runtime::cia402::State;
use edsgen_runtime::master::nmt_frame;
use edsgen_runtime::od::access::{Readable, Writable};
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::{CanFrame, Entry, OdValue};

use edsgen_decode::Decoder;
use edsgen_sim::cards::{cp301, goodrive350};
use edsgen_sim::drives::{ec_tx508, Card, CARDS};

/// The CP301's node-ID on the demo bus.
pub const CP301_NODE: u8 = 2;
/// The Goodrive350's node-ID (the manual's examples use 3).
pub const GOODRIVE350_NODE: u8 = 3;

/// One checked step of the demo.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    /// What the step does, as the manual says it.
    pub name: String,
    /// `Ok` with what was seen, or `Err` with what went wrong.
    pub outcome: Result<String, String>,
}

/// What happened: the decoded trace and the steps.
#[derive(Debug, Default)]
pub struct Report {
    /// Text lines in order: section headings, decoded frames, and step results.
    pub lines: Vec<String>,
    /// Every step, in order.
    pub steps: Vec<Step>,
}

impl Report {
    /// Whether every step behaved as the manual says.
    pub fn passed(&self) -> bool {
        self.steps.iter().all(|step| step.outcome.is_ok())
    }
}

/// The report being written: frames decoded by the cards' descriptions, long runs of one PDO
/// folded, headings and steps.
pub struct Trace {
    decoder: Decoder,
    run: Run,
    report: Report,
}

/// Trace lines of one PDO's COB-ID in a row: the first two are printed, the rest counted, the
/// last kept, so that a ramp's hundred PDOs read as four lines.
#[derive(Default)]
struct Run {
    id: Option<u16>,
    count: usize,
    last: Option<String>,
}

impl Trace {
    /// A trace that decodes the two drives' frames, after `report`'s lines.
    fn new(report: Report) -> Self {
        let mut decoder = Decoder::new();
        for (node, name) in [(CP301_NODE, "cp301"), (GOODRIVE350_NODE, "goodrive350")] {
            if let Some(card) = Card::named(name) {
                decoder.describe(node, &card.model());
            }
        }
        Trace {
            decoder,
            run: Run::default(),
            report,
        }
    }

    /// Decodes a frame seen at `at` into the report.
    fn frame(&mut self, at: StdDuration, frame: &CanFrame) {
        for line in self.decoder.decode(at, frame) {
            self.line(frame.std_id(), line);
        }
    }

    /// Adds a decoded line, folding long runs of one PDO's COB-ID (each SDO line says
    /// something new, so those are never folded).
    fn line(&mut self, id: Option<u16>, line: String) {
        let pdo = id.is_some_and(|id| (0x181..=0x57F).contains(&id));
        if pdo && id == self.run.id {
            self.run.count += 1;
            if self.run.count <= 2 {
                self.report.lines.push(format!("  {line}"));
            } else {
                self.run.last = Some(line);
            }
            return;
        }
        self.end_run();
        self.run = Run {
            id,
            count: 1,
            last: None,
        };
        self.report.lines.push(format!("  {line}"));
    }

    /// Closes a folded run: how many lines it hid, and its last line.
    fn end_run(&mut self) {
        let run = std::mem::take(&mut self.run);
        if let Some(last) = run.last {
            if run.count > 3 {
                let hidden = run.count - 3;
                self.report
                    .lines
                    .push(format!("  … {hidden} more like these"));
            }
            self.report.lines.push(format!("  {last}"));
        }
    }

    /// Records a step: what was seen, or what went wrong.
    fn step(&mut self, name: &str, outcome: Result<String, String>) {
        self.end_run();
        self.report.lines.push(match &outcome {
            Ok(seen) => format!("  ok    {name}: {seen}"),
            Err(problem) => format!("  FAIL  {name}: {problem}"),
        });
        self.report.steps.push(Step {
            name: name.to_string(),
            outcome,
        });
    }

    fn heading(&mut self, text: &str) {
        self.end_run();
        self.report.lines.push(String::new());
        self.report.lines.push(format!("== {text}"));
    }

    /// Takes in a report of steps run in another process (its lines already written).
    fn merge(&mut self, report: Report) {
        self.end_run();
        self.report.lines.extend(report.lines);
        self.report.steps.extend(report.steps);
    }

    fn finish(mut self) -> Report {
        self.end_run();
        self.report
    }
}

/// What the workflows need from a bus: typed SDO, frames out, time passing, the drives' frames
/// seen, and, where the drives run in this process, their faults.
trait Link {
    /// The report, with every frame so far decoded into it.
    fn trace(&mut self) -> &mut Trace;
    /// The report, at the end.
    fn into_trace(self) -> Trace;
    /// Reads an entry of a node, typed.
    fn read<T: OdValue, D, A: Readable>(
        &mut self,
        node: u8,
        entry: Entry<T, D, A>,
    ) -> Result<T, String>;
    /// Writes an entry of a node.
    fn write<T: OdValue, D, A: Writable>(
        &mut self,
        node: u8,
        entry: Entry<T, D, A>,
        value: T,
    ) -> Result<(), String>;
    /// Sends a frame (NMT, a PDO).
    fn send(&mut self, frame: CanFrame) -> Result<(), String>;
    /// Lets `span` pass on the bus.
    fn wait(&mut self, span: StdDuration) -> Result<(), String>;
    /// The frames with `id` the drives sent since the last call (the record is then cleared).
    fn take_seen(&mut self, id: u16) -> Vec<CanFrame>;
    /// Injects a fault into the simulated Goodrive350; `false` where there is none here.
    fn inject_goodrive350_fault(&mut self, fault: u8) -> bool;
    /// Removes the injected fault's cause; `false` where there is no simulated drive here.
    fn remove_goodrive350_fault_cause(&mut self) -> bool;
    /// How far, in rpm, a speed read at a given time may be from the ramp's value there: 0 where
    /// time is the bus's own, more where reads land a few milliseconds late.
    fn slack(&self) -> i16;
}

/// Expects `actual` within `slack` of `expected` (exactly, with no slack).
fn near(actual: i16, expected: i16, slack: i16) -> Result<String, String> {
    if actual.abs_diff(expected) <= slack.unsigned_abs() {
        Ok(format!("{actual}"))
    } else if slack == 0 {
        Err(format!("got {actual}, expected {expected}"))
    } else {
        Err(format!("got {actual}, expected {expected} ± {slack}"))
    }
}

/// Expects `actual` to equal `expected`.
fn expect<T: PartialEq + std::fmt::Debug>(actual: T, expected: T) -> Result<String, String> {
    if actual == expected {
        Ok(format!("{actual:?}"))
    } else {
        Err(format!("got {actual:?}, expected {expected:?}"))
    }
}

/// Validates the bundled description files, the five EDS files and the EC-TX508's ESI file:
/// no errors.
fn validate_cards() -> Report {
    let mut report = Report::default();
    report
        .lines
        .push("== validate the bundled description files".into());
    let esi = load::load_bundled(Path::new(ec_tx508::ESI_PATH), ec_tx508::ESI, None);
    let files = CARDS
        .iter()
        .map(|card| (card.eds_path, card.loaded()))
        .chain([(ec_tx508::ESI_PATH, esi)]);
    for (path, loaded) in files {
        let diagnostics = loaded
            .diagnostics
            .iter()
            .chain(loaded.overlay_diagnostics())
            .collect::<Vec<_>>();
        let count = |s| diagnostics.iter().filter(|d| d.severity == s).count();
        let (errors, warnings) = (count(Severity::Error), count(Severity::Warning));
        let line = format!("{errors} error(s), {warnings} warning(s)");
        let outcome = if errors == 0 { Ok(line) } else { Err(line) };
        let name = format!("{path} is valid");
        report.lines.push(match &outcome {
            Ok(seen) => format!("  ok    {name}: {seen}"),
            Err(problem) => format!("  FAIL  {name}: {problem}"),
        });
        report.steps.push(Step { name, outcome });
    }
    report
}

/// Both CANopen workflows on a link, after starting the nodes.
fn workflows(mut link: impl Link) -> Trace {
    link.trace().heading("NMT: start all nodes");
    if let Err(problem) = link.send(nmt_frame(NmtCommand::Start, 0)) {
        link.trace().step("NMT start", Err(problem));
    }
    if let Err(problem) = cp301_velocity_mode(&mut link) {
        link.trace().step("CP301 workflow", Err(problem));
    }
    if let Err(problem) = goodrive350_run(&mut link) {
        link.trace().step("Goodrive350 workflow", Err(problem));
    }
    link.into_trace()
}

/// Which sections run over a real wire (root only) instead of in this process.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Wires {
    /// The EC-TX508 over a veth pair, `edsgen simulate --ethercat` at the far end, ethercrab
    /// here (feature `ethercrab`).
    pub ethercat: bool,
    /// The EtherNet/IP card between two network namespaces, `edsgen simulate --enip` in one,
    /// the demo's scanner in the other (TCP 44818, UDP 2222).
    pub enip: bool,
    /// The PROFINET card between two network namespaces, `edsgen simulate --profinet` in one,
    /// the demo's controller in the other (DCP and RT_CLASS_1 frames, UDP 34964).
    pub profinet: bool,
}

pub use enip_wire::scan as enip_scanner;
pub use profinet_wire::control as profinet_controller;

/// Runs the whole demo in this process: the CANopen drives on the in-memory bus, then the
/// EC-TX508's cyclic exchange.
pub fn run() -> Report {
    run_with(Wires::default())
}

/// Runs the whole demo, the sections `wires` names over a real wire where this process can
/// (root, and the features they need; where it cannot, standard error says why and the section
/// runs in this process).
pub fn run_with(wires: Wires) -> Report {
    let trace = Trace::new(validate_cards());
    let mut trace = match memory::InMemory::new(trace) {
        Ok(link) => workflows(link),
        Err(problem) => return failed_to_start("power up the simulated drives", problem),
    };
    if wires.ethercat {
        ethercat_wire::run(&mut trace);
    } else {
        ethercat::run(&mut trace);
    }
    if wires.enip {
        enip_wire::run(&mut trace);
    } else {
        enip::run(&mut trace);
    }
    if wires.profinet {
        profinet_wire::run(&mut trace);
    } else {
        profinet::run(&mut trace);
    }
    dp::run(&mut trace);
    trace.finish()
}

/// Runs the whole demo as one machine (`edsgen demo --machine`, root): the six description files
/// validated, then `edsgen simulate --machine` serving the bundled cards in a network namespace
/// and each bus driven from the far side of its wire (see `machine`). Not root: says so on
/// standard error and runs the demo in this process.
pub fn run_machine() -> Report {
    if !netns::is_root() {
        eprintln!(
            "{}; every card runs in this process instead",
            netns::not_root("demo --machine")
        );
        return run();
    }
    let mut trace = Trace::new(validate_cards());
    machine::run(&mut trace);
    trace.finish()
}

/// `edsgen demo-role canopen-master ADDR`, run by `--machine` in the machine's namespace: both
/// CANopen workflows against the CP301 (node 2) and the Goodrive350 (node 3) on the socketcand
/// bus at `addr`, in real time, every frame decoded; the report to print as JSON.
pub fn canopen_master(addr: &str) -> Report {
    match remote::Remote::connect(addr, Trace::new(Report::default())) {
        Ok(link) => workflows(link).finish(),
        Err(problem) => {
            let mut trace = Trace::new(Report::default());
            trace.step("join the bus", Err(problem));
            trace.finish()
        }
    }
}

/// Runs the CANopen workflows against the drives on the socketcand bus at `addr` (CP301 at
/// node 2, Goodrive350 at node 3), in real time; the EC-TX508 is not run (no EtherCAT network).
pub fn run_on_bus(addr: &str) -> Report {
    let trace = Trace::new(validate_cards());
    let mut trace = match remote::Remote::connect(addr, trace) {
        Ok(link) => workflows(link),
        Err(problem) => return failed_to_start("join the bus", problem),
    };
    ethercat::not_run(&mut trace);
    enip::not_run(&mut trace);
    profinet::run(&mut trace);
    // The DP card needs no CANopen bus: it runs in this process on profirust's simulated bus.
    dp::run(&mut trace);
    trace.finish()
}

fn failed_to_start(name: &str, problem: String) -> Report {
    let mut report = validate_cards();
    report.lines.push(format!("  FAIL  {name}: {problem}"));
    report.steps.push(Step {
        name: name.into(),
        outcome: Err(problem),
    });
    report
}

fn cp301_velocity_mode(bench: &mut impl Link) -> Result<(), String> {
    use cp301::od;
    let node = CP301_NODE;
    bench
        .trace()
        .heading("CP301 (node 2): CiA 402 velocity mode, manual §5.3");
    bench.write(node, od::VL_TARGET_VELOCITY, 1500)?;
    // Ramps of 1 s up and 2 s down (to and from 1500 rpm), so that a run on a real bus is short.
    bench.write(node, od::VL_RAMP_FUNCTION_TIME, 1_000)?;
    bench.write(node, od::VL_SLOW_DOWN_TIME, 2_000)?;
    for (controlword, state) in [
        (0x06, State::ReadyToSwitchOn),
        (0x07, State::SwitchedOn),
        (0x0F, State::OperationEnabled),
    ] {
        bench.write(node, od::CONTROLWORD, controlword)?;
        let statusword = bench.read(node, od::STATUSWORD)?;
        let name = format!("6040h = {controlword:02X}h: {state:?}");
        bench.trace().step(
            &name,
            expect(State::from_statusword(statusword), Some(state)),
        );
    }
    bench.write(node, od::CONTROLWORD, 0x7F)?;
    bench.wait(StdDuration::from_millis(500))?;
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    let slack = bench.slack();
    bench.trace().step(
        "6040h = 7Fh: ramping up, 6044h at 0.5 s (604Fh: 1 s to 1500 rpm)",
        near(speed, 750, slack),
    );
    bench.wait(StdDuration::from_millis(600))?;
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    let statusword = bench.read(node, od::STATUSWORD)?;
    bench
        .trace()
        .step("6044h at 1.1 s: 1500 rpm", expect(speed, 1500));
    bench.trace().step(
        "6041h bit 10: target reached",
        expect(statusword & 0x0400 != 0, true),
    );
    bench.write(node, od::VL_TARGET_VELOCITY, -1500)?;
    bench.wait(StdDuration::from_millis(2_000))?;
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.trace().step(
        "6042h = -1500: through zero after 6050h's 2 s",
        near(speed, 0, slack),
    );
    bench.wait(StdDuration::from_millis(1_100))?;
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.trace().step(
        "6044h 1.1 s later: -1500 rpm, reversed",
        expect(speed, -1500),
    );
    bench.write(node, od::CONTROLWORD, 0x06)?;
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.trace().step(
        "6040h = 06h: shutdown, the output off (605Bh = 0)",
        expect(speed, 0),
    );
    Ok(())
}

/// A PDO1 parameter write (§3.5.2): the response's code, error and data.
fn goodrive350_parameter(
    bench: &mut impl Link,
    address: u16,
    value: u16,
) -> Result<(u16, u16, u16), String> {
    use goodrive350::pdo;
    let node = GOODRIVE350_NODE;
    let request = pdo::Rpdo1 {
        request_code: 2,
        parameter_address: address,
        requested_data: value,
    };
    let payload = request.to_bytes();
    let frame = CanFrame::new(pdo::Rpdo1::cob_id(node), &payload).ok_or("a PDO1 frame")?;
    bench.take_seen(0);
    bench.send(frame)?;
    // PDO1 Tx has an inhibit time: give the answer 100 ms.
    bench.wait(StdDuration::from_millis(100))?;
    let answers = bench.take_seen(pdo::Tpdo1::cob_id(node));
    let answer = answers.last().ok_or("no PDO1 Tx answer")?;
    let response = pdo::Tpdo1::from_slice(answer.data()).map_err(|e| format!("{e:?}"))?;
    Ok((
        response.response_code,
        response.error_code,
        response.response_data,
    ))
}

/// The Goodrive350 manual's workflow (chapter 3): parameters by PDO1, run at 50.00 Hz by PDO2,
/// an injected fault with its emergency, and the fault reset.
fn goodrive350_run(bench: &mut impl Link) -> Result<(), String> {
    use goodrive350::pdo;
    let node = GOODRIVE350_NODE;
    bench
        .trace()
        .heading("Goodrive350 (node 3): EC-TX105 PDO protocol, manual chapter 3");
    for (name, address, value) in [
        ("P00.01 = 2 (run commands from communication)", 0x0001, 2),
        ("P00.02 = 1 (CANopen)", 0x0002, 1),
        ("P00.06 = 9 (frequency from CANopen)", 0x0006, 9),
        ("P15.03 = 1 (setting 2 is the frequency)", 0x0F03, 1),
        (
            "P15.13 = 1 (returned value 1: running frequency)",
            0x0F0D,
            1,
        ),
        ("P15.14 = 4 (returned value 2: output voltage)", 0x0F0E, 4),
        ("P00.11 = 20 (acceleration time 2.0 s)", 0x000B, 20),
        ("P00.12 = 20 (deceleration time 2.0 s)", 0x000C, 20),
    ] {
        let answer = goodrive350_parameter(bench, address, value)?;
        bench
            .trace()
            .step(&format!("PDO1 write {name}"), expect(answer, (1, 0, value)));
    }
    let answer = goodrive350_parameter(bench, 0x071B, 5)?;
    bench.trace().step(
        "PDO1 write P07.27 (read-only): error 07h",
        expect(answer, (3, 7, 0)),
    );

    let run = pdo::Rpdo2 {
        control_word: 1,
        setting_1: 0,
        setting_2: 5000,
        setting_3: 0,
    };
    let payload = run.to_bytes();
    bench.take_seen(0);
    bench.send(CanFrame::new(pdo::Rpdo2::cob_id(node), &payload).ok_or("a PDO2 frame")?)?;
    bench.wait(StdDuration::from_millis(2_200))?;
    let reports = bench.take_seen(pdo::Tpdo2::cob_id(node));
    let last = reports.last().ok_or("no PDO2 Tx")?;
    let status = pdo::Tpdo2::from_slice(last.data()).map_err(|e| format!("{e:?}"))?;
    bench.trace().step(
        &format!(
            "PDO2 run forward at 50.00 Hz: {} PDO2 Tx while ramping, the last (SW, Hz × 100, V)",
            reports.len()
        ),
        expect(
            (
                status.status_word,
                status.returned_value_1,
                status.returned_value_2,
            ),
            (0x0101, 5000, 380),
        ),
    );

    if !bench.inject_goodrive350_fault(1) {
        bench.trace().step(
            "fault OUT1 injected, and its reset",
            Ok("not run: the drive is not in this process".into()),
        );
        return Ok(());
    }
    let emcy = bench.take_seen(0x080 + u16::from(node));
    let code = emcy
        .first()
        .map(|f| u16::from_le_bytes([f.data()[0], f.data()[1]]));
    bench.trace().step(
        "fault OUT1 injected: EMCY 3000h with VFD error code 1",
        expect(
            (code, emcy.first().map(|f| f.data()[3])),
            (Some(0x3000), Some(1)),
        ),
    );
    bench.remove_goodrive350_fault_cause();
    let reset = pdo::Rpdo2 {
        control_word: 7,
        ..run
    };
    let payload = reset.to_bytes();
    bench.send(CanFrame::new(pdo::Rpdo2::cob_id(node), &payload).ok_or("a PDO2 frame")?)?;
    bench.wait(StdDuration::from_millis(100))?;
    let emcy = bench.take_seen(0x080 + u16::from(node));
    bench.trace().step(
        "fault reset (CW 7): the error-reset EMCY",
        expect(emcy.first().map(|f| f.data().to_vec()), Some(vec![0; 8])),
    );
    Ok(())
}
