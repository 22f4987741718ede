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
    let mut modules = Vec::new();
    let mut excluded = String::new();
    for (name, path) in corpus_files(&dir) {
        let module = corpus_module(&name);
        match generate(&path, &module) {
            Ok(code) => modules.push((module, code)),
            Err(d) => excluded.push_str(&format!(
                "{name}: {}[{}] line {}: {}\n",
                d.severity.as_str(),
                d.code(),
                d.span.map_or(0, |s| s.line),
                d.message
            )),
        }
    }
    let generated = modules.len();
    insta::assert_snapshot!("corpus_excluded", excluded);
    assert!(generated > 0, "no corpus file generated code");
    let index = write_modules("corpus-compile", &modules);
    build_compile_check(&index, None, "corpus-compile");
    eprintln!("{generated} corpus files generated and compiled");
}
