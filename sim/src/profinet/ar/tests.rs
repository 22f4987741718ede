use super::*;
use crate::profinet::controller::{connected, response, Controller};

const DEVICE: Mac = [2, 0, 0, 0, 3, 0x50];
const CONTROLLER: Mac = [2, 0, 0, 0, 0, 1];
const FROM: Peer = ([10, 0, 0, 1], 49152);

/// The card's configuration, read once.
fn config() -> DeviceConfig {
    static CONFIG: std::sync::OnceLock<DeviceConfig> = std::sync::OnceLock::new();
    CONFIG
        .get_or_init(|| {
            let read = edsgen_model::read::read_bytes(
                std::path::Path::new("goodrive350-pn.xml"),
                include_bytes!("../../../../eds/goodrive350-pn.xml"),
            );
            DeviceConfig::from_gsdml(read.device.profinet().expect("a GSDML"))
        })
        .clone()
}

fn cm() -> Cm {
    Cm::new(config(), DEVICE, (0x0350, 0x0350, 1), "Goodrive350")
}

fn at(ms: u64) -> Instant {
    Instant::from_millis(ms)
}

/// The answer's status and blocks.
fn call(cm: &mut Cm, pdu: &[u8]) -> (PnioStatus, Vec<u8>) {
    response(&cm.handle_datagram(at(0), FROM, pdu).expect("an answer")).expect("a response")
}

#[test]
fn the_card_has_the_access_point_its_ports_and_the_drive_module() {
    let c = config();
    type Shape = Vec<(u16, u32, Vec<(u16, u32, u16, u16)>)>;
    let shape: Shape = c
        .slots
        .iter()
        .map(|s| {
            let subs = s
                .submodules
                .iter()
                .map(|x| (x.subslot, x.ident, x.input_len, x.output_len))
                .collect();
            (s.slot, s.module_ident, subs)
        })
        .collect();
    assert_eq!(
        shape,
        vec![
            (
                0,
                1,
                vec![
                    (1, 1, 0, 0),
                    (0x8000, 0x8000, 0, 0),
                    (0x8001, 0x8001, 0, 0),
                    (0x8002, 0x8002, 0, 0)
                ]
            ),
            (1, 0x10, vec![(1, 0x10, 32, 32)]),
        ]
    );
    assert_eq!((c.send_clocks, c.min_device_interval), (vec![32], 32));
}

#[test]
fn a_device_access_ar_reads_the_real_identification_and_is_released() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 7);
    ctl.ar.ar_type = connect::AR_TYPE_IOSAR;
    let mut blocks = Vec::new();
    append_block(&mut blocks, |b| ctl.ar.emit(b));
    let (status, args) = call(&mut cm, &ctl.connect(&blocks));
    assert_eq!(status, PnioStatus::OK);
    assert_eq!(args[..2], [0x81, 0x01]);
    assert_eq!(args.len(), 34);
    let (status, args) = call(&mut cm, &ctl.read(0, 1, 0xF000));
    assert_eq!(status, PnioStatus::OK);
    assert_eq!(args[36..40], [0, 0, 0, 60]);
    assert_eq!(
        args[64..],
        [
            0x00, 0x13, 0, 56, 1, 1, 0, 1, 0, 0, 0, 0, 0, 2, // one API, two slots
            0, 0, 0, 0, 0, 1, 0, 4, 0, 1, 0, 0, 0, 1, 0x80, 0, 0, 0, 0x80, 0, 0x80, 1, 0, 0, 0x80,
            1, 0x80, 2, 0, 0, 0x80, 2, // slot 0
            0, 1, 0, 0, 0, 0x10, 0, 1, 0, 1, 0, 0, 0, 0x10 // slot 1
        ]
    );
    let (status, args) = call(&mut cm, &ctl.read(0, 1, 0xAFF0));
    assert_eq!(status, PnioStatus::OK);
    assert_eq!(args[64..72], [0, 0x20, 0, 56, 1, 0, 0x03, 0x50]);
    assert_eq!(&args[72..83], b"Goodrive350");
    let (status, args) = call(&mut cm, &ctl.release());
    assert_eq!(status, PnioStatus::OK);
    assert_eq!(args[..2], [0x81, 0x14]);
    assert_eq!(args[28..30], [0, 8]);
    let events: Vec<_> = std::iter::from_fn(|| cm.poll_event()).collect();
    assert_eq!(events.len(), 2);
    assert_eq!(events[1], ArEvent::Released);
    // The AR is gone: a read names an unknown AR.
    let (status, _) = call(&mut cm, &ctl.read(0, 1, 0xF000));
    assert_eq!(status, PnioStatus::new(0xDE, 0x80, 0xB5, 0));
}

