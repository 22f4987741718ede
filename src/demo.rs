//! `edsgen demo`: the bundled cards at work. The five EDS files are validated; then a master built
//! from the generated bindings brings a simulated CP301 (node 2) and a simulated Goodrive350
//! (node 3) through their manuals' workflows on the in-memory bus, every frame decoded by name.
//!
//! Time is the bus's own (simulated): the manuals' ramps of several seconds run in no time, and
//! every run gives the same frames at the same instants. Each step checks what the manual says
//! should happen; the demo passes only if every step does.

use std::collections::VecDeque;
use std::path::Path;
use std::time::Duration as StdDuration;

use edsgen_codegen::diag::Severity;
use edsgen_codegen::{read, validate};
use edsgen_runtime::cia402::State;
use edsgen_runtime::master::{nmt_frame, SdoClient};
use edsgen_runtime::vbus::{BusDevice, VirtualBus};
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::{CanFrame, Duration, Entry, Instant, OdValue};

use crate::cards::{cp301, goodrive350};
use crate::decode::Decoder;
use crate::drives::{Card, Cp301, Goodrive350, CARDS};

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

/// The master's side of the demo bus: one SDO client per node, and frames to send (NMT, PDOs).
struct DemoMaster {
    clients: Vec<SdoClient>,
    outbox: VecDeque<CanFrame>,
}

impl DemoMaster {
    fn client(&mut self, node: u8) -> &mut SdoClient {
        match self.clients.iter().position(|c| c.node_id() == node) {
            Some(i) => &mut self.clients[i],
            None => {
                self.clients.push(SdoClient::new(node));
                let last = self.clients.len() - 1;
                &mut self.clients[last]
            }
        }
    }
}

impl BusDevice for DemoMaster {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        for client in &mut self.clients {
            client.handle_frame(now, frame);
        }
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        if let Some(frame) = self.outbox.pop_front() {
            return Some(frame);
        }
        self.clients.iter_mut().find_map(|c| c.poll_transmit(now))
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.clients.iter().filter_map(|c| c.poll_timeout()).min()
    }
    fn handle_timeout(&mut self, now: Instant) {
        for client in &mut self.clients {
            client.handle_timeout(now);
        }
    }
}

/// The demo bus: the master, the two drives, the decoder and the report.
struct Bench {
    bus: VirtualBus,
    master: DemoMaster,
    cp301: Cp301,
    goodrive350: Goodrive350,
    decoder: Decoder,
    /// Frames the drives sent since the last look, for the steps to check.
    seen: Vec<(Instant, CanFrame)>,
    /// Consecutive trace lines of one COB-ID, folded (see [`Bench::trace`]).
    run: Run,
    report: Report,
}

/// Trace lines of one COB-ID in a row: the first two are printed, the rest counted, the last
/// kept, so that a ramp's hundred PDOs read as four lines.
#[derive(Default)]
struct Run {
    id: Option<u16>,
    count: usize,
    last: Option<String>,
}

/// How long an SDO answer may take on the demo bus (it takes none: the bus is instant).
const SDO_WAIT: Duration = Duration::from_millis(100);

impl Bench {
    fn new() -> Result<Self, String> {
        let now = Instant::from_millis(0);
        let cp301 = Cp301::new(CP301_NODE, now).map_err(|e| format!("{e:?}"))?;
        let goodrive350 = Goodrive350::new(GOODRIVE350_NODE, now).map_err(|e| format!("{e:?}"))?;
        let mut decoder = Decoder::new();
        for (node, name) in [(CP301_NODE, "cp301"), (GOODRIVE350_NODE, "goodrive350")] {
            if let Some(card) = Card::named(name) {
                decoder.describe(node, &card.model());
            }
        }
        let mut bench = Bench {
            bus: VirtualBus::new(now),
            master: DemoMaster {
                clients: Vec::new(),
                outbox: VecDeque::new(),
            },
            cp301,
            goodrive350,
            decoder,
            seen: Vec::new(),
            run: Run::default(),
            report: Report::default(),
        };
        bench.run_until(now);
        Ok(bench)
    }

    /// Runs the bus to `until`, decoding every frame into the report.
    fn run_until(&mut self, until: Instant) {
        self.bus.run_until(
            until,
            &mut [&mut self.master, &mut self.cp301, &mut self.goodrive350],
        );
        for (at, sender, frame) in self.bus.take_log() {
            if sender != 0 {
                self.seen.push((at, frame));
            }
            let lines = self
                .decoder
                .decode(StdDuration::from_micros(at.as_micros()), &frame);
            for line in lines {
                self.trace(frame.std_id(), line);
            }
        }
    }

