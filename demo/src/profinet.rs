//! The Goodrive350's PROFINET card in the demo: a controller finds the card by DCP Identify (its
//! GSDML's name of station, VendorID and DeviceID), names it, establishes an AR over RPC
//! (Connect with IOCRs, AlarmCR and expected submodules, PrmEnd, the device's ApplicationReady
//! answered), then exchanges the 16-word images in RT_CLASS_1 frames every 4 ms: CW commands
//! and the frequency reference out, the SW and the running frequency back, a PKW read and a
//! refused PKW write; it releases the AR, and a second AR whose controller falls silent ends in
//! the watchdog's E-PN, which a third AR reads back (PKW read of P07.27). The frames and
//! datagrams are the bytes a controller puts on the wire (`edsgen_sim::profinet::controller`
//! builds the requests); the images are built and read with the card's generated types
//! (`cards::goodrive350_pn`) and `edsgen_runtime::pkw_pzd`.
//!
//! Two links carry them ([`Transport`]): by default the simulated card in this process, in the
//! cycles' own time ([`InProcess`]); with `--profinet`, raw Ethernet frames and UDP 34964 over a
//! veth pair to `edsgen simulate --profinet` in another network namespace, in real time
//! ([`super::profinet_wire`]).

use edsgen_model::model::Profinet;
use edsgen_runtime::pkw_pzd::{ByteOrder, ErrorNumber, InputImage, PkwResponse, IMAGE_BYTES};
use edsgen_runtime::profinet::wire::dcp::{self as dcpw, emit_plain_block};
use edsgen_runtime::profinet::wire::rpc::{PnioStatus, Uuid, RPC_PORT};
use edsgen_runtime::profinet::wire::rt::{RtFrame, DATA_STATUS_GOOD};
use edsgen_runtime::profinet::wire::{Ethernet, Mac};
use edsgen_runtime::Instant;
use edsgen_sim::drives::pkw_pzd::{Bus, PkwPzdDrive};
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::ar::{ArEvent, Peer};
use edsgen_sim::profinet::controller::{connected, response, Controller};
use edsgen_sim::profinet::device::{Device, DeviceEvent, Link, Transmit};

use super::profinet_wire::{answer, dcp_request as request, find};
use super::{expect, Trace};
use card::modules::pkw_pzd_16_words::subslot_1::{Input, Output};
use edsgen_sim::cards::goodrive350_pn as card;

/// In this process: the card's and the controller's MAC addresses and the controller's RPC
/// endpoint.
const DEVICE: Mac = [0x02, 0x00, 0x00, 0x00, 0x03, 0x50];
const CONTROLLER: Mac = [0x02, 0x00, 0x00, 0x00, 0x00, 0x01];
const CONTROLLER_RPC: Peer = ([192, 168, 0, 1], 49152);
/// How many cycles a step may take (the default ramp needs 10 s to 50 Hz: 2500 cycles of 4 ms).
const LIMIT: u32 = 5000;

/// The AR's timing, as the Connect asks for it, and how late a real wire may see what is due.
#[derive(Debug, Clone, Copy)]
pub(super) struct Timing {
    /// The send interval of both CRs (ms): a power of two, 1 to 512.
    pub(super) interval_ms: u64,
    /// The DataHoldFactor: the card's watchdog expires `factor` intervals after the last output
    /// frame.
    pub(super) factor: u16,
    /// How much earlier and how much later than the watchdog's time the card may be seen to
    /// stop (ms): in this process, up to the two intervals between its last input frame and
    /// the watchdog, and not later.
    pub(super) early_ms: u64,
    pub(super) late_ms: u64,
}

impl Timing {
    /// The watchdog's time (ms).
    pub(super) fn watchdog_ms(self) -> u64 {
        self.interval_ms * u64::from(self.factor)
    }
}

/// What the controller sees when it falls silent.
pub(super) struct Silence {
    /// Whether the card ended the AR (in this process: its Aborted event; on a wire: its input
    /// frames stopped).
    pub(super) aborted: bool,
    /// From the controller's last output frame to the AR's end (ms; on a wire: to the card's
    /// last input frame).
    pub(super) after_ms: u64,
    /// How it was seen, where there is more to say than the step's values (a wire).
    pub(super) seen: String,
}