/// An IO AR up to data exchange; the Controller and the events.
fn to_data(cm: &mut Cm) -> (Controller, CrLayout) {
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    let blocks = ctl.connect_blocks(&config(), 32, 8, 3);
    let (status, args) = call(cm, &ctl.connect(&blocks));
    assert_eq!(status, PnioStatus::OK);
    let c = connected(&args).expect("IOCR answers");
    assert_eq!((c.frame_ids, c.diff), ((0xC001, 0xC102), None));
    let Some(ArEvent::Connected {
        ar_type: 1,
        layout: Some(layout),
        diff: false,
    }) = cm.poll_event()
    else {
        panic!("no Connected event")
    };
    let (status, args) = call(cm, &ctl.prm_end());
    assert_eq!(status, PnioStatus::OK);
    assert_eq!(
        (&args[..2], &args[28..30]),
        (&[0x81, 0x10][..], &[0, 8][..])
    );
    let (to, ready) = cm.poll_datagram().expect("ApplicationReady");
    assert_eq!(to, ([10, 0, 0, 1], 34964));
    assert!(!cm.data_valid());
    let done = ctl
        .answer_ready(&ready)
        .expect("an ApplicationReady request");
    assert_eq!(cm.handle_datagram(at(1), FROM, &done), None);
    assert!(cm.data_valid());
    assert_eq!(cm.poll_event(), Some(ArEvent::PrmEnd));
    assert_eq!(cm.poll_event(), Some(ArEvent::DataStart));
    (ctl, layout)
}

#[test]
fn an_io_ar_gives_the_layout_profinet_py_builds_and_reaches_data() {
    let mut cm = cm();
    let (mut ctl, layout) = to_data(&mut cm);
    let objects = |v: &[crate::profinet::cyclic::DataObject]| {
        v.iter()
            .map(|o| (o.slot, o.subslot, o.offset, o.len))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        objects(&layout.inputs),
        vec![
            (0, 1, 0, 0),
            (0, 0x8000, 1, 0),
            (0, 0x8001, 2, 0),
            (0, 0x8002, 3, 0),
            (1, 1, 4, 32)
        ]
    );
    assert_eq!(layout.input_iocs, vec![37]);
    assert_eq!(objects(&layout.outputs), vec![(1, 1, 0, 32)]);
    assert_eq!((layout.input_len, layout.output_len), (40, 40));
    assert_eq!(layout.interval, Duration::from_millis(8));
    assert_eq!((layout.controller, layout.device), (CONTROLLER, DEVICE));
    let (status, _) = call(&mut cm, &ctl.release());
    assert_eq!(status, PnioStatus::OK);
    assert!(!cm.data_valid());
}

