//! Fuzz the simulated EtherNet/IP adapter's parsers and state machine (`edsgen_sim::enip`): the
//! input is cut into messages by its first byte's bits and fed as encapsulation messages on one
//! TCP client (after a RegisterSession, so SendRRData reaches the objects), as bare Message
//! Router requests (the card's objects, its Parameter object included), as SendUnitData on a
//! class-3 connection opened first, and as class-1 datagrams (a class-1 connection, O->T ID
//! 0x1000_0002, is opened first too). Must not panic; afterwards the adapter must still answer
//! a Get_Attribute_Single of the Identity object. The messages are written with the runtime's
//! wire formats (`edsgen_runtime::enip::wire`). The adapter is set up once and cloned for each
//! input (reading the card's EDS takes milliseconds).
#![no_main]

use edsgen_runtime::enip::wire::cpf::{item, Item, SendDataRepr};
use edsgen_runtime::enip::wire::encap::EncapRepr;
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::{Duration, Instant};
use edsgen_sim::drives::pkw_pzd::PkwPzdDrive;
use edsgen_sim::enip::{device, Adapter, Peer};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

fn encap(command: u16, session: u32, data: &[u8]) -> Vec<u8> {
    EncapRepr::request(command, session, [0; 8], data)
        .to_vec()
        .expect("a message fits")
}

fn send_data(items: &[Item<'_>]) -> Vec<u8> {
    SendDataRepr { timeout: 0, items }
        .to_vec()
        .expect("items fit")
}

fn unconnected(request: &[u8]) -> Vec<u8> {
    send_data(&[
        Item::new(item::NULL_ADDRESS, &[]),
        Item::new(item::UNCONNECTED_DATA, request),
    ])
}

/// The card with a session, a class-3 and a class-1 connection, as every input starts.
fn set_up() -> Adapter<PkwPzdDrive> {
    // The card: assemblies 100 and 150 of 32 bytes, configuration 1, and the Parameter object
    // of its EDS.
    let mut a = device::goodrive350([127, 0, 0, 1], Instant::from_micros(0));
    let _ = a.handle(
        Instant::from_micros(0),
        Peer::Tcp(1),
        &encap(0x65, 0, &[1, 0, 0, 0]),
    );
    // A class-3 connection to the Message Router (its O->T ID is 0x1000_0001), RPI 1 s.
    let mut open = vec![
        0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 0, 0, 0, 0, 7, 0, 0, 0x30,
    ];
    open.extend_from_slice(&[1, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 0]);
    for _ in 0..2 {
        open.extend_from_slice(&1_000_000u32.to_le_bytes());
        open.extend_from_slice(&0x43FEu16.to_le_bytes());
    }
    open.extend_from_slice(&[0xA3, 2, 0x20, 0x02, 0x24, 0x01]);
    let _ = a.handle(
        Instant::from_micros(0),
        Peer::Tcp(1),
        &encap(0x6F, 1, &unconnected(&open)),
    );
    // A class-1 connection (its O->T ID is 0x1000_0002), RPI 1 s: O->T to the output assembly
    // 150 (32 bytes after the sequence count and the run/idle header), T->O from the input
    // assembly 100, so that class-1 datagrams reach a connection.
    let mut open = vec![
        0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 0, 0, 0, 0, 8, 0, 0, 0x30,
    ];
    open.extend_from_slice(&[2, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 0]);
    for size in [38u16, 34] {
        open.extend_from_slice(&1_000_000u32.to_le_bytes());
        open.extend_from_slice(&(0x4600 | size).to_le_bytes());
    }
    open.extend_from_slice(&[0x01, 4, 0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    let _ = a.handle(
        Instant::from_micros(0),
        Peer::Tcp(1),
        &encap(0x6F, 1, &unconnected(&open)),
    );
    while a.poll_transmit(Instant::from_micros(0)).is_some() {}
    assert_eq!(a.connections().len(), 1, "the class-1 connection is open");
    a
}

fuzz_target!(|data: &[u8]| {
    static SET_UP: OnceLock<Adapter<PkwPzdDrive>> = OnceLock::new();
    let mut a = SET_UP.get_or_init(set_up).clone();
    let mut now = Instant::from_micros(0);
    let mut rest = data;
    while let Some((&head, tail)) = rest.split_first() {
        let len = usize::from(head & 0x3F).min(tail.len());
        let (chunk, next) = tail.split_at(len);
        rest = next;
        now = now + Duration::from_micros(u64::from(head) * 1000);
        match head >> 6 {
            0 => {
                let _ = a.handle(now, Peer::Tcp(1), chunk);
            }
            1 if head & 0x20 != 0 => {
                // SendUnitData on the class-3 connection: the chunk is sequence count + request.
                let address = 0x1000_0001u32.to_le_bytes();
                let unit = send_data(&[
                    Item::new(item::CONNECTED_ADDRESS, &address),
                    Item::new(item::CONNECTED_DATA, chunk),
                ]);
                let _ = a.handle(now, Peer::Tcp(1), &encap(0x70, 1, &unit));
            }
            1 => {
                let _ = a.handle(now, Peer::Tcp(1), &encap(0x6F, 1, &unconnected(chunk)));
            }
            2 => {
                let _ = a.handle(now, Peer::Io(1), chunk);
            }
            _ => {
                a.handle_timeout(now);
                while a.poll_transmit(now).is_some() {}
                while a.poll_event().is_some() {}
            }
        }
    }
    let get = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01];
    while a.poll_transmit(now).is_some() {}
    a.handle(now, Peer::Tcp(1), &encap(0x6F, 1, &unconnected(&get)))
        .expect("a whole message");
    assert!(matches!(a.poll_transmit(now), Some((Peer::Tcp(1), _))));
});
