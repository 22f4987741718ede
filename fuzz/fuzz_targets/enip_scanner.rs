//! Fuzz the scanner side of the EtherNet/IP wire formats (`edsgen_sim::enip::wire`), which
//! `edsgen enip io` runs on what a device sends: class-1 datagrams, Forward_Open reply data and
//! sockaddr items; and a Forward_Open whose T→O sockaddr item is the input, into the adapter. Must
//! not panic; a datagram that parses re-emits to the same bytes; a sockaddr that parses re-emits
//! to its first 8 bytes.
#![no_main]

use std::collections::BTreeMap;

use edsgen_runtime::Instant;
use edsgen_sim::enip::wire::{
    self, emit_items, item, io_datagram, parse_forward_open_reply, parse_io_datagram,
    parse_sockaddr, Encapsulation, ForwardOpen,
};
use edsgen_sim::enip::{Adapter, Assembly, Identity};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some((id, sequence, payload)) = parse_io_datagram(data) {
        let again = io_datagram(id, sequence, payload);
        assert_eq!(parse_io_datagram(&again), Some((id, sequence, payload)));
    }
    let _ = parse_forward_open_reply(data);
    if let Some((port, address)) = parse_sockaddr(data) {
        assert_eq!(wire::sockaddr(port, address)[..8], data[..8]);
    }
    let mut assemblies = BTreeMap::new();
    assemblies.insert(100, Assembly { data: vec![0; 4], consumed: false });
    assemblies.insert(150, Assembly { data: vec![0; 4], consumed: true });
    let identity = Identity {
        vendor: 0,
        device_type: 12,
        product_code: 1,
        revision: (1, 1),
        serial: 1,
        name: "fuzz".to_owned(),
    };
    let mut a = Adapter::new(identity, assemblies, [127, 0, 0, 1]);
    a.config_instances.push(1);
    let encap = |session: u32, command: u16, data: Vec<u8>| {
        Encapsulation { command, session, status: 0, context: [0; 8], options: 0, data }.emit()
    };
    let _ = a.handle(1, &encap(0, 0x65, vec![1, 0, 0, 0]), Instant::from_micros(0));
    let open = ForwardOpen {
        large: data.len() % 2 == 1,
        t_o_id: 1,
        serial: 1,
        vendor: 1,
        originator_serial: 1,
        multiplier: 0,
        o_t_rpi: 10_000,
        o_t_params: wire::network_params(data.len() % 2 == 1, 2, 2, false, 10),
        t_o_rpi: 10_000,
        t_o_params: wire::network_params(data.len() % 2 == 1, 2, 2, false, 6),
        transport: 1,
        path: vec![0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64],
    };
    let request = open.request();
    let mut rr = vec![0; 6];
    rr.extend(emit_items(&[
        (item::NULL_ADDRESS, &[]),
        (item::UNCONNECTED_DATA, &request),
        (item::SOCKADDR_T_O, data),
    ]));
    let (reply, _) = a.handle(1, &encap(1, 0x6F, rr), Instant::from_micros(0)).expect("whole");
    assert!(reply.is_some());
    let port = a.connections().first().and_then(|c| c.t_o_port);
    assert_eq!(port, parse_sockaddr(data).map(|(p, _)| p));
});