#[test]
fn records_are_written_with_their_length_and_read_back() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    let blocks = ctl.connect_blocks(&config(), 32, 8, 3);
    call(&mut cm, &ctl.connect(&blocks));
    let record: Vec<u8> = (1..=11u16).flat_map(|w| w.to_be_bytes()).collect();
    let (status, args) = call(&mut cm, &ctl.write(1, 1, 256, &record));
    assert_eq!(status, PnioStatus::OK);
    assert_eq!((args.len(), args[..2].to_vec()), (64, vec![0x80, 0x08]));
    let (_, args) = call(&mut cm, &ctl.read(1, 1, 256));
    assert_eq!(args[64..], record[..]);
    let refused = |cm: &mut Cm, pdu: Vec<u8>| call(cm, &pdu).0;
    assert_eq!(
        refused(&mut cm, ctl.write(1, 1, 256, &record[..20])),
        PnioStatus::new(0xDF, 0x80, 0xB1, 0)
    );
    assert_eq!(
        refused(&mut cm, ctl.write(1, 1, 258, &record)),
        PnioStatus::new(0xDF, 0x80, 0xB0, 0)
    );
    assert_eq!(
        refused(&mut cm, ctl.write(2, 1, 256, &record)),
        PnioStatus::new(0xDF, 0x80, 0xB2, 0)
    );
    assert_eq!(
        refused(&mut cm, ctl.read(1, 1, 0x1234)),
        PnioStatus::new(0xDE, 0x80, 0xB0, 0)
    );
    let events: Vec<_> = std::iter::from_fn(|| cm.poll_event()).collect();
    assert_eq!(
        events[1],
        ArEvent::RecordWritten {
            slot: 1,
            subslot: 1,
            index: 256,
            data: record
        }
    );
    assert_eq!(events.len(), 2);
}

#[test]
fn connects_the_device_cannot_serve_are_refused_with_their_field() {
    let refused = |edit: &dyn Fn(&mut Vec<u8>)| {
        let mut cm = cm();
        let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
        let mut blocks = ctl.connect_blocks(&config(), 32, 8, 3);
        edit(&mut blocks);
        call(&mut cm, &ctl.connect(&blocks)).0
    };
    // The input IOCR starts at 75, after the ARBlockReq with its 17-byte station name:
    // IOCRProperties at +12, SendClockFactor at +20, ReductionRatio at +22.
    assert_eq!(
        refused(&|b| b[96] = 16),
        PnioStatus::new(0xDB, 0x81, 0x02, 10)
    );
    // ReductionRatio 3 is not among the GSDML's.
    assert_eq!(
        refused(&|b| b[98] = 3),
        PnioStatus::new(0xDB, 0x81, 0x02, 11)
    );
    // RT_CLASS_3.
    assert_eq!(
        refused(&|b| b[90] = 3),
        PnioStatus::new(0xDB, 0x81, 0x02, 7)
    );
    // ARType 2.
    assert_eq!(refused(&|b| b[7] = 2), PnioStatus::new(0xDB, 0x81, 0x01, 4));
    // The nil ARUUID.
    assert_eq!(
        refused(&|b| b[8..24].fill(0)),
        PnioStatus::new(0xDB, 0x81, 0x01, 5)
    );
    // CMInitiatorActivityTimeoutFactor (bytes 52-53) 0 or 1001: outside 1 to 1000.
    assert_eq!(
        refused(&|b| b[52..54].copy_from_slice(&[0, 0])),
        PnioStatus::new(0xDB, 0x81, 0x01, 10)
    );
    assert_eq!(
        refused(&|b| b[52..54].copy_from_slice(&1001u16.to_be_bytes())),
        PnioStatus::new(0xDB, 0x81, 0x01, 10)
    );
    assert_eq!(
        refused(&|b| b[52..54].copy_from_slice(&0xFF40u16.to_be_bytes())),
        PnioStatus::new(0xDB, 0x81, 0x01, 10)
    );
    // An unknown block type.
    assert_eq!(
        refused(&|b| b[75] = 0x7F),
        PnioStatus::new(0xDB, 0x81, 0x40, 0x01)
    );
    // No IOCRs at all.
    assert_eq!(
        refused(&|b| b.truncate(75)),
        PnioStatus::new(0xDB, 0x81, 0x40, 0x02)
    );
    assert_eq!(refused(&|_| {}), PnioStatus::OK);
}

#[test]
fn a_second_ar_is_refused_while_one_is_up() {
    let mut cm = cm();
    to_data(&mut cm);
    let mut other = Controller::new(CONTROLLER, cm.object(), 10);
    let blocks = other.connect_blocks(&config(), 32, 8, 3);
    assert_eq!(
        call(&mut cm, &other.connect(&blocks)).0,
        PnioStatus::new(0xDB, 0x81, 0x40, 0x04)
    );
}

