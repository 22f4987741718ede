//! Every file of the third-party GSD corpus (`EDSGEN_GSD_CORPUS`, else `../shared/gsd-corpus`
//! beside the workspace) reads without a panic, as its `MANIFEST.tsv` says: the encoding, the
//! GSD_Revision and Modular_Station its notes record, an Ident_Number and at least one module
//! whose configuration bytes decode; the reader and validator codes are printed per file.

mod corpus_support;

use std::collections::BTreeMap;
use std::path::PathBuf;

use edsgen_model::model::{decode_cfg, Format, TextEncoding};
use edsgen_model::read::read_file;
use edsgen_model::validate;

/// The corpus directory, or `None` after a visible skip (a failure under `CI=true`).
fn corpus() -> Option<PathBuf> {
    corpus_support::corpus("EDSGEN_GSD_CORPUS", "gsd-corpus")
}

/// A note of the form `key value` (one word) among the `;`-separated notes.
fn note<'a>(notes: &'a str, key: &str) -> Option<&'a str> {
    notes
        .split(';')
        .map(str::trim)
        .filter_map(|n| n.split_once(' '))
        .find_map(|(k, v)| (k == key && !v.trim().contains(' ')).then_some(v.trim()))
}

#[test]
fn every_corpus_gsd_file_reads_as_its_manifest_says() {
    let Some(dir) = corpus() else { return };
    let text = std::fs::read_to_string(dir.join("MANIFEST.tsv")).expect("MANIFEST.tsv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split('\t').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (file, encoding, notes) = (column("file"), column("encoding"), column("notes"));
    let mut by_code: BTreeMap<&str, usize> = BTreeMap::new();
    let mut count = 0;
    for line in lines.filter(|l| !l.trim().is_empty()) {
        let cells: Vec<&str> = line.split('\t').collect();
        let path = dir.join(cells[file]);
        let read = std::panic::catch_unwind(|| read_file(&path))
            .unwrap_or_else(|_| panic!("reader panicked on {}", path.display()))
            .expect("readable");
        count += 1;
        let device = &read.device;
        assert_eq!(device.source.format, Format::Gsd, "{}", cells[file]);
        let expected = match cells[encoding] {
            "ascii" => TextEncoding::Ascii,
            "latin-1" => TextEncoding::Latin1,
            "utf-8" => TextEncoding::Utf8,
            other => panic!("unknown encoding {other}"),
        };
        assert_eq!(device.source.encoding, expected, "{}", cells[file]);
        let dp = device.dp().expect("a DP part");
        let notes = cells[notes];
        if let Some(modular) = note(notes, "modular") {
            assert_eq!(dp.modular_station, modular == "yes", "{}", cells[file]);
        }
        if let Some(revision) = note(notes, "GSD_Revision") {
            assert_eq!(dp.gsd_revision, revision.parse().ok(), "{}", cells[file]);
        }
        assert!(dp.ident_number.is_some(), "{}: Ident_Number", cells[file]);
        let mut diagnostics = read.diagnostics.clone();
        diagnostics.extend(validate::validate(device));
        let mut codes: Vec<&str> = diagnostics.iter().map(|d| d.rule.code).collect();
        codes.sort_unstable();
        codes.dedup();
        // A file without modules (one in the corpus) is told so; the others' decode.
        assert_eq!(
            dp.modules.is_empty(),
            codes.contains(&"GSD017"),
            "{}",
            cells[file]
        );
        if !dp.modules.is_empty() {
            let decoded = dp.modules.iter().filter(|m| decode_cfg(&m.config).is_ok());
            assert!(decoded.count() > 0, "{}: no module decodes", cells[file]);
        }
        for code in &codes {
            *by_code.entry(code).or_default() += 1;
        }
        eprintln!(
            "{}: {} modules, {} definitions, codes {codes:?}",
            cells[file],
            dp.modules.len(),
            dp.prm_definitions.len()
        );
        // UTF-8 where ISO 8859-1 is expected is reported.
        assert_eq!(
            codes.contains(&"GSD003"),
            expected == TextEncoding::Utf8,
            "{}",
            cells[file]
        );
    }
    assert!(count >= 30, "only {count} files in the manifest");
    eprintln!("files per code: {by_code:?}");
}
