//! The simulators' own cost: each simulated device's processing of one frame or datagram, through
//! the sans-IO core its driver calls, with the device already in cyclic exchange. No socket, no
//! scheduler: what a frame costs the simulator itself.
//!
//! - EtherCAT: the EC-TX508 SubDevice (its ESI and drive), the cycle frame ethercrab sends (LRW
//!   of the 21-byte outputs and 23-byte inputs, and the AL status read: 86 bytes). Goal: 1 µs.
//!   And a segment of 1, 16 and 64 EC-TX508s: the frames of one cycle (LRWs of 30 SubDevices'
//!   images at most, the AL status BRD) through every SubDevice, per SubDevice.
//! - EtherNet/IP: a class-1 O→T datagram (32 bytes) consumed, and the T→O datagram produced.
//! - PROFIBUS-DP: a Data_Exchange telegram to the Goodrive350 DP card and its answer.
//! - PROFINET: an RT_CLASS_1 output frame to the Goodrive350 PN card and its input frame.
//! - CANopen: the node `edsgen simulate` builds from an EDS at run time (CP301): an SDO
//!   expedited upload, and a 2-byte RPDO written into the dictionary.
//!
//! `cargo bench -p edsgen-sim --bench frames`.

use std::collections::BTreeMap;
use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use edsgen_runtime::dp::fdl::{self, DataRepr, MAX_TELEGRAM_LEN};
use edsgen_runtime::dp::slave::sap;
use edsgen_runtime::dp::DpState;
use edsgen_runtime::enip::wire::cpf::{item, CpfRepr, Item, Items};
use edsgen_runtime::enip::wire::encap::EncapRepr;
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::node::Node;
use edsgen_runtime::{CanFrame, Duration, Instant};
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::drives::pkw_pzd::{Bus, PkwPzdDrive};
use edsgen_sim::enip::{Adapter, Assembly, Identity, Peer};
use edsgen_sim::ethercat::ec_tx508::EcTx508Behaviour;
use edsgen_sim::ethercat::frame::{Command, FrameBuilder};
use edsgen_sim::ethercat::{AlState, EsiDevice, Segment, SubDevice};
use edsgen_sim::profinet::drive::{card_layout, CardCycle};

fn description(name: &str) -> edsgen_model::model::Device {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../eds")
        .join(name);
    edsgen_model::read::read_file(&path)
        .expect("a bundled description")
        .device
}

// --- EtherCAT --------------------------------------------------------------------------------

const STATION: u16 = 0x1001;

/// Sends one datagram to the SubDevice; the data that came back.
fn one(
    device: &mut SubDevice<EsiDevice>,
    now: u64,
    command: Command,
    address: (u16, u16),
    data: &[u8],
) -> Vec<u8> {
    let mut frame = FrameBuilder::new([0x10; 6])
        .datagram(command, 1, address, data, 0)
        .build();
    assert!(device.process_frame(Instant(now), &mut frame));
    frame[26..26 + data.len()].to_vec()
}