#[test]
fn expected_modules_that_differ_get_the_module_diff_block() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    let mut wrong = config();
    wrong.slots[1].module_ident = 0x11;
    wrong.slots[0].submodules[0].ident = 0x2;
    wrong.slots.push(config::RealSlot {
        slot: 2,
        module_ident: 0x10,
        submodules: vec![],
    });
    let blocks = ctl.connect_blocks(&wrong, 32, 8, 3);
    let (status, args) = call(&mut cm, &ctl.connect(&blocks));
    assert_eq!(status, PnioStatus::OK);
    let diff = connected(&args)
        .and_then(|c| c.diff)
        .expect("a ModuleDiffBlock");
    assert_eq!(
        diff.apis,
        vec![ApiIdent {
            api: 0,
            modules: vec![
                SlotIdent {
                    slot: 0,
                    module_ident: 1,
                    state: MODULE_PROPER,
                    submodules: vec![(1, 1, SUBMODULE_WRONG)]
                },
                SlotIdent {
                    slot: 1,
                    module_ident: 0x10,
                    state: MODULE_WRONG,
                    submodules: vec![(1, 0x10, SUBMODULE_WRONG)]
                },
                SlotIdent {
                    slot: 2,
                    module_ident: 0,
                    state: MODULE_NO,
                    submodules: vec![]
                },
            ]
        }]
    );
}

#[test]
fn application_ready_is_sent_again_then_the_ar_is_aborted() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    let blocks = ctl.connect_blocks(&config(), 32, 8, 3);
    call(&mut cm, &ctl.connect(&blocks));
    call(&mut cm, &ctl.prm_end());
    let first = cm.poll_datagram().expect("ApplicationReady");
    assert_eq!(cm.poll_timeout(), Some(at(1000)));
    cm.handle_timeout(at(1000));
    assert_eq!(cm.poll_datagram(), Some(first));
    cm.handle_timeout(at(2000));
    cm.handle_timeout(at(3000));
    let events: Vec<_> = std::iter::from_fn(|| cm.poll_event()).collect();
    assert_eq!(events.last(), Some(&ArEvent::Aborted));
    assert_eq!(cm.poll_timeout(), None);
}

#[test]
fn a_repeated_request_gets_the_same_answer_and_other_interfaces_a_reject() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    let blocks = ctl.connect_blocks(&config(), 32, 8, 3);
    let connect = ctl.connect(&blocks);
    let first = cm.handle_datagram(at(0), FROM, &connect);
    assert_eq!(cm.handle_datagram(at(5), FROM, &connect), first);
    let mut other = connect.clone();
    other[27] = 0x02; // the controller interface
    let reject = cm.handle_datagram(at(0), FROM, &other).expect("a reject");
    assert_eq!(
        (reject[1], &reject[80..]),
        (REJECT, &[0x1C, 0x01, 0x00, 0x03][..])
    );
    assert_eq!(cm.handle_datagram(at(0), FROM, &connect[..70]), None);
    // A ping of the call gets its answer again; of another, "no call" (type 5, no body).
    let mut ping = connect.clone();
    ping[1] = PING;
    assert_eq!(cm.handle_datagram(at(6), FROM, &ping), first);
    ping[64..68].copy_from_slice(&[0, 0, 0, 9]);
    let nocall = cm.handle_datagram(at(6), FROM, &ping).expect("no call");
    assert_eq!((nocall.len(), nocall[1]), (80, NOCALL));
}

#[test]
fn a_controller_silent_before_prm_end_loses_its_ar_after_its_activity_timeout() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    let blocks = ctl.connect_blocks(&config(), 32, 8, 3);
    call(&mut cm, &ctl.connect(&blocks));
    // CMInitiatorActivityTimeoutFactor 100: 10 s.
    assert_eq!(cm.poll_timeout(), Some(at(10_000)));
    cm.handle_timeout(at(9_999));
    assert_eq!(cm.poll_event().map(|e| e == ArEvent::Aborted), Some(false));
    assert_eq!(cm.poll_event(), None);
    cm.handle_timeout(at(10_000));
    assert_eq!(cm.poll_event(), Some(ArEvent::Aborted));
    // Another controller may connect now.
    let mut other = Controller::new(CONTROLLER, cm.object(), 10);
    assert_eq!(call(&mut cm, &other.connect(&blocks)).0, PnioStatus::OK);
}

