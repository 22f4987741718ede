//! Hostile input to the whole device, in process: a recorded good exchange (DCP Identify, Get
//! and Set, Connect, Write, Read, PrmEnd, ApplicationReady's Done, output frames, Release)
//! mutated a few thousand times with a fixed seed (bytes flipped, cut short, grown, lengths
//! made huge); every answer the device builds must be one its sockets can send: a frame of at
//! most 1514 bytes, a datagram of at most 1464 bytes (one 1500-byte IP packet) to a peer with
//! a port.

use super::*;
use crate::profinet::controller::{connected, response, Controller};
use crate::profinet::wire::dcp;
use crate::profinet::wire::rpc::Uuid;
use crate::profinet::wire::{append, Ethernet, Mac};

const DEVICE: Mac = [2, 0, 0, 0, 3, 0x50];
const CONTROLLER: Mac = [2, 0, 0, 0, 0, 1];
const FROM: Peer = ([10, 0, 0, 1], 49152);

/// The card's station and configuration, read once.
fn card() -> &'static (Station, DeviceConfig) {
    static CARD: std::sync::OnceLock<(Station, DeviceConfig)> = std::sync::OnceLock::new();
    CARD.get_or_init(|| {
        let read = edsgen_model::read::read_bytes(
            std::path::Path::new("goodrive350-pn.xml"),
            include_bytes!("../../../../eds/goodrive350-pn.xml"),
        );
        let pn = read.device.profinet().expect("a GSDML");
        let mut station = crate::profinet::station::from_gsdml(pn, DEVICE);
        station.ip = [[10, 0, 0, 2], [255, 255, 255, 0], [0; 4]];
        (station, DeviceConfig::from_gsdml(pn))
    })
}

fn device() -> Device {
    let (station, config) = card();
    Device::new(station.clone(), config.clone(), None)
}

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn dcp_frame(dst: Mac, frame_id: u16, service: u8, xid: u32, blocks: &[u8]) -> Vec<u8> {
    let mut f = vec![0; 14 + dcp::HEADER_LEN + blocks.len()];
    let n = dcp::request(&mut f, dst, CONTROLLER, frame_id, service, xid, blocks).unwrap_or(0);
    f.truncate(n);
    f
}

/// What a controller sends in a good session: (is a datagram, bytes).
pub(super) fn recorded() -> Vec<(bool, Vec<u8>)> {
    let mut out = Vec::new();
    let mut name = [0; 16];
    let n = dcp::emit_plain_block(&mut name, dcp::NAME_OF_STATION, b"goodrive350-pn").unwrap_or(0);
    out.push((
        false,
        dcp_frame(dcp::MULTICAST_IDENTIFY, 0xFEFE, 5, 1, &name[..n]),
    ));
    out.push((
        false,
        dcp_frame(dcp::MULTICAST_IDENTIFY, 0xFEFE, 5, 2, &[0xFF, 0xFF, 0, 0]),
    ));
    out.push((
        false,
        dcp_frame(DEVICE, 0xFEFD, 3, 3, &[2, 2, 2, 1, 1, 2, 0xFF, 0xFF]),
    ));
    let mut set = [0; 20];
    let n = dcp::emit_plain_block(&mut set, dcp::NAME_OF_STATION, b"\x00\x01drive-7").unwrap_or(0);
    out.push((false, dcp_frame(DEVICE, 0xFEFD, 4, 4, &set[..n])));
    let mut device = device();
    let object = Uuid::pnio_object(1, 0x0350, 0x0350);
    let mut ctl = Controller::new(CONTROLLER, object, 3);
    let config = card().1.clone();
    let now = Instant::from_millis(0);
    let connect = ctl.connect(&ctl.connect_blocks(&config, 32, 8, 3));
    let answer = device
        .handle_datagram(now, FROM, &connect)
        .expect("an answer");
    let (_, args) = response(&answer).expect("a response");
    let ids = connected(&args).expect("IOCRs").frame_ids;
    out.push((true, connect));
    out.push((true, ctl.write(1, 1, 256, &[0; 22])));
    out.push((true, ctl.read(1, 1, 256)));
    out.push((true, ctl.read(0, 1, 0xAFF0)));
    let prm_end = ctl.prm_end();
    device.handle_datagram(now, FROM, &prm_end);
    out.push((true, prm_end));
    let (_, ready) = device.poll_datagram().expect("ApplicationReady");
    out.push((true, ctl.answer_ready(&ready).expect("a Done")));
    let mut frame = Vec::new();
    append(&mut frame, |b| Ethernet::emit(DEVICE, CONTROLLER, b));
    let c_sdu = [0x80u8; 40];
    let rt = crate::profinet::wire::rt::RtFrame {
        frame_id: ids.1,
        c_sdu: &c_sdu,
        cycle_counter: 0,
        data_status: crate::profinet::wire::rt::DATA_STATUS_GOOD,
        transfer_status: 0,
    };
    append(&mut frame, |b| rt.emit(b));
    out.push((false, frame));
    out.push((true, ctl.release()));
    out
}

