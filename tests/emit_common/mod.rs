//! Shared by the code-generation integration tests: the corpus's and the cards' files, reading
//! and generating a file, and building `tests/compile-check` against generated modules. The
//! corpus itself (or a skip) comes from `process_support`, which each test crate declares too.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

use edsgen_codegen::emit;
use edsgen_model::diag::{self, Diagnostic, Severity};
use edsgen_model::{read, validate};

use crate::process_support::{root, target_dir};

/// Every corpus file (relative name, path), in MANIFEST order (the EDS and the ESI corpus).
pub fn corpus_files(dir: &Path) -> Vec<(String, PathBuf)> {
    let manifest = std::fs::read_to_string(dir.join("MANIFEST.tsv")).unwrap();
    manifest
        .lines()
        .skip(1)
        .filter_map(|line| line.split('\t').next())
        .filter(|f| !f.is_empty())
        .map(|f| (f.to_owned(), dir.join(f)))
        .collect()
}

/// The card description files in `eds/` (EDS, DCF, ESI and GSD), sorted.
pub fn card_files() -> Vec<PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(root().join("eds"))
        .map(|dir| {
            dir.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension().is_some_and(|e| {
                        ["eds", "dcf", "xml", "gsd"]
                            .iter()
                            .any(|x| e.eq_ignore_ascii_case(x))
                    })
                })
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// Reads, validates and generates one file: the code, or the first error diagnostic (read,
/// validation or generation) that stops it.
pub fn generate(path: &Path, module: &str) -> Result<String, Diagnostic> {
    let read = with_overlay(path, read::read_file(path).unwrap());
    generate_from(read, module)
}

/// `read` with the overlay beside `path` applied, as the builder applies it (the cards'
/// `eds/rd11.toml`); an overlay error fails the test.
pub fn with_overlay(path: &Path, mut read: read::Read) -> read::Read {
    let overlay = edsgen_model::overlay::path_for(path);
    if let Ok(text) = std::fs::read_to_string(&overlay) {
        let diags = edsgen_model::overlay::apply(&text, &mut read.device);
        assert_eq!(diags, vec![], "{}", overlay.display());
    }
    read
}

pub fn generate_from(read: read::Read, module: &str) -> Result<String, Diagnostic> {
    let mut diags = read.diagnostics;
    diags.extend(validate::validate(&read.device));
    diag::sort(&mut diags);
    if let Some(first) = diags.iter().find(|d| d.severity == Severity::Error) {
        return Err(first.clone());
    }
    emit::generate_module(&read.device, module)
        .map(|g| g.code)
        .map_err(|diags| {
            diags
                .into_iter()
                .find(|d| d.severity == Severity::Error)
                .unwrap()
        })
}

/// Builds `tests/compile-check` including `generated` with `RUSTFLAGS=-D warnings`, for `target`
/// (the host when `None`), in `<target directory>/<dir>`.
pub fn build_compile_check(generated: &Path, target: Option<&str>, dir: &str) {
    build_compile_check_with(generated, target, dir, &[]);
}

/// [`build_compile_check`] with features of the compile-check crate (`private`).
pub fn build_compile_check_with(
    generated: &Path,
    target: Option<&str>,
    dir: &str,
    features: &[&str],
) {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.arg("build")
        .arg("--manifest-path")
        .arg(root().join("tests/compile-check/Cargo.toml"))
        .arg("--target-dir")
        .arg(target_dir().join(dir))
        .env("RUSTFLAGS", "-D warnings")
        .env("EDSGEN_GENERATED", generated)
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("CARGO_ENCODED_RUSTFLAGS");
    if let Some(t) = target {
        cmd.arg("--target").arg(t);
    }
    if !features.is_empty() {
        cmd.arg("--features").arg(features.join(","));
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "building generated code failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Writes generated modules and an index including them into `<target directory>/<dir>/`;
/// returns the index.
pub fn write_modules(dir: &str, modules: &[(String, String)]) -> PathBuf {
    let out = target_dir().join(dir).join("generated");
    std::fs::create_dir_all(&out).unwrap();
    let mut index = String::new();
    for (name, code) in modules {
        let file = out.join(format!("{name}.rs"));
        if std::fs::read_to_string(&file).ok().as_deref() != Some(code.as_str()) {
            std::fs::write(&file, code).unwrap();
        }
        index.push_str(&format!("include!({:?});\n", file.display().to_string()));
    }
    let index_file = out.join("all.rs");
    if std::fs::read_to_string(&index_file).ok().as_deref() != Some(index.as_str()) {
        std::fs::write(&index_file, index).unwrap();
    }
    index_file
}

/// Generates every file of the corpus at `dir` whose description the validator and generator
/// accept: the modules (name, code), and one line per file left out with the diagnostic that
/// stops it.
pub fn generate_corpus(dir: &Path) -> (Vec<(String, String)>, String) {
    let mut modules = Vec::new();
    let mut excluded = String::new();
    for (name, path) in corpus_files(dir) {
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
    (modules, excluded)
}

/// A unique module name for a corpus file.
pub fn corpus_module(name: &str) -> String {
    emit::module_name(name)
}
