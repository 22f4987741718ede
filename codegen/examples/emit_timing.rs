//! Times code generation per file the way a build script runs it (build with the default `dev`
//! profile for build.rs figures): reading with the overlay beside the file, then
//! `emit::generate_module`, best of `--runs N` (default 5), and the planning step alone. `--out DIR` also writes each module
//! to `DIR/NAME.rs` (the file's path with `/` as `__`), to compare outputs of two versions.
//!
//! `cargo run -p edsgen-codegen --example emit_timing -- [--runs N] [--out DIR] FILE...`

use std::path::PathBuf;
use std::time::{Duration, Instant};

use edsgen_codegen::{builder, emit};

use edsgen_model::{overlay, read};

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut runs, mut out, mut files) = (5u32, None, Vec::new());
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--runs" => runs = args.next().and_then(|n| n.parse().ok()).unwrap_or(runs),
            "--out" => out = args.next().map(PathBuf::from),
            _ => files.push(PathBuf::from(arg)),
        }
    }
    for path in files {
        let Ok(mut read) = read::read_file(&path) else {
            println!("{}: unreadable", path.display());
            continue;
        };
        if let Ok(text) = std::fs::read_to_string(overlay::path_for(&path)) {
            overlay::apply(&text, &mut read.device);
        }
        let module = builder::default_module(&path);
        let mut best_plan = Duration::MAX;
        for _ in 0..runs.max(1) {
            let start = Instant::now();
            std::hint::black_box(emit::plan::plan(&read.device));
            best_plan = best_plan.min(start.elapsed());
        }
        let mut best = Duration::MAX;
        let mut code = None;
        for _ in 0..runs.max(1) {
            let start = Instant::now();
            let generated = emit::generate_module(&read.device, &module);
            best = best.min(start.elapsed());
            code = generated.ok().map(|g| g.code);
        }
        let Some(code) = code else {
            println!("{}: not generated", path.display());
            continue;
        };
        println!(
            "{:>8.1} ms (plan {:>6.1} ms)  {}",
            best.as_secs_f64() * 1e3,
            best_plan.as_secs_f64() * 1e3,
            path.display()
        );
        if let Some(dir) = &out {
            let name = path
                .to_string_lossy()
                .trim_start_matches("./")
                .replace('/', "__");
            std::fs::write(dir.join(format!("{name}.rs")), code).expect("writing the output");
        }
    }
}
