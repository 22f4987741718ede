//! Writes the seeds of the wire targets into `fuzz/seeds/TARGET/` (committed; `scripts/fuzz.sh`
//! copies them into the corpus): good exchanges recorded from the project's own masters and
//! simulated devices, each cut the way its target cuts its input. Regenerate with
//!
//!     cargo run --manifest-path fuzz/Cargo.toml --target-dir target --example seeds
//!
//! (the workspace's target directory: its dependencies are built already).

use std::fs;
use std::path::{Path, PathBuf};

use edsgen_runtime::dp::fdl::{self, DataRepr, MAX_TELEGRAM_LEN};
use edsgen_runtime::dp::slave::sap;
use edsgen_runtime::enip::wire::connection_manager::{
    network_params, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use edsgen_runtime::enip::wire::cpf::{item, CpfRepr, Item, SendDataRepr};
use edsgen_runtime::enip::wire::encap::EncapRepr;
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::profinet::wire::dcp;
use edsgen_runtime::profinet::wire::rpc::{PnioStatus, Uuid, HEADER_LEN, NDR_LEN};
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::enip::{device, Peer};
use edsgen_sim::ethercat::frame::{Command, FrameBuilder};
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::controller::Controller;
use edsgen_sim::profinet::wire::alarm::*;

/// The simulated PROFINET device's MAC in the pn_* targets.
const PN_DEVICE: [u8; 6] = [0x02, 0, 0, 0, 0x03, 0x50];
/// The controller's MAC.
const PN_CONTROLLER: [u8; 6] = [0x02, 0, 0, 0, 0, 0x01];
/// The piece separator of pn_rpc and pn_alarm.
const CUT: [u8; 2] = [0xFF, 0xFE];

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("seeds");
    let mut out = Seeds { root };
    pn_dcp(&mut out);
    pn_rpc(&mut out);
    pn_alarm(&mut out);
    dp_fdl(&mut out);
    ethercat_frame(&mut out);
    ethercat_coe(&mut out);
    enip(&mut out);
    demo_report(&mut out);
}

struct Seeds {
    root: PathBuf,
}

impl Seeds {
    fn write(&mut self, target: &str, name: &str, bytes: &[u8]) {
        let dir = self.root.join(target);
        fs::create_dir_all(&dir).expect("a seeds directory");
        fs::write(dir.join(name), bytes).expect("a seed written");
    }
}

fn dcp_frame(dst: [u8; 6], frame_id: u16, service: u8, xid: u32, blocks: &[u8]) -> Vec<u8> {
    let mut f = vec![0; 14 + dcp::HEADER_LEN + blocks.len()];
    let n = dcp::request(&mut f, dst, PN_CONTROLLER, frame_id, service, xid, blocks)
        .expect("a DCP request fits");
    f.truncate(n);
    f
}

fn block(option: (u8, u8), data: &[u8]) -> Vec<u8> {
    let mut b = vec![0; 4 + data.len() + 1];
    let n = dcp::emit_plain_block(&mut b, option, data).expect("a block fits");
    b.truncate(n);
    b
}

/// pn_dcp: one Ethernet frame each; what `edsgen pn` sends.
fn pn_dcp(out: &mut Seeds) {
    let by_name = block(dcp::NAME_OF_STATION, b"goodrive350-pn");
    let all = dcp::ALL_SELECTOR;
    let frames = [
        (
            "identify-all",
            dcp_frame(dcp::MULTICAST_IDENTIFY, 0xFEFE, 5, 1, &[all.0, all.1, 0, 0]),
        ),
        (
            "identify-name",
            dcp_frame(dcp::MULTICAST_IDENTIFY, 0xFEFE, 5, 2, &by_name),
        ),
        (
            "get",
            dcp_frame(PN_DEVICE, 0xFEFD, 3, 3, &[2, 2, 1, 2, 2, 1, 2, 3, 2, 7]),
        ),
        (
            "set-signal",
            dcp_frame(
                PN_DEVICE,
                0xFEFD,
                4,
                4,
                &block(dcp::CONTROL_SIGNAL, &[0, 0, 1, 0]),
            ),
        ),
        (
            "set-name",
            dcp_frame(
                PN_DEVICE,
                0xFEFD,
                4,
                5,
                &block(dcp::NAME_OF_STATION, b"\x00\x01drive-1"),
            ),
        ),
        (
            "set-ip",
            dcp_frame(
                PN_DEVICE,
                0xFEFD,
                4,
                6,
                &block(
                    dcp::IP_PARAMETER,
                    &[0, 1, 10, 0, 0, 2, 255, 255, 255, 0, 10, 0, 0, 1],
                ),
            ),
        ),
        (
            "reset",
            dcp_frame(
                PN_DEVICE,
                0xFEFD,
                4,
                7,
                &block(dcp::CONTROL_RESET_TO_FACTORY, &[0, 0, 0, 2]),
            ),
        ),
    ];
    for (name, frame) in frames {
        out.write("pn_dcp", name, &frame);
    }
}

