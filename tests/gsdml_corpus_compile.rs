//! Every GSDML corpus file that validates without errors generates code (identity constants,
//! typed big-endian images per submodule, parameter records) that compiles as one `no_std`
//! crate under `-D warnings`; the files left out are pinned with the diagnostic that excludes
//! them. Two files also compile with a chosen configuration (the overlay's `[modules]`,
//! [`CONFIGURED`]).

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::gsdml_corpus_dir;

/// Corpus files generated again with an overlay choosing their modules: p-net's sample with
/// modules only allowed in slots, SEW's MOVI-C with its third access point.
const CONFIGURED: [(&str, &str); 2] = [
    (
        "rtlabs-com__p-net/GSDML-V2.4-RT-Labs-P-Net-Sample-App-20230424.xml",
        r#"slots = ["IDM_40", "3=IDM_40"]"#,
    ),
    (
        "HeisenZergA__SEWProfinetLabview/GSDML-V2.34-SEW-MOVI-C-Decentralized-Electronics-20200731-071447.xml",
        "access_point = \"DFC2xA V4.0\"\nslots = [\"2=1PD_InOut\", \"3=2PD_InOut\"]",
    ),
];

#[test]
fn every_valid_gsdml_corpus_file_generates_code_that_compiles() {
    let Some(dir) = gsdml_corpus_dir() else {
        return;
    };
    let (mut modules, excluded) = generate_corpus(&dir);
    for (file, table) in CONFIGURED {
        let path = dir.join(file);
        let mut read = edsgen_model::read::read_file(&path).unwrap();
        let overlay = format!("[modules]\n{table}\n");
        let diags = edsgen_model::overlay::apply(&overlay, &mut read.device);
        assert_eq!(diags, vec![], "{file}");
        let module = format!("{}_configured", corpus_module(file));
        let code = generate_from(read, &module).unwrap();
        assert!(code.contains("pub mod configuration"), "{file}");
        modules.push((module, code));
    }
    let generated = modules.len();
    insta::assert_snapshot!("gsdml_corpus_excluded", excluded);
    assert!(generated > 0, "no GSDML corpus file generated code");
    let index = write_modules("gsdml-corpus-compile", &modules);
    build_compile_check(&index, None, "gsdml-corpus-compile");
    eprintln!("{generated} GSDML corpus files generated and compiled");
}
