//! Fuzz the runtime's EtherNet/IP wire formats (`edsgen_runtime::enip::wire`) and the
//! originator core (`edsgen_runtime::enip::originator`), which `edsgen enip` and the demo run on
//! what a device sends: any bytes as an encapsulation message, CPF items, a Message Router
//! response, an EPATH, Forward_Open and its reply, Forward_Close, a class-1 datagram (one that
//! parses re-emits to itself), a class-3 message, an identity item and a sockaddr item (one that
//! parses re-emits to its first 8 bytes), and as the replies a session reads; then as the T→O
//! sockaddr item of a Forward_Open into the simulated adapter, whose connection then has that
//! item's port. Must not panic.
#![no_main]

use std::collections::BTreeMap;

use edsgen_runtime::enip::originator::{Class1, Session};
use edsgen_runtime::enip::wire::connection_manager::{
    network_params, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr, Triad, DEFAULT_TICKS,
};
use edsgen_runtime::enip::wire::cpf::{item, Item, Items, SendDataRepr, Sockaddr};
use edsgen_runtime::enip::wire::encap::{EncapRepr, IdentityItem};
use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::io::{ConnectedMessage, IoDatagram};
use edsgen_runtime::enip::wire::message::{RequestRepr, ResponseRepr};
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::Instant;
use edsgen_sim::enip::{Adapter, Assembly, Identity, Peer};
use libfuzzer_sys::fuzz_target;

/// A layout that parsed re-emits to bytes that parse to it again.
fn round_trip<T: Emit + PartialEq + std::fmt::Debug>(
    parsed: T,
    parse: impl Fn(&[u8]) -> Option<T>,
) {
    let bytes = parsed.to_vec().expect("a parsed layout re-emits");
    assert_eq!(parse(&bytes), Some(parsed));
}

fuzz_target!(|data: &[u8]| {
    if let Ok(datagram) = IoDatagram::parse(data) {
        let again = datagram.to_vec().expect("re-emits");
        assert_eq!(IoDatagram::parse(&again), Ok(datagram));
    }
    if let Ok(message) = ConnectedMessage::parse(data) {
        let again = message.to_vec().expect("re-emits");
        assert_eq!(ConnectedMessage::parse(&again), Ok(message));
    }
    if let Ok(reply) = ForwardOpenReply::parse(data) {
        round_trip(reply, |b| ForwardOpenReply::parse(b).ok());
    }
    if let Ok(sockaddr) = Sockaddr::parse(data) {
        assert_eq!(sockaddr.to_bytes()[..8], data[..8]);
    }
    let _ = EncapRepr::parse_prefix(data);
    let _ = Items::parse(data).map(|items| items.iter().count());
    let _ = RequestRepr::parse(data);
    let _ = ResponseRepr::parse(data).map(|r| r.extended_status(0));
    let _ = Path::parse(data).map(|p| p.points().len());
    let _ = ForwardOpenRepr::parse(data, data.len() % 2 == 0);
    let _ = ForwardCloseRepr::parse(data);
    let _ = IdentityItem::parse(data);
    let session = Session::new(*b"fuzzfuzz");
    let _ = session.rr_data_reply(data);
    let _ = session.unit_data_reply(data);
    let _ = Class1::new(1, 2, true, data.len() % 2 == 0).consume(data);

    let mut assemblies = BTreeMap::new();
    assemblies.insert(
        100,
        Assembly {
            data: vec![0; 4],
            consumed: false,
        },
    );
    assemblies.insert(
        150,
        Assembly {
            data: vec![0; 4],
            consumed: true,
        },
    );
    let identity = Identity {
        vendor: 0,
        device_type: 12,
        product_code: 1,
        revision: (1, 1),
        serial: 1,
        name: "fuzz".to_owned(),
    };
    let mut a = Adapter::new(identity, assemblies, [127, 0, 0, 1]);
    a.device.config_instances.push(1);
    let encap = |session: u32, command: u16, data: &[u8]| {
        EncapRepr::request(command, session, [0; 8], data).to_vec()
    };
    let register = encap(0, 0x65, &[1, 0, 0, 0]).expect("fits");
    let _ = a.handle(Instant::from_micros(0), Peer::Tcp(1), &register);
    while a.poll_transmit(Instant::from_micros(0)).is_some() {}
    let large = data.len() % 2 == 1;
    let open = ForwardOpenRepr {
        large,
        ticks: DEFAULT_TICKS,
        o_t_id: 0,
        t_o_id: 1,
        triad: Triad {
            serial: 1,
            vendor: 1,
            originator_serial: 1,
        },
        multiplier: 0,
        o_t_rpi: 10_000,
        o_t_params: network_params(large, 2, 2, false, 10),
        t_o_rpi: 10_000,
        t_o_params: network_params(large, 2, 2, false, 6),
        transport: 1,
        path: &[0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64],
    };
    let request = open.to_vec().expect("fits");
    let items = [
        Item::new(item::NULL_ADDRESS, &[]),
        Item::new(item::UNCONNECTED_DATA, &request),
        Item::new(item::SOCKADDR_T_O, data),
    ];
    // An item longer than 65535 bytes cannot be sent.
    let Ok(rr) = (SendDataRepr {
        timeout: 0,
        items: &items,
    })
    .to_vec() else {
        return;
    };
    let Ok(message) = encap(1, 0x6F, &rr) else {
        return;
    };
    a.handle(Instant::from_micros(0), Peer::Tcp(1), &message)
        .expect("whole");
    assert!(a.poll_transmit(Instant::from_micros(0)).is_some());
    let port = a.connections().first().and_then(|c| c.t_o_port);
    assert_eq!(port, Sockaddr::parse(data).ok().map(|s| s.port));
});
