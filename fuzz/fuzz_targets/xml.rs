//! Fuzz the XDD/XDC reader and the validator: any bytes must read without a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let read = edsgen_codegen::read::read_bytes(Path::new("fuzz.xdd"), data);
    let _ = edsgen_codegen::validate::validate(&read.device);
    let _ = edsgen_codegen::dump::to_json(&read.device);
});
