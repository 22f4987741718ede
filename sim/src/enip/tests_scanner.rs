//! The scanner side of the wire formats (`wire::ForwardOpen`, `forward_close_request`,
//! `io_datagram`, sockaddr items) against exact bytes, and against the adapter core: a
//! Forward_Open built by them opens a connection, its T→O sockaddr item sets the port T→O data
//! goes to, its datagrams land in the O→T assembly, and the Forward_Close closes it.

use std::collections::BTreeMap;

use edsgen_runtime::Instant;

use super::wire::{
    emit_items, forward_close_request, io_datagram, item, network_params, parse_forward_open_reply,
    parse_io_datagram, parse_items, parse_sockaddr, sockaddr, Encapsulation, ForwardOpen,
};
use super::{Adapter, Assembly, Event, Identity};

const T0: Instant = Instant::from_micros(0);

fn adapter() -> Adapter {
    let mut assemblies = BTreeMap::new();
    for (instance, consumed) in [(100, false), (150, true)] {
        assemblies.insert(
            instance,
            Assembly {
                data: vec![0; 4],
                consumed,
            },
        );
    }
    let identity = Identity {
        vendor: 1,
        device_type: 12,
        product_code: 2,
        revision: (1, 1),
        serial: 3,
        name: "T".to_owned(),
    };
    let mut a = Adapter::new(identity, assemblies, [127, 0, 0, 1]);
    a.config_instances.push(1);
    a
}

fn open(large: bool) -> ForwardOpen {
    ForwardOpen {
        large,
        t_o_id: 0x2000_0001,
        serial: 7,
        vendor: 0xEDE5,
        originator_serial: 0x0102_0304,
        multiplier: 1,
        o_t_rpi: 20_000,
        o_t_params: network_params(large, 2, 2, false, 10),
        t_o_rpi: 20_000,
        t_o_params: network_params(large, 2, 2, false, 6),
        transport: 0x01,
        path: vec![0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64],
    }
}

/// SendRRData with `items` after the unconnected request; the Message Router response.
fn send(a: &mut Adapter, session: u32, request: &[u8], extra: &[(u16, &[u8])]) -> Vec<u8> {
    let mut all: Vec<(u16, &[u8])> =
        vec![(item::NULL_ADDRESS, &[]), (item::UNCONNECTED_DATA, request)];
    all.extend_from_slice(extra);
    let mut data = vec![0; 6];
    data.extend(emit_items(&all));
    let message = Encapsulation {
        command: 0x6F,
        session,
        status: 0,
        context: [0; 8],
        options: 0,
        data,
    };
    let (reply, _) = a.handle(9, &message.emit(), T0).expect("complete");
    let (reply, _) = Encapsulation::parse(&reply.expect("a reply")).expect("parses");
    let items = parse_items(&reply.data[6..]).expect("items");
    items[1].1.to_vec()
}

fn session(a: &mut Adapter) -> u32 {
    let register = Encapsulation {
        command: 0x65,
        session: 0,
        status: 0,
        context: [0; 8],
        options: 0,
        data: vec![1, 0, 0, 0],
    };
    let (reply, _) = a.handle(9, &register.emit(), T0).expect("complete");
    Encapsulation::parse(&reply.expect("a reply"))
        .expect("parses")
        .0
        .session
}

#[test]
fn forward_open_bytes_small_and_large() {
    let small = open(false).request();
    assert_eq!(
        small,
        [
            0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 0, 0, 0, 0, 0x01, 0, 0, 0x20, 7, 0, 0xE5,
            0xED, 0x04, 0x03, 0x02, 0x01, 1, 0, 0, 0, 0x20, 0x4E, 0, 0, 0x0A, 0x48, 0x20, 0x4E, 0,
            0, 0x06, 0x48, 0x01, 4, 0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64
        ]
    );
    let large = open(true).request();
    assert_eq!(large[0], 0x5B);
    // 32-bit parameter words: O→T at 32..36, T→O at 40..44.
    assert_eq!(&large[32..36], &[0x0A, 0, 0, 0x48]);
    assert_eq!(&large[40..44], &[0x06, 0, 0, 0x48]);
    assert_eq!(large.len(), small.len() + 4);
    assert_eq!(
        forward_close_request(7, 0xEDE5, 0x0102_0304, &[0x20, 0x04]),
        [
            0x4E, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 7, 0, 0xE5, 0xED, 4, 3, 2, 1, 1, 0, 0x20,
            0x04
        ]
    );
    assert_eq!(
        sockaddr(0x1234, [127, 0, 0, 1]),
        [0, 2, 0x12, 0x34, 127, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        parse_sockaddr(&sockaddr(2222, [0; 4])),
        Some((2222, [0; 4]))
    );
    assert_eq!(parse_sockaddr(&[0, 2, 8]), None);
    let datagram = io_datagram(0x1000_0001, 5, &[5, 0, 1, 0, 0, 0]);
    assert_eq!(
        datagram,
        [2, 0, 0x02, 0x80, 8, 0, 1, 0, 0, 0x10, 5, 0, 0, 0, 0xB1, 0, 6, 0, 5, 0, 1, 0, 0, 0]
    );
    assert_eq!(
        parse_io_datagram(&datagram),
        Some((0x1000_0001, 5, &[5, 0, 1, 0, 0, 0][..]))
    );
    assert_eq!(parse_io_datagram(&datagram[..10]), None);
}

#[test]
fn the_adapter_honours_the_t_o_sockaddr_and_the_scanner_frames() {
    let mut a = adapter();
    let s = session(&mut a);
    let port = sockaddr(40_000, [0; 4]);
    let reply = send(
        &mut a,
        s,
        &open(false).request(),
        &[(item::SOCKADDR_T_O, &port)],
    );
    assert_eq!(&reply[..4], &[0xD4, 0, 0, 0]);
    let (o_t_id, t_o_id, o_t_api, t_o_api) = parse_forward_open_reply(&reply[4..]).expect("reply");
    assert_eq!((t_o_id, o_t_api, t_o_api), (0x2000_0001, 20_000, 20_000));
    assert_eq!(a.connections()[0].t_o_port, Some(40_000));
    assert_eq!(a.take_events(), vec![Event::Opened(o_t_id)]);
    // Sequence count 1, run, 4 bytes.
    a.receive_io(
        9,
        &io_datagram(o_t_id, 1, &[1, 0, 1, 0, 0, 0, 9, 8, 7, 6]),
        T0,
    );
    assert_eq!(a.assemblies[&150].data, [9, 8, 7, 6]);
    let produced = a.poll(T0);
    let (id, sequence, data) = parse_io_datagram(&produced[0].1).expect("T→O");
    assert_eq!(
        (id, sequence, data),
        (0x2000_0001, 1, &[1, 0, 0, 0, 0, 0][..])
    );
    let close = forward_close_request(7, 0xEDE5, 0x0102_0304, &open(false).path);
    assert_eq!(&send(&mut a, s, &close, &[])[..4], &[0xCE, 0, 0, 0]);
    assert!(a.connections().is_empty());
    // Without the item: the default port.
    let reply = send(&mut a, s, &open(true).request(), &[]);
    assert_eq!(&reply[..4], &[0xDB, 0, 0, 0]);
    assert_eq!(a.connections()[0].t_o_port, None);
}
