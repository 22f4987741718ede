//! Every ESI corpus file whose first device validates without errors generates code (CoE
//! dictionary, SyncManagers, PDO structs and process images) that compiles as one `no_std` crate
//! under `-D warnings`; the files left out are pinned with the diagnostic that excludes them.
//! Two modular devices also compile with module instances chosen (the overlay's `[modules]`,
//! [`CONFIGURED`]).

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::esi_corpus_dir;

/// Corpus files generated again with an overlay plugging modules: UTRIO's UC20 coupler with
/// output and input modules, Weidmüller's UR20 coupler with its safety module.
const CONFIGURED: [(&str, &str); 2] = [
    (
        "linuxcnc-ethercat__linuxcnc-ethercat/scripts__esi__UTRIO-UC20-RTU-EC-A_20251104.xml",
        r#"slots = ["UC20-16DO-P", "UC20-8DI-NP", "UC20-4AI-U", "UC20-16DO-N"]"#,
    ),
    (
        "ethercat-rs__ethercat-esi/tests__fixtures__Weidmueller_UR20_FBC.xml",
        r#"slots = ["UR20-4DI-4DO-PN-FSOE-V2"]"#,
    ),
];

#[test]
fn every_valid_esi_corpus_file_generates_code_that_compiles() {
    let Some(dir) = esi_corpus_dir() else { return };
    let (mut modules, excluded) = generate_corpus(&dir);
    for (file, slots) in CONFIGURED {
        let path = dir.join(file);
        let mut read = edsgen_model::read::read_file(&path).unwrap();
        let overlay = format!("[modules]\n{slots}\n");
        let diags = edsgen_model::overlay::apply(&overlay, &mut read.device);
        assert_eq!(diags, vec![], "{file}");
        let module = format!("{}_configured", corpus_module(file));
        let code = generate_from(read, &module).unwrap();
        assert!(
            code.contains("pub struct Outputs") || code.contains("pub struct Inputs"),
            "{file}"
        );
        modules.push((module, code));
    }
    let generated = modules.len();
    insta::assert_snapshot!("esi_corpus_excluded", excluded);
    assert!(generated > 0, "no ESI corpus file generated code");
    let index = write_modules("esi-corpus-compile", &modules);
    build_compile_check(&index, None, "esi-corpus-compile");
    eprintln!("{generated} ESI corpus files generated and compiled");
}
