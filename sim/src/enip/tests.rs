//! The adapter core against exact bytes: sessions, identity, explicit messaging with its general
//! status codes, Forward_Open/Forward_Close with their extended statuses, class-1 I/O and the
//! timeout; and garbage never panics. Class-3 connections are `tests_class3`'s; the fixture and
//! request helpers here serve both.

use std::collections::BTreeMap;

use edsgen_runtime::{Duration, Instant};

use edsgen_runtime::enip::wire::cpf::item;

use super::tests_support::{emit_items, events, parse_items, produce, Encapsulation};
use super::{Adapter, Assembly, Event, Identity};

pub(super) fn adapter() -> Adapter {
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
    let mut a = Adapter::new(
        Identity {
            vendor: 0,
            device_type: 12,
            product_code: 350,
            revision: (1, 10),
            serial: 0x1234_5678,
            name: "GD350".to_owned(),
        },
        assemblies,
        [192, 168, 0, 1],
    );
    a.device.config_instances.push(1);
    a
}

pub(super) const T0: Instant = Instant::from_micros(0);

pub(super) fn encap(command: u16, session: u32, data: &[u8]) -> Vec<u8> {
    Encapsulation {
        command,
        session,
        status: 0,
        context: *b"ctx12345",
        options: 0,
        data: data.to_vec(),
    }
    .emit()
}

pub(super) fn reply<A: super::EnipApplication>(a: &mut Adapter<A>, bytes: &[u8]) -> Encapsulation {
    let (out, used) = a.request(7, bytes, T0).expect("complete");
    assert_eq!(used, bytes.len());
    Encapsulation::parse(&out.expect("a reply"))
        .expect("parses")
        .0
}

pub(super) fn session<A: super::EnipApplication>(a: &mut Adapter<A>) -> u32 {
    reply(a, &encap(0x65, 0, &[1, 0, 0, 0])).session
}

/// A Message Router request over SendRRData; the response's bytes.
pub(super) fn explicit<A: super::EnipApplication>(
    a: &mut Adapter<A>,
    handle: u32,
    request: &[u8],
) -> Vec<u8> {
    let mut data = vec![0; 6];
    data.extend(emit_items(&[
        (item::NULL_ADDRESS, &[]),
        (item::UNCONNECTED_DATA, request),
    ]));
    let r = reply(a, &encap(0x6F, handle, &data));
    assert_eq!(r.status, 0);
    let items = parse_items(&r.data[6..]).expect("items");
    items[1].1.to_vec()
}

#[test]
fn register_session_and_its_refusals() {
    let mut a = adapter();
    let r = reply(&mut a, &encap(0x65, 0, &[1, 0, 0, 0]));
    assert_eq!(
        (r.command, r.session, r.status, r.data.clone()),
        (0x65, 1, 0, vec![1, 0, 0, 0])
    );
    assert_eq!(&r.context, b"ctx12345");
    assert_eq!(reply(&mut a, &encap(0x65, 0, &[2, 0, 0, 0])).status, 0x69);
    assert_eq!(reply(&mut a, &encap(0x65, 0, &[1, 0])).status, 0x65);
    assert_eq!(reply(&mut a, &encap(0x6F, 99, &[0; 16])).status, 0x64);
    assert_eq!(reply(&mut a, &encap(0x0123, 1, &[])).status, 0x01);
    // UnRegisterSession has no reply and ends the session.
    assert_eq!(
        a.request(7, &encap(0x66, 1, &[]), T0).expect("complete").0,
        None
    );
    assert_eq!(reply(&mut a, &encap(0x6F, 1, &[0; 16])).status, 0x64);
}

/// Over UDP (client `u64::MAX`) the TCP-only commands (CIP Vol 2 Table 2-3.2) get the
/// encapsulation status 0x0001, invalid command, with no data and no session; ListIdentity works.
#[test]
fn tcp_only_commands_refused_over_udp() {
    let mut a = adapter();
    for (command, data) in [
        (0x65, &[1u8, 0, 0, 0][..]),
        (0x6F, &[0; 16]),
        (0x70, &[0; 16]),
    ] {
        let (out, _) = a
            .request(u64::MAX, &encap(command, 0, data), T0)
            .expect("complete");
        let mut expected = encap(command, 0, &[]);
        expected[8] = 0x01;
        assert_eq!(out.expect("a reply"), expected);
    }
    // No session was registered: the first over TCP gets handle 1.
    assert_eq!(session(&mut a), 1);
    let (out, _) = a
        .request(u64::MAX, &encap(0x63, 0, &[]), T0)
        .expect("complete");
    assert_eq!(&out.expect("a reply")[..2], &[0x63, 0]);
}

