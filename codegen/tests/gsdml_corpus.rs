//! Every file of the third-party GSDML corpus (`EDSGEN_GSDML_CORPUS`, else
//! `../shared/gsdml-corpus` beside the workspace): read without a panic as GSDML, with the text
//! encoding and modularity its `MANIFEST.tsv` records, and a snapshot of each file's identity,
//! counts and diagnostic codes (reader and validator).

mod corpus_support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use edsgen_model::model::{Format, TextEncoding};
use edsgen_model::read::read_file;
use edsgen_model::validate;

/// The corpus directory, or `None` after a visible skip (a failure under `CI=true`).
fn corpus() -> Option<PathBuf> {
    corpus_support::corpus("EDSGEN_GSDML_CORPUS", "gsdml-corpus")
}

/// (file, encoding, notes) per MANIFEST.tsv row.
fn manifest(dir: &Path) -> Vec<(String, String, String)> {
    let text = std::fs::read_to_string(dir.join("MANIFEST.tsv")).expect("MANIFEST.tsv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split('\t').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("MANIFEST.tsv has no column {name}"))
    };
    let (file, encoding, notes) = (column("file"), column("encoding"), column("notes"));
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cols: Vec<&str> = l.split('\t').collect();
            (
                cols[file].to_owned(),
                cols[encoding].to_owned(),
                cols[notes].to_owned(),
            )
        })
        .collect()
}

#[test]
fn every_gsdml_corpus_file_reads_as_its_manifest_says() {
    let Some(dir) = corpus() else { return };
    let rows = manifest(&dir);
    assert_eq!(rows.len(), 17, "the manifest lists 17 files");
    let mut summary = String::new();
    for (file, encoding, notes) in &rows {
        let read = read_file(&dir.join(file)).expect("readable");
        let device = &read.device;
        assert_eq!(device.source.format, Format::Gsdml, "{file}");
        let expected = match encoding.as_str() {
            "latin-1" => TextEncoding::Latin1,
            "utf-8-bom" => TextEncoding::Utf8Bom,
            "utf-8" if read.text.is_ascii() => TextEncoding::Ascii,
            "utf-8" => TextEncoding::Utf8,
            _ => TextEncoding::Ascii,
        };
        assert_eq!(device.source.encoding, expected, "{file}");
        let pn = device.profinet().expect("a PROFINET side");
        if notes.contains("no ModuleItem") {
            assert!(pn.modules.is_empty(), "{file}: no ModuleItem");
        }
        if let Some(n) = count_in(notes, "modules") {
            assert_eq!(pn.modules.len(), n, "{file}: modules");
        }
        if let Some(n) = count_in(notes, "DAPs") {
            assert_eq!(pn.access_points.len(), n, "{file}: access points");
        }
        let mut codes: BTreeMap<&str, usize> = BTreeMap::new();
        let mut all = read.diagnostics.clone();
        all.extend(validate::validate(device));
        for d in &all {
            *codes.entry(d.code()).or_default() += 1;
        }
        let submodules: usize = pn.modules.iter().map(|m| m.submodules.len()).sum();
        let records: usize = pn
            .modules
            .iter()
            .flat_map(|m| &m.submodules)
            .map(|s| s.records.len())
            .sum();
        summary.push_str(&format!(
            "{file}: vendor {:#06x} device {:#06x}, {} DAP(s), {} module(s), {submodules} submodule(s), {records} record(s); {:?}\n",
            pn.vendor_id.as_ref().map_or(0, |v| v.value),
            pn.device_id.as_ref().map_or(0, |v| v.value),
            pn.access_points.len(),
            pn.modules.len(),
            codes
        ));
    }
    insta::assert_snapshot!("gsdml_corpus_summary", summary);
}

/// The number before `word` in the manifest's notes (`12 modules`), if the notes give one.
fn count_in(notes: &str, word: &str) -> Option<usize> {
    let words: Vec<&str> = notes
        .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
        .collect();
    words
        .windows(2)
        .find(|w| w[1] == word)
        .and_then(|w| w[0].parse().ok())
}

/// A drive's extended channel diagnoses as the corpus's SEW file gives them: 800
/// `ExtChannelDiagItem`s under 53 of its 70 `ChannelDiagItem`s (57 under error type 4162), each
/// with one 32-bit additional value; no PN015/PN016/PN017 (the summary above pins no codes for
/// it); and the subslot labels of its first access point.
#[test]
fn the_sew_drive_s_extended_channel_diagnoses_are_read() {
    let Some(dir) = corpus() else { return };
    let file = "HeisenZergA__SEWProfinetLabview/GSDML-V2.34-SEW-MOVI-C-Decentralized-Electronics-20200731-071447.xml";
    let read = read_file(&dir.join(file)).expect("readable");
    let pn = read.device.profinet().expect("a PROFINET side");
    let diags = &pn.channel_diagnostics;
    assert_eq!(diags.len(), 70);
    assert_eq!(diags.iter().filter(|d| !d.ext.is_empty()).count(), 53);
    assert_eq!(diags.iter().map(|d| d.ext.len()).sum::<usize>(), 800);
    let most = diags.iter().max_by_key(|d| d.ext.len()).expect("some");
    assert_eq!((most.error_type, most.ext.len()), (4162, 57));
    let overcurrent = diags
        .iter()
        .find(|d| d.error_type == 4097)
        .expect("error type 4097");
    let first = &overcurrent.ext[0];
    assert_eq!(first.error_type.value, 1);
    assert_eq!(
        first.name.as_deref(),
        Some(
            "E-1.1 Short circuit in motor output terminals 'Overcurrent in output stage or faulty \
             output stage control detected, and output stage inhibited by hardware'"
        )
    );
    // Its access points label their interface and ports (`SubslotList`).
    let labels: Vec<(u16, Option<&str>)> = pn.access_points[0]
        .subslot_labels
        .iter()
        .map(|l| (l.subslot.value, l.text.as_deref()))
        .collect();
    assert_eq!(
        labels,
        [
            (32768, Some("X1")),
            (32769, Some("X1 P1")),
            (32770, Some("X1 P2"))
        ]
    );
    assert!(diags
        .iter()
        .flat_map(|d| &d.ext)
        .flat_map(|x| &x.add_values)
        .all(|v| v.id == Some(1) && v.data_type.value == "Unsigned32"));
}
