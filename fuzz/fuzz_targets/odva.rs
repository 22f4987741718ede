//! Fuzz the ODVA EDS (EtherNet/IP, CIP) reader, the CIP rules and the CIP emitter: any bytes must
//! read, validate, dump and generate without a panic. The file is named `fuzz.eds`, as a user's
//! would be; the format is then picked by content, so inputs without a `[File]` or `[Device]`
//! header exercise the CiA 306 reader instead (the seeds have them).
#![no_main]

use edsgen_model::read::read_bytes;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let read = read_bytes(Path::new("fuzz.eds"), data);
    if read.device.cip().is_none() {
        return;
    }
    let _ = edsgen_model::validate::validate(&read.device);
    let _ = edsgen_model::dump::to_json(&read.device);
    let _ = edsgen_codegen::emit::generate_module(&read.device, "fuzz");
});
