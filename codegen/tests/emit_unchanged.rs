//! The generated code of the five cards (with their overlays) and of every corpus file the
//! emitter generates, pinned byte for byte: the length and a 64-bit FNV-1a digest of each
//! module in one snapshot, taken from the emitter that formatted the whole module with
//! `prettyplease`. And every module reads back unchanged through `syn` and `prettyplease`: the
//! parts written directly as text are formatted exactly as `prettyplease` formats them.
//!
//! Without the corpus only the cards are checked, against the cards' lines of the snapshot
//! (`corpus_support` records the corpus's part as skipped).

mod corpus_support;

use std::path::{Path, PathBuf};

use corpus_support::corpus_dir;
use edsgen_codegen::{builder, emit};
use edsgen_model::{overlay, read};

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The cards in `eds/`, then the corpus files in MANIFEST order: (name shown, path); and
/// whether the corpus was there.
fn inputs() -> (Vec<(String, PathBuf)>, bool) {
    let cards = ["cp301", "goodrive350", "hd1e", "ms300", "rd11"];
    let mut inputs: Vec<_> = cards
        .iter()
        .map(|c| {
            (
                format!("eds/{c}.eds"),
                repo_root().join(format!("eds/{c}.eds")),
            )
        })
        .collect();
    let corpus = corpus_dir();
    if let Some(corpus) = &corpus {
        let manifest = std::fs::read_to_string(corpus.join("MANIFEST.tsv")).unwrap();
        inputs.extend(
            manifest
                .lines()
                .skip(1)
                .filter_map(|line| line.split('\t').next())
                .filter(|f| !f.is_empty())
                .map(|f| (f.to_owned(), corpus.join(f))),
        );
    }
    (inputs, corpus.is_some())
}

/// The snapshot's lines for the cards (`eds/...`), as the snapshot file holds them.
fn card_lines_of_snapshot() -> String {
    let snapshot = Path::new(env!("CARGO_MANIFEST_DIR")).join(
        "tests/snapshots/emit_unchanged__generated_code_of_every_card_and_corpus_file_is_unchanged.snap",
    );
    let text = std::fs::read_to_string(snapshot).unwrap();
    text.lines()
        .filter(|line| line.starts_with("eds/"))
        .map(|line| format!("{line}\n"))
        .collect()
}

/// The module for `path` as build.rs generates it (overlay applied, module named after the
/// file), or `None` when the emitter refuses the file.
fn generated(path: &Path) -> Option<String> {
    let mut read = read::read_file(path).ok()?;
    if let Ok(text) = std::fs::read_to_string(overlay::path_for(path)) {
        assert_eq!(overlay::apply(&text, &mut read.device), vec![]);
    }
    let module = builder::default_module(path);
    emit::generate_module(&read.device, &module)
        .ok()
        .map(|g| g.code)
}

fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[test]
fn generated_code_of_every_card_and_corpus_file_is_unchanged() {
    let mut digests = String::new();
    let mut not_formatted = Vec::new();
    let (inputs, with_corpus) = inputs();
    for (name, path) in inputs {
        let Some(code) = generated(&path) else {
            digests.push_str(&format!("{name}: not generated\n"));
            continue;
        };
        digests.push_str(&format!(
            "{name}: {} bytes, {:016x}\n",
            code.len(),
            fnv1a64(code.as_bytes())
        ));
        // The first line is the `// @generated` comment, which `syn` does not keep.
        let (header, body) = code.split_once('\n').unwrap_or_default();
        let reformatted = syn::parse_file(body).map(|file| prettyplease::unparse(&file));
        if !header.starts_with("// @generated") || reformatted.ok().as_deref() != Some(body) {
            not_formatted.push(name);
        }
    }
    assert_eq!(
        not_formatted,
        Vec::<String>::new(),
        "not as prettyplease formats them"
    );
    if with_corpus {
        insta::assert_snapshot!(digests);
    } else {
        assert_eq!(digests, card_lines_of_snapshot());
    }
}

/// Every identifier of `tokens`, nested groups included.
fn identifiers(tokens: proc_macro2::TokenStream, out: &mut Vec<String>) {
    for token in tokens {
        match token {
            proc_macro2::TokenTree::Ident(ident) => out.push(ident.to_string()),
            proc_macro2::TokenTree::Group(group) => identifiers(group.stream(), out),
            _ => {}
        }
    }
}

#[test]
fn no_identifier_of_the_cards_is_longer_than_64_characters() {
    // The five CANopen cards and the EtherCAT card: an ARRAY's or RECORD's members live in a
    // module of their own, so no name repeats its object's.
    let cards = [
        "eds/cp301.eds",
        "eds/goodrive350.eds",
        "eds/hd1e.eds",
        "eds/ms300.eds",
        "eds/rd11.eds",
        "eds/ec-tx508.xml",
    ];
    let mut longest = (String::new(), "");
    for card in cards {
        let code = generated(&repo_root().join(card)).expect("the card generates");
        let tokens: proc_macro2::TokenStream = code.parse().expect("the code tokenizes");
        let mut names = Vec::new();
        identifiers(tokens, &mut names);
        for name in names {
            if name.len() > longest.0.len() {
                longest = (name, card);
            }
        }
    }
    println!(
        "longest identifier: {} ({} characters, {})",
        longest.0,
        longest.0.len(),
        longest.1
    );
    assert!(longest.0.len() <= 64, "{longest:?}");
    assert_eq!(
        longest,
        (
            "ACCELERATION_AND_DECELERATION_REFERENCE_FREQUENCY_01_09_P_20".to_owned(),
            "eds/cp301.eds"
        )
    );
}
