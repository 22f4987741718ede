//! Reading and validating the whole corpus, against python `canopen.import_od` on the same files.
//!
//! Criterion measures edsgen; the python baseline is timed in the same run (best of five passes,
//! after a warm-up) by `scripts/bench_canopen.py` in the project's venv, and the ratio is printed.
//! The comparison uses the files python can import; edsgen is also measured on all 119.

// The venv lookup the python-timing examples use.
#[path = "../examples/venv/mod.rs"]
mod venv;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion};
use edsgen_model::{read, validate};

fn corpus_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("EDSGEN_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/eds-corpus"));
    dir.join("python_canopen_baseline.tsv")
        .is_file()
        .then_some(dir)
}

/// (all corpus files, the ones python imports), from the baseline table.
fn corpus_files(dir: &Path) -> (Vec<PathBuf>, Vec<PathBuf>) {
    let table =
        std::fs::read_to_string(dir.join("python_canopen_baseline.tsv")).unwrap_or_default();
    let mut all = Vec::new();
    let mut python_ok = Vec::new();
    for line in table.lines().skip(1) {
        let mut cols = line.split('\t');
        let (Some(file), Some(result)) = (cols.next(), cols.next()) else {
            continue;
        };
        let path = dir.join(file);
        if result == "ok" {
            python_ok.push(path.clone());
        }
        all.push(path);
    }
    (all, python_ok)
}

fn read_and_validate(files: &[PathBuf]) -> usize {
    let mut count = 0;
    for path in files {
        if let Ok(r) = read::read_file(path) {
            count += r.diagnostics.len() + validate::validate(&r.device).len();
        }
    }
    count
}

fn python_seconds(files: &[PathBuf]) -> Option<f64> {
    let python = venv::python().inspect_err(|why| eprintln!("{why}")).ok()?;
    let out = Command::new(python)
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/bench_canopen.py"))
        .args(files)
        .output()
        .ok()?;
    String::from_utf8(out.stdout).ok()?.trim().parse().ok()
}

fn bench(c: &mut Criterion) {
    let Some(dir) = corpus_dir() else {
        eprintln!("corpus not found: set EDSGEN_CORPUS; benchmark skipped");
        return;
    };
    let (all, python_ok) = corpus_files(&dir);
    let mut group = c.benchmark_group("corpus");
    group.sample_size(20);
    group.bench_function("edsgen_read_validate_python_importable", |b| {
        b.iter(|| read_and_validate(&python_ok))
    });
    group.bench_function("edsgen_read_validate_all", |b| {
        b.iter(|| read_and_validate(&all))
    });
    group.finish();

    // Same-run ratio against python, best of five passes each.
    read_and_validate(&python_ok);
    let ours = (0..5)
        .map(|_| {
            let start = Instant::now();
            read_and_validate(&python_ok);
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min);
    match python_seconds(&python_ok) {
        Some(py) => println!(
            "corpus ({} files python imports): edsgen {:.2} ms, python canopen {:.2} ms, edsgen is {:.1}x faster",
            python_ok.len(),
            ours * 1e3,
            py * 1e3,
            py / ours
        ),
        None => println!("python baseline unavailable (run scripts/python-venv.sh); edsgen {:.2} ms", ours * 1e3),
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
