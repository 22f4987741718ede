//! The Goodrive350's PROFINET card in the demo, in this process: a controller finds the card by
//! DCP Identify (its GSDML's name of station, VendorID and DeviceID), names it, then exchanges
//! the 16-word images in RT_CLASS_1 frames every 4 ms: CW commands and the frequency reference
//! out, the SW and the running frequency back, a PKW read and a refused PKW write, and when the
//! controller falls silent the watchdog's E-PN. The frames are the bytes a controller would put
//! on the wire; the images are built and read with the card's generated types
//! (`cards::goodrive350_pn`) and `edsgen_runtime::pkw_pzd`.

use edsgen_runtime::pkw_pzd::{ByteOrder, ErrorNumber, InputImage, PkwResponse, IMAGE_BYTES};
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::drives::pkw_pzd::{Bus, PkwPzdDrive};
use edsgen_sim::profinet::dcp::{Dcp, Station};
use edsgen_sim::profinet::drive::{card_layout, CardCycle};
use edsgen_sim::profinet::wire::dcp::{self as dcpw, emit_plain_block, request, response_blocks};
use edsgen_sim::profinet::wire::rt::{RtFrame, DATA_STATUS_GOOD};
use edsgen_sim::profinet::wire::{Ethernet, Mac};

use super::{expect, Trace};
use crate::cards::goodrive350_pn as card;
use card::modules::pkw_pzd_16_words::subslot_1::{Input, Output};

const DEVICE: Mac = [0x02, 0x00, 0x00, 0x00, 0x03, 0x50];
const CONTROLLER: Mac = [0x02, 0x00, 0x00, 0x00, 0x00, 0x01];
/// The send interval (ms) and the watchdog factor.
const INTERVAL_MS: u64 = 4;
const FACTOR: u16 = 3;
/// How many cycles a step may take (the default ramp needs 10 s to 50 Hz: 2500 cycles).
const LIMIT: u32 = 5000;

/// The PROFINET card's section of the demo.
pub(super) fn run(trace: &mut Trace) {
    trace.heading(
        "Goodrive350 PROFINET card (simulated in this process): DCP, then RT_CLASS_1 frames every 4 ms",
    );
    if let Err(problem) = workflow(trace) {
        trace.step("Goodrive350 PROFINET workflow", Err(problem));
    }
}

/// A DCP answer's block: option, BlockInfo, data.
type Block = ((u8, u8), u16, Vec<u8>);

/// The DCP blocks of a device's answer to `frame`, or why there is none.
fn answer(dcp: &mut Dcp, frame: &[u8]) -> Result<Vec<Block>, String> {
    let reply = dcp.handle(frame).ok_or("the device did not answer")?;
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

/// The controller and the card, joined by frames.
struct Bench {
    card: CardCycle,
    ms: u64,
    input: Input,
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
            frame_id: 0xC000,
            c_sdu: &c_sdu,
            cycle_counter: (self.ms * 32) as u16,
            data_status: DATA_STATUS_GOOD,
            transfer_status: 0,
        }
        .emit(&mut frame);
        self.card.handle(now, &frame);
        self.card.handle_timeout(now);
        let reply = self.card.poll_transmit(now).ok_or("no input frame")?;
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

fn decode_input(frame: &[u8]) -> Result<Input, String> {
    let eth = Ethernet::parse(frame).ok_or("a short input frame")?;
    let rt = RtFrame::parse(&frame[eth.payload..], IMAGE_BYTES + 2).ok_or("a short RT frame")?;
    let bytes: [u8; IMAGE_BYTES + 1] = rt.c_sdu[..IMAGE_BYTES + 1]
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
    let mut dcp = Dcp::new(station);

    let identify = request(
        dcpw::MULTICAST_IDENTIFY,
        CONTROLLER,
        dcpw::FRAME_IDENTIFY_REQUEST,
        dcpw::SERVICE_IDENTIFY,
        1,
        &[0xFF, 0xFF, 0, 0],
    );
    let blocks = answer(&mut dcp, &identify)?;
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
    let blocks = answer(&mut dcp, &set)?;
    let mut by_name = Vec::new();
    emit_plain_block(&mut by_name, dcpw::NAME_OF_STATION, b"gd350-line-1");
    let found = dcp
        .handle(&request(
            dcpw::MULTICAST_IDENTIFY,
            CONTROLLER,
            dcpw::FRAME_IDENTIFY_REQUEST,
            dcpw::SERVICE_IDENTIFY,
            3,
            &by_name,
        ))
        .is_some();
    trace.step(
        "DCP Set name of station `gd350-line-1`, then Identify by that name",
        expect((blocks[0].2.first().copied(), found), (Some(0), true)),
    );

    let layout = card_layout(
        CONTROLLER,
        DEVICE,
        Duration::from_millis(INTERVAL_MS),
        FACTOR,
    );
    let drive = PkwPzdDrive::bus_controlled(Bus::Profinet, Instant::from_millis(0));
    let mut bench = Bench {
        card: CardCycle::new(layout, drive, Instant::from_millis(0)),
        ms: 0,
        input: Input::default(),
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

    // The controller falls silent: the card goes on sending its inputs, and its watchdog expires
    // after FACTOR intervals without an output frame.
    let silent_from = Instant::from_millis(bench.ms);
    let mut at = silent_from;
    let mut input = bench.input;
    for _ in 0..100 {
        at = bench.card.poll_timeout();
        bench.card.handle_timeout(at);
        if let Some(reply) = bench.card.poll_transmit(at) {
            input = decode_input(&reply)?;
        }
        if bench.card.drive().vfd().fault().is_some() {
            break;
        }
    }
    trace.step(
        "the controller stops sending: watchdog, E-PN (fault 57)",
        expect(
            (
                input.sw_status_word & 0xFF,
                bench.card.drive().vfd().fault(),
                (at - silent_from).as_micros() <= INTERVAL_MS * 1000 * u64::from(FACTOR),
            ),
            (4, Some(57), true),
        ),
    );
    Ok(())
}
