//! Fuzz the GSD (PROFIBUS-DP) reader and the validator: any bytes must read without a panic.
//!
//! The input's length picks the name, so that no byte of the text is spent on it: even lengths
//! are read as `fuzz.gsd` (the format by extension), odd ones as `fuzz.txt` (the format by
//! content: GSD only when the first line that is not a comment is `#Profibus_DP`). Each is
//! validated and dumped, as `edsgen validate` and `edsgen dump` do; every module's
//! configuration bytes are decoded, and the default parameterisation built.
#![no_main]

use edsgen_model::model::decode_cfg;
use edsgen_model::read::read_bytes;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let name = if data.len() % 2 == 0 {
        "fuzz.gsd"
    } else {
        "fuzz.txt"
    };
    let read = read_bytes(Path::new(name), data);
    let _ = edsgen_model::validate::validate(&read.device);
    let _ = edsgen_model::dump::to_json(&read.device);
    if let Some(dp) = read.device.dp() {
        for module in &dp.modules {
            let _ = decode_cfg(&module.config);
            let _ = module.io_lengths();
        }
        let _ = dp.default_user_prm_data();
    }
});
