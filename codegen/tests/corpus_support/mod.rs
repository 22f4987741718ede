//! Shared by the codegen tests that read the third-party corpus: where it is, and the one rule
//! for its absence, as in the root crate's `tests/process_support` (which these tests cannot
//! include: it needs the `edsgen` binary, and this crate is tested on its own).

use std::path::{Path, PathBuf};

/// The corpus (`EDSGEN_CORPUS`, else `../shared/eds-corpus` beside the workspace, present
/// where its `MANIFEST.tsv` is), or `None` with a message saying the test skips it; under
/// `CI=true` a failure instead.
pub fn corpus_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("EDSGEN_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/eds-corpus"));
    if dir.join("MANIFEST.tsv").is_file() {
        return Some(dir);
    }
    let why = format!("no corpus at {} (set EDSGEN_CORPUS)", dir.display());
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{why}");
    eprintln!("skipping: {why}");
    None
}