#[test]
fn a_little_endian_request_is_answered_in_little_endian() {
    let mut cm = cm();
    let mut ctl = Controller::new(CONTROLLER, cm.object(), 9);
    ctl.ar.ar_type = connect::AR_TYPE_IOSAR;
    let mut blocks = Vec::new();
    append_block(&mut blocks, |b| ctl.ar.emit(b));
    let (be, _) = RpcHeader::parse(&ctl.connect(&blocks)).expect("a request");
    let le = RpcHeader {
        little_endian: true,
        ..be
    };
    let pdu = rpc_pdu(&le, &Ndr::request(4068, blocks.len() as u32, true), &blocks);
    let answer = cm.handle_datagram(at(0), FROM, &pdu).expect("an answer");
    assert_eq!(answer[4], 0x10);
    let (header, body) = RpcHeader::parse(&answer).expect("a response");
    assert_eq!((header.packet_type, header.little_endian), (RESPONSE, true));
    // PNIOStatus 0 and ArgsLength 34, little-endian; the blocks stay big-endian.
    assert_eq!(body[..8], [0, 0, 0, 0, 34, 0, 0, 0]);
    assert_eq!(body[20..22], [0x81, 0x01]);
}

#[test]
fn truncated_and_flipped_requests_never_panic_and_are_answered_as_rpc() {
    let mut ctl = Controller::new(CONTROLLER, cm().object(), 9);
    let blocks = ctl.connect_blocks(&config(), 32, 8, 3);
    let pdus = [
        ctl.connect(&blocks),
        ctl.write(1, 1, 256, &[0; 22]),
        ctl.read(0, 1, 0xF000),
        ctl.prm_end(),
        ctl.release(),
    ];
    for pdu in &pdus {
        for cut in 0..pdu.len() {
            let mut cm = cm();
            if let Some(answer) = cm.handle_datagram(at(0), FROM, &pdu[..cut]) {
                assert!(RpcHeader::parse(&answer).is_some());
            }
        }
        for at_byte in 0..pdu.len() {
            let mut cm = cm();
            call(&mut cm, &pdus[0]);
            let mut flipped = pdu.clone();
            flipped[at_byte] ^= 0xA5;
            if let Some(answer) = cm.handle_datagram(at(1), FROM, &flipped) {
                assert!(RpcHeader::parse(&answer).is_some());
            }
            cm.handle_timeout(at(20_000));
        }
    }
}

#[test]
fn a_read_implicit_with_the_nil_ar_uuid_reads_i_m0_and_records_without_an_ar() {
    use crate::profinet::controller::{read_data, read_implicit};
    let mut cm = cm();
    let object = Uuid::pnio_object(1, 0x0350, 0x0350);
    let (status, args) = call(
        &mut cm,
        &read_implicit(object, Uuid([7; 16]), (0, 1, 0xAFF0)),
    );
    assert!(status.is_ok(), "{status:?}");
    let mut im0 = vec![0x00, 0x20, 0x00, 0x38, 0x01, 0x00, 0x03, 0x50];
    im0.extend_from_slice(b"Goodrive350         0001            ");
    im0.extend_from_slice(&[0, 1, b'V', 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0]);
    assert_eq!(read_data(&args), Some(&im0[..]));
    // Record 256 of the drive's subslot: its default mapping; an index it lacks is refused
    // with ErrorCode1 0xB0 (invalid index).
    let (status, args) = call(&mut cm, &read_implicit(object, Uuid([8; 16]), (1, 1, 256)));
    assert!(status.is_ok(), "{status:?}");
    assert_eq!(read_data(&args).map(<[u8]>::len), Some(22));
    let (status, _) = call(&mut cm, &read_implicit(object, Uuid([9; 16]), (1, 1, 999)));
    assert_eq!(status, PnioStatus::new(0xDE, 0x80, 0xB0, 0));
}
