use super::*;
use crate::profinet::wire::block::Block;
use crate::profinet::wire::records::*;
use crate::profinet::wire::rpc::PnioStatus;
use crate::profinet::wire::BufferTooSmall;

const AR: Uuid = Uuid([0x11; 16]);

fn append(out: &mut Vec<u8>, emit: impl FnOnce(&mut [u8]) -> Result<usize, BufferTooSmall>) {
    let start = out.len();
    out.resize(start + 1514, 0);
    let written = emit(&mut out[start..]).expect("room");
    out.truncate(start + written);
}

/// A block appended to a vector, as the simulator writes them.
trait AppendTo {
    fn append_to(&self, out: &mut Vec<u8>);
}

macro_rules! append_to {
    ($($t:ty),*) => {$(
        impl AppendTo for $t {
            fn append_to(&self, out: &mut Vec<u8>) {
                append(out, |b| self.emit(b));
            }
        }
    )*};
}

append_to!(
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

fn split(args: &[u8]) -> Result<Vec<Block<'_>>, usize> {
    crate::profinet::wire::block::blocks(args).collect()
}

fn one(bytes: &[u8]) -> Block<'_> {
    let blocks = split(bytes).expect("blocks");
    assert_eq!(blocks.len(), 1);
    blocks[0]
}

#[test]
fn ar_block_req_bytes_and_back() {
    let req = ArBlockReq {
        ar_type: 1,
        ar_uuid: AR,
        session_key: 0x0102,
        initiator_mac: [2, 0, 0, 0, 0, 1],
        initiator_object: Uuid([0x22; 16]),
        properties: 0x11,
        timeout_factor: 100,
        udp_rt_port: 0x8892,
        station_name: b"tp".to_vec(),
    };
    let mut out = Vec::new();
    req.append_to(&mut out);
    assert_eq!(out.len(), 60);
    assert_eq!(out[..8], [0x01, 0x01, 0x00, 0x38, 0x01, 0x00, 0x00, 0x01]);
    assert_eq!(out[24..32], [0x01, 0x02, 2, 0, 0, 0, 0, 1]);
    assert_eq!(
        out[48..],
        [0, 0, 0, 0x11, 0, 100, 0x88, 0x92, 0, 2, b't', b'p']
    );
    let b = one(&out);
    assert_eq!((b.block_type, b.version), (AR_BLOCK_REQ, (1, 0)));
    assert_eq!(ArBlockReq::parse(b.body), Some(req));
    assert_eq!(ArBlockReq::parse(&b.body[..b.body.len() - 1]), None);
}

#[test]
fn ar_block_res_and_iocr_res_and_alarm_res_bytes() {
    let mut out = Vec::new();
    ArBlockRes {
        ar_type: 1,
        ar_uuid: AR,
        session_key: 7,
        responder_mac: [2, 0, 0, 0, 3, 0x50],
        udp_rt_port: 0x8892,
    }
    .append_to(&mut out);
    assert_eq!(out[..8], [0x81, 0x01, 0x00, 0x1E, 0x01, 0x00, 0x00, 0x01]);
    assert_eq!(out[24..], [0, 7, 2, 0, 0, 0, 3, 0x50, 0x88, 0x92]);
    let mut out = Vec::new();
    IocrBlockRes {
        iocr_type: IOCR_OUTPUT,
        reference: 2,
        frame_id: 0xC102,
    }
    .append_to(&mut out);
    assert_eq!(out, [0x81, 0x02, 0, 8, 1, 0, 0, 2, 0, 2, 0xC1, 0x02]);
    assert_eq!(
        IocrBlockRes::parse(one(&out).body).map(|r| r.frame_id),
        Some(0xC102)
    );
    let mut out = Vec::new();
    AlarmCrBlockRes {
        alarm_cr_type: 1,
        local_alarm_reference: 1,
        max_alarm_data_length: 200,
    }
    .append_to(&mut out);
    assert_eq!(out, [0x81, 0x03, 0, 8, 1, 0, 0, 1, 0, 1, 0, 200]);
}

