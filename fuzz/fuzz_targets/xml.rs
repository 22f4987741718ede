//! Fuzz the XML readers (XDD/XDC and ESI) and the validator: any bytes must read without a panic.
//!
//! The file name picks the format, and an XDC is judged like a DCF (commissioning, actualValue on
//! read-only entries), so the input's length picks it: odd lengths are read as `fuzz.xdc`, even
//! ones as `fuzz.xml`, which the root element routes to the ESI reader (`EtherCATInfo`) or the
//! XDD reader. No byte of the text is spent on the choice.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let name = if data.len() % 2 == 1 {
        "fuzz.xdc"
    } else {
        "fuzz.xml"
    };
    let read = edsgen_model::read::read_bytes(Path::new(name), data);
    let _ = edsgen_model::validate::validate(&read.device);
    let _ = edsgen_model::dump::to_json(&read.device);
});
