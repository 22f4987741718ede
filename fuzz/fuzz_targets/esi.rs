//! Fuzz the ESI (EtherCAT ESI XML) reader and the validator: any bytes must read without a panic.
//!
//! Its own target rather than a third format in `xml`: the seeds (shrunk ESI files) and the
//! dictionary (`fuzz/dict/esi.dict`) differ from the XDD ones, and a corpus of both would spend
//! most mutations of one format's inputs in the other's reader.
//!
//! The input's length picks the path, so that no byte of the text is spent on it: even lengths
//! are read as `fuzz.esi` (the first device), validated and dumped, as `edsgen validate` does;
//! odd ones are named `fuzz.xml`, so the format is picked by content (the root element), and
//! every device of the file is read (`read_all`, as the corpus tests do), validated and dumped.
#![no_main]

use edsgen_model::read::{esi, read_bytes};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if data.len() % 2 == 1 {
        let read = read_bytes(Path::new("fuzz.xml"), data);
        let _ = edsgen_model::validate::validate(&read.device);
        for (device, _) in esi::read_all(Path::new("fuzz.xml"), data) {
            let _ = edsgen_model::validate::validate(&device);
            let _ = edsgen_model::dump::to_json(&device);
        }
    } else {
        let read = read_bytes(Path::new("fuzz.esi"), data);
        let _ = edsgen_model::validate::validate(&read.device);
        let _ = edsgen_model::dump::to_json(&read.device);
    }
});