    /// Adds a decoded line to the report, folding long runs of one COB-ID.
    fn trace(&mut self, id: Option<u16>, line: String) {
        if id.is_some() && id == self.run.id {
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

    fn wait(&mut self, span: Duration) {
        self.run_until(self.bus.now() + span);
    }

    fn send(&mut self, frame: CanFrame) {
        self.master.outbox.push_back(frame);
        self.run_until(self.bus.now());
    }

    /// Runs the bus until node's SDO client has a result, at most [`SDO_WAIT`].
    fn sdo_result(&mut self, node: u8) -> Result<(), String> {
        let deadline = self.bus.now() + SDO_WAIT;
        loop {
            self.run_until(self.bus.now());
            if let Some(result) = self.master.client(node).poll_result() {
                return result
                    .map(|_| ())
                    .map_err(|e| format!("SDO abort {:08X}h", e.code()));
            }
            if self.bus.now() >= deadline {
                return Err("no SDO answer".into());
            }
            self.run_until(self.bus.now() + Duration::from_millis(1));
        }
    }

    fn read<T: OdValue, D>(&mut self, node: u8, entry: Entry<T, D>) -> Result<T, String> {
        let now = self.bus.now();
        self.master
            .client(node)
            .read(now, entry)
            .map_err(|e| format!("{e:?}"))?;
        self.sdo_result(node)?;
        self.master
            .client(node)
            .take_value(&entry)
            .ok_or_else(|| "a value of the wrong length".to_string())
    }

    fn write<T: OdValue, D>(
        &mut self,
        node: u8,
        entry: Entry<T, D>,
        value: T,
    ) -> Result<(), String> {
        let now = self.bus.now();
        self.master
            .client(node)
            .write(now, entry, &value)
            .map_err(|e| format!("{e:?}"))?;
        self.sdo_result(node)
    }

    /// Records a step; `check` says what was seen or what went wrong.
    fn step(&mut self, name: &str, outcome: Result<String, String>) {
        self.end_run();
        let line = match &outcome {
            Ok(seen) => format!("  ok    {name}: {seen}"),
            Err(problem) => format!("  FAIL  {name}: {problem}"),
        };
        self.report.lines.push(line);
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

    /// The frames with `id` the drives sent since the last call, clearing the record.
    fn take_seen(&mut self, id: u16) -> Vec<CanFrame> {
        let seen = std::mem::take(&mut self.seen);
        seen.into_iter()
            .filter(|(_, f)| f.std_id() == Some(id))
            .map(|(_, f)| f)
            .collect()
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

/// Validates the bundled description files: no errors.
fn validate_cards(report: &mut Report) {
    report
        .lines
        .push("== validate the bundled EDS files".into());
    for card in &CARDS {
        let path = card.eds_path;
        let read = read::read_bytes(Path::new(path), card.eds);
        let mut diagnostics = read.diagnostics;
        diagnostics.extend(validate::validate(&read.device));
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
}

/// The CP301 manual's velocity mode (§5.3): target 1500 rpm, ramps, 6040h = 06h, 07h, 0Fh, 7Fh,
/// the speed read back while ramping, then reverse with -1500 rpm.
fn cp301_velocity_mode(bench: &mut Bench) -> Result<(), String> {
    use cp301::od;
    let node = CP301_NODE;
    bench.heading("CP301 (node 2): CiA 402 velocity mode, manual §5.3");
    bench.write(node, od::VL_TARGET_VELOCITY, 1500)?;
    bench.write(node, od::VL_RAMP_FUNCTION_TIME, 5000)?;
    bench.write(node, od::VL_SLOW_DOWN_TIME, 10_000)?;
    for (controlword, state) in [
        (0x06, State::ReadyToSwitchOn),
        (0x07, State::SwitchedOn),
        (0x0F, State::OperationEnabled),
    ] {
        bench.write(node, od::CONTROLWORD, controlword)?;
        let statusword = bench.read(node, od::STATUSWORD)?;
        let name = format!("6040h = {controlword:02X}h: {state:?}");
        bench.step(
            &name,
            expect(State::from_statusword(statusword), Some(state)),
        );
    }
    bench.write(node, od::CONTROLWORD, 0x7F)?;
    bench.wait(Duration::from_millis(2_500));
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.step(
        "6040h = 7Fh: ramping up, 6044h at 2.5 s (604Fh: 5 s to 1500 rpm)",
        expect(speed, 750),
    );
    bench.wait(Duration::from_millis(2_500));
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    let statusword = bench.read(node, od::STATUSWORD)?;
    bench.step("6044h at 5 s: 1500 rpm", expect(speed, 1500));
    bench.step(
        "6041h bit 10: target reached",
        expect(statusword & 0x0400 != 0, true),
    );
    bench.write(node, od::VL_TARGET_VELOCITY, -1500)?;
    bench.wait(Duration::from_millis(10_000));
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.step(
        "6042h = -1500: through zero after 6050h's 10 s",
        expect(speed, 0),
    );
    bench.wait(Duration::from_millis(5_000));
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.step("6044h 5 s later: -1500 rpm, reversed", expect(speed, -1500));
    bench.write(node, od::CONTROLWORD, 0x06)?;
    let speed = bench.read(node, od::VL_VELOCITY_ACTUAL_VALUE)?;
    bench.step(
        "6040h = 06h: shutdown, the output off (605Bh = 0)",
        expect(speed, 0),
    );
    Ok(())
}

/// A PDO1 parameter write (§3.5.2): the response's code, error and data.
fn goodrive350_parameter(
    bench: &mut Bench,
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
    let payload = request.encode();
    let frame = CanFrame::new(pdo::Rpdo1::cob_id(node), &payload).ok_or("a PDO1 frame")?;
    bench.take_seen(0);
    bench.send(frame);
    // PDO1 Tx has an inhibit time: give the answer 100 ms.
    bench.wait(Duration::from_millis(100));
    let answers = bench.take_seen(pdo::Tpdo1::cob_id(node));
    let answer = answers.last().ok_or("no PDO1 Tx answer")?;
    let response = pdo::Tpdo1::decode(answer.data()).map_err(|e| format!("{e:?}"))?;
    Ok((
        response.response_code,
        response.error_code,
        response.response_data,
    ))
}

/// The Goodrive350 manual's workflow (chapter 3): parameters by PDO1, run at 50.00 Hz by PDO2,
/// an injected fault with its emergency, and the fault reset.
fn goodrive350_run(bench: &mut Bench) -> Result<(), String> {
    use goodrive350::pdo;
    let node = GOODRIVE350_NODE;
    bench.heading("Goodrive350 (node 3): EC-TX105 PDO protocol, manual chapter 3");
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
    ] {
        let answer = goodrive350_parameter(bench, address, value)?;
        bench.step(&format!("PDO1 write {name}"), expect(answer, (1, 0, value)));
    }
    let answer = goodrive350_parameter(bench, 0x071B, 5)?;
    bench.step(
        "PDO1 write P07.27 (read-only): error 07h",
        expect(answer, (3, 7, 0)),
    );

    let run = pdo::Rpdo2 {
        control_word: 1,
        setting_1: 0,
        setting_2: 5000,
        setting_3: 0,
    };
    let payload = run.encode();
    bench.take_seen(0);
    bench.send(CanFrame::new(pdo::Rpdo2::cob_id(node), &payload).ok_or("a PDO2 frame")?);
    bench.wait(Duration::from_millis(11_000));
    let reports = bench.take_seen(pdo::Tpdo2::cob_id(node));
    let last = reports.last().ok_or("no PDO2 Tx")?;
    let status = pdo::Tpdo2::decode(last.data()).map_err(|e| format!("{e:?}"))?;
    bench.step(
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

    bench.goodrive350.inject_fault(bench.bus.now(), 1);
    bench.run_until(bench.bus.now());
    let emcy = bench.take_seen(0x080 + u16::from(node));
    let code = emcy
        .first()
        .map(|f| u16::from_le_bytes([f.data()[0], f.data()[1]]));
    bench.step(
        "fault OUT1 injected: EMCY 3000h with VFD error code 1",
        expect(
            (code, emcy.first().map(|f| f.data()[3])),
            (Some(0x3000), Some(1)),
        ),
    );
    bench.goodrive350.remove_fault_cause();
    let reset = pdo::Rpdo2 {
        control_word: 7,
        ..run
    };
    let payload = reset.encode();
    bench.send(CanFrame::new(pdo::Rpdo2::cob_id(node), &payload).ok_or("a PDO2 frame")?);
    bench.wait(Duration::from_millis(100));
    let emcy = bench.take_seen(0x080 + u16::from(node));
    bench.step(
        "fault reset (CW 7): the error-reset EMCY",
        expect(emcy.first().map(|f| f.data().to_vec()), Some(vec![0; 8])),
    );
    Ok(())
}

/// Runs the whole demo.
pub fn run() -> Report {
    let mut report = Report::default();
    validate_cards(&mut report);
    let mut bench = match Bench::new() {
        Ok(bench) => bench,
        Err(problem) => {
            report.steps.push(Step {
                name: "power up the simulated drives".into(),
                outcome: Err(problem),
            });
            return report;
        }
    };
    bench.report = report;
    bench.heading("NMT: start all nodes");
    bench.send(nmt_frame(NmtCommand::Start, 0));
    if let Err(problem) = cp301_velocity_mode(&mut bench) {
        bench.step("CP301 workflow", Err(problem));
    }
    if let Err(problem) = goodrive350_run(&mut bench) {
        bench.step("Goodrive350 workflow", Err(problem));
    }
    bench.report
}