/// pn_rpc: the controller core's Connect, Write, PrmEnd, (the answer to ApplicationReady), Read
/// and Release of the card's GSDML, each as its opnum and arguments (the target writes the RPC
/// header).
fn pn_rpc(out: &mut Seeds) {
    let read = edsgen_model::read::read_bytes(
        Path::new("goodrive350-pn.xml"),
        include_bytes!("../../eds/goodrive350-pn.xml"),
    );
    let config = DeviceConfig::from_gsdml(read.device.profinet().expect("the card's GSDML"));
    let mut ctl = Controller::new(PN_CONTROLLER, Uuid::pnio_object(1, 0x0350, 0x0350), 9);
    let blocks = ctl.connect_blocks(&config, 32, 8, 3);
    let requests = [
        ("connect", 0u8, ctl.connect(&blocks)),
        ("write", 3, ctl.write(1, 1, 256, &[0; 22])),
        ("prm-end", 4, ctl.prm_end()),
        // The controller's answer to the device's ApplicationReady (the target writes it).
        ("ready", 6, vec![0; HEADER_LEN + NDR_LEN]),
        ("read", 2, ctl.read(1, 1, 256)),
        ("release", 1, ctl.release()),
    ];
    let mut session = Vec::new();
    for (name, opnum, pdu) in requests {
        let mut piece = vec![opnum];
        piece.extend_from_slice(&pdu[HEADER_LEN + NDR_LEN..]);
        assert!(
            !piece.windows(2).any(|w| w == CUT),
            "{name} holds the separator"
        );
        out.write("pn_rpc", name, &piece);
        if !session.is_empty() {
            session.extend_from_slice(&CUT);
        }
        session.extend_from_slice(&piece);
    }
    out.write("pn_rpc", "session", &session);
}

/// pn_alarm: the controller's side of the two alarms the target's device sends: ACK each
/// DATA, then an AlarmAck in a DATA of its own, as pieces `[PDUType, SendSeqNum, AckSeqNum,
/// var part]`.
fn pn_alarm(out: &mut Seeds) {
    let ack = AlarmAck {
        high: false,
        source: AlarmSource {
            alarm_type: ALARM_DIAGNOSIS,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: SPEC_CHANNEL_DIAGNOSIS,
        },
        status: PnioStatus([0; 4]),
    };
    let mut var = vec![0; 64];
    let n = ack.emit(&mut var).expect("an AlarmAck fits");
    var.truncate(n);
    let piece = |pdu_type: u8, send: u16, ack_seq: u16, var: &[u8]| {
        let mut p = vec![pdu_type];
        p.extend_from_slice(&send.to_be_bytes());
        p.extend_from_slice(&ack_seq.to_be_bytes());
        p.extend_from_slice(var);
        p
    };
    let pieces = [
        piece(PDU_ACK, 0xFFFF, 0, &[]),
        piece(PDU_DATA, 0, 0, &var),
        piece(PDU_ACK, 0, 1, &[]),
        piece(PDU_DATA, 1, 1, &var),
        piece(PDU_NACK, 1, 1, &[]),
        piece(PDU_ERR, 1, 1, &[0xDE, 0x81, 0x3C, 0x00]),
    ];
    out.write("pn_alarm", "ack-data", &pieces[..4].join(&CUT[..]));
    out.write("pn_alarm", "nack-err", &pieces[4..].join(&CUT[..]));
}

