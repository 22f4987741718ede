//! Fuzz the EDS/DCF reader and the validator: any bytes must read without a panic.
//!
//! The file name picks the format, and a DCF reads and validates differently (CompactPDO's
//! disabled PDOs, commissioning and ParameterValue rules), so the input's length picks it: odd
//! lengths are read as `fuzz.dcf`, even ones as `fuzz.eds`. Both halves of the corpus stay alive,
//! and no byte of the text is spent on the choice.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let name = if data.len() % 2 == 1 {
        "fuzz.dcf"
    } else {
        "fuzz.eds"
    };
    let read = edsgen_model::read::read_bytes(Path::new(name), data);
    let _ = edsgen_model::validate::validate(&read.device);
    let _ = edsgen_model::dump::to_json(&read.device);
});
