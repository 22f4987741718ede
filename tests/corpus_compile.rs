//! Every corpus file that validates without errors generates code that compiles as one `no_std`
//! crate under `-D warnings` (missing docs included); the files left out are pinned with the
//! diagnostic that excludes them.

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::corpus_dir;

#[test]
fn every_valid_corpus_file_generates_code_that_compiles() {
    let Some(dir) = corpus_dir() else { return };
    let (modules, excluded) = generate_corpus(&dir);
    let generated = modules.len();
    insta::assert_snapshot!("corpus_excluded", excluded);
    assert!(generated > 0, "no corpus file generated code");
    let index = write_modules("corpus-compile", &modules);
    build_compile_check(&index, None, "corpus-compile");
    eprintln!("{generated} corpus files generated and compiled");
}
