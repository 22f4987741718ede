//! Every ODVA EDS corpus file generates code (identity, assembly images, connections) that
//! compiles as one `no_std` crate under `-D warnings`, included publicly and in a private module.
//! The files the validator refuses (whose `edsgen generate` and `build.rs` stop) are pinned with
//! the diagnostic that stops them, and are generated here all the same (their images follow the
//! larger of the written size and the members), so every file the reader reads is proven to give
//! code that compiles. The hand-written ODVA EDS files of the tests (no corpus file has an
//! `EnumN`; `codegen/tests/odva/enums.eds` has enumerations whose names need care) compile the
//! same way, without the corpus.

mod emit_common;
mod process_support;

use edsgen_codegen::emit;

use edsgen_model::read;
use emit_common::*;
use process_support::odva_corpus_dir;

#[test]
fn every_odva_corpus_file_generates_code_that_compiles() {
    let Some(dir) = odva_corpus_dir() else { return };
    let (_, excluded) = generate_corpus(&dir);
    insta::assert_snapshot!("odva_corpus_excluded", excluded);
    let mut modules = Vec::new();
    for (name, path) in corpus_files(&dir) {
        let module = corpus_module(&name);
        let read = read::read_file(&path).unwrap();
        let code = emit::generate_module(&read.device, &module)
            .unwrap_or_else(|d| panic!("{name}: {d:?}"))
            .code;
        modules.push((module, code));
    }
    assert_eq!(modules.len(), 16, "MANIFEST.tsv rows");
    let index = write_modules("odva-corpus-compile", &modules);
    build_compile_check(&index, None, "odva-corpus-compile");
    build_compile_check_with(&index, None, "odva-corpus-compile", &["private"]);
}

#[test]
fn hand_written_odva_files_generate_code_that_compiles() {
    let mut modules = Vec::new();
    for file in [
        "codegen/tests/odva/io.eds",
        "codegen/tests/odva/enums.eds",
        "tests/enip/io.eds",
    ] {
        let module = format!("hand_{}", modules.len());
        let read = read::read_file(&process_support::root().join(file)).unwrap();
        let code = emit::generate_module(&read.device, &module)
            .unwrap_or_else(|d| panic!("{file}: {d:?}"))
            .code;
        modules.push((module, code));
    }
    let index = write_modules("odva-hand-compile", &modules);
    build_compile_check(&index, None, "odva-hand-compile");
    build_compile_check_with(&index, None, "odva-hand-compile", &["private"]);
}
