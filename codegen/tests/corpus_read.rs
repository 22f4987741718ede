//! Every EDS and DCF of the vendor corpus reads without panicking, and every file yields objects;
//! prints a per-file and per-rule summary.
//! Without the corpus the test is skipped (`corpus_support`).

mod corpus_support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use corpus_support::corpus_dir;
use edsgen_model::diag::Severity;
use edsgen_model::model::Format;
use edsgen_model::read;

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, out);
        } else if path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("eds") || e.eq_ignore_ascii_case("dcf"))
        {
            out.push(path);
        }
    }
}

#[test]
fn every_corpus_eds_and_dcf_reads() {
    let Some(dir) = corpus_dir() else { return };
    let mut files = Vec::new();
    collect(&dir, &mut files);
    files.sort();
    assert!(
        !files.is_empty(),
        "no EDS/DCF files under {}",
        dir.display()
    );
    let mut by_rule: BTreeMap<(&str, &str), usize> = BTreeMap::new();
    let (mut objects, mut entries, mut implicit) = (0usize, 0usize, 0usize);
    for path in &files {
        let bytes = std::fs::read(path).unwrap();
        let result = std::panic::catch_unwind(|| read::read_bytes(path, &bytes));
        let read = result.unwrap_or_else(|_| panic!("reader panicked on {}", path.display()));
        let is_dcf = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("dcf"));
        assert_eq!(
            read.device.source.format,
            if is_dcf { Format::Dcf } else { Format::Eds },
            "{}",
            path.display()
        );
        assert!(
            !read.device.objects.is_empty(),
            "no objects read from {}",
            path.display()
        );
        for object in read.device.objects.values() {
            objects += 1;
            entries += object.subs.len();
            implicit += object.subs.values().filter(|s| s.implicit).count();
            if !object.object_type.has_subs() {
                assert_eq!(
                    object.subs.keys().copied().collect::<Vec<_>>(),
                    vec![0],
                    "{:04X} in {}",
                    object.index,
                    path.display()
                );
            }
        }
        // Every diagnostic with a span points into the file.
        let line_count = read.text.lines().count().max(1) as u32;
        for d in &read.diagnostics {
            if let Some(span) = d.span {
                assert!(
                    span.line >= 1 && span.line <= line_count,
                    "{} line {} of {} in {}",
                    d.code(),
                    span.line,
                    line_count,
                    path.display()
                );
            }
            *by_rule.entry((d.code(), d.severity.as_str())).or_default() += 1;
        }
        let errors = read
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .count();
        println!(
            "{:>5} objects {:>4} reader errors  {}",
            read.device.objects.len(),
            errors,
            path.strip_prefix(&dir).unwrap_or(path).display()
        );
    }
    println!(
        "{} files, {objects} objects, {entries} entries ({implicit} implicit)",
        files.len()
    );
    for ((code, severity), count) in &by_rule {
        println!("{code} {severity:<7} {count}");
    }
}
