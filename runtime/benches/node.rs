//! Cost per frame of the device node on the host: inject one frame, process it, collect the
//! response (and drain the application events), for (a) an SDO expedited upload of 1017h:00 and
//! (b) a 2-byte RPDO written into the OD. `examples/frame_cost.rs` runs the same loops for
//! `valgrind --tool=callgrind` (instructions per frame; see `scripts/node-cost.sh`).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use edsgen_runtime::node::Node;
use edsgen_runtime::{CanFrame, Instant};

#[path = "../tests/node_support/node_od.rs"]
mod node_od;

use node_od::TestOd;

fn operational_node() -> Node<TestOd> {
    let now = Instant::from_millis(0);
    let mut node = Node::new(TestOd::new(3), 3, now).unwrap();
    node.handle_frame(now, &CanFrame::new(0x000, &[0x01, 0x03]).unwrap());
    while node.poll_transmit(now).is_some() {}
    while node.poll_event().is_some() {}
    node
}

fn frame_cost(c: &mut Criterion) {
    let now = Instant::from_millis(1);
    let mut node = operational_node();
    let upload = CanFrame::new(0x603, &[0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]).unwrap();
    c.bench_function("sdo_expedited_upload_1017", |b| {
        b.iter(|| {
            node.handle_frame(now, black_box(&upload));
            let response = node.poll_transmit(now);
            while let Some(event) = node.poll_event() {
                black_box(event);
            }
            black_box(response)
        })
    });
    let mut node = operational_node();
    let rpdo = CanFrame::new(0x203, &[0x34, 0x12]).unwrap();
    c.bench_function("rpdo_2_bytes_into_od", |b| {
        b.iter(|| {
            node.handle_frame(now, black_box(&rpdo));
            let response = node.poll_transmit(now);
            while let Some(event) = node.poll_event() {
                black_box(event);
            }
            black_box(response)
        })
    });
}

criterion_group!(benches, frame_cost);
criterion_main!(benches);
