//! The simulated HD1-E card against its manual fragment on the in-memory bus, node-ID 3: PDO1
//! reads and writes parameters (§8.2) with the response codes of Table 20 and the error codes of
//! Table 21, frame for frame.

mod drive_support;

use drive_support::{ms, Bench};
use edsgen_sim::drives::Hd1e;

#[test]
fn pdo1_parameter_access_answers_with_tables_20_and_21() {
    let mut bench = Bench::booted(Hd1e::new(3, ms(0)).expect("node-ID 3"));
    bench.send(0, 0x000, &[0x01, 0x03]);
    // One request every 100 ms: PDO1 Tx has an inhibit time.
    for (i, (request, response)) in [
        // Write P10.01 = 1 (Table 19's example parameter): success, the data written.
        (
            [0x02, 0x00, 0x01, 0x0A, 0x01, 0x00],
            "183: 01 00 00 00 01 00 00 00",
        ),
        // Read it back.
        (
            [0x01, 0x00, 0x01, 0x0A, 0x00, 0x00],
            "183: 01 00 00 00 01 00 00 00",
        ),
        // P10.01 takes 0–1: operation failed (04h).
        (
            [0x02, 0x00, 0x01, 0x0A, 0x02, 0x00],
            "183: 03 00 04 00 00 00 00 00",
        ),
        // No parameter P10.02: illegal data address (02h).
        (
            [0x01, 0x00, 0x02, 0x0A, 0x00, 0x00],
            "183: 03 00 02 00 00 00 00 00",
        ),
        // Request code 3 does not exist: illegal command (01h).
        (
            [0x03, 0x00, 0x00, 0x0A, 0x00, 0x00],
            "183: 03 00 01 00 00 00 00 00",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let at = 100 * (i as u64 + 1);
        assert_eq!(
            bench.send(at, 0x203, &request),
            [response],
            "{request:02X?}"
        );
    }
    assert_eq!(bench.drive.parameter(0x0A01), Some(1));
}
