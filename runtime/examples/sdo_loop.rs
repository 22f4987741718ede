//! Runs a fixed number of SDO expedited-upload request/response pairs through the server, for
//! instruction counting: `valgrind --tool=callgrind target/release/examples/sdo_loop 10000`
//! (`scripts/callgrind-sdo.sh` subtracts a run of 0 pairs and divides).
//!
//! Each pair: the request `40 00 10 00 ..` (read 1000h:00, UNSIGNED32) handed to
//! `SdoServer::handle`, then the response taken from `SdoServer::poll_transmit`.

mod common;

use std::hint::black_box;

use common::DriveOd;
use edsgen_runtime::sdo::SdoServer;
use edsgen_runtime::{Duration, Instant};

const REQUEST: [u8; 8] = [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];
const RESPONSE: [u8; 8] = [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00];

/// Runs `pairs` request/response pairs; returns how many responses matched.
#[inline(never)]
fn run_pairs(server: &mut SdoServer, od: &mut DriveOd, pairs: u64) -> u64 {
    let mut matched = 0;
    for i in 0..pairs {
        let now = Instant::from_micros(i * 100);
        server.handle(now, black_box(&REQUEST), od);
        if let Some(response) = server.poll_transmit(now, od) {
            matched += u64::from(black_box(response) == RESPONSE);
        }
    }
    matched
}

fn main() {
    let pairs = match std::env::args().nth(1) {
        None => 10_000,
        Some(arg) => match arg.parse::<u64>() {
            Ok(pairs) => pairs,
            Err(_) => {
                eprintln!("usage: sdo_loop [PAIRS]  (default 10000)");
                std::process::exit(2);
            }
        },
    };
    let mut server = SdoServer::new(Duration::from_millis(1_000));
    let mut od = DriveOd::new();
    let matched = run_pairs(&mut server, &mut od, pairs);
    println!("{matched} of {pairs} SDO upload pairs answered {RESPONSE:02X?}");
    if matched != pairs {
        std::process::exit(1);
    }
}