fn iocr(iocr_type: u16, frame_id: u16) -> IocrBlockReq {
    IocrBlockReq {
        iocr_type,
        reference: iocr_type,
        lt: 0x8892,
        properties: 1,
        data_length: 40,
        frame_id,
        send_clock_factor: 32,
        reduction_ratio: 8,
        phase: 1,
        sequence: 0,
        frame_send_offset: 0xFFFF_FFFF,
        watchdog_factor: 6,
        data_hold_factor: 6,
        tag_header: 0xC000,
        multicast_mac: [0; 6],
        apis: vec![IocrApi {
            api: 0,
            data: vec![FrameEntry {
                slot: 1,
                subslot: 1,
                offset: 0,
            }],
            iocs: vec![FrameEntry {
                slot: 1,
                subslot: 1,
                offset: 33,
            }],
        }],
    }
}

#[test]
fn iocr_block_req_bytes_and_back() {
    let req = iocr(IOCR_INPUT, 0xC001);
    let mut out = Vec::new();
    req.append_to(&mut out);
    assert_eq!(out.len(), 6 + 38 + 2 + 4 + 2 + 6 + 2 + 6);
    assert_eq!(
        out[..26],
        [
            0x01, 0x02, 0x00, 0x3E, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x88, 0x92, 0, 0, 0, 1, 0,
            40, 0xC0, 0x01, 0, 32, 0, 8, 0, 1
        ]
    );
    assert_eq!(
        out[44..],
        [0, 1, 0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0, 0, 0, 1, 0, 1, 0, 1, 0, 33]
    );
    assert_eq!(IocrBlockReq::parse(one(&out).body), Some(req));
}

#[test]
fn alarm_cr_block_req_bytes_and_back() {
    let req = AlarmCrBlockReq {
        alarm_cr_type: 1,
        lt: 0x8892,
        properties: 0,
        rta_timeout_factor: 1,
        rta_retries: 3,
        local_alarm_reference: 1,
        max_alarm_data_length: 200,
        tag_header_high: 0xC000,
        tag_header_low: 0xA000,
    };
    let mut out = Vec::new();
    req.append_to(&mut out);
    assert_eq!(
        out,
        [
            0x01, 0x03, 0, 22, 1, 0, 0, 1, 0x88, 0x92, 0, 0, 0, 0, 0, 1, 0, 3, 0, 1, 0, 200, 0xC0,
            0, 0xA0, 0
        ]
    );
    assert_eq!(AlarmCrBlockReq::parse(one(&out).body), Some(req));
}

#[test]
fn expected_submodules_and_module_diff_bytes_and_back() {
    let req = ExpectedSubmoduleBlockReq {
        slots: vec![ExpectedSlot {
            api: 0,
            slot: 1,
            module_ident: 0x10,
            module_properties: 0,
            submodules: vec![ExpectedSubmodule {
                subslot: 1,
                ident: 0x10,
                properties: 3,
                data: vec![
                    DataDescription {
                        direction: DATA_INPUT,
                        length: 32,
                        iocs_len: 1,
                        iops_len: 1,
                    },
                    DataDescription {
                        direction: DATA_OUTPUT,
                        length: 32,
                        iocs_len: 1,
                        iops_len: 1,
                    },
                ],
            }],
        }],
    };
    let mut out = Vec::new();
    req.append_to(&mut out);
    assert_eq!(
        out,
        [
            0x01, 0x04, 0, 38, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0x10, 0, 0, 0, 1, 0, 1, 0, 0,
            0, 0x10, 0, 3, 0, 1, 0, 32, 1, 1, 0, 2, 0, 32, 1, 1
        ]
    );
    assert_eq!(ExpectedSubmoduleBlockReq::parse(one(&out).body), Some(req));

    let diff = ModuleDiffBlock {
        apis: vec![ApiIdent {
            api: 0,
            modules: vec![SlotIdent {
                slot: 1,
                module_ident: 0x10,
                state: MODULE_PROPER,
                submodules: vec![(1, 0x10, SUBMODULE_WRONG)],
            }],
        }],
    };
    let mut out = Vec::new();
    diff.append_to(&mut out);
    assert_eq!(
        out,
        [
            0x81, 0x04, 0, 28, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0x10, 0, 2, 0, 1, 0, 1,
            0, 0, 0, 0x10, 0x90, 0x00
        ]
    );
    assert_eq!(ModuleDiffBlock::parse(one(&out).body), Some(diff));
}

