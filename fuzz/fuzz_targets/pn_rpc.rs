//! Fuzz the simulated PROFINET device's connection management and the RPC and block parsers:
//! the input, cut into pieces at 0xFF 0xFE, goes to the device in turn; a piece whose first byte
//! is below 6 becomes the argument of a well-formed request with that opnum (so that the block
//! parsers see it), a piece whose first byte is 6 the controller's answer to the device's last
//! ApplicationReady request (when it is for the AR of the seeds' Connect, whose AR UUID is
//! `[9; 16]`), any other piece is a datagram as it is. Nothing may panic; every answer is an RPC
//! PDU that parses, with the request's sequence number, and the ApplicationReady requests the
//! device sends parse too. Each block of a request's argument that reads as one of the
//! Connect's (`runtime::profinet::wire::connect`) is written again and reads back the same.
#![no_main]

use edsgen_runtime::profinet::wire::block::blocks;
use edsgen_runtime::profinet::wire::connect::*;
use edsgen_runtime::profinet::wire::rpc::{Ndr, RpcHeader, Uuid};
use edsgen_runtime::Instant;
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::ar::Cm;
use edsgen_sim::profinet::controller::Controller;
use edsgen_sim::profinet::wire::rpc_pdu;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

fn config() -> &'static DeviceConfig {
    static CONFIG: OnceLock<DeviceConfig> = OnceLock::new();
    CONFIG.get_or_init(|| {
        let read = edsgen_model::read::read_bytes(
            std::path::Path::new("goodrive350-pn.xml"),
            include_bytes!("../../eds/goodrive350-pn.xml"),
        );
        DeviceConfig::from_gsdml(read.device.profinet().expect("the card's GSDML"))
    })
}

/// Writes `repr` again and reads it back: the same repr, as `parse` of the new block's body.
macro_rules! round_trip {
    ($body:expr, $($t:ident),*) => {$(
        if let Some(repr) = $t::parse($body) {
            let mut buf = vec![0; 4 + usize::from(u16::MAX)];
            if let Ok(n) = repr.emit(&mut buf) {
                let again = blocks(&buf[..n]).next().and_then(Result::ok).expect("one block");
                assert_eq!($t::parse(again.body), Some(repr));
            }
        }
    )*};
}

fn connect_blocks_round_trip(args: &[u8]) {
    for block in blocks(args).flatten() {
        round_trip!(
            block.body,
            ArBlockReq,
            ArBlockRes,
            IocrBlockReq,
            IocrBlockRes,
            AlarmCrBlockReq,
            AlarmCrBlockRes,
            ExpectedSubmoduleBlockReq,
            ModuleDiffBlock,
            RealIdentificationData
        );
    }
}

fuzz_target!(|data: &[u8]| {
    let mut cm = Cm::new(
        config().clone(),
        [2, 0, 0, 0, 3, 0x50],
        (0x0350, 0x0350, 1),
        "x",
    );
    let mut pieces = Vec::new();
    let mut rest = data;
    while let Some(at) = rest.windows(2).position(|w| w == [0xFF, 0xFE]) {
        pieces.push(&rest[..at]);
        rest = &rest[at + 2..];
    }
    pieces.push(rest);
    let controller = Controller::new([2, 0, 0, 0, 0, 1], Uuid::pnio_object(1, 0x0350, 0x0350), 9);
    let mut ready = None;
    for (n, piece) in pieces.into_iter().enumerate() {
        let pdu = match piece.split_first() {
            Some((&opnum, args)) if opnum < 6 => {
                connect_blocks_round_trip(args);
                let header = RpcHeader::request(
                    cm.object(),
                    Uuid::PNIO_DEVICE,
                    Uuid([7; 16]),
                    n as u32,
                    u16::from(opnum),
                );
                rpc_pdu(&header, &Ndr::request(4068, args.len() as u32, false), args)
            }
            Some((&6, _)) => {
                let answer = ready
                    .take()
                    .and_then(|r: Vec<u8>| controller.answer_ready(&r));
                answer.unwrap_or_else(|| piece.to_vec())
            }
            _ => piece.to_vec(),
        };
        let now = Instant::from_millis(n as u64 * 10);
        if let Some(answer) = cm.handle_datagram(now, ([10, 0, 0, 1], 34964), &pdu) {
            let (sent, _) = RpcHeader::parse(&pdu).expect("only a PDU is answered");
            let (header, _) = RpcHeader::parse(&answer).expect("the answer parses");
            assert_eq!(header.sequence, sent.sequence);
        }
        while let Some((_, request)) = cm.poll_datagram() {
            assert!(RpcHeader::parse(&request).is_some());
            ready = Some(request);
        }
        cm.handle_timeout(now);
        while cm.poll_event().is_some() {}
    }
});