#[test]
fn list_identity_bytes() {
    let mut a = adapter();
    let r = reply(&mut a, &encap(0x63, 0, &[]));
    let mut body = vec![
        1, 0, 0, 2, 0xAF, 0x12, 192, 168, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0,
    ];
    body.extend_from_slice(&[0, 0, 12, 0, 0x5E, 0x01, 1, 10, 0, 0, 0x78, 0x56, 0x34, 0x12]);
    body.extend_from_slice(&[5, b'G', b'D', b'3', b'5', b'0', 3]);
    assert_eq!(r.data, emit_items(&[(0x0C, &body)]));
}

#[test]
fn explicit_messages_and_general_status() {
    let mut a = adapter();
    let s = session(&mut a);
    // Get_Attribute_Single @1/1/3: product code 350.
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x03]),
        vec![0x8E, 0, 0, 0, 0x5E, 0x01]
    );
    // @1/1/7: the name as a short string.
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07]),
        vec![0x8E, 0, 0, 0, 5, b'G', b'D', b'3', b'5', b'0']
    );
    // @4/100/3: the input assembly's 32 bytes.
    let mut expected = vec![0x8E, 0, 0, 0];
    expected.extend_from_slice(&[0; 32]);
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 3, 0x20, 0x04, 0x24, 0x64, 0x30, 0x03]),
        expected
    );
    // Refusals.
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x63]),
        vec![0x8E, 0, 0x14, 0]
    );
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 2, 0x20, 0x70, 0x24, 0x01]),
        vec![0x8E, 0, 0x05, 0]
    );
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 2, 0x20, 0x04, 0x24, 0x65]),
        vec![0x8E, 0, 0x16, 0]
    );
    assert_eq!(
        explicit(&mut a, s, &[0x4B, 2, 0x20, 0x01, 0x24, 0x01]),
        vec![0xCB, 0, 0x08, 0]
    );
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 5, 0x20]),
        vec![0x8E, 0, 0x13, 0]
    );
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 1, 0xE0, 0x01]),
        vec![0x8E, 0, 0x04, 0]
    );
    // Set_Attribute_Single on the output assembly: too little, too much, exact.
    let set = |n: usize| {
        let mut r = vec![0x10, 3, 0x20, 0x04, 0x24, 0x96, 0x30, 0x03];
        r.extend(std::iter::repeat_n(0xAA, n));
        r
    };
    assert_eq!(explicit(&mut a, s, &set(31)), vec![0x90, 0, 0x13, 0]);
    assert_eq!(explicit(&mut a, s, &set(33)), vec![0x90, 0, 0x15, 0]);
    assert_eq!(explicit(&mut a, s, &set(32)), vec![0x90, 0, 0x00, 0]);
    assert_eq!(a.device.assemblies[&150].data, vec![0xAA; 32]);
    // The input assembly is the adapter's: not settable.
    let mut r = vec![0x10, 3, 0x20, 0x04, 0x24, 0x64, 0x30, 0x03];
    r.extend([0; 32]);
    assert_eq!(explicit(&mut a, s, &r), vec![0x90, 0, 0x0E, 0]);
}

