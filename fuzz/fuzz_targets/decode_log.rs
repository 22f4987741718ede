//! Fuzz the log reader of `edsgen decode` (`edsgen_decode::log::LogReader`: candump `-L` and
//! default, Vector ASC, PCAN TRC, recognised by content) with the bus decoder behind it: any
//! bytes, read line by line, every frame decoded, then the unfinished transfers.
//!
//! Properties: nothing panics and reading never stops before the end (bytes that are not UTF-8
//! included); the tally counts every frame returned and every warning; every decoded line starts
//! with the frame's time.
#![no_main]

use std::time::Duration;

use edsgen_decode::log::{Entry, LogReader};
use edsgen_decode::Decoder;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let mut reader = LogReader::new(bytes);
    let mut decoder = Decoder::new();
    let (mut frames, mut warnings) = (0u64, 0u64);
    let mut last = Duration::ZERO;
    while let Some(entry) = reader.next_entry().expect("reading a slice cannot fail") {
        match entry {
            Entry::Frame { time_us, frame } => {
                frames += 1;
                last = Duration::from_micros(time_us);
                let time = format!("{}.{:06}", last.as_secs(), last.subsec_micros());
                for line in decoder.decode(last, &frame) {
                    assert!(
                        line.starts_with(&time),
                        "`{line}` does not start with {time}"
                    );
                }
            }
            Entry::Warning(..) => warnings += 1,
        }
    }
    let _ = decoder.finish(last);
    let tally = reader.tally();
    assert_eq!((tally.frames, tally.unreadable), (frames, warnings));
});
