//! Fuzz the AlarmCR's machines and the alarm frame parsers: an alarm is sent, then the input,
//! cut into pieces at 0xFF 0xFE, goes in turn to the AlarmCR; a piece whose first byte is below
//! 5 becomes the variable part of a well-formed frame of the controller of that PDUType (its
//! SendSeqNum and AckSeqNum from the next bytes), any other piece is an Ethernet frame as it is;
//! each piece also moves time on by its length × 10 ms. Nothing may panic; every frame the
//! device sends parses, goes to the controller with the references of the AlarmCR, and a
//! DATA's variable part is an AlarmNotification.
#![no_main]

use edsgen_runtime::profinet::wire::connect::AlarmCrBlockReq;
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::profinet::alarm::AlarmCr;
use edsgen_sim::profinet::wire::alarm::*;
use libfuzzer_sys::fuzz_target;

const CONTROLLER: [u8; 6] = [2, 0, 0, 0, 0, 1];
const DEVICE: [u8; 6] = [2, 0, 0, 0, 3, 0x50];

fn alarm() -> AlarmNotification {
    AlarmNotification {
        high: false,
        source: AlarmSource {
            alarm_type: ALARM_DIAGNOSIS,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: SPEC_CHANNEL_DIAGNOSIS,
        },
        module_ident: 0x10,
        submodule_ident: 0x10,
        payload: None,
    }
}

fuzz_target!(|data: &[u8]| {
    let req = AlarmCrBlockReq {
        alarm_cr_type: 1,
        lt: 0x8892,
        properties: 0,
        rta_timeout_factor: 1,
        rta_retries: 3,
        local_alarm_reference: 3,
        max_alarm_data_length: 200,
        tag_header_high: 0xC000,
        tag_header_low: 0xA000,
    };
    let mut cr = AlarmCr::new(&req, 1, DEVICE, CONTROLLER);
    let mut now = Instant::from_millis(0);
    cr.send(now, alarm());
    cr.send(now, alarm());
    let mut rest = data;
    let mut pieces = Vec::new();
    while let Some(at) = rest.windows(2).position(|w| w == [0xFF, 0xFE]) {
        pieces.push(&rest[..at]);
        rest = &rest[at + 2..];
    }
    pieces.push(rest);
    for piece in pieces {
        let frame = match piece {
            [pdu_type, s0, s1, a0, a1, var @ ..] if *pdu_type < 5 => {
                let header = RtaHeader {
                    dst: 1,
                    src: 3,
                    pdu_type: *pdu_type,
                    version: RTA_VERSION,
                    add_flags: WINDOW_1 | TACK,
                    send_seq: u16::from_be_bytes([*s0, *s1]),
                    ack_seq: u16::from_be_bytes([*a0, *a1]),
                };
                emit_frame(DEVICE, CONTROLLER, 0xA000, FRAME_ID_LOW, &header, var)
            }
            _ => piece.to_vec(),
        };
        cr.handle_frame(now, &frame);
        now = now + Duration::from_millis(piece.len() as u64 * 10);
        if cr.poll_timeout().is_some_and(|t| t <= now) {
            cr.handle_timeout(now);
        }
        while let Some(out) = cr.poll_frame() {
            let rta = RtaFrame::parse(&out).expect("the device's frames parse");
            assert_eq!((rta.eth.dst, rta.eth.src), (CONTROLLER, DEVICE));
            assert_eq!((rta.header.dst, rta.header.src), (3, 1));
            if rta.header.pdu_type == PDU_DATA {
                assert!(AlarmNotification::parse(rta.var_part).is_some());
            }
        }
        while cr.poll_event().is_some() {}
    }
});
