//! Fuzz the report `edsgen demo-role enip-scanner` prints and `edsgen demo --enip` reads back
//! (`Report::from_json`): any bytes, as text, must not panic; a report read writes back
//! (`Report::to_json`) to text that reads as the same report.
#![no_main]

use edsgen_demo::Report;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(report) = Report::from_json(&text) {
        let again = Report::from_json(&report.to_json()).expect("a report written reads back");
        assert_eq!(again.lines, report.lines);
        assert_eq!(again.steps, report.steps);
    }
});