#[test]
fn real_identification_data_bytes() {
    let real = RealIdentificationData {
        apis: vec![ApiIdent {
            api: 0,
            modules: vec![SlotIdent {
                slot: 0,
                module_ident: 1,
                state: 0,
                submodules: vec![(1, 1, 0), (0x8000, 0x8000, 0)],
            }],
        }],
    };
    let mut out = Vec::new();
    real.append_to(&mut out);
    assert_eq!(
        out,
        [
            0x00, 0x13, 0, 30, 1, 1, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 2, 0, 1, 0, 0, 0,
            1, 0x80, 0, 0, 0, 0x80, 0
        ]
    );
    assert_eq!(RealIdentificationData::parse(one(&out).body), Some(real));
}

#[test]
fn record_headers_are_64_bytes_and_read_back() {
    let req = IodHeader::request(IOD_READ_REQ, 3, AR, (0, 1, 0xF000), 4096);
    let mut out = Vec::new();
    append(&mut out, |b| req.emit(b));
    assert_eq!(out.len(), 64);
    assert_eq!(out[..8], [0x00, 0x09, 0x00, 0x3C, 0x01, 0x00, 0x00, 0x03]);
    assert_eq!(out[24..36], [0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0xF0, 0x00]);
    assert_eq!(out[36..40], [0, 0, 0x10, 0]);
    assert_eq!(IodHeader::parse(IOD_READ_REQ, one(&out).body), Some(req));

    let res = IodHeader::request(IOD_WRITE_REQ, 3, AR, (1, 1, 256), 22)
        .response(22, PnioStatus::new(0xDF, 0x80, 0xB0, 0));
    let mut out = Vec::new();
    append(&mut out, |b| res.emit(b));
    assert_eq!(out.len(), 64);
    assert_eq!(out[..2], [0x80, 0x08]);
    assert_eq!(out[40..48], [0, 0, 0, 0, 0xDF, 0x80, 0xB0, 0]);
    assert_eq!(IodHeader::parse(0x8008, one(&out).body), Some(res));
    assert_eq!(IodHeader::parse(0x0001, one(&out).body), None);
}

#[test]
fn control_blocks_and_their_done() {
    let req = IodControl {
        block_type: PRM_END_REQ,
        ar_uuid: AR,
        session_key: 5,
        command: CMD_PRM_END,
        properties: 0,
    };
    let mut out = Vec::new();
    append(&mut out, |b| req.emit(b));
    assert_eq!(out.len(), 32);
    assert_eq!(out[..8], [0x01, 0x10, 0, 28, 1, 0, 0, 0]);
    assert_eq!(out[24..], [0, 5, 0, 0, 0, 1, 0, 0]);
    let done = req.done();
    assert_eq!((done.block_type, done.command), (0x8110, CMD_DONE));
    assert_eq!(IodControl::parse(PRM_END_REQ, one(&out).body), Some(req));
}

