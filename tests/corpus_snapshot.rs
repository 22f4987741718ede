//! Every corpus file (EDS, DCF, XDD, XDC) through the reader and the validator: no panic, and the
//! count of diagnostics by code and severity per file in one snapshot, so any change of judgement
//! shows up in review.
//! Without the corpus the test is skipped (`process_support::corpus_dir`).

mod process_support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use edsgen_model::{read, validate};
use process_support::corpus_dir;

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, out);
        } else if path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
            ["eds", "dcf", "xdd", "xdc"].contains(&e.to_ascii_lowercase().as_str())
        }) {
            out.push(path);
        }
    }
}

#[test]
fn corpus_diagnostic_counts() {
    let Some(dir) = corpus_dir() else { return };
    let mut files = Vec::new();
    collect(&dir, &mut files);
    files.sort();
    assert_eq!(files.len(), 119, "the corpus holds 119 description files");

    let mut report = String::new();
    let mut panicked = Vec::new();
    for path in &files {
        let name = path
            .strip_prefix(&dir)
            .unwrap_or(path)
            .display()
            .to_string();
        let result = std::panic::catch_unwind(|| {
            let read = read::read_file(path).map_err(|e| e.to_string())?;
            let mut diags = read.diagnostics;
            diags.extend(validate::validate(&read.device));
            Ok::<_, String>(diags)
        });
        let diags = match result {
            Ok(Ok(diags)) => diags,
            Ok(Err(err)) => {
                report.push_str(&format!("{name}: read failed: {err}\n"));
                continue;
            }
            Err(_) => {
                panicked.push(name);
                continue;
            }
        };
        let mut by_code: BTreeMap<(&str, &str), usize> = BTreeMap::new();
        for d in &diags {
            *by_code.entry((d.code(), d.severity.as_str())).or_default() += 1;
        }
        let count = |sev: &str| diags.iter().filter(|d| d.severity.as_str() == sev).count();
        report.push_str(&format!(
            "{name}: {} error(s), {} warning(s), {} info(s)\n",
            count("error"),
            count("warning"),
            count("info")
        ));
        for ((code, sev), n) in by_code {
            report.push_str(&format!("  {code} {sev} x{n}\n"));
        }
    }
    assert!(panicked.is_empty(), "panicked on: {panicked:?}");
    insta::assert_snapshot!(report);
}
