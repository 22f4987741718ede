//! Fuzz the simulated EtherNet/IP adapter's parsers and state machine (`edsgen_sim::enip`): the
//! input is cut into messages by its first byte's bits and fed as encapsulation messages on one
//! TCP client (after a RegisterSession, so SendRRData reaches the objects), as bare Message
//! Router requests (the card's objects, its Parameter object included), as SendUnitData on a class-3 connection opened first, and as class-1
//! datagrams. Must not panic; afterwards the adapter must still answer a Get_Attribute_Single of
//! the Identity object.
#![no_main]

use edsgen_runtime::{Duration, Instant};
use edsgen_sim::enip::wire::{emit_items, item, Encapsulation};
use edsgen_sim::enip::device;
use libfuzzer_sys::fuzz_target;

fn encap(command: u16, session: u32, data: Vec<u8>) -> Vec<u8> {
    Encapsulation { command, session, status: 0, context: [0; 8], options: 0, data }.emit()
}

fuzz_target!(|data: &[u8]| {
    // The card: assemblies 100 and 150 of 32 bytes, configuration 1, and the Parameter object
    // of its EDS.
    let (mut a, _) = device::goodrive350([127, 0, 0, 1], Instant::from_micros(0));
    let _ = a.handle(1, &encap(0x65, 0, vec![1, 0, 0, 0]), Instant::from_micros(0));
    // A class-3 connection to the Message Router (its O->T ID is 0x1000_0001), RPI 1 s.
    let mut open = vec![0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E, 0, 0, 0, 0, 7, 0, 0, 0x30];
    open.extend_from_slice(&[1, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 0]);
    for _ in 0..2 {
        open.extend_from_slice(&1_000_000u32.to_le_bytes());
        open.extend_from_slice(&0x43FEu16.to_le_bytes());
    }
    open.extend_from_slice(&[0xA3, 2, 0x20, 0x02, 0x24, 0x01]);
    let mut rr = vec![0; 6];
    rr.extend(emit_items(&[(item::NULL_ADDRESS, &[]), (item::UNCONNECTED_DATA, &open)]));
    let _ = a.handle(1, &encap(0x6F, 1, rr), Instant::from_micros(0));
    let mut now = Instant::from_micros(0);
    let mut rest = data;
    while let Some((&head, tail)) = rest.split_first() {
        let len = usize::from(head & 0x3F).min(tail.len());
        let (chunk, next) = tail.split_at(len);
        rest = next;
        now = now + Duration::from_micros(u64::from(head) * 1000);
        match head >> 6 {
            0 => {
                let _ = a.handle(1, chunk, now);
            }
            1 if head & 0x20 != 0 => {
                // SendUnitData on the class-3 connection: the chunk is sequence count + request.
                let mut unit = vec![0; 6];
                unit.extend(emit_items(&[
                    (item::CONNECTED_ADDRESS, &0x1000_0001u32.to_le_bytes()),
                    (item::CONNECTED_DATA, chunk),
                ]));
                let _ = a.handle(1, &encap(0x70, 1, unit), now);
            }
            1 => {
                let mut rr = vec![0; 6];
                rr.extend(emit_items(&[(item::NULL_ADDRESS, &[]), (item::UNCONNECTED_DATA, chunk)]));
                let _ = a.handle(1, &encap(0x6F, 1, rr), now);
            }
            2 => a.receive_io(1, chunk, now),
            _ => {
                let _ = a.poll(now);
            }
        }
    }
    let get = vec![0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01];
    let mut rr = vec![0; 6];
    rr.extend(emit_items(&[(item::NULL_ADDRESS, &[]), (item::UNCONNECTED_DATA, &get)]));
    let (reply, _) = a.handle(1, &encap(0x6F, 1, rr), now).expect("a whole message");
    assert!(reply.is_some());
});
