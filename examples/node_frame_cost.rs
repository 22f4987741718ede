//! The device node's cost per frame over a generated OD (the Goodrive350 card from `eds/`), for
//! `valgrind --tool=callgrind` (see `scripts/node-cost.sh`): `node_frame_cost sdo|rpdo N` runs N
//! frames of (a) an SDO expedited upload of 1017h:00 or (b) a 2-byte RPDO (RPDO1 remapped by SDO
//! to 2100h:00, UNSIGNED16), each: inject the frame, process it, collect the response, drain the
//! events.

use edsgen_runtime::node::Node;
use edsgen_runtime::{CanFrame, Instant};
use edsgen_sim::cards::goodrive350::Od;
use std::hint::black_box;

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).expect("a valid frame")
}

/// An operational Goodrive350 node whose RPDO1 carries 2 bytes.
pub fn operational_node(now: Instant) -> Node<Od> {
    let mut node = Node::new(Od::new(3), 3, now).expect("node-ID 3");
    for request in [
        frame(0x603, &[0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x80]), // RPDO1 off
        frame(0x603, &[0x2F, 0x00, 0x16, 0x00, 0, 0, 0, 0]),             // mapping off
        frame(0x603, &[0x23, 0x00, 0x16, 0x01, 0x10, 0x00, 0x00, 0x21]), // 2100h:00, 16 bits
        frame(0x603, &[0x2F, 0x00, 0x16, 0x00, 1, 0, 0, 0]),             // one object
        frame(0x603, &[0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x00]), // RPDO1 on
        frame(0x000, &[0x01, 0x03]),
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

fn main() {
    let mut args = std::env::args().skip(1);
    let case = args.next().unwrap_or_default();
    let count: u64 = args.next().and_then(|n| n.parse().ok()).unwrap_or(1000);
    let request = match case.as_str() {
        "sdo" => frame(0x603, &[0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]),
        "rpdo" => frame(0x203, &[0x34, 0x12]),
        _ => {
            eprintln!("usage: node_frame_cost sdo|rpdo N");
            std::process::exit(2);
        }
    };
    let now = Instant::from_millis(0);
    let mut node = operational_node(now);
    let mut answered = 0u64;
    for _ in 0..count {
        node.handle_frame(now, black_box(&request));
        if black_box(node.poll_transmit(now)).is_some() {
            answered += 1;
        }
        while let Some(event) = node.poll_event() {
            black_box(event);
        }
    }
    println!("{case}: {count} frames, {answered} answers");
}