/// dp_fdl: a master's start-up of the Goodrive350 DP card (station 2) to data exchange.
fn dp_fdl(out: &mut Seeds) {
    let mut fcb = false;
    let mut request = |dsap: Option<u8>, data: &[u8]| {
        fcb = !fcb;
        emit(DataRepr {
            da: 2,
            sa: 1,
            dsap,
            ssap: dsap.map(|_| 62),
            fc: 0x40 | 0x10 | if fcb { 0x20 } else { 0 } | fdl::request::SRD_LOW,
            data,
        })
    };
    let status = emit(DataRepr {
        da: 2,
        sa: 1,
        dsap: None,
        ssap: None,
        fc: 0x40 | fdl::request::FDL_STATUS,
        data: &[],
    });
    let mut outputs = vec![0u8; 32];
    outputs[8..10].copy_from_slice(&0x047Fu16.to_be_bytes());
    let telegrams = [
        status,
        request(Some(sap::SLAVE_DIAG), &[]),
        request(Some(sap::SET_PRM), &[0x08, 10, 10, 11, 0x03, 0x50, 0]),
        request(Some(sap::CHK_CFG), &[0xF3, 0xFB]),
        request(Some(sap::SLAVE_DIAG), &[]),
        request(Some(sap::GET_CFG), &[]),
        request(None, &outputs),
        request(None, &outputs),
    ];
    let global_control = emit(DataRepr {
        da: 127,
        sa: 1,
        dsap: Some(sap::GLOBAL_CONTROL),
        ssap: Some(62),
        fc: 0x40 | fdl::request::SDN_HIGH,
        data: &[0x08, 0],
    });
    out.write("dp_fdl", "start-up", &telegrams.concat());
    let mut more = telegrams.concat();
    more.extend_from_slice(&global_control);
    more.push(0xE5);
    more.extend_from_slice(&[0xDC, 2, 1]);
    out.write("dp_fdl", "start-up-global-control", &more);
}

fn emit(t: DataRepr<'_>) -> Vec<u8> {
    let mut buf = [0; MAX_TELEGRAM_LEN];
    let n = t.emit(&mut buf).expect("a telegram fits");
    buf[..n].to_vec()
}

/// ethercat_frame: a master's start-up of the target's SubDevice (its SII's SyncManagers:
/// mailboxes at 0x1000/0x1080, outputs at 0x1100, inputs at 0x1180) to Op, each frame after
/// its length byte.
fn ethercat_frame(out: &mut Seeds) {
    const STATION: u16 = 0x1001;
    let frame = |command: Command, address: (u16, u16), data: &[u8]| {
        FrameBuilder::new([0x10; 6])
            .datagram(command, 1, address, data, 0)
            .build()
    };
    let fpwr = |ado: u16, data: &[u8]| frame(Command::Fpwr, (STATION, ado), data);
    let al = frame(Command::Fprd, (STATION, 0x0130), &[0; 6]);
    let mut mailbox = vec![10, 0, 0, 0, 0, 0x13, 0x00, 0x20, 0x40, 0x18, 0x10, 1];
    mailbox.resize(128, 0);
    let frames = [
        frame(Command::Bwr, (0, 0x0120), &[0x11, 0]),
        frame(Command::Bwr, (0, 0x0600), &[0; 32]),
        frame(Command::Bwr, (0, 0x0800), &[0; 32]),
        frame(Command::Apwr, (0, 0x0010), &STATION.to_le_bytes()),
        fpwr(0x0502, &[0, 1, 8, 0, 0, 0]),
        frame(Command::Fprd, (STATION, 0x0508), &[0; 4]),
        fpwr(0x0800, &sm(0x1000, 128, 0x26)),
        fpwr(0x0808, &sm(0x1080, 128, 0x22)),
        fpwr(0x0500, &[1]),
        fpwr(0x0120, &[0x12, 0]),
        al.clone(),
        fpwr(0x1000, &mailbox),
        frame(Command::Fprd, (STATION, 0x1080), &[0; 128]),
        fpwr(0x0810, &sm(0x1100, 4, 0x64)),
        fpwr(0x0818, &sm(0x1180, 2, 0x20)),
        fpwr(0x0600, &fmmu(0, 4, 0x1100, 2)),
        fpwr(0x0610, &fmmu(4, 2, 0x1180, 1)),
        fpwr(0x0120, &[4, 0]),
        al.clone(),
        frame(Command::Lrw, (0, 0), &[0; 6]),
        fpwr(0x0120, &[8, 0]),
        al,
        frame(Command::Lrw, (0, 0), &[1, 2, 3, 4, 0, 0]),
        FrameBuilder::new([0x10; 6])
            .datagram(Command::Brd, 1, (0, 0x0130), &[0; 2], 0)
            .datagram(Command::Lrw, 2, (0, 0), &[0; 6], 0)
            .build(),
    ];
    let mut all = Vec::new();
    for f in &frames {
        all.push(u8::try_from(f.len()).expect("a frame under 256 bytes"));
        all.extend_from_slice(f);
    }
    out.write("ethercat_frame", "start-up", &all);
}