/// One mutation of `bytes`.
fn mutate(rng: &mut Rng, bytes: &[u8]) -> Vec<u8> {
    let mut m = bytes.to_vec();
    match rng.below(6) {
        0 => m.truncate(rng.below(bytes.len() + 1)),
        1 => {
            for _ in 0..=rng.below(4) {
                let at = rng.below(m.len());
                if let Some(b) = m.get_mut(at) {
                    *b ^= 1 << rng.below(8);
                }
            }
        }
        2 => {
            let at = rng.below(m.len());
            if let Some(b) = m.get_mut(at) {
                *b = rng.next() as u8;
            }
        }
        3 => {
            // A 16-bit field made huge.
            let at = rng.below(m.len().saturating_sub(1));
            if let Some(w) = m.get_mut(at..at + 2) {
                w.copy_from_slice(&[0xFF, rng.next() as u8]);
            }
        }
        4 => {
            let extra = rng.below(1600);
            m.extend((0..extra).map(|_| rng.next() as u8));
        }
        _ => {
            let start = 14.min(m.len());
            for b in m.iter_mut().skip(start + rng.below(40)) {
                *b = rng.next() as u8;
            }
        }
    }
    m
}

/// Why `transmit` cannot go out on a socket, if it cannot.
fn unsendable(transmit: &Transmit) -> Option<String> {
    match transmit {
        Transmit::Frame(f) if f.len() > 1514 => Some(format!("a frame of {} bytes", f.len())),
        Transmit::Frame(f) if f.len() < 14 => Some(format!("a frame of {} bytes", f.len())),
        Transmit::Datagram(to, _) if to.1 == 0 => {
            Some(format!("a datagram to port 0 of {:?}", to.0))
        }
        Transmit::Datagram(_, d) if d.len() > 1464 => {
            Some(format!("a datagram of {} bytes", d.len()))
        }
        _ => None,
    }
}

#[test]
fn thousands_of_mutated_frames_get_only_sendable_answers() {
    let good = recorded();
    assert_eq!(good.len(), 12);
    let mut rng = Rng(0x5EED_0034);
    let mut problems = Vec::new();
    for round in 0..4000 {
        let mut device = device();
        let mut now = 0;
        let victim = rng.below(good.len());
        for (n, (datagram, bytes)) in good.iter().enumerate() {
            let bytes = if n == victim {
                mutate(&mut rng, bytes)
            } else {
                bytes.clone()
            };
            now += 1;
            let t = Instant::from_millis(now);
            let link = if *datagram {
                Link::Rpc(FROM)
            } else {
                Link::Ethernet
            };
            device.handle(t, link, &bytes);
            while let Some(transmit) = device.poll_transmit(t) {
                if let Some(problem) = unsendable(&transmit) {
                    problems.push(format!(
                        "round {round}, input {n} ({}): {problem}",
                        bytes.len()
                    ));
                }
            }
        }
    }
    assert!(
        problems.is_empty(),
        "{} problems: {:#?}",
        problems.len(),
        &problems[..problems.len().min(20)]
    );
}

