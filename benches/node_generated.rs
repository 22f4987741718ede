//! The device node's cost per frame over a generated OD (the Goodrive350 card from `eds/`):
//! inject one frame, process it, collect the response, drain the events, for (a) an SDO
//! expedited upload of 1017h:00 and (b) a 2-byte RPDO (RPDO1 remapped by SDO to 2100h:00).
//! `runtime/benches/node.rs` measures the same loops over the runtime's hand-written test OD.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use edsgen_runtime::node::Node;
use edsgen_runtime::{CanFrame, Instant};
use edsgen_sim::cards::goodrive350::Od;

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn operational_node(now: Instant) -> Node<Od> {
    let mut node = Node::new(Od::new(3), 3, now).unwrap();
    for request in [
        frame(0x603, &[0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x80]),
        frame(0x603, &[0x2F, 0x00, 0x16, 0x00, 0, 0, 0, 0]),
        frame(0x603, &[0x23, 0x00, 0x16, 0x01, 0x10, 0x00, 0x00, 0x21]),
        frame(0x603, &[0x2F, 0x00, 0x16, 0x00, 1, 0, 0, 0]),
        frame(0x603, &[0x23, 0x00, 0x14, 0x01, 0x03, 0x02, 0x00, 0x00]),
        frame(0x000, &[0x01, 0x03]),
    ] {
        node.handle_frame(now, &request);
        while let Some(response) = node.poll_transmit(now) {
            assert_ne!(response.data().first(), Some(&0x80), "setup aborted");
        }
    }
    while node.poll_event().is_some() {}
    node
}

fn frame_cost(c: &mut Criterion) {
    let now = Instant::from_millis(1);
    for (name, request) in [
        (
            "goodrive350_sdo_expedited_upload_1017",
            frame(0x603, &[0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]),
        ),
        (
            "goodrive350_rpdo_2_bytes_into_od",
            frame(0x203, &[0x34, 0x12]),
        ),
    ] {
        let mut node = operational_node(now);
        c.bench_function(name, |b| {
            b.iter(|| {
                node.handle_frame(now, black_box(&request));
                let response = node.poll_transmit(now);
                while let Some(event) = node.poll_event() {
                    black_box(event);
                }
                black_box(response)
            })
        });
    }
}

criterion_group!(benches, frame_cost);
criterion_main!(benches);