fn sync_manager(start: u16, len: u16, control: u8) -> Vec<u8> {
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

/// What a MainDevice writes to take an EC-TX508 to Op, in order: the SII offered, the mailbox
/// and process data SyncManagers, FMMUs for the 21-byte outputs at `logical` and the 23-byte
/// inputs after them, and the AL states.
fn to_op(logical: u32) -> Vec<(u16, Vec<u8>)> {
    vec![
        // The SII offered to the device, as SOEM and ethercrab do before Pre-Op.
        (0x0500, vec![1]),
        (0x0800, sync_manager(0x1000, 512, 0x26)),
        (0x0808, sync_manager(0x1400, 512, 0x22)),
        (0x0120, vec![2, 0]),
        (0x0810, sync_manager(0x1800, 21, 0x64)),
        (0x0818, sync_manager(0x1C00, 23, 0x20)),
        (0x0600, fmmu(logical, 21, 0x1800, 2)),
        (0x0610, fmmu(logical + 21, 23, 0x1C00, 1)),
        (0x0120, vec![4, 0]),
        (0x0120, vec![8, 0]),
    ]
}

/// The EC-TX508 SubDevice, its drive behind it.
fn ec_tx508() -> SubDevice<EsiDevice> {
    let model = description("ec-tx508.xml");
    let behaviour = EcTx508Behaviour::new(&model, Instant(0));
    EsiDevice::subdevice(&model, Some(Box::new(behaviour))).expect("the ESI serves")
}

/// The EC-TX508 in Op, as a MainDevice leaves it ([`to_op`], its images at logical 0).
fn ec_tx508_in_op() -> SubDevice<EsiDevice> {
    let mut d = ec_tx508();
    let mut now = 0;
    let mut write = |d: &mut SubDevice<EsiDevice>, command, address, data: &[u8]| {
        now += 1_000;
        one(d, now, command, address, data)
    };
    write(&mut d, Command::Apwr, (0, 0x0010), &STATION.to_le_bytes());
    for (register, value) in to_op(0) {
        write(&mut d, Command::Fpwr, (STATION, register), &value);
    }
    assert_eq!(d.state(), AlState::Op);
    d
}

/// A segment of `n` EC-TX508s in Op: stations 0x1001 up, each one's 44 bytes of images after
/// the one before's in the logical space.
fn segment_in_op(n: usize) -> Segment<EsiDevice> {
    let mut segment = Segment::new((0..n).map(|_| ec_tx508()).collect());
    let mut now = 0;
    let mut send = |segment: &mut Segment<EsiDevice>, command, address, data: &[u8]| {
        now += 100;
        let mut frame = FrameBuilder::new([0x10; 6])
            .datagram(command, 1, address, data, 0)
            .build();
        assert!(segment.process_frame(Instant(now), &mut frame));
        let wkc_at = 26 + data.len();
        u16::from_le_bytes([frame[wkc_at], frame[wkc_at + 1]])
    };
    for k in 0..n {
        let station = STATION + k as u16;
        let position = 0u16.wrapping_sub(k as u16);
        assert_eq!(
            send(
                &mut segment,
                Command::Apwr,
                (position, 0x0010),
                &station.to_le_bytes()
            ),
            1
        );
        for (register, value) in to_op(44 * k as u32) {
            assert_eq!(
                send(&mut segment, Command::Fpwr, (station, register), &value),
                1
            );
        }
    }
    assert!(segment.devices().iter().all(|d| d.state() == AlState::Op));
    segment
}

/// The frames of one cycle of a segment of `n` EC-TX508s, as a MainDevice sends them: LRWs of
/// 30 SubDevices' images at most each (1,320 bytes), the first frame with the AL status BRD.
fn segment_cycle(n: usize) -> Vec<Vec<u8>> {
    (0..n)
        .step_by(30)
        .map(|first| {
            let count = (n - first).min(30);
            let mut outputs = vec![0u8; 44 * count];
            for k in 0..count {
                outputs[44 * k..44 * k + 2].copy_from_slice(&0x000Fu16.to_le_bytes());
            }
            let logical = (44 * first) as u32;
            let address = (logical as u16, (logical >> 16) as u16);
            let frame =
                FrameBuilder::new([0x10; 6]).datagram(Command::Lrw, 1, address, &outputs, 0);
            let frame = if first == 0 {
                frame.datagram(Command::Brd, 2, (0, 0x0130), &[0, 0], 0)
            } else {
                frame
            };
            frame.build()
        })
        .collect()
}

fn ethercat(c: &mut Criterion) {
    let mut device = ec_tx508_in_op();
    let mut outputs = [0u8; 44];
    outputs[..2].copy_from_slice(&0x000Fu16.to_le_bytes());
    let cycle = FrameBuilder::new([0x10; 6])
        .datagram(Command::Lrw, 1, (0, 0), &outputs, 0)
        .datagram(Command::Brd, 2, (0, 0x0130), &[0, 0], 0)
        .build();
    assert_eq!(cycle.len(), 86);
    let mut frame = cycle.clone();
    let mut now = 1_000_000u64;
    c.bench_function(
        "ethercat: EC-TX508 cycle frame (LRW 21+23 bytes, AL status)",
        |b| {
            b.iter(|| {
                frame.copy_from_slice(&cycle);
                now += 1_000;
                black_box(device.process_frame(Instant(now), black_box(&mut frame)))
            })
        },
    );
    // A segment's cycle, per SubDevice (the throughput's elements): every frame of the cycle
    // through every SubDevice.
    let mut group = c.benchmark_group("ethercat segment: cycle per SubDevice (EC-TX508s)");
    for n in [1, 16, 64] {
        let mut segment = segment_in_op(n);
        let cycle = segment_cycle(n);
        let mut frames = cycle.clone();
        // Every SubDevice counts 3 on its LRW, and once on the BRD.
        for frame in &mut frames {
            assert!(segment.process_frame(Instant(now), frame));
        }
        let lrw_wkc = |frame: &[u8]| {
            let len = usize::from(u16::from_le_bytes([frame[22], frame[23]]) & 0x07FF);
            u16::from_le_bytes([frame[26 + len], frame[27 + len]])
        };
        let counted: u16 = frames.iter().map(|f| lrw_wkc(f)).sum();
        assert_eq!(usize::from(counted), 3 * n);
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| {
                now += 1_000;
                for (frame, sent) in frames.iter_mut().zip(&cycle) {
                    frame.copy_from_slice(sent);
                    black_box(segment.process_frame(Instant(now), black_box(frame)));
                }
            })
        });
    }
    group.finish();
}