/// A Forward_Open 150 -> 100 at `rpi_us`, config instance 1, sizes `o_t`/`t_o` (with the
/// sequence count and header), serial `serial`.
pub(super) fn forward_open(serial: u16, rpi_us: u32, o_t: u16, t_o: u16) -> Vec<u8> {
    let mut r = vec![0x54, 2, 0x20, 0x06, 0x24, 0x01];
    r.extend_from_slice(&[0x0A, 0x0E]);
    r.extend_from_slice(&0u32.to_le_bytes());
    r.extend_from_slice(&0x2000_0002u32.to_le_bytes());
    r.extend_from_slice(&serial.to_le_bytes());
    r.extend_from_slice(&0x0001u16.to_le_bytes());
    r.extend_from_slice(&0x0BAD_CAFEu32.to_le_bytes());
    r.extend_from_slice(&[0, 0, 0, 0]); // multiplier 0 (x4), reserved
    r.extend_from_slice(&rpi_us.to_le_bytes());
    r.extend_from_slice(&(0x4600 | o_t).to_le_bytes());
    r.extend_from_slice(&rpi_us.to_le_bytes());
    r.extend_from_slice(&(0x4600 | t_o).to_le_bytes());
    r.push(0x01);
    r.push(4);
    r.extend_from_slice(&[0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    r
}

fn io_packet(id: u32, sequence: u16, run: bool, data: &[u8]) -> Vec<u8> {
    let mut address = id.to_le_bytes().to_vec();
    address.extend_from_slice(&u32::from(sequence).to_le_bytes());
    let mut payload = sequence.to_le_bytes().to_vec();
    payload.extend_from_slice(&u32::from(run).to_le_bytes());
    payload.extend_from_slice(data);
    emit_items(&[
        (item::SEQUENCED_ADDRESS, &address),
        (item::CONNECTED_DATA, &payload),
    ])
}

#[test]
fn forward_open_io_timeout_and_forward_close() {
    let mut a = adapter();
    let s = session(&mut a);
    // Sizes: 32 + 2 (sequence) + 4 (run/idle) O->T, 32 + 2 T->O.
    assert_eq!(
        explicit(&mut a, s, &forward_open(1, 50_000, 37, 34)),
        vec![0xD4, 0, 0x01, 2, 0x27, 0x01, 38, 0]
    );
    let ok = explicit(&mut a, s, &forward_open(1, 50_000, 38, 34));
    assert_eq!(&ok[..4], &[0xD4, 0, 0, 0]);
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    assert_eq!(&ok[8..12], &0x2000_0002u32.to_le_bytes());
    assert_eq!(events(&mut a), vec![Event::Opened(id)]);
    // The same triad again: connection in use.
    assert_eq!(
        &explicit(&mut a, s, &forward_open(1, 50_000, 38, 34))[..6],
        &[0xD4, 0, 0x01, 1, 0x00, 0x01]
    );
    // T->O now, then at the RPI.
    let out = produce(&mut a, T0);
    assert_eq!(out.len(), 1);
    let items = parse_items(&out[0].1).expect("items");
    assert_eq!(
        items[0],
        (item::SEQUENCED_ADDRESS, &[2, 0, 0, 0x20, 1, 0, 0, 0][..])
    );
    assert_eq!(&items[1].1[..2], &[1, 0]);
    assert_eq!(items[1].1.len(), 34);
    assert!(produce(&mut a, T0 + Duration::from_micros(49_000)).is_empty());
    assert_eq!(produce(&mut a, T0 + Duration::from_micros(50_000)).len(), 1);
    // O->T data lands in assembly 150.
    a.io(
        7,
        &io_packet(id, 1, true, &[0x11; 32]),
        T0 + Duration::from_micros(60_000),
    );
    assert_eq!(a.device.assemblies[&150].data, vec![0x11; 32]);
    assert!(a.connections()[0].run);
    assert_eq!(events(&mut a), vec![Event::Consumed(150)]);
    // Owned: explicit writes conflict with the connection.
    let mut set = vec![0x10, 3, 0x20, 0x04, 0x24, 0x96, 0x30, 0x03];
    set.extend([0; 32]);
    assert_eq!(explicit(&mut a, s, &set), vec![0x90, 0, 0x10, 0]);
    // Forward_Close with the triad; again: not found.
    let mut close = vec![0x4E, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    close.extend_from_slice(&1u16.to_le_bytes());
    close.extend_from_slice(&1u16.to_le_bytes());
    close.extend_from_slice(&0x0BAD_CAFEu32.to_le_bytes());
    close.extend_from_slice(&[4, 0, 0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    assert_eq!(&explicit(&mut a, s, &close)[..4], &[0xCE, 0, 0, 0]);
    assert_eq!(events(&mut a), vec![Event::Closed(id)]);
    assert_eq!(
        &explicit(&mut a, s, &close)[..6],
        &[0xCE, 0, 0x01, 1, 0x07, 0x01]
    );
    // A new connection that stops producing: closed after 4 x RPI.
    let ok = explicit(&mut a, s, &forward_open(2, 50_000, 38, 34));
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    events(&mut a);
    let t1 = T0 + Duration::from_micros(100_000);
    a.io(7, &io_packet(id, 1, true, &[0; 32]), t1);
    produce(&mut a, t1 + Duration::from_micros(199_000));
    assert_eq!(a.connections().len(), 1);
    produce(&mut a, t1 + Duration::from_micros(200_000));
    assert!(a.connections().is_empty());
    assert_eq!(
        events(&mut a),
        vec![Event::Consumed(150), Event::TimedOut(id)]
    );
}

#[test]
fn garbage_never_panics() {
    let mut a = adapter();
    let s = session(&mut a);
    let ok = explicit(&mut a, s, &class3_open(0x54, 1, 2_000_000, 0xA3, &ROUTER));
    let id = u32::from_le_bytes([ok[4], ok[5], ok[6], ok[7]]);
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    for n in 0..2000usize {
        let len = n % 90;
        let bytes: Vec<u8> = (0..len)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                x as u8
            })
            .collect();
        let _ = a.request(7, &bytes, T0);
        let _ = a.route(7, &bytes, T0);
        a.io(7, &bytes, T0);
        let mut wrapped = vec![0; 6];
        wrapped.extend(emit_items(&[
            (item::NULL_ADDRESS, &[]),
            (item::UNCONNECTED_DATA, &bytes),
        ]));
        let _ = a.request(7, &encap(0x6F, s, &wrapped), T0);
        let mut unit = vec![0; 6];
        unit.extend(emit_items(&[
            (item::CONNECTED_ADDRESS, &id.to_le_bytes()),
            (item::CONNECTED_DATA, &bytes),
        ]));
        let _ = a.request(7, &encap(0x70, s, &unit), T0);
    }
    // The class-3 connection lived through it.
    assert!(a.explicit_connections().iter().any(|c| c.o_t_id == id));
    // Still serving.
    assert_eq!(
        explicit(&mut a, s, &[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01]),
        vec![0x8E, 0, 0, 0, 0, 0]
    );
}

#[test]
fn large_forward_open_takes_32_bit_parameters() {
    let mut a = adapter();
    let s = session(&mut a);
    let mut r = vec![0x5B, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    r.extend_from_slice(&0u32.to_le_bytes());
    r.extend_from_slice(&0x3000_0003u32.to_le_bytes());
    r.extend_from_slice(&9u16.to_le_bytes());
    r.extend_from_slice(&1u16.to_le_bytes());
    r.extend_from_slice(&7u32.to_le_bytes());
    r.extend_from_slice(&[1, 0, 0, 0]); // multiplier 1 (x8)
    r.extend_from_slice(&100_000u32.to_le_bytes());
    r.extend_from_slice(&(0x4600_0000u32 | 38).to_le_bytes());
    r.extend_from_slice(&100_000u32.to_le_bytes());
    r.extend_from_slice(&(0x4600_0000u32 | 34).to_le_bytes());
    r.push(0x01);
    r.push(4);
    r.extend_from_slice(&[0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    let ok = explicit(&mut a, s, &r);
    assert_eq!(&ok[..4], &[0xDB, 0, 0, 0]);
    assert_eq!(&ok[8..12], &0x3000_0003u32.to_le_bytes());
    let c = &a.connections()[0];
    assert_eq!(c.timeout, Duration::from_micros(800_000));
    // One byte more than the path: too much data.
    r.push(0);
    assert_eq!(explicit(&mut a, s, &r), vec![0xDB, 0, 0x15, 0]);
}

/// A class-3 Forward_Open (`service` 0x54 or 0x5B) to the Message Router: T→O ID 0x3000_0007,
/// serial `serial`, RPI `rpi_us`, multiplier 0 (×4), sizes 510 variable, transport `transport`,
/// connection path `path`.
pub(super) fn class3_open(
    service: u8,
    serial: u16,
    rpi_us: u32,
    transport: u8,
    path: &[u8],
) -> Vec<u8> {
    let large = service == 0x5B;
    let mut r = vec![service, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    r.extend_from_slice(&0u32.to_le_bytes());
    r.extend_from_slice(&0x3000_0007u32.to_le_bytes());
    r.extend_from_slice(&serial.to_le_bytes());
    r.extend_from_slice(&0x0001u16.to_le_bytes());
    r.extend_from_slice(&0x0BAD_CAFEu32.to_le_bytes());
    r.extend_from_slice(&[0, 0, 0, 0]);
    for _ in 0..2 {
        r.extend_from_slice(&rpi_us.to_le_bytes());
        if large {
            r.extend_from_slice(&0x4200_01FEu32.to_le_bytes());
        } else {
            r.extend_from_slice(&0x43FEu16.to_le_bytes());
        }
    }
    r.push(transport);
    r.push((path.len() / 2) as u8);
    r.extend_from_slice(path);
    r
}

/// The Message Router's path (class 2, instance 1).
pub(super) const ROUTER: [u8; 4] = [0x20, 0x02, 0x24, 0x01];
