//! Every file of the third-party ODVA EDS corpus (`EDSGEN_ODVA_CORPUS`, else
//! `../shared/odva-eds-corpus` beside the workspace): read without a panic as an ODVA EDS, with
//! an identity and connections, no text (CIP001) problem, and a snapshot of the
//! parts read and the diagnostic codes (reader and validator) of each file.

mod corpus_support;

use std::collections::BTreeMap;
use std::path::PathBuf;

use edsgen_model::model::Format;
use edsgen_model::read::read_file;
use edsgen_model::validate;

/// The corpus directory, or `None` after a visible skip (a failure under `CI=true`).
fn corpus() -> Option<PathBuf> {
    corpus_support::corpus("EDSGEN_ODVA_CORPUS", "odva-eds-corpus")
}

#[test]
fn every_corpus_odva_file_reads() {
    let Some(dir) = corpus() else { return };
    let manifest = std::fs::read_to_string(dir.join("MANIFEST.tsv")).expect("MANIFEST.tsv");
    let files: Vec<&str> = manifest
        .lines()
        .skip(1)
        .filter_map(|l| l.split('\t').next())
        .filter(|f| !f.is_empty())
        .collect();
    assert_eq!(files.len(), 16, "MANIFEST.tsv rows");
    let mut codes: BTreeMap<&str, BTreeMap<&'static str, usize>> = BTreeMap::new();
    let mut parts: BTreeMap<&str, String> = BTreeMap::new();
    for file in &files {
        let read = read_file(&dir.join(file)).expect("readable");
        assert_eq!(read.device.source.format, Format::OdvaEds, "{file}");
        let cip = read.device.cip().expect("cip");
        assert!(cip.identity.vendor_code.is_some(), "{file}: VendCode");
        assert!(!cip.connections.is_empty(), "{file}: connections");
        parts.insert(
            file,
            format!(
                "{} params, {} assemblies, {} connections, {} ports",
                cip.params.len(),
                cip.assemblies.len(),
                cip.connections.len(),
                cip.ports.len()
            ),
        );
        let mut all = read.diagnostics.clone();
        all.extend(validate::validate(&read.device));
        assert!(
            all.iter().all(|d| d.rule.code != "CIP001"),
            "{file}: {:?}",
            all.iter().find(|d| d.rule.code == "CIP001")
        );
        let entry = codes.entry(file).or_default();
        for d in &all {
            *entry.entry(d.rule.code).or_default() += 1;
        }
    }
    let text: String = codes
        .iter()
        .map(|(file, c)| {
            let list: Vec<String> = c.iter().map(|(code, n)| format!("{code}x{n}")).collect();
            format!("{file}: {}; {}\n", parts[file], list.join(" "))
        })
        .collect();
    insta::assert_snapshot!("odva_corpus_diagnostic_codes", text);
}
