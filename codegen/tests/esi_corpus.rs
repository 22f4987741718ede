//! Every file of the third-party ESI corpus (`EDSGEN_ESI_CORPUS`, else `../shared/esi-corpus`
//! beside the workspace): read without a panic, with the device count, dictionary presence and
//! largest PDO that its `MANIFEST.tsv` records, and a snapshot of the diagnostic codes (reader
//! and validator) of each file's first device.

mod corpus_support;

use std::collections::BTreeMap;
use std::path::Path;

use edsgen_model::read::{esi, read_file};
use edsgen_model::{rules, validate};

/// One MANIFEST.tsv row: the columns this test compares.
struct Row {
    file: String,
    devices: usize,
    has_dictionary: bool,
    max_pdo_bits: u32,
    quirks: String,
}

fn manifest(dir: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(dir.join("MANIFEST.tsv")).expect("MANIFEST.tsv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split('\t').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("MANIFEST.tsv has no column {name}"))
    };
    let (file, devices, dictionary, bits, quirks) = (
        column("file"),
        column("devices"),
        column("has_dictionary"),
        column("max_pdo_bits"),
        column("quirks"),
    );
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|line| {
            let cells: Vec<&str> = line.split('\t').collect();
            Row {
                file: cells[file].to_owned(),
                devices: cells[devices].parse().expect("devices"),
                has_dictionary: cells[dictionary] == "yes",
                max_pdo_bits: cells[bits].parse().expect("max_pdo_bits"),
                quirks: cells[quirks].to_owned(),
            }
        })
        .collect()
}

#[test]
fn every_corpus_esi_file_reads_as_its_manifest_says() {
    let Some(dir) = corpus_support::esi_corpus() else {
        return;
    };
    let rows = manifest(&dir);
    assert_eq!(rows.len(), 30, "MANIFEST.tsv rows");
    let mut codes: BTreeMap<String, BTreeMap<&'static str, usize>> = BTreeMap::new();
    for row in &rows {
        let path = dir.join(&row.file);
        let bytes = std::fs::read(&path).expect("corpus file");
        let first = read_file(&path).expect("corpus file");
        let mut found = first.diagnostics.clone();
        found.extend(validate::validate(&first.device));
        let counts = codes.entry(row.file.clone()).or_default();
        for d in &found {
            *counts.entry(d.rule.code).or_insert(0) += 1;
        }
        if first
            .diagnostics
            .iter()
            .any(|d| std::ptr::eq(d.rule, &rules::XML_MALFORMED))
        {
            assert!(
                row.quirks.contains("MALFORMED"),
                "{}: not well-formed",
                row.file
            );
            continue;
        }
        let all = esi::read_all(&path, &bytes);
        assert_eq!(all.len(), row.devices, "{}: devices", row.file);
        // The manifest counts the dictionaries and PDOs of the file's modules too.
        let with_objects = all.iter().any(|(d, _)| {
            !d.objects.is_empty()
                || d.ethercat()
                    .into_iter()
                    .flat_map(|ec| &ec.modules)
                    .any(|m| !m.objects.is_empty())
        });
        // A file of modules without a device (EDS801) is not read.
        let unread = row.devices == 0 && row.quirks.contains("Modules");
        assert!(
            with_objects == row.has_dictionary || unread,
            "{}: has_dictionary",
            row.file
        );
        let max_bits = all
            .iter()
            .filter_map(|(d, _)| d.ethercat())
            .flat_map(|ec| {
                let modules = ec
                    .modules
                    .iter()
                    .flat_map(|m| m.rx_pdos.iter().chain(&m.tx_pdos));
                ec.rx_pdos.iter().chain(&ec.tx_pdos).chain(modules)
            })
            .map(|p| p.entries.iter().map(|e| u32::from(e.bit_len)).sum::<u32>())
            .max()
            .unwrap_or(0);
        if !unread {
            assert_eq!(max_bits, row.max_pdo_bits, "{}: max PDO bits", row.file);
        }
        for (device, _) in &all {
            let ec = device.ethercat().expect("an ESI device");
            for object in device.objects.values() {
                assert!(object.span.line > 0, "{}: {:04X}h", row.file, object.index);
            }
            assert!(ec.span.line > 0, "{}", row.file);
        }
    }
    insta::assert_debug_snapshot!("esi_corpus_diagnostic_codes", codes);
}
