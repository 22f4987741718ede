//! Fuzz the overlays (`NAME.toml` beside a description, `edsgen_model::overlay`): any bytes as
//! an overlay applied to one of the bundled descriptions, then generated. The first byte picks
//! the description (the Goodrive350's GSDML, GSD and ODVA EDS cards, whose `[pkw_pzd]` keys
//! differ, and its CiA 306 EDS for the other tables); the rest is the overlay's text (lossy
//! UTF-8, as `read_to_string` would refuse what is not). Must not panic, and every diagnostic
//! points into the overlay's text.
#![no_main]

use edsgen_model::model::Device;
use edsgen_model::overlay;
use edsgen_model::read::read_bytes;
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;

/// (name, bytes) of the descriptions an overlay may be applied to.
const DESCRIPTIONS: [(&str, &[u8]); 4] = [
    (
        "goodrive350-pn.xml",
        include_bytes!("../../eds/goodrive350-pn.xml"),
    ),
    (
        "goodrive350-dp.gsd",
        include_bytes!("../../eds/goodrive350-dp.gsd"),
    ),
    (
        "goodrive350-enip.eds",
        include_bytes!("../../eds/goodrive350-enip.eds"),
    ),
    (
        "goodrive350.eds",
        include_bytes!("../../eds/goodrive350.eds"),
    ),
];

fuzz_target!(|data: &[u8]| {
    let Some((&pick, text)) = data.split_first() else {
        return;
    };
    // Read once (milliseconds each), cloned for each input.
    static READ: OnceLock<Vec<Device>> = OnceLock::new();
    let read = READ.get_or_init(|| {
        DESCRIPTIONS
            .iter()
            .map(|(name, bytes)| read_bytes(Path::new(name), bytes).device)
            .collect()
    });
    let mut device = read[usize::from(pick) % read.len()].clone();
    let text = String::from_utf8_lossy(text);
    let lines = text.lines().count().max(1) as u32 + 1;
    for diag in overlay::apply(&text, &mut device) {
        if let Some(span) = diag.span {
            assert!(
                span.line <= lines,
                "{diag:?} beyond the overlay's {lines} lines"
            );
        }
    }
    let _ = edsgen_codegen::emit::generate(&device, "fuzz");
});