/// A DCP Get asking for the name of station 700 times (a 1424-byte request) is answered with
/// the blocks that fit one frame: 74 of them, 1506 bytes; the frame outgrew the interface
/// before (14,026 bytes, "Message too long" from the socket, and the simulator exited).
#[test]
fn a_dcp_get_of_700_options_is_answered_within_one_frame() {
    let mut device = device();
    let t = Instant::from_millis(1);
    let get = [2u8, 2].repeat(700);
    device.handle(t, Link::Ethernet, &dcp_frame(DEVICE, 0xFEFD, 3, 3, &get));
    let Some(Transmit::Frame(answer)) = device.poll_transmit(t) else {
        panic!("no answer");
    };
    assert_eq!(answer.len(), 1506);
    // FrameID, Get response, Xid 3, no delay, DCPDataLength 74 × 20.
    assert_eq!(answer[14..24], [0xFE, 0xFD, 3, 1, 0, 0, 0, 3, 0, 0]);
    assert_eq!(answer[24..26], (74u16 * 20).to_be_bytes());
    let mut block = vec![2, 2, 0, 16, 0, 0];
    block.extend_from_slice(b"goodrive350-pn");
    for n in 0..74 {
        assert_eq!(answer[26 + 20 * n..46 + 20 * n], block[..], "block {n}");
    }
    assert!(device.poll_transmit(t).is_none());
}

/// A DCP Set of 300 Signal blocks: the Control/Response blocks that fit one frame (186, 1514
/// bytes; 2,426 before).
#[test]
fn a_dcp_set_of_300_blocks_is_answered_within_one_frame() {
    let mut device = device();
    let t = Instant::from_millis(1);
    let set = [5u8, 3, 0, 2, 0, 0].repeat(300);
    device.handle(t, Link::Ethernet, &dcp_frame(DEVICE, 0xFEFD, 4, 7, &set));
    let Some(Transmit::Frame(answer)) = device.poll_transmit(t) else {
        panic!("no answer");
    };
    assert_eq!(answer.len(), 1514);
    assert_eq!(
        answer[14..26],
        [0xFE, 0xFD, 4, 1, 0, 0, 0, 7, 0, 0, 0x05, 0xD0]
    );
    for n in 0..186 {
        assert_eq!(
            answer[26 + 8 * n..34 + 8 * n],
            [5, 4, 0, 3, 5, 3, 0, 0],
            "block {n}"
        );
    }
}

/// An RPC request from UDP port 0, or from an address nobody has, gets no answer (a socket
/// refuses a datagram there: "Invalid argument", and the simulator exited); the same request
/// from a port is answered.
#[test]
fn rpc_requests_that_cannot_be_answered_are_ignored() {
    let connect = recorded()
        .into_iter()
        .find(|(datagram, _)| *datagram)
        .map(|(_, pdu)| pdu)
        .expect("a Connect");
    for from in [
        ([10, 0, 0, 1], 0),
        ([0, 0, 0, 0], 49152),
        ([255, 255, 255, 255], 49152),
        ([224, 0, 0, 1], 49152),
    ] {
        let mut device = device();
        let t = Instant::from_millis(1);
        device.handle(t, Link::Rpc(from), &connect);
        assert!(device.poll_transmit(t).is_none(), "{from:?}");
    }
    let mut device = device();
    let t = Instant::from_millis(1);
    device.handle(t, Link::Rpc(FROM), &connect);
    assert!(matches!(
        device.poll_transmit(t),
        Some(Transmit::Datagram(to, _)) if to == FROM
    ));
}
