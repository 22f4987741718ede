//! Every GSD corpus file that validates without errors generates code (identity, baud rates,
//! User_Prm_Data, and per module its Chk_Cfg bytes and images) that compiles as one `no_std`
//! crate under `-D warnings`, included publicly and in a private module; the files left out are
//! pinned with the diagnostic that excludes them. Modular stations also compile with a chosen
//! configuration (the overlay's `[modules]`, [`CONFIGURED`]).

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::gsd_corpus_dir;

/// Corpus files generated again with an overlay choosing their modules: a MICROMASTER's second
/// PPO, a PA device's three slots, an ET 200M with its three configuration slots and two
/// signal modules.
const CONFIGURED: [(&str, &str); 3] = [
    (
        "ivangre4__PLC_Programms/SIEM8046.gse",
        r#"slots = ["PPO 3:   0 PKW / 2 PZD"]"#,
    ),
    (
        "zhaoxuji__profibus_DP_PA_soft/DPV10008.gsd",
        r#"slots = ["AI16 (temperature)", "DI8 (enable-status)", "DO8 (enable-ctr)"]"#,
    ),
    (
        "ivangre4__PLC_Programms/SIEM801D.GSE",
        r#"slots = ["Config for Slot1", "Config for Slot2", "Config for Slot3",
                   "6ES7 321-1BH0*-0AA0 16DI", "6ES7 321-1CF00-0AA0 8DI"]"#,
    ),
];

#[test]
fn every_valid_gsd_corpus_file_generates_code_that_compiles() {
    let Some(dir) = gsd_corpus_dir() else { return };
    let (mut modules, excluded) = generate_corpus(&dir);
    for (file, slots) in CONFIGURED {
        let path = dir.join(file);
        let mut read = edsgen_model::read::read_file(&path).unwrap();
        let overlay = format!("[modules]\n{slots}\n");
        let diags = edsgen_model::overlay::apply(&overlay, &mut read.device);
        assert_eq!(diags, vec![], "{file}");
        let module = format!("{}_configured", corpus_module(file));
        let code = generate_from(read, &module).unwrap();
        assert!(code.contains("pub mod configuration"), "{file}");
        modules.push((module, code));
    }
    let generated = modules.len();
    insta::assert_snapshot!("gsd_corpus_excluded", excluded);
    assert!(generated > 0, "no GSD corpus file generated code");
    let index = write_modules("gsd-corpus-compile", &modules);
    build_compile_check(&index, None, "gsd-corpus-compile");
    build_compile_check_with(&index, None, "gsd-corpus-compile", &["private"]);
    eprintln!("{generated} GSD corpus files generated and compiled");
}