fn sm(start: u16, len: u16, control: u8) -> Vec<u8> {
    let mut r = start.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[control, 0, 1, 0]);
    r
}

fn fmmu(logical: u32, len: u16, physical: u16, kind: u8) -> Vec<u8> {
    let mut r = logical.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[0, 7]);
    r.extend_from_slice(&physical.to_le_bytes());
    r.extend_from_slice(&[0, kind, 1, 0, 0, 0]);
    r
}

/// ethercat_coe: SDO requests on CP301's dictionary, each after a byte whose upper six bits
/// are its length (the answer's room: 8 + the low six bits).
fn ethercat_coe(out: &mut Seeds) {
    let sessions: [(&str, &[&[u8]]); 4] = [
        // Expedited upload of 1018h:01, expedited download of 1017h.
        (
            "expedited",
            &[
                &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0],
                &[0x2B, 0x17, 0x10, 0, 0xE8, 3, 0, 0],
            ],
        ),
        // Segmented upload of 1008h (the device name), then an abort.
        (
            "segmented-upload",
            &[
                &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0],
                &[0x60, 0, 0, 0, 0, 0, 0, 0],
                &[0x70, 0, 0, 0, 0, 0, 0, 0],
                &[0x80, 0x08, 0x10, 0, 0, 0, 0x04, 0x05],
            ],
        ),
        // Complete access upload of 1018h, and of 1A00h.
        (
            "complete-access",
            &[
                &[0x50, 0x18, 0x10, 0, 0, 0, 0, 0],
                &[0x50, 0x00, 0x1A, 0, 0, 0, 0, 0],
            ],
        ),
        // A normal (sized) download of 4 bytes to 1017h, then one refused by the guard.
        (
            "normal-download",
            &[
                &[0x21, 0x17, 0x10, 0, 4, 0, 0, 0, 0xE8, 3, 0, 0],
                &[0x23, 0x00, 0x20, 0, 1, 0, 0, 0],
            ],
        ),
    ];
    for (name, requests) in sessions {
        let mut bytes = Vec::new();
        for r in requests {
            bytes.push(u8::try_from(r.len() << 2).expect("a short request") | 0x3);
            bytes.extend_from_slice(r);
        }
        out.write("ethercat_coe", name, &bytes);
    }
}

fn encap(command: u16, session: u32, data: &[u8]) -> Vec<u8> {
    EncapRepr::request(command, session, [0; 8], data)
        .to_vec()
        .expect("a message fits")
}

