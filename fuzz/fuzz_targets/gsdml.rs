//! Fuzz the GSDML (PROFINET) reader, the validator, the JSON dump and the emitter: any bytes must
//! read without a panic. Inputs are named `fuzz.xml`, so the format is picked by content as
//! `edsgen validate` picks it; the reader is called directly too, so that mutations which lose
//! the root element still exercise it.
#![no_main]

use edsgen_model::read::{gsdml, read_bytes};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let read = read_bytes(Path::new("fuzz.xml"), data);
    let _ = edsgen_model::validate::validate(&read.device);
    let direct = gsdml::read(Path::new("fuzz.xml"), data);
    let _ = edsgen_model::validate::validate(&direct.device);
    let _ = edsgen_model::dump::to_json(&direct.device);
    if direct.device.profinet().is_some() {
        let _ = edsgen_codegen::emit::generate(&direct.device, "fuzz");
    }
});
