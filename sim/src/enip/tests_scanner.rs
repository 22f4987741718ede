//! The scanner side of the runtime's wire formats (`ForwardOpenRepr`, `ForwardCloseRepr`,
//! `IoDatagram`, sockaddr items; their bytes are tested in the runtime) against the adapter
//! core: a Forward_Open built by them opens a connection, its T→O sockaddr item sets the port
//! T→O data goes to, its datagrams land in the O→T assembly, and the Forward_Close closes it.

use std::collections::BTreeMap;

use edsgen_runtime::enip::wire::connection_manager::{
    network_params, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use edsgen_runtime::enip::wire::cpf::{item, Sockaddr};
use edsgen_runtime::enip::wire::io::IoDatagram;
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::Instant;

use super::tests_support::{emit_items, events, parse_items, produce, Encapsulation};
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
    a.device.config_instances.push(1);
    a
}

const PATH: [u8; 8] = [0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64];

const TRIAD: Triad = Triad {
    serial: 7,
    vendor: 0xEDE5,
    originator_serial: 0x0102_0304,
};

fn open(large: bool) -> Vec<u8> {
    ForwardOpenRepr {
        large,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: 0x2000_0001,
        triad: TRIAD,
        multiplier: 1,
        o_t_rpi: 20_000,
        o_t_params: network_params(large, 2, 2, false, 10),
        t_o_rpi: 20_000,
        t_o_params: network_params(large, 2, 2, false, 6),
        transport: 0x01,
        path: &PATH,
    }
    .to_vec()
    .expect("fits")
}

fn datagram(connection: u32, sequence: u32, data: &[u8]) -> Vec<u8> {
    IoDatagram {
        connection,
        sequence,
        data,
    }
    .to_vec()
    .expect("fits")
}

/// SendRRData with `items` after the unconnected request; the Message Router response.
pub(super) fn send<A: super::EnipApplication>(
    a: &mut Adapter<A>,
    session: u32,
    request: &[u8],
    extra: &[(u16, &[u8])],
) -> Vec<u8> {
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
    let (reply, _) = a.request(9, &message.emit(), T0).expect("complete");
    let (reply, _) = Encapsulation::parse(&reply.expect("a reply")).expect("parses");
    let items = parse_items(&reply.data[6..]).expect("items");
    items[1].1.to_vec()
}

pub(super) fn session<A: super::EnipApplication>(a: &mut Adapter<A>) -> u32 {
    let register = Encapsulation {
        command: 0x65,
        session: 0,
        status: 0,
        context: [0; 8],
        options: 0,
        data: vec![1, 0, 0, 0],
    };
    let (reply, _) = a.request(9, &register.emit(), T0).expect("complete");
    Encapsulation::parse(&reply.expect("a reply"))
        .expect("parses")
        .0
        .session
}

#[test]
fn the_adapter_honours_the_t_o_sockaddr_and_the_scanner_frames() {
    let mut a = adapter();
    let s = session(&mut a);
    let port = Sockaddr {
        port: 40_000,
        address: [0; 4],
    }
    .to_bytes();
    let reply = send(&mut a, s, &open(false), &[(item::SOCKADDR_T_O, &port)]);
    assert_eq!(&reply[..4], &[0xD4, 0, 0, 0]);
    let opened = ForwardOpenReply::parse(&reply[4..]).expect("reply");
    let o_t_id = opened.o_t_id;
    assert_eq!(
        (opened.t_o_id, opened.triad, opened.o_t_api, opened.t_o_api),
        (0x2000_0001, TRIAD, 20_000, 20_000)
    );
    assert_eq!(a.connections()[0].t_o_port, Some(40_000));
    assert_eq!(events(&mut a), vec![Event::Opened(o_t_id)]);
    // Sequence count 1, run, 4 bytes.
    a.io(9, &datagram(o_t_id, 1, &[1, 0, 1, 0, 0, 0, 9, 8, 7, 6]), T0);
    assert_eq!(a.device.assemblies[&150].data, [9, 8, 7, 6]);
    let produced = produce(&mut a, T0);
    let produced = IoDatagram::parse(&produced[0].1).expect("T→O");
    assert_eq!(
        produced,
        IoDatagram {
            connection: 0x2000_0001,
            sequence: 1,
            data: &[1, 0, 0, 0, 0, 0],
        }
    );
    let close = ForwardCloseRepr {
        ticks: DEFAULT_TICKS,
        triad: TRIAD,
        path: &PATH,
    };
    let close = close.to_vec().expect("fits");
    assert_eq!(&send(&mut a, s, &close, &[])[..4], &[0xCE, 0, 0, 0]);
    assert!(a.connections().is_empty());
    // Without the item: the default port.
    let reply = send(&mut a, s, &open(true), &[]);
    assert_eq!(&reply[..4], &[0xDB, 0, 0, 0]);
    assert_eq!(a.connections()[0].t_o_port, None);
}
