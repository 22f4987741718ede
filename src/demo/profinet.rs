//! The Goodrive350's PROFINET card in the demo, in this process: a controller finds the card by
//! DCP Identify (its GSDML's name of station, VendorID and DeviceID), names it, establishes an AR
//! over RPC (Connect with IOCRs, AlarmCR and expected submodules, PrmEnd, the device's
//! ApplicationReady answered), then exchanges the 16-word images in RT_CLASS_1 frames every
//! 4 ms: CW commands and the frequency reference out, the SW and the running frequency back, a
//! PKW read and a refused PKW write; it releases the AR, and a second AR whose controller falls
//! silent ends in the watchdog's E-PN. The frames and datagrams are the bytes a controller would
//! put on the wire (`edsgen_sim::profinet::controller` builds the requests); the images are
//! built and read with the card's generated types (`cards::goodrive350_pn`) and
//! `edsgen_runtime::pkw_pzd`.

use edsgen_runtime::pkw_pzd::{ByteOrder, ErrorNumber, InputImage, PkwResponse, IMAGE_BYTES};
use edsgen_runtime::Instant;
use edsgen_sim::drives::pkw_pzd::{Bus, PkwPzdDrive};
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::ar::{ArEvent, Peer};
use edsgen_sim::profinet::controller::{connected, response, Controller};
use edsgen_sim::profinet::dcp::Station;
use edsgen_sim::profinet::device::{Device, DeviceEvent};
use edsgen_sim::profinet::wire::dcp::{self as dcpw, emit_plain_block, request, response_blocks};
use edsgen_sim::profinet::wire::rpc::{PnioStatus, Uuid};
use edsgen_sim::profinet::wire::rt::{RtFrame, DATA_STATUS_GOOD};
use edsgen_sim::profinet::wire::{Ethernet, Mac};

use super::{expect, Trace};
use crate::cards::goodrive350_pn as card;
use card::modules::pkw_pzd_16_words::subslot_1::{Input, Output};

const DEVICE: Mac = [0x02, 0x00, 0x00, 0x00, 0x03, 0x50];
const CONTROLLER: Mac = [0x02, 0x00, 0x00, 0x00, 0x00, 0x01];
/// The controller's RPC endpoint.
const CONTROLLER_RPC: Peer = ([192, 168, 0, 1], 49152);
/// The send interval (ms) and the watchdog factor.
const INTERVAL_MS: u64 = 4;
const FACTOR: u16 = 3;
/// How many cycles a step may take (the default ramp needs 10 s to 50 Hz: 2500 cycles).
const LIMIT: u32 = 5000;

/// The PROFINET card's section of the demo.
pub(super) fn run(trace: &mut Trace) {
    trace.heading(
        "Goodrive350 PROFINET card (simulated in this process): DCP, an AR over RPC, RT_CLASS_1 frames every 4 ms",
    );
    if let Err(problem) = workflow(trace) {
        trace.step("Goodrive350 PROFINET workflow", Err(problem));
    }
}

/// A DCP answer's block: option, BlockInfo, data.
type Block = ((u8, u8), u16, Vec<u8>);

/// The DCP blocks of a device's answer to `frame`, or why there is none.
fn answer(device: &mut Device, frame: &[u8]) -> Result<Vec<Block>, String> {
    let reply = device
        .handle_frame(Instant::from_millis(0), frame)
        .ok_or("the device did not answer")?;
    let eth = Ethernet::parse(&reply).ok_or("a short answer")?;
    let (_, blocks) =
        dcpw::DcpHeader::parse(&reply[eth.payload..]).ok_or("a malformed DCP answer")?;
    Ok(response_blocks(blocks)
        .map(|(o, i, d)| (o, i, d.to_vec()))
        .collect())
}

fn find(blocks: &[Block], option: (u8, u8)) -> Result<Vec<u8>, String> {
    blocks
        .iter()
        .find(|b| b.0 == option)
        .map(|b| b.2.clone())
        .ok_or_else(|| format!("no block {option:?} in the answer"))
}

/// The controller and the card, joined by frames and datagrams.
struct Bench {
    card: Device,
    ms: u64,
    input: Input,
    /// The FrameIDs of the AR's input and output CR.
    frame_ids: (u16, u16),
}

