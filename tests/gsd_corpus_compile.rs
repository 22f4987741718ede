//! Every GSD corpus file that validates without errors generates code (identity, baud rates,
//! User_Prm_Data, and per module its Chk_Cfg bytes and images) that compiles as one `no_std`
//! crate under `-D warnings`, included publicly and in a private module; the files left out are
//! pinned with the diagnostic that excludes them.

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::gsd_corpus_dir;

#[test]
fn every_valid_gsd_corpus_file_generates_code_that_compiles() {
    let Some(dir) = gsd_corpus_dir() else { return };
    let (modules, excluded) = generate_corpus(&dir);
    let generated = modules.len();
    insta::assert_snapshot!("gsd_corpus_excluded", excluded);
    assert!(generated > 0, "no GSD corpus file generated code");
    let index = write_modules("gsd-corpus-compile", &modules);
    build_compile_check(&index, None, "gsd-corpus-compile");
    build_compile_check_with(&index, None, "gsd-corpus-compile", &["private"]);
    eprintln!("{generated} GSD corpus files generated and compiled");
}
