//! Every GSDML corpus file that validates without errors generates code (identity constants,
//! typed big-endian images per submodule, parameter records) that compiles as one `no_std`
//! crate under `-D warnings`; the files left out are pinned with the diagnostic that excludes
//! them.

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::gsdml_corpus_dir;

#[test]
fn every_valid_gsdml_corpus_file_generates_code_that_compiles() {
    let Some(dir) = gsdml_corpus_dir() else {
        return;
    };
    let (modules, excluded) = generate_corpus(&dir);
    let generated = modules.len();
    insta::assert_snapshot!("gsdml_corpus_excluded", excluded);
    assert!(generated > 0, "no GSDML corpus file generated code");
    let index = write_modules("gsdml-corpus-compile", &modules);
    build_compile_check(&index, None, "gsdml-corpus-compile");
    eprintln!("{generated} GSDML corpus files generated and compiled");
}