fn send_rr(request: &[u8], more: &[Item<'_>]) -> Vec<u8> {
    let mut items = vec![
        Item::new(item::NULL_ADDRESS, &[]),
        Item::new(item::UNCONNECTED_DATA, request),
    ];
    items.extend_from_slice(more);
    SendDataRepr {
        timeout: 0,
        items: &items,
    }
    .to_vec()
    .expect("items fit")
}

/// enip: the target's chunks (a header byte: the kind in its top two bits, the length in its
/// low six) from a scanner's session; enip_scanner: what the simulated adapter answers to it
/// (encapsulation replies, Message Router responses, a Forward_Open reply, class-1 datagrams)
/// and a sockaddr item.
fn enip(out: &mut Seeds) {
    let get = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
    let get_all = [0x01, 2, 0x20, 0x01, 0x24, 0x01];
    let get_parameter = [0x0E, 3, 0x20, 0x0F, 0x24, 0x03, 0x30, 0x01];
    let set_parameter = [0x10, 3, 0x20, 0x0F, 0x24, 0x03, 0x30, 0x01, 0x88, 0x13];
    let read_assembly = [0x0E, 3, 0x20, 0x04, 0x24, 0x96, 0x30, 0x03];
    let mut chunks = Vec::new();
    let mut chunk = |kind: u8, bytes: &[u8]| {
        assert!(bytes.len() < 64);
        chunks.push((kind << 6) | bytes.len() as u8);
        chunks.extend_from_slice(bytes);
    };
    chunk(0, &encap(0x63, 0, &[]));
    chunk(0, &encap(0x04, 0, &[]));
    chunk(0, &encap(0x6F, 1, &send_rr(&get, &[])));
    chunk(1, &get_all);
    chunk(1, &get_parameter);
    chunk(1, &set_parameter);
    chunk(1, &read_assembly);
    // SendUnitData: sequence count 1 and a Get_Attribute_List of 11 attributes (32 bytes).
    let mut unit = vec![1, 0, 0x03, 2, 0x20, 0x01, 0x24, 0x01, 11, 0];
    for a in 1..=11u16 {
        unit.extend_from_slice(&a.to_le_bytes());
    }
    chunk(1, &unit);
    // A class-1 datagram on the connection the target opens (O->T ID 0x1000_0002): sequence 1,
    // run, 32 bytes of outputs.
    let mut address = 0x1000_0002u32.to_le_bytes().to_vec();
    address.extend_from_slice(&1u32.to_le_bytes());
    let mut payload = vec![1, 0, 1, 0, 0, 0];
    payload.extend_from_slice(&[0; 32]);
    let datagram = CpfRepr {
        items: &[
            Item::new(item::SEQUENCED_ADDRESS, &address),
            Item::new(item::CONNECTED_DATA, &payload),
        ],
    };
    chunk(2, &datagram.to_vec().expect("a datagram fits"));
    chunk(3, &[]);
    out.write("enip", "session", &chunks);

    // The same session and a Forward_Open on the card itself, for enip_scanner.
    let mut adapter = device::goodrive350([127, 0, 0, 1], Instant::from_micros(0));
    let open = ForwardOpenRepr {
        large: false,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: 0x2000_0001,
        triad: Triad {
            serial: 1,
            vendor: 1,
            originator_serial: 1,
        },
        multiplier: 0,
        o_t_rpi: 10_000,
        o_t_params: network_params(false, 2, 1, false, 32 + 6),
        t_o_rpi: 10_000,
        t_o_params: network_params(false, 2, 1, false, 32 + 2),
        transport: 1,
        path: &[0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64],
    }
    .to_vec()
    .expect("a Forward_Open fits");
    let sockaddr = [0, 2, 0x08, 0xAE, 127, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0];
    let requests = [
        encap(0x65, 0, &[1, 0, 0, 0]),
        encap(0x63, 0, &[]),
        encap(0x04, 0, &[]),
        encap(0x6F, 1, &send_rr(&get, &[])),
        encap(0x6F, 1, &send_rr(&get_all, &[])),
        encap(
            0x6F,
            1,
            &send_rr(&open, &[Item::new(item::SOCKADDR_T_O, &sockaddr)]),
        ),
    ];
    let mut now = Instant::from_micros(0);
    let mut n = 0;
    let mut record = |bytes: &[u8]| {
        n += 1;
        out.write("enip_scanner", &format!("reply-{n}"), bytes);
    };
    for request in &requests {
        let _ = adapter.handle(now, Peer::Tcp(1), request);
        while let Some((_, reply)) = adapter.poll_transmit(now) {
            record(&reply);
            // The CPF items and the Message Router response inside a SendRRData reply.
            if let Some(items) = reply.get(24 + 6..) {
                record(items);
            }
            if let Some(response) = reply.get(24 + 16..) {
                record(response);
            }
        }
    }
    for _ in 0..2 {
        now = now + Duration::from_millis(10);
        adapter.handle_timeout(now);
        while let Some((_, datagram)) = adapter.poll_transmit(now) {
            record(&datagram);
        }
    }
    out.write("enip_scanner", "sockaddr", &sockaddr);
}

/// demo_report: a report as `edsgen demo-role enip-scanner` prints it.
fn demo_report(out: &mut Seeds) {
    let report = edsgen_demo::Report {
        lines: vec![
            "== EtherNet/IP: scanner".to_owned(),
            "ListIdentity: INVT Goodrive350 at 10.0.0.2".to_owned(),
            "step 1: ok \"quoted\" \\ tab\t".to_owned(),
        ],
        steps: vec![
            edsgen_demo::Step {
                name: "Forward_Open".to_owned(),
                outcome: Ok("connection 1".to_owned()),
            },
            edsgen_demo::Step {
                name: "Run at 50 Hz".to_owned(),
                outcome: Err("no answer".to_owned()),
            },
        ],
    };
    out.write("demo_report", "report.json", report.to_json().as_bytes());
}
