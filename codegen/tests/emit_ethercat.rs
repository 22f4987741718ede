//! The EtherCAT emitter on a hand-built ESI model (independent of the ESI reader): the checked-in
//! module `ethercat_runtime.rs` exercises is current, deterministic, and holds no CANopen-only
//! items.

mod emit_support;

use edsgen_codegen::emit;
use emit_support::*;

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/generated/ec_hand.rs");

/// Regenerate with `EDSGEN_BLESS=1`.
#[test]
fn checked_in_ethercat_module_is_current() {
    let generated = emit::generate_module(&ethercat_like(), "ec_hand").expect("generates");
    if std::env::var_os("EDSGEN_BLESS").is_some() {
        std::fs::write(FIXTURE, &generated.code).unwrap();
    }
    let on_disk = std::fs::read_to_string(FIXTURE).unwrap();
    assert!(
        on_disk == generated.code,
        "tests/generated/ec_hand.rs is stale; run with EDSGEN_BLESS=1"
    );
    assert_eq!(generated.diagnostics, vec![]);
    let again = emit::generate_module(&ethercat_like(), "ec_hand").expect("generates");
    assert_eq!(again.code, generated.code);
}

#[test]
fn an_esi_device_gets_no_canopen_pdo_items() {
    let code = emit::generate(&ethercat_like(), "ec_hand").expect("generates");
    for canopen in [
        "cob_id",
        "NR_OF_RXPDO",
        "NR_OF_TXPDO",
        "pub mod pdo",
        "Rpdo1",
    ] {
        assert!(!code.contains(canopen), "{canopen} in an ESI module");
    }
    for item in [
        "pub mod ethercat",
        "pub const IDENTITY",
        "pub struct RxPdo1600",
        "pub struct RxPdo1601",
        "pub struct RxPdo1602",
        "pub struct TxPdo1A00",
        "pub struct TxPdo1A01",
        "pub struct Outputs",
        "pub struct Inputs",
        "pub const CONTROL_WORD",
    ] {
        assert!(code.contains(item), "{item} missing");
    }
}

#[test]
fn two_output_sync_managers_get_an_image_each_named_by_number() {
    let mut device = ethercat_like();
    let ec = device.ethercat_mut().unwrap();
    ec.rx_pdos[1].sm = Some(4);
    let code = emit::generate(&device, "ec_hand").expect("generates");
    for item in [
        "pub struct Sm2Outputs",
        "pub struct Sm4Outputs",
        "pub struct Inputs",
    ] {
        assert!(code.contains(item), "{item} missing");
    }
    assert!(!code.contains("pub struct Outputs"));
    // 1602h excludes 1601h, which is on SM4 now: both are in images.
    assert!(!code.contains("excluded by a PDO above"));
    assert!(code.contains("pub rx_pdo_1602: RxPdo1602"));
}
