//! Shared by the codegen tests that read the third-party corpus: where it is, and the one rule
//! for its absence (a visible skip, a failure under `CI=true`), from the workspace's
//! `tests/skip_support` (the root's `tests/process_support` needs the `edsgen` binary, and this
//! crate is tested on its own).
// Each test crate uses only some of these helpers.
#![allow(dead_code, unused_imports)]

#[path = "../../../tests/skip_support/mod.rs"]
mod skip_support;
pub use skip_support::{corpus, esi_corpus, skip};

use std::path::PathBuf;

/// The corpus (`EDSGEN_CORPUS`, else `../shared/eds-corpus` beside the workspace, present
/// where its `MANIFEST.tsv` is), or `None` after a [`skip`].
pub fn corpus_dir() -> Option<PathBuf> {
    skip_support::eds_corpus()
}