// --- EtherNet/IP -----------------------------------------------------------------------------

fn encapsulation(command: u16, session: u32, data: &[u8]) -> Vec<u8> {
    EncapRepr {
        command,
        session,
        status: 0,
        context: *b"speed123",
        options: 0,
        data,
    }
    .to_vec()
    .expect("fits")
}

fn items(list: &[(u16, &[u8])]) -> Vec<u8> {
    let items: Vec<Item<'_>> = list.iter().map(|(k, d)| Item::new(*k, d)).collect();
    CpfRepr { items: &items }.to_vec().expect("fits")
}

/// An adapter with a 32-byte input assembly 100 and a 32-byte output assembly 150, a class-1
/// connection open between them at a 1 ms RPI; its O→T connection ID.
fn adapter_with_connection() -> (Adapter, u32) {
    let mut assemblies = BTreeMap::new();
    assemblies.insert(
        100,
        Assembly {
            data: vec![0; 32],
            consumed: false,
        },
    );
    assemblies.insert(
        150,
        Assembly {
            data: vec![0; 32],
            consumed: true,
        },
    );
    let identity = Identity {
        vendor: 0,
        device_type: 12,
        product_code: 350,
        revision: (1, 10),
        serial: 0x1234_5678,
        name: "GD350".to_owned(),
    };
    let mut a = Adapter::new(identity, assemblies, [192, 168, 0, 1]);
    a.device.config_instances.push(1);
    let t0 = Instant::from_micros(0);
    a.handle(t0, Peer::Tcp(7), &encapsulation(0x65, 0, &[1, 0, 0, 0]))
        .expect("complete");
    let (_, reply) = a.poll_transmit(t0).expect("a session");
    let session = u32::from_le_bytes([reply[4], reply[5], reply[6], reply[7]]);
    // Forward_Open 150 -> 100, config instance 1, RPI 1 ms, sizes 38 O→T and 34 T→O.
    let mut open = vec![0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    open.extend_from_slice(&0u32.to_le_bytes());
    open.extend_from_slice(&0x2000_0002u32.to_le_bytes());
    open.extend_from_slice(&1u16.to_le_bytes());
    open.extend_from_slice(&0x0001u16.to_le_bytes());
    open.extend_from_slice(&0x0BAD_CAFEu32.to_le_bytes());
    open.extend_from_slice(&[0, 0, 0, 0]);
    for size in [38u16, 34] {
        open.extend_from_slice(&1_000u32.to_le_bytes());
        open.extend_from_slice(&(0x4600 | size).to_le_bytes());
    }
    open.extend_from_slice(&[0x01, 4, 0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    let mut data = vec![0; 6];
    data.extend(items(&[
        (item::NULL_ADDRESS, &[]),
        (item::UNCONNECTED_DATA, &open),
    ]));
    a.handle(t0, Peer::Tcp(7), &encapsulation(0x6F, session, &data))
        .expect("complete");
    let (_, reply) = a.poll_transmit(t0).expect("a reply");
    let found = Items::parse(&reply[24 + 6..]).expect("items");
    let answer = found.iter().nth(1).expect("the response").data;
    assert_eq!(answer[..4], [0xD4, 0, 0, 0], "Forward_Open succeeds");
    (
        a,
        u32::from_le_bytes([answer[4], answer[5], answer[6], answer[7]]),
    )
}

fn ethernet_ip(c: &mut Criterion) {
    let (mut adapter, id) = adapter_with_connection();
    let mut sequence = 0u16;
    let mut now = Instant::from_micros(0);
    c.bench_function(
        "ethernet/ip: class-1 O→T datagram in, T→O datagram out",
        |b| {
            b.iter(|| {
                sequence = sequence.wrapping_add(1);
                now = now + Duration::from_micros(1_000);
                let mut address = id.to_le_bytes().to_vec();
                address.extend_from_slice(&u32::from(sequence).to_le_bytes());
                let mut payload = sequence.to_le_bytes().to_vec();
                payload.extend_from_slice(&1u32.to_le_bytes());
                payload.extend_from_slice(&[0x11; 32]);
                let datagram = items(&[
                    (item::SEQUENCED_ADDRESS, &address),
                    (item::CONNECTED_DATA, &payload),
                ]);
                let _ = adapter.handle(now, Peer::Io(7), black_box(&datagram));
                adapter.handle_timeout(now);
                while let Some(out) = adapter.poll_transmit(now) {
                    black_box(out);
                }
                while let Some(event) = adapter.poll_event() {
                    black_box(event);
                }
            })
        },
    );
}

// --- PROFIBUS-DP -----------------------------------------------------------------------------

const DP_MASTER: u8 = 1;
const DP_SLAVE: u8 = 2;

fn telegram(dsap: Option<u8>, fcb: bool, data: &[u8]) -> Vec<u8> {
    let mut buf = [0; MAX_TELEGRAM_LEN];
    let n = DataRepr {
        da: DP_SLAVE,
        sa: DP_MASTER,
        dsap,
        ssap: dsap.map(|_| 62),
        fc: 0x40 | 0x10 | if fcb { 0x20 } else { 0 } | fdl::request::SRD_LOW,
        data,
    }
    .emit(&mut buf)
    .expect("fits");
    buf[..n].to_vec()
}

fn profibus_dp(c: &mut Criterion) {
    let ms = Instant::from_millis;
    let mut slave = edsgen_sim::dp::card::goodrive350(DP_SLAVE, ms(0)).expect("the card");
    let mut buf = [0; MAX_TELEGRAM_LEN];
    let mut fcb = false;
    for (at, dsap, data) in [
        (1, Some(sap::SLAVE_DIAG), vec![]),
        (2, Some(sap::SET_PRM), vec![0x08, 10, 10, 11, 0x03, 0x50, 0]),
        (3, Some(sap::CHK_CFG), vec![0xF3, 0xFB]),
        (4, Some(sap::SLAVE_DIAG), vec![]),
    ] {
        fcb = !fcb;
        slave.handle(ms(at), &telegram(dsap, fcb, &data));
        slave.poll_transmit(ms(at), &mut buf).expect("an answer");
    }
    assert_eq!(slave.state(), DpState::DataExchange);
    // Data_Exchange: PKW read of P00.10, run forward at 25.00 Hz; the FCB toggles each time.
    let mut outputs = [0u8; 32];
    outputs[..4].copy_from_slice(&[0, 1, 0, 10]);
    outputs[8..12].copy_from_slice(&[0, 1, 0x09, 0xC4]);
    let requests = [
        telegram(None, !fcb, &outputs),
        telegram(None, fcb, &outputs),
    ];
    let mut n = 0usize;
    let mut now = 10_000u64;
    c.bench_function(
        "profibus-dp: Data_Exchange telegram (32 bytes each way)",
        |b| {
            b.iter(|| {
                n += 1;
                now += 2;
                slave.handle(ms(now), black_box(&requests[n % 2]));
                black_box(slave.poll_transmit(ms(now), &mut buf))
            })
        },
    );
}

// --- PROFINET --------------------------------------------------------------------------------

const PN_DEVICE: [u8; 6] = [0x02, 0x00, 0x00, 0x00, 0x03, 0x50];
const PN_CONTROLLER: [u8; 6] = [0x02, 0x00, 0x00, 0x00, 0x00, 0x01];

fn profinet(c: &mut Criterion) {
    let ms = Instant::from_millis;
    let layout = card_layout(PN_CONTROLLER, PN_DEVICE, Duration::from_millis(1), 3);
    let mut card = CardCycle::new(
        layout,
        PkwPzdDrive::bus_controlled(Bus::Profinet, ms(0)),
        ms(0),
    );
    // The output frame: 16 words (PKW read of P00.10, CW run forward, PZD2 50.00 Hz), IOPS and
    // IOCS good, cycle counter, DataStatus, TransferStatus.
    let mut frame = Vec::new();
    frame.extend_from_slice(&PN_DEVICE);
    frame.extend_from_slice(&PN_CONTROLLER);
    frame.extend_from_slice(&[0x88, 0x92, 0xC0, 0x00]);
    for word in [1u16, 10, 0, 0, 1, 5000, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0] {
        frame.extend_from_slice(&word.to_be_bytes());
    }
    frame.extend_from_slice(&[0x80, 0x80, 0, 0, 0, 0, 0, 0]);
    frame.extend_from_slice(&[0x00, 0x80, 0x35, 0x00]);
    card.handle(ms(1), &frame);
    assert!(card.poll_transmit(ms(1)).is_some(), "an input frame");
    let mut now = 2u64;
    c.bench_function(
        "profinet: RT_CLASS_1 output frame in, input frame out",
        |b| {
            b.iter(|| {
                now += 1;
                card.handle(ms(now), black_box(&frame));
                black_box(card.poll_transmit(ms(now)))
            })
        },
    );
}

// --- CANopen ---------------------------------------------------------------------------------

fn can(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).expect("a CAN frame")
}

/// The CP301 node as `edsgen simulate` builds it, operational, RPDO1 mapping 6040h (2 bytes).
fn cp301_node(now: Instant) -> Node<RuntimeDictionary> {
    let dictionary = RuntimeDictionary::new(&description("cp301.eds"), 3);
    let mut node = Node::new(dictionary, 3, now).expect("a node");
    for request in [
        can(0x603, &[0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x80]),
        can(0x603, &[0x2F, 0x00, 0x16, 0x00, 0, 0, 0, 0]),
        can(0x603, &[0x23, 0x00, 0x16, 0x01, 0x10, 0x00, 0x40, 0x60]),
        can(0x603, &[0x2F, 0x00, 0x16, 0x00, 1, 0, 0, 0]),
        can(0x603, &[0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x00]),
        can(0x000, &[0x01, 0x03]),
    ] {
        node.handle_frame(now, &request);
        while let Some(response) = node.poll_transmit(now) {
            assert_ne!(
                response.data().first(),
                Some(&0x80),
                "setup aborted: {response:?}"
            );
        }
    }
    while node.poll_event().is_some() {}
    node
}

fn canopen(c: &mut Criterion) {
    let now = Instant::from_millis(1);
    for (name, request) in [
        (
            "canopen: CP301 node from its EDS, SDO expedited upload of 1017h",
            can(0x603, &[0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]),
        ),
        (
            "canopen: CP301 node from its EDS, 2-byte RPDO into 6040h",
            can(0x203, &[0x0F, 0x00]),
        ),
    ] {
        let mut node = cp301_node(now);
        c.bench_function(name, |b| {
            b.iter(|| {
                node.handle_frame(now, black_box(&request));
                let response = node.poll_transmit(now);
                while let Some(event) = node.poll_event() {
                    black_box(event);
                }
                black_box(response)
            })
        });
    }
}

criterion_group!(
    benches,
    ethercat,
    ethernet_ip,
    profibus_dp,
    profinet,
    canopen
);
criterion_main!(benches);