/// What carries the controller's frames and datagrams to the card and back.
pub(super) trait Transport {
    /// The controller's MAC address: the source of its frames.
    fn controller_mac(&self) -> Mac;
    /// The timing of the ARs on this link.
    fn timing(&self) -> Timing;
    /// A DCP request frame to the card; the card's answer (`None` when none came).
    fn dcp(&mut self, request: &[u8]) -> Result<Option<Vec<u8>>, String>;
    /// One RPC request to the card's endpoint (UDP 34964); its response.
    fn call(&mut self, pdu: &[u8]) -> Result<Vec<u8>, String>;
    /// The RPC request the card sends of its own to the controller's UDP 34964
    /// (ApplicationReady).
    fn card_request(&mut self) -> Result<Vec<u8>, String>;
    /// Answers that request.
    fn answer(&mut self, pdu: &[u8]) -> Result<(), String>;
    /// The AR events the card reports, where it runs in this process (on a wire its log is
    /// shown after the section).
    fn card_events(&mut self) -> Option<Vec<&'static str>>;
    /// The time of the next cycle (ms since the first): the cycles' own in this process, the
    /// clock's on a wire (where a cycle may take longer than the interval: the sockets' read
    /// timeouts go by the kernel's ticks).
    fn now_ms(&self) -> u64;
    /// One send interval: the output frame at its start, then the last input frame the card
    /// sent (`None` if none came yet).
    fn cycle(&mut self, frame: &[u8]) -> Result<Option<Vec<u8>>, String>;
    /// After a Release: whether the card has stopped sending input frames.
    fn sending_stopped(&mut self) -> Result<bool, String>;
    /// The controller falls silent until the card ends the AR (or long enough to show it does
    /// not).
    fn fall_silent(&mut self) -> Result<Silence, String>;
}

/// The card in this process, in the cycles' own time.
struct InProcess {
    card: Device,
    ms: u64,
}

impl InProcess {
    fn now(&self) -> Instant {
        Instant::from_millis(self.ms)
    }
}

/// In this process: the card's send interval (ms) and watchdog factor.
const INTERVAL_MS: u64 = 4;
const FACTOR: u16 = 3;

impl Transport for InProcess {
    fn controller_mac(&self) -> Mac {
        CONTROLLER
    }

    fn timing(&self) -> Timing {
        Timing {
            interval_ms: INTERVAL_MS,
            factor: FACTOR,
            early_ms: 2 * INTERVAL_MS,
            late_ms: 0,
        }
    }

    fn dcp(&mut self, request: &[u8]) -> Result<Option<Vec<u8>>, String> {
        self.card.handle(self.now(), Link::Ethernet, request);
        Ok(self
            .card
            .poll_transmit(self.now())
            .and_then(Transmit::frame))
    }

    fn call(&mut self, pdu: &[u8]) -> Result<Vec<u8>, String> {
        self.card.handle(self.now(), Link::Rpc(CONTROLLER_RPC), pdu);
        let answer = self
            .card
            .poll_transmit(self.now())
            .and_then(Transmit::datagram);
        answer
            .map(|(_, pdu)| pdu)
            .ok_or_else(|| "the card did not answer".to_owned())
    }

    fn card_request(&mut self) -> Result<Vec<u8>, String> {
        let sent = self
            .card
            .poll_transmit(self.now())
            .and_then(Transmit::datagram);
        let (to, pdu) = sent.ok_or("no ApplicationReady")?;
        if to != (CONTROLLER_RPC.0, RPC_PORT) {
            return Err(format!("ApplicationReady sent to {to:?}"));
        }
        Ok(pdu)
    }

    fn answer(&mut self, pdu: &[u8]) -> Result<(), String> {
        let from = (CONTROLLER_RPC.0, RPC_PORT);
        self.card.handle(self.now(), Link::Rpc(from), pdu);
        Ok(())
    }

