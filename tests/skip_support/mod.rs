//! The one rule for what a test needs and cannot find (a third-party corpus, the venv's python,
//! a rustup target): [`skip`], shared by the test crates of the whole workspace (the root's, the
//! codegen's, the runtime's), each including this file with `#[path]`.
//!
//! A skip passes the test, but not silently: the harness hides a passing test's standard error,
//! so each skip also appends a line (`test<TAB>reason`) to [`skip_log`] in the target directory,
//! which `scripts/test` empties at its start and lists at its end ("skipped: N checks"). Under
//! `CI=true` a skip is a failure instead: CI has everything.
// Each test crate uses only some of these helpers.
#![allow(dead_code)]

use std::fmt::Display;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Whether the tests run under CI (`CI=true`), where nothing may be skipped.
pub fn ci() -> bool {
    std::env::var("CI").as_deref() == Ok("true")
}

/// `None`, after saying why the running test skips (what) on standard error and in
/// [`skip_log`]; under `CI=true` a failure instead.
pub fn skip<T>(why: impl Display) -> Option<T> {
    assert!(!ci(), "{why}");
    let test = std::thread::current()
        .name()
        .filter(|name| *name != "main")
        .map_or_else(
            || env!("CARGO_CRATE_NAME").to_owned(),
            |name| format!("{}::{name}", env!("CARGO_CRATE_NAME")),
        );
    eprintln!("skipping {test}: {why}");
    let line = format!("{test}\t{}\n", why.to_string().replace(['\n', '\t'], " "));
    // One write of one short line to a file opened for appending: concurrent tests do not mix
    // their lines. A log that cannot be written loses only the summary, not the message above.
    if let Ok(mut log) = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(skip_log())
    {
        let _ = log.write_all(line.as_bytes());
    }
    None
}

/// The workspace root (where `Cargo.lock` is), from the including crate's manifest directory.
pub fn workspace_root() -> &'static Path {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .find(|dir| dir.join("Cargo.lock").is_file())
        .unwrap_or(manifest)
}

/// The cargo target directory this test runs from (`CARGO_TARGET_DIR`, or the workspace's
/// `target/`): the nearest ancestor of the test executable holding cargo's `CACHEDIR.TAG`.
pub fn target_dir() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|exe| {
            exe.ancestors()
                .find(|dir| dir.join("CACHEDIR.TAG").is_file())
                .map(Path::to_path_buf)
        })
        .or_else(|| std::env::var_os("CARGO_TARGET_DIR").map(PathBuf::from))
        .unwrap_or_else(|| workspace_root().join("target"))
}

/// The skip log: `skipped-tests.tsv` in the [`target_dir`], one `test<TAB>reason` line per
/// skip.
pub fn skip_log() -> PathBuf {
    target_dir().join("skipped-tests.tsv")
}

/// The third-party corpus `name` (`eds-corpus`, `gsd-corpus`, ...): the folder named by the
/// environment variable `variable`, else `../shared/NAME` beside the workspace; present where
/// its `MANIFEST.tsv` is. `None` (a [`skip`]) when absent.
pub fn corpus(variable: &str, name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os(variable)
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("../shared").join(name));
    if dir.join("MANIFEST.tsv").is_file() {
        Some(dir)
    } else {
        skip(format!("no {name} at {} (set {variable})", dir.display()))
    }
}

/// The EDS corpus (`EDSGEN_CORPUS`, else `../shared/eds-corpus`), or a [`skip`].
pub fn eds_corpus() -> Option<PathBuf> {
    corpus("EDSGEN_CORPUS", "eds-corpus")
}

/// The ESI corpus (`EDSGEN_ESI_CORPUS`, else `../shared/esi-corpus`), or a [`skip`].
pub fn esi_corpus() -> Option<PathBuf> {
    corpus("EDSGEN_ESI_CORPUS", "esi-corpus")
}