#[test]
fn split_refuses_short_and_overrunning_blocks() {
    assert_eq!(split(&[0x01, 0x01, 0x00]), Err(0));
    assert_eq!(split(&[0x01, 0x01, 0x00, 0x01, 0x01]), Err(0));
    assert_eq!(split(&[0x01, 0x01, 0x00, 0x04, 1, 0, 9]), Err(0));
    let two = [0, 1, 0, 2, 1, 0, 0, 2, 0, 3, 1, 0, 7];
    let blocks = split(&two).expect("two blocks");
    assert_eq!(blocks[1].body, [7]);
    assert_eq!(split(&two[..12]), Err(6));
}

#[test]
fn the_views_walk_the_lists_without_allocating_and_refuse_every_truncation() {
    let mut out = Vec::new();
    iocr(IOCR_INPUT, 0xC001).append_to(&mut out);
    let body = one(&out).body;
    let view = IocrBlockReqPacket::new_checked(body).expect("a whole IOCRBlockReq");
    assert_eq!(
        (view.fields().frame_id, view.fields().data_length),
        (0xC001, 40)
    );
    let api = view.apis().next().expect("one API");
    let entry = |offset| FrameEntry {
        slot: 1,
        subslot: 1,
        offset,
    };
    assert_eq!(api.data.collect::<Vec<_>>(), [entry(0)]);
    assert_eq!(api.iocs.collect::<Vec<_>>(), [entry(33)]);
    for len in 0..body.len() {
        assert!(
            IocrBlockReqPacket::new_checked(&body[..len]).is_none(),
            "{len}"
        );
    }

    let mut out = Vec::new();
    ArBlockReq {
        ar_type: 1,
        ar_uuid: AR,
        session_key: 1,
        initiator_mac: [2; 6],
        initiator_object: AR,
        properties: 0,
        timeout_factor: 1,
        udp_rt_port: 0x8892,
        station_name: b"plc".to_vec(),
    }
    .append_to(&mut out);
    let body = one(&out).body;
    let view = ArBlockReqPacket::new_checked(body).expect("a whole ARBlockReq");
    assert_eq!(
        (view.station_name(), view.fields().session_key),
        (&b"plc"[..], 1)
    );
    assert!(ArBlockReqPacket::new_checked(&body[..body.len() - 1]).is_none());

    // Slot 1 with one submodule of input and output (two DataDescriptions), slot 2 with none.
    let expected = [
        0, 2, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0x10, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0x10, 0, 3, 0, 1, 0, 32,
        1, 1, 0, 2, 0, 32, 1, 1, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0x20, 0, 0, 0, 0,
    ];
    let view = ExpectedSubmoduleBlockReqPacket::new_checked(&expected[..]).expect("checked");
    let slots: Vec<_> = view
        .slots()
        .map(|s| (s.slot, s.submodules.count()))
        .collect();
    assert_eq!(slots, [(1, 1), (2, 0)]);
    let sub = view.slots().next().unwrap().submodules.next().unwrap();
    assert_eq!(
        (sub.ident, sub.data().len(), sub.data()[1].direction),
        (0x10, 2, DATA_OUTPUT)
    );
    for len in 0..expected.len() {
        assert!(ExpectedSubmoduleBlockReqPacket::new_checked(&expected[..len]).is_none());
    }

    let diff = [
        0, 1, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0x10, 0, 2, 0, 1, 0, 1, 0, 0, 0, 0x10, 0x90, 0,
    ];
    let view = IdentificationPacket::module_diff(&diff[..]).expect("checked");
    let module = view.apis().next().unwrap().modules.next().unwrap();
    assert_eq!((module.slot, module.state), (1, MODULE_PROPER));
    assert_eq!(
        module.submodules.collect::<Vec<_>>(),
        [(1, 0x10, SUBMODULE_WRONG)]
    );
    for len in 0..diff.len() {
        assert!(
            IdentificationPacket::module_diff(&diff[..len]).is_none(),
            "{len}"
        );
    }
    // The same bytes without states are another list: its submodule runs past the end.
    assert!(IdentificationPacket::real_identification(&diff[..]).is_none());
}
