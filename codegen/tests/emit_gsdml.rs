//! The GSDML emitter's module constants: where a module may go, as the default access point's
//! `ModuleItemRef` says.

use std::path::Path;

use edsgen_codegen::emit;
use edsgen_model::read::read_file;

#[test]
fn a_module_names_the_slots_the_access_point_allows() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.xml");
    let code = emit::generate(&read_file(&path).unwrap().device, "goodrive350_pn").unwrap();
    for constant in [
        "pub const ALLOWED_IN_SLOTS: &[u16] = &[1];",
        "pub const FIXED_IN_SLOTS: &[u16] = &[];",
        "pub const USED_IN_SLOTS: &[u16] = &[1];",
    ] {
        assert_eq!(code.matches(constant).count(), 1, "{constant} in {code}");
    }
}

#[test]
fn a_value_list_becomes_an_enum_in_its_record() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.xml");
    let code = emit::generate(&read_file(&path).unwrap().device, "goodrive350_pn").unwrap();
    let squeezed: String = code.split_whitespace().collect();
    for part in [
        "pubenumP1632ReceivedPzd2Values{",
        "///`Setfrequency(0-Fmax,0.01Hz)`(1).SetFrequency0Fmax001Hz,",
        "Self::SetFrequency0Fmax001Hz=>1,",
        "1=>{::core::result::Result::Ok(Self::SetFrequency0Fmax001Hz)}",
        "other=>::core::result::Result::Err(other),",
    ] {
        assert!(squeezed.contains(part), "{part} in {code}");
    }
}

#[test]
fn a_named_bit_gets_a_getter_and_a_setter_beside_its_mask() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.xml");
    let code = emit::generate(&read_file(&path).unwrap().device, "goodrive350_pn").unwrap();
    let squeezed: String = code.split_whitespace().collect();
    for part in [
        "pubconstSW_STATUS_WORD_OVERLOAD_PRE_ALARM:u16=1<<12;",
        "///Whetherbit12of`sw_status_word`isset([`Self::SW_STATUS_WORD_OVERLOAD_PRE_ALARM`]).\
         pubconstfnsw_status_word_overload_pre_alarm(self)->bool{\
         self.sw_status_word&Self::SW_STATUS_WORD_OVERLOAD_PRE_ALARM!=0}",
        "pubfnset_sw_status_word_overload_pre_alarm(&mutself,on:bool){ifon{\
         self.sw_status_word|=Self::SW_STATUS_WORD_OVERLOAD_PRE_ALARM;}else{\
         self.sw_status_word&=!Self::SW_STATUS_WORD_OVERLOAD_PRE_ALARM;}}",
        "pubconstfncw_control_word_heartbeat_reference(self)->bool{",
    ] {
        assert_eq!(squeezed.matches(part).count(), 1, "{part} in {code}");
    }
    // One getter and one setter per named bit: 8 in the input's status word, 8 in the output's
    // control word.
    assert_eq!(squeezed.matches("pubconstfnsw_status_word_").count(), 8);
    assert_eq!(squeezed.matches("pubconstfncw_control_word_").count(), 8);
    assert_eq!(squeezed.matches("pubfnset_sw_status_word_").count(), 8);
    assert_eq!(squeezed.matches("pubfnset_cw_control_word_").count(), 8);
}

const RECORDS_FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/generated/pn_records.rs");

/// `tests/gsdml/records.xml`, generated as `gsdml_records.rs` includes it: the checked-in module
/// is current and deterministic, and it is clean (regenerate with `EDSGEN_BLESS=1`).
#[test]
fn checked_in_record_module_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gsdml/records.xml");
    let read = read_file(&path).unwrap();
    let mut diags = read.diagnostics.clone();
    diags.extend(edsgen_model::validate::validate(&read.device));
    assert!(diags.is_empty(), "{diags:?}");
    let generated = emit::generate_module(&read.device, "pn_records").expect("generates");
    if std::env::var_os("EDSGEN_BLESS").is_some() {
        std::fs::write(RECORDS_FIXTURE, &generated.code).unwrap();
    }
    let on_disk = std::fs::read_to_string(RECORDS_FIXTURE).unwrap();
    assert!(
        on_disk == generated.code,
        "tests/generated/pn_records.rs is stale; run with EDSGEN_BLESS=1"
    );
    let again = emit::generate_module(&read.device, "pn_records").expect("generates");
    assert_eq!(again.code, generated.code, "deterministic");
}
