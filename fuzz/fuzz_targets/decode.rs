//! Fuzz the runtime's `candump -L` trace reader and the bus decoder: any text, read line by line
//! by `TraceReader`, every record decoded, then the unfinished transfers (`decode_log` fuzzes
//! the reader of every log format that `edsgen decode` uses).
//!
//! The input's length picks the decoder, so that no byte of the text is spent on it: odd lengths
//! decode with node 5 described by `eds/cp301.eds` (names, types, PDO mappings followed through
//! the SDO writes seen), even ones without a description (everything by its COB-ID alone).
//!
//! Properties: nothing panics; every line that reads re-formats (`format_line`) to a line that
//! reads back to the same record (a round trip), and `parse_line` agrees with the reader; every
//! decoded line starts with the record's time as candump prints it. Reading stops at the first
//! line that is not UTF-8.
#![no_main]

use std::sync::OnceLock;
use std::time::Duration;

use edsgen_decode::Decoder;
use edsgen_host::trace::{format_line, parse_line, TraceReadError, TraceReader};
use edsgen_model::model::Device;
use libfuzzer_sys::fuzz_target;

/// The node the description is given for.
const NODE_ID: u8 = 5;

/// CP301, read once.
fn cp301() -> &'static Device {
    static DEVICE: OnceLock<Device> = OnceLock::new();
    DEVICE.get_or_init(|| {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../eds/cp301.eds");
        edsgen_model::read::read_file(std::path::Path::new(path))
            .expect("eds/cp301.eds is readable")
            .device
    })
}

fuzz_target!(|text: &[u8]| {
    let mut decoder = Decoder::new();
    if text.len() % 2 == 1 {
        decoder.describe(NODE_ID, cp301());
    }
    let mut last = Duration::ZERO;
    for record in TraceReader::new(text) {
        let record = match record {
            Ok(record) => record,
            Err(TraceReadError::Parse(_)) => continue,
            Err(TraceReadError::Io(..)) => break,
        };
        let line = format_line(record.timestamp_us, &record.channel, &record.frame);
        let again = parse_line(&line)
            .unwrap_or_else(|e| panic!("{record:?} formatted as `{line}` does not read: {e}"));
        assert_eq!(again, record, "formatted as `{line}`");
        last = Duration::from_micros(record.timestamp_us);
        let time = format!("{}.{:06}", last.as_secs(), last.subsec_micros());
        for decoded in decoder.decode(last, &record.frame) {
            assert!(
                decoded.starts_with(&time),
                "`{decoded}` does not start with the time {time}"
            );
        }
    }
    let _ = decoder.finish(last);
});
