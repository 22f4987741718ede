//! SDO server throughput: one expedited upload of an UNSIGNED32 (request in, response out) per
//! iteration, against the generated-style dictionary the `sdo_loop` example uses.

#[path = "../examples/common/mod.rs"]
mod common;

use std::hint::black_box;

use common::DriveOd;
use criterion::{criterion_group, criterion_main, Criterion};
use edsgen_runtime::sdo::SdoServer;
use edsgen_runtime::{Duration, Instant};

fn expedited_upload_pair(c: &mut Criterion) {
    let request = [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];
    let mut server = SdoServer::new(Duration::from_millis(1_000));
    let mut od = DriveOd::new();
    let now = Instant::from_millis(1);
    assert_eq!(
        {
            server.handle(now, &request, &mut od);
            server.poll_transmit(now, &od)
        },
        Some([0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00])
    );
    c.bench_function("sdo_expedited_upload_u32_pair", |b| {
        b.iter(|| {
            server.handle(now, black_box(&request), &mut od);
            black_box(server.poll_transmit(now, &od))
        })
    });
}

criterion_group!(benches, expedited_upload_pair);
criterion_main!(benches);