    fn card_events(&mut self) -> Option<Vec<&'static str>> {
        Some(ar_events(&mut self.card))
    }

    fn now_ms(&self) -> u64 {
        self.ms
    }

    fn cycle(&mut self, frame: &[u8]) -> Result<Option<Vec<u8>>, String> {
        let now = self.now();
        self.card.handle(now, Link::Ethernet, frame);
        self.card.handle_timeout(now);
        let reply = self.card.poll_transmit(now).and_then(Transmit::frame);
        self.ms += INTERVAL_MS;
        Ok(reply)
    }

    fn sending_stopped(&mut self) -> Result<bool, String> {
        Ok(self.card.poll_transmit(self.now()).is_none())
    }

    /// The card's watchdog expires after FACTOR intervals without an output frame.
    fn fall_silent(&mut self) -> Result<Silence, String> {
        let last_output = self.ms.saturating_sub(INTERVAL_MS);
        let mut at = self.now();
        let mut aborted = false;
        for _ in 0..100 {
            let Some(next) = self.card.poll_timeout() else {
                break;
            };
            at = next;
            self.card.handle_timeout(at);
            while self.card.poll_transmit(at).is_some() {}
            aborted |= ar_events(&mut self.card).contains(&"Aborted");
            if aborted {
                break;
            }
        }
        let at_ms = at.as_micros().div_ceil(1000);
        self.ms = self.ms.max(at_ms);
        Ok(Silence {
            aborted,
            after_ms: at_ms.saturating_sub(last_output),
            seen: String::new(),
        })
    }
}

/// The card's GSDML, as the controller is configured with it and the simulated card is built
/// from it.
fn gsdml() -> Result<Profinet, String> {
    edsgen_model::load::load_bundled(
        std::path::Path::new("eds/goodrive350-pn.xml"),
        include_bytes!("../../eds/goodrive350-pn.xml"),
        Some(include_str!("../../eds/goodrive350-pn.toml")),
    )
    .device
    .profinet()
    .cloned()
    .ok_or_else(|| "the card's GSDML did not read".to_owned())
}

/// The PROFINET card's section of the demo, in this process.
pub(super) fn run(trace: &mut Trace) {
    trace.heading(
        "Goodrive350 PROFINET card (simulated in this process): DCP, an AR over RPC, RT_CLASS_1 frames every 4 ms",
    );
    let link = gsdml().map(|pn| {
        let station = edsgen_sim::profinet::station::from_gsdml(&pn, DEVICE);
        let drive = PkwPzdDrive::bus_controlled(Bus::Profinet, Instant::from_millis(0));
        InProcess {
            card: Device::new(station, DeviceConfig::from_gsdml(&pn), Some(drive)),
            ms: 0,
        }
    });
    let done = link.and_then(|mut link| workflow(trace, &mut link));
    if let Err(problem) = done {
        trace.step("Goodrive350 PROFINET workflow", Err(problem));
    }
}

/// The controller and the card, joined by a [`Transport`].
struct Bench<'a> {
    link: &'a mut dyn Transport,
    /// The controller's and the card's MAC addresses.
    controller: Mac,
    card: Mac,
    config: DeviceConfig,
    object: Uuid,
    timing: Timing,
    input: Input,
    /// The FrameIDs of the AR's input and output CR.
    frame_ids: (u16, u16),
}

