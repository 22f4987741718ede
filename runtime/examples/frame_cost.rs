//! The benchmark loops of `benches/node.rs` as a plain program, for counting instructions with
//! `valgrind --tool=callgrind`: `frame_cost sdo|rpdo N` runs N frames. The cost per frame is the
//! difference between two runs with different N divided by the difference of N, which cancels
//! the setup (see `scripts/node-cost.sh`).

use edsgen_runtime::node::Node;
use edsgen_runtime::{CanFrame, Instant};
use std::hint::black_box;

#[path = "../tests/node_support/node_od.rs"]
mod node_od;

fn main() {
    let mut args = std::env::args().skip(1);
    let case = args.next().unwrap_or_default();
    let count: u64 = args.next().and_then(|n| n.parse().ok()).unwrap_or(1000);
    let frame = match case.as_str() {
        "sdo" => CanFrame::new(0x603, &[0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]),
        "rpdo" => CanFrame::new(0x203, &[0x34, 0x12]),
        _ => {
            eprintln!("usage: frame_cost sdo|rpdo N");
            std::process::exit(2);
        }
    }
    .expect("a valid frame");
    let now = Instant::from_millis(0);
    let mut node = Node::new(node_od::TestOd::new(3), 3, now).expect("node-ID 3");
    node.handle_frame(
        now,
        &CanFrame::new(0x000, &[0x01, 0x03]).expect("NMT frame"),
    );
    while node.poll_transmit(now).is_some() {}
    while node.poll_event().is_some() {}
    let mut answered = 0u64;
    for _ in 0..count {
        node.handle_frame(now, black_box(&frame));
        if black_box(node.poll_transmit(now)).is_some() {
            answered += 1;
        }
        while let Some(event) = node.poll_event() {
            black_box(event);
        }
    }
    println!("{case}: {count} frames, {answered} answers");
}
