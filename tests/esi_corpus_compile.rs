//! Every ESI corpus file whose first device validates without errors generates code (CoE
//! dictionary, SyncManagers, PDO structs and process images) that compiles as one `no_std` crate
//! under `-D warnings`; the files left out are pinned with the diagnostic that excludes them.

mod emit_common;
mod process_support;

use emit_common::*;
use process_support::esi_corpus_dir;

#[test]
fn every_valid_esi_corpus_file_generates_code_that_compiles() {
    let Some(dir) = esi_corpus_dir() else { return };
    let (modules, excluded) = generate_corpus(&dir);
    let generated = modules.len();
    insta::assert_snapshot!("esi_corpus_excluded", excluded);
    assert!(generated > 0, "no ESI corpus file generated code");
    let index = write_modules("esi-corpus-compile", &modules);
    build_compile_check(&index, None, "esi-corpus-compile");
    eprintln!("{generated} ESI corpus files generated and compiled");
}
