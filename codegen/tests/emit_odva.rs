//! The CIP emitter on `tests/odva/io.eds`: the checked-in module `odva_runtime.rs` exercises is
//! current and deterministic, and holds no CANopen item (no object dictionary).

use std::path::Path;

use edsgen_codegen::emit;

use edsgen_model::read;

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/generated/odva_io.rs");

fn io() -> read::Read {
    read::read_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/odva/io.eds"))
        .expect("tests/odva/io.eds")
}

/// Regenerate with `EDSGEN_BLESS=1`.
#[test]
fn checked_in_odva_module_is_current() {
    let generated = emit::generate_module(&io().device, "odva_io").expect("generates");
    if std::env::var_os("EDSGEN_BLESS").is_some() {
        std::fs::write(FIXTURE, &generated.code).unwrap();
    }
    let on_disk = std::fs::read_to_string(FIXTURE).unwrap();
    assert!(
        on_disk == generated.code,
        "tests/generated/odva_io.rs is stale; run with EDSGEN_BLESS=1"
    );
    let again = emit::generate_module(&io().device, "odva_io").expect("generates");
    assert_eq!(again.code, generated.code, "deterministic");
}

#[test]
fn the_module_is_cips_not_canopens() {
    let code = emit::generate(&io().device, "odva_io").expect("generates");
    for absent in ["ObjectDictionary", "NR_OF_RXPDO", "pub struct Od"] {
        assert!(!code.contains(absent), "{absent} in the CIP module");
    }
    // Of the runtime, the images name only the image API's error and its length check.
    let mut named: Vec<&str> = code
        .match_indices("::edsgen_runtime::")
        .map(|(at, _)| {
            let rest = &code[at..];
            &rest[..rest
                .find(|c: char| !(c.is_alphanumeric() || "_:".contains(c)))
                .unwrap()]
        })
        .collect();
    named.sort_unstable();
    named.dedup();
    assert_eq!(
        named,
        [
            "::edsgen_runtime::PdoError",
            "::edsgen_runtime::support::payload::"
        ]
    );
    for present in [
        "pub const VENDOR_ID: u16 = 0x1234;",
        "pub const PRODUCT_NAME: &str = \"IO test\";",
        "pub struct Inputs {",
        "pub const INSTANCE: u32 = 150;",
        "pub const EXCLUSIVE_OWNER: Connection = Connection {",
    ] {
        assert!(code.contains(present), "{present} not in the CIP module");
    }
}
