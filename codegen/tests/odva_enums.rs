//! The CIP emitter's enumerations (`EnumN` → Rust enums) on `tests/odva/enums.eds`, whose names
//! need care: the checked-in module `generated/odva_enums.rs` is current and deterministic, its
//! names are the ones the rules give (clashes with images, `Connection`, the prelude and each
//! other resolved), and it is included here and run: `TryFrom<raw>`, `raw()` and `From` for
//! every variant, the raw value back for an unnamed one.

use std::path::Path;

use edsgen_codegen::emit;

use edsgen_model::read;

include!("generated/odva_enums.rs");

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/generated/odva_enums.rs");

fn generated() -> String {
    let read = read::read_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/odva/enums.eds"))
        .expect("tests/odva/enums.eds");
    emit::generate_module(&read.device, "odva_enums")
        .expect("generates")
        .code
}

/// Regenerate with `EDSGEN_BLESS=1`.
#[test]
fn checked_in_module_is_current_and_deterministic() {
    let code = generated();
    if std::env::var_os("EDSGEN_BLESS").is_some() {
        std::fs::write(FIXTURE, &code).unwrap();
    }
    let on_disk = std::fs::read_to_string(FIXTURE).unwrap();
    assert!(
        on_disk == code,
        "tests/generated/odva_enums.rs is stale; run with EDSGEN_BLESS=1"
    );
    assert_eq!(generated(), code, "deterministic");
}

#[test]
fn names_are_resolved_and_documented() {
    let code = generated();
    for present in [
        // Param1 `Inputs` clashes with the image `Inputs`: its number is appended.
        "pub enum Inputs1 {",
        "pub struct Inputs {",
        // `Connection` and `Option` are taken: the number again, also between the two `Option`s.
        "pub enum Connection2 {",
        "pub enum Option3 {",
        "pub enum Option4 {",
        // The image's fields link their enumerations.
        "/// Param1 `Inputs` (values: [`Inputs1`]): bit 0 of the image, 8 bits.",
        "/// Param2 `Connection` (values: [`Connection2`]): bit 8 of the image, 16 bits.",
        // What has no variant is said.
        "/// Without a variant (outside `u8`, or a second text for a value): 300 `Too big`, 1 \
         `Again`.",
        "/// `4-20 mA` (3).",
    ] {
        assert!(code.contains(present), "{present} not in:\n{code}");
    }
    // A REAL parameter's enumeration gets no enum.
    assert!(!code.contains("enum Gain"));
}

#[test]
fn variants_convert_both_ways() {
    use odva_enums::*;
    let all = [
        (Inputs1::Off, 0),
        (Inputs1::OffValue1, 1),
        (Inputs1::Value2, 2),
        (Inputs1::N420MA, 3),
        (Inputs1::Value4, 4),
        (Inputs1::Type, 5),
    ];
    for (variant, raw) in all {
        assert_eq!(variant.raw(), raw);
        assert_eq!(u8::from(variant), raw);
        assert_eq!(Inputs1::try_from(raw), Ok(variant));
    }
    assert_eq!(Inputs1::try_from(6), Err(6));
    assert_eq!(Connection2::try_from(-1i16), Ok(Connection2::Reverse));
    assert_eq!(i16::from(Connection2::Reverse), -1);
    assert_eq!(Connection2::try_from(-2i16), Err(-2));
    assert_eq!(Option3::Yes.raw(), 1u16);
    assert_eq!(Option4::try_from(1u8), Ok(Option4::Yes));
    let image = Inputs {
        inputs: Inputs1::N420MA.raw(),
        connection: Connection2::Forward.into(),
        option: Option3::Yes.raw(),
    };
    assert_eq!(image.to_bytes(), [3, 1, 0, 1, 0]);
}
