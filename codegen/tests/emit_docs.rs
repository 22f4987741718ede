//! Rustdoc of the generated modules renders the file's identifiers as written: a code span
//! holds no markdown escapes (`DAP_GD350_PN`, not `DAP\_GD350\_PN`), a backtick in the text
//! gets a longer fence.

use std::path::Path;

use edsgen_codegen::emit;
use edsgen_codegen::emit::plan::code_span;
use edsgen_model::read::read_file;

#[test]
fn code_spans_show_identifiers_as_written() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.xml");
    let code = emit::generate(&read_file(&path).unwrap().device, "goodrive350_pn").unwrap();
    assert!(
        code.contains("/// The default access point `DAP_GD350_PN`'s ModuleIdentNumber (slot 0).")
    );
    assert!(code.contains("/// Module `MOD_PKW_PZD_16`: PKW PZD 16 words."));
    assert!(!code.contains("\\_"), "{code}");
}

#[test]
fn a_code_span_is_fenced_around_backticks() {
    assert_eq!(code_span("DAP_1"), "`DAP_1`");
    assert_eq!(code_span("a`b"), "`` a`b ``");
    assert_eq!(code_span("``x"), "``` ``x ```");
    assert_eq!(code_span("tab\there"), "`tab here`");
}