impl Bench<'_> {
    /// One cycle: the controller's output frame, then the card's input frame.
    fn cycle(&mut self, output: &Output) -> Result<(), String> {
        let data = output.to_bytes_with_iops(card::IOXS_GOOD);
        // The output CR: the module's data and IOPS, then the IOCS for its inputs.
        let mut c_sdu = data.to_vec();
        c_sdu.push(card::IOXS_GOOD);
        let rt = RtFrame {
            frame_id: self.frame_ids.1,
            c_sdu: &c_sdu,
            cycle_counter: (self.link.now_ms() * 32) as u16,
            data_status: DATA_STATUS_GOOD,
            transfer_status: 0,
        };
        let mut frame = vec![0; 14 + rt.buffer_len()];
        let header = Ethernet::emit(self.card, self.controller, &mut frame);
        header
            .and_then(|at| rt.emit(&mut frame[at..]))
            .map_err(|_| "the output frame does not fit")?;
        let reply = self.link.cycle(&frame)?.ok_or("no input frame")?;
        self.input = decode_input(&reply)?;
        Ok(())
    }

    /// Cycles with `output` until `done` holds for the input, at most [`LIMIT`]: how many.
    fn until(&mut self, output: &Output, done: impl Fn(&Input) -> bool) -> Result<u32, String> {
        for n in 1..=LIMIT {
            self.cycle(output)?;
            if done(&self.input) {
                return Ok(n);
            }
        }
        Err(format!(
            "not within {LIMIT} cycles; the inputs are {:?}",
            self.input
        ))
    }

    /// One RPC call of the controller to the card: the answer's status and blocks.
    fn call(&mut self, pdu: &[u8]) -> Result<(PnioStatus, Vec<u8>), String> {
        let answer = self.link.call(pdu)?;
        response(&answer).ok_or_else(|| "the card's answer is no RPC response".to_owned())
    }

    /// An AR (its UUID from `seed`) up to data exchange: Connect for the card's configuration,
    /// PrmEnd, the card's ApplicationReady answered. The FrameIDs, and the AR's steps as the
    /// card reports them (in this process) or as the controller saw them (on a wire).
    fn establish(&mut self, seed: u8) -> Result<((u16, u16), Vec<&'static str>), String> {
        let mut ctl = Controller::new(self.controller, self.object, seed);
        let (rr, factor) = (self.timing.interval_ms as u16, self.timing.factor);
        let blocks = ctl.connect_blocks(&self.config, 32, rr, factor);
        let mut seen = Vec::new();
        let (status, args) = self.call(&ctl.connect(&blocks))?;
        if !status.is_ok() {
            return Err(format!("Connect refused: {:02x?}", status.0));
        }
        seen.push("Connected");
        let frame_ids = connected(&args).ok_or("no IOCRBlockRes")?.frame_ids;
        let (status, _) = self.call(&ctl.prm_end())?;
        if !status.is_ok() {
            return Err(format!("PrmEnd refused: {:02x?}", status.0));
        }
        seen.push("PrmEnd");
        let ready = self.link.card_request()?;
        let done = ctl
            .answer_ready(&ready)
            .ok_or("not an ApplicationReady request")?;
        self.link.answer(&done)?;
        seen.push("DataStart");
        self.frame_ids = frame_ids;
        Ok((frame_ids, self.link.card_events().unwrap_or(seen)))
    }

    /// Releases the AR of `seed`: whether the card said yes, and the AR's end as the card
    /// reports it (in this process) or as the controller saw it (on a wire).
    fn release(&mut self, seed: u8) -> Result<(bool, Vec<&'static str>), String> {
        let mut ctl = Controller::new(self.controller, self.object, seed);
        let (status, _) = self.call(&ctl.release())?;
        let seen = if status.is_ok() {
            vec!["Released"]
        } else {
            vec![]
        };
        Ok((status.is_ok(), self.link.card_events().unwrap_or(seen)))
    }
}

/// Where the module's inputs sit in the input CR: after the IOPS of the access point's four
/// submodules without IO data (the layout the Controller asks for).
const INPUT_OFFSET: usize = 4;

fn decode_input(frame: &[u8]) -> Result<Input, String> {
    let eth = Ethernet::parse(frame).ok_or("a short input frame")?;
    let rt = RtFrame::parse(&frame[eth.payload..], 40).ok_or("a short RT frame")?;
    let bytes: [u8; IMAGE_BYTES + 1] = rt.c_sdu[INPUT_OFFSET..INPUT_OFFSET + IMAGE_BYTES + 1]
        .try_into()
        .map_err(|_| "a short C_SDU")?;
    let (input, iops) = Input::from_bytes_with_iops(&bytes);
    if iops != card::IOXS_GOOD {
        return Err(format!("IOPS {iops:#04x}"));
    }
    Ok(input)
}