impl Bench {
    /// One cycle: the controller's output frame, then the card's input frame.
    fn cycle(&mut self, output: &Output) -> Result<(), String> {
        let now = Instant::from_millis(self.ms);
        let data = output.encode_with_iops(card::IOXS_GOOD);
        // The output CR: the module's data and IOPS, then the IOCS for its inputs.
        let mut c_sdu = data.to_vec();
        c_sdu.push(card::IOXS_GOOD);
        let mut frame = Vec::new();
        Ethernet::emit(DEVICE, CONTROLLER, &mut frame);
        RtFrame {
            frame_id: self.frame_ids.1,
            c_sdu: &c_sdu,
            cycle_counter: (self.ms * 32) as u16,
            data_status: DATA_STATUS_GOOD,
            transfer_status: 0,
        }
        .emit(&mut frame);
        self.card.handle_frame(now, &frame);
        self.card.handle_timeout(now);
        let reply = self.card.poll_frame(now).ok_or("no input frame")?;
        self.input = decode_input(&reply)?;
        self.ms += INTERVAL_MS;
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
    let (input, iops) = Input::decode_with_iops(&bytes);
    if iops != card::IOXS_GOOD {
        return Err(format!("IOPS {iops:#04x}"));
    }
    Ok(input)
}

/// The input as the PKW/PZD protocol reads it.
fn typed(input: &Input) -> Result<InputImage, String> {
    let bytes: [u8; IMAGE_BYTES] = input.encode();
    InputImage::parse(&bytes, ByteOrder::BigEndian).map_err(|e| format!("{e:?}"))
}

fn workflow(trace: &mut Trace) -> Result<(), String> {
    let gsdml = edsgen_codegen::read::read_bytes(
        std::path::Path::new("goodrive350-pn.xml"),
        include_bytes!("../../eds/goodrive350-pn.xml"),
    );
    let pn = gsdml
        .device
        .profinet
        .as_ref()
        .ok_or("the card's GSDML did not read")?;
    let station: Station = edsgen_sim::profinet::station::from_gsdml(pn, DEVICE);
    let object = Uuid::pnio_object(
        u16::from_be_bytes([station.instance.0, station.instance.1]),
        station.device_id,
        station.vendor_id,
    );
    let config = DeviceConfig::from_gsdml(pn);
    let drive = PkwPzdDrive::bus_controlled(Bus::Profinet, Instant::from_millis(0));
    let mut device = Device::new(station, config.clone(), Some(drive));

    let identify = request(
        dcpw::MULTICAST_IDENTIFY,
        CONTROLLER,
        dcpw::FRAME_IDENTIFY_REQUEST,
        dcpw::SERVICE_IDENTIFY,
        1,
        &[0xFF, 0xFF, 0, 0],
    );
    let blocks = answer(&mut device, &identify)?;
    let name = String::from_utf8_lossy(&find(&blocks, dcpw::NAME_OF_STATION)?).into_owned();
    let ids = find(&blocks, dcpw::DEVICE_ID)?;
    let ids = (
        u16::from_be_bytes([ids[0], ids[1]]),
        u16::from_be_bytes([ids[2], ids[3]]),
    );
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

    let mut set = Vec::new();
    emit_plain_block(&mut set, dcpw::NAME_OF_STATION, b"\x00\x01gd350-line-1");
    let set = request(
        DEVICE,
        CONTROLLER,
        dcpw::FRAME_GET_SET,
        dcpw::SERVICE_SET,
        2,
        &set,
    );
    let blocks = answer(&mut device, &set)?;
    let mut by_name = Vec::new();
    emit_plain_block(&mut by_name, dcpw::NAME_OF_STATION, b"gd350-line-1");
    let found = device
        .handle_frame(
            Instant::from_millis(0),
            &request(
                dcpw::MULTICAST_IDENTIFY,
                CONTROLLER,
                dcpw::FRAME_IDENTIFY_REQUEST,
                dcpw::SERVICE_IDENTIFY,
                3,
                &by_name,
            ),
        )
        .is_some();
    trace.step(
        "DCP Set name of station `gd350-line-1`, then Identify by that name",
        expect((blocks[0].2.first().copied(), found), (Some(0), true)),
    );

    let (frame_ids, events) = establish(&mut device, &config, object, 1, Instant::from_millis(0))?;
    trace.step(
        "RPC Connect (IOCRs, AlarmCR, expected submodules), PrmEnd, ApplicationReady",
        expect(
            (frame_ids, events.as_slice()),
            ((0xC001, 0xC102), &["Connected", "PrmEnd", "DataStart"][..]),
        ),
    );
    let mut bench = Bench {
        card: device,
        ms: 0,
        input: Input::default(),
        frame_ids,
    };
    let run = Output {
        cw_control_word: 0x0001,
        pzd2_reference_value_p16_32: 5000,
        ..Output::default()
    };
    let cycles = bench.until(&run, |i| i.pzd2_actual_value_p16_43 == 5000)?;
    let sw = typed(&bench.input)?.status;
    trace.step(
        "CW 1 (run forward) and PZD2 5000: the drive ramps to 50.00 Hz",
        expect(
            (sw.0 & 0xFF, bench.input.pzd2_actual_value_p16_43),
            (1, 5000),
        )
        .map(|seen| {
            format!(
                "{seen} after {cycles} cycles ({} ms)",
                cycles as u64 * INTERVAL_MS
            )
        }),
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

    let mut ctl = Controller::new(CONTROLLER, object, 1);
    let now = Instant::from_millis(bench.ms);
    let (status, _) = call(&mut bench.card, now, &ctl.release())?;
    let events = ar_events(&mut bench.card);
    trace.step(
        "RPC Release: the AR ends and the card stops sending",
        expect(
            (
                status.is_ok(),
                events.as_slice(),
                bench.card.poll_frame(now).is_none(),
            ),
            (true, &["Released"][..], true),
        ),
    );

    // A second AR, whose controller falls silent after a few cycles: the card's watchdog
    // expires after FACTOR intervals without an output frame and aborts the AR.
    bench.frame_ids = establish(&mut bench.card, &config, object, 2, now)?.0;
    for _ in 0..3 {
        bench.cycle(&stop)?;
    }
    let silent_from = Instant::from_millis(bench.ms);
    let mut at = silent_from;
    let mut aborted = false;
    for _ in 0..100 {
        let Some(next) = bench.card.poll_timeout() else {
            break;
        };
        at = next;
        bench.card.handle_timeout(at);
        while bench.card.poll_frame(at).is_some() {}
        aborted |= ar_events(&mut bench.card).contains(&"Aborted");
        if aborted {
            break;
        }
    }
    let fault = bench.card.drive().and_then(|d| d.vfd().fault());
    trace.step(
        "the controller stops sending: watchdog, E-PN (fault 57), the AR aborted",
        expect(
            (
                fault,
                aborted,
                (at - silent_from).as_micros() <= INTERVAL_MS * 1000 * u64::from(FACTOR),
            ),
            (Some(57), true, true),
        ),
    );
    Ok(())
}

/// One RPC call of the controller to the card at `now`: the answer's status and blocks.
fn call(device: &mut Device, now: Instant, pdu: &[u8]) -> Result<(PnioStatus, Vec<u8>), String> {
    let answer = device
        .handle_datagram(now, CONTROLLER_RPC, pdu)
        .ok_or("the card did not answer")?;
    response(&answer).ok_or_else(|| "the card's answer is no RPC response".to_owned())
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

/// An AR (its UUID from `seed`) up to data exchange at `now`: Connect for the card's
/// configuration every 4 ms, PrmEnd, the card's ApplicationReady answered. The FrameIDs and
/// the AR events.
fn establish(
    device: &mut Device,
    config: &DeviceConfig,
    object: Uuid,
    seed: u8,
    now: Instant,
) -> Result<((u16, u16), Vec<&'static str>), String> {
    let mut ctl = Controller::new(CONTROLLER, object, seed);
    let blocks = ctl.connect_blocks(config, 32, INTERVAL_MS as u16, FACTOR);
    let (status, args) = call(device, now, &ctl.connect(&blocks))?;
    if !status.is_ok() {
        return Err(format!("Connect refused: {:02x?}", status.0));
    }
    let frame_ids = connected(&args).ok_or("no IOCRBlockRes")?.frame_ids;
    let (status, _) = call(device, now, &ctl.prm_end())?;
    if !status.is_ok() {
        return Err(format!("PrmEnd refused: {:02x?}", status.0));
    }
    let (to, ready) = device.poll_datagram().ok_or("no ApplicationReady")?;
    if to != (CONTROLLER_RPC.0, 34964) {
        return Err(format!("ApplicationReady sent to {to:?}"));
    }
    let done = ctl
        .answer_ready(&ready)
        .ok_or("not an ApplicationReady request")?;
    device.handle_datagram(now, (CONTROLLER_RPC.0, 34964), &done);
    Ok((frame_ids, ar_events(device)))
}