/// The input as the PKW/PZD protocol reads it.
fn typed(input: &Input) -> Result<InputImage, String> {
    let bytes: [u8; IMAGE_BYTES] = input.to_bytes();
    InputImage::parse(&bytes, ByteOrder::BigEndian).map_err(|e| format!("{e:?}"))
}

/// The steps, on either link.
pub(super) fn workflow(trace: &mut Trace, link: &mut dyn Transport) -> Result<(), String> {
    let pn = gsdml()?;
    // What the controller is configured with: the GSDML's identity and access point.
    let station = edsgen_sim::profinet::station::from_gsdml(&pn, [0; 6]);
    let object = Uuid::pnio_object(
        u16::from_be_bytes([station.instance.0, station.instance.1]),
        station.device_id,
        station.vendor_id,
    );
    let controller = link.controller_mac();

    let identify = request(
        dcpw::MULTICAST_IDENTIFY,
        controller,
        dcpw::FRAME_IDENTIFY_REQUEST,
        dcpw::SERVICE_IDENTIFY,
        1,
        &[0xFF, 0xFF, 0, 0],
    );
    let (device, blocks) = answer(link, &identify)?;
    let name = String::from_utf8_lossy(&find(&blocks, dcpw::NAME_OF_STATION)?).into_owned();
    let ids = find(&blocks, dcpw::DEVICE_ID)?;
    let ids = match ids[..] {
        [v0, v1, d0, d1, ..] => (u16::from_be_bytes([v0, v1]), u16::from_be_bytes([d0, d1])),
        _ => return Err(format!("a short DeviceID block: {ids:02x?}")),
    };
    trace.step(
        "DCP Identify all: the card answers with its GSDML's name and IDs",
        expect(
            (name.as_str(), ids),
            (
                card::DNS_COMPATIBLE_NAME,
                (card::VENDOR_ID, card::DEVICE_ID),
            ),
        ),
    );

    let mut set = [0; 20];
    let n = emit_plain_block(&mut set, dcpw::NAME_OF_STATION, b"\x00\x01gd350-line-1")
        .map_err(|_| "the Set block does not fit")?;
    let set = request(
        device,
        controller,
        dcpw::FRAME_GET_SET,
        dcpw::SERVICE_SET,
        2,
        &set[..n],
    );
    let (_, blocks) = answer(link, &set)?;
    let mut by_name = [0; 16];
    let n = emit_plain_block(&mut by_name, dcpw::NAME_OF_STATION, b"gd350-line-1")
        .map_err(|_| "the filter block does not fit")?;
    let found = link
        .dcp(&request(
            dcpw::MULTICAST_IDENTIFY,
            controller,
            dcpw::FRAME_IDENTIFY_REQUEST,
            dcpw::SERVICE_IDENTIFY,
            3,
            &by_name[..n],
        ))?
        .is_some();
    trace.step(
        "DCP Set name of station `gd350-line-1`, then Identify by that name",
        expect(
            (blocks.first().and_then(|b| b.2.first().copied()), found),
            (Some(0), true),
        ),
    );

    let timing = link.timing();
    let mut bench = Bench {
        link,
        controller,
        card: device,
        config: DeviceConfig::from_gsdml(&pn),
        object,
        timing,
        input: Input::default(),
        frame_ids: (0, 0),
    };
    let (frame_ids, events) = bench.establish(1)?;
    trace.step(
        "RPC Connect (IOCRs, AlarmCR, expected submodules), PrmEnd, ApplicationReady",
        expect(
            (frame_ids, events.as_slice()),
            ((0xC001, 0xC102), &["Connected", "PrmEnd", "DataStart"][..]),
        ),
    );
    let run = Output {
        cw_control_word: 0x0001,
        pzd2_reference_value_p16_32: 5000,
        ..Output::default()
    };
    let started = bench.link.now_ms();
    let cycles = bench.until(&run, |i| i.pzd2_actual_value_p16_43 == 5000)?;
    let took = bench.link.now_ms() - started;
    let sw = typed(&bench.input)?.status;
    trace.step(
        "CW 1 (run forward) and PZD2 5000: the drive ramps to 50.00 Hz",
        expect(
            (sw.0 & 0xFF, bench.input.pzd2_actual_value_p16_43),
            (1, 5000),
        )
        .map(|seen| format!("{seen} after {cycles} cycles ({took} ms)")),
    );

    let read = Output {
        pkw1_task_identification: 1,
        pkw2_parameter_address: 0x000B,
        ..run
    };
    bench.until(&read, |i| i.pkw1_response_identification == 1)?;
    trace.step(
        "PKW read of P00.11 (acceleration time)",
        expect(
            typed(&bench.input)?.pkw,
            PkwResponse::Word {
                address: 0x000B,
                value: 100,
            },
        ),
    );

    let write = Output {
        pkw1_task_identification: 4,
        pkw2_parameter_address: 0x000B,
        pkw4_value_low_word: 50,
        ..run
    };
    bench.until(&write, |i| i.pkw1_response_identification == 3)?;
    trace.step(
        "PKW write without CW bit 8 (enable writing): refused",
        expect(
            typed(&bench.input)?.pkw,
            PkwResponse::Refused {
                address: 0x000B,
                error: ErrorNumber::InvalidCommand,
            },
        ),
    );

    let stop = Output {
        cw_control_word: 0x0005,
        ..Output::default()
    };
    let cycles = bench.until(&stop, |i| i.sw_status_word & 0xFF == 3)?;
    trace.step(
        "CW 5 (stop): the drive decelerates and stops",
        expect(bench.input.pzd2_actual_value_p16_43, 0)
            .map(|seen| format!("{seen} after {cycles} cycles")),
    );

    let (released, events) = bench.release(1)?;
    let stopped = bench.link.sending_stopped()?;
    trace.step(
        "RPC Release: the AR ends and the card stops sending",
        expect(
            (released, events.as_slice(), stopped),
            (true, &["Released"][..], true),
        ),
    );

    // A second AR, whose controller falls silent after a few cycles: the card's watchdog
    // expires after `factor` intervals without an output frame and aborts the AR, and the
    // drive trips E-PN; a third AR reads the fault back (P07.27, type of present fault).
    bench.establish(2)?;
    for _ in 0..3 {
        bench.cycle(&stop)?;
    }
    let silence = bench.link.fall_silent()?;
    let watchdog = timing.watchdog_ms();
    let in_time = (watchdog.saturating_sub(timing.early_ms)..=watchdog + timing.late_ms)
        .contains(&silence.after_ms);
    bench.establish(3)?;
    let fault = Output {
        pkw1_task_identification: 1,
        pkw2_parameter_address: 0x071B,
        ..Output::default()
    };
    bench.until(&fault, |i| i.pkw1_response_identification != 0)?;
    let fault = match typed(&bench.input)?.pkw {
        PkwResponse::Word {
            address: 0x071B,
            value,
        } => Some(value),
        _ => None,
    };
    bench.release(3)?;
    let checked = expect((fault, silence.aborted, in_time), (Some(57), true, true));
    trace.step(
        "the controller stops sending: watchdog, E-PN (fault 57), the AR aborted",
        if silence.seen.is_empty() {
            checked
        } else {
            checked.map(|seen| format!("{seen}; {}", silence.seen))
        },
    );
    Ok(())
}

/// The names of the AR events since the last call.
fn ar_events(device: &mut Device) -> Vec<&'static str> {
    std::iter::from_fn(|| device.poll_event())
        .filter_map(|e| match e {
            DeviceEvent::Ar(ArEvent::Connected { .. }) => Some("Connected"),
            DeviceEvent::Ar(ArEvent::PrmEnd) => Some("PrmEnd"),
            DeviceEvent::Ar(ArEvent::DataStart) => Some("DataStart"),
            DeviceEvent::Ar(ArEvent::Released) => Some("Released"),
            DeviceEvent::Ar(ArEvent::Aborted) => Some("Aborted"),
            _ => None,
        })
        .collect()
}
