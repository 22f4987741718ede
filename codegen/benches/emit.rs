//! Code generation and generated code, per call: generating each bundled card and the biggest
//! corpus file, typed PDO encode/decode, OD read/write through the generated `ObjectDictionary`
//! implementation, and the typed `get`/`set`.
//!
//! Each figure has a baseline measured in the same run (the `baseline:` functions): reading and
//! validating the same file for generation, and the same work written by hand, without any
//! checks, for the PDOs and the OD accesses. The README reports the ratios.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};
use edsgen_codegen::emit;
use edsgen_model::read;
use edsgen_runtime::ObjectDictionary;

#[allow(dead_code, missing_docs)]
mod generated {
    include!("../tests/generated/gd350.rs");
}
use generated::gd350::{od as address, pdo, Od};

/// The corpus directory: `EDSGEN_CORPUS`, else `../shared/eds-corpus` beside the workspace.
fn corpus_dir() -> PathBuf {
    std::env::var_os("EDSGEN_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/eds-corpus"))
}

/// The device in `path` as build.rs reads it (with the overlay beside it), if it reads.
fn device(path: &Path) -> Option<edsgen_model::model::Device> {
    let mut read = read::read_file(path).ok()?;
    if let Ok(text) = std::fs::read_to_string(edsgen_model::overlay::path_for(path)) {
        edsgen_model::overlay::apply(&text, &mut read.device);
    }
    Some(read.device)
}

/// Generating each bundled card's module and the biggest corpus file's (Sevcon `V6.dcf`), as
/// build.rs does; the baseline is reading and validating the same file.
fn generation(c: &mut Criterion) {
    let cards = ["cp301", "goodrive350", "hd1e", "ms300", "rd11"]
        .map(|card| Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../eds/{card}.eds")));
    let v6 = corpus_dir().join("amperaufsc__Sevcon/V6.dcf");
    if !v6.is_file() {
        eprintln!("no corpus (set EDSGEN_CORPUS); skipping V6.dcf");
    }
    for path in cards.iter().chain([&v6]).filter(|p| p.is_file()) {
        let Some(device) = device(path) else {
            continue;
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let module = edsgen_codegen::builder::default_module(path);
        let entries: usize = device.objects.values().map(|o| o.subs.len()).sum();
        c.bench_function(&format!("generate {name} ({entries} entries)"), |b| {
            b.iter(|| emit::generate(black_box(&device), &module))
        });
        c.bench_function(&format!("baseline: read and validate {name}"), |b| {
            b.iter(|| {
                read::read_file(black_box(path))
                    .map(|read| edsgen_model::validate::validate(&read.device).len())
            })
        });
    }
}

fn pdos(c: &mut Criterion) {
    let rpdo = pdo::Rpdo2 {
        control_word: 1,
        setting_2: 5000,
        ..Default::default()
    };
    c.bench_function("Rpdo2 encode (4 x u16)", |b| {
        b.iter(|| black_box(&rpdo).to_bytes())
    });
    let frame = [0x01, 0x01, 0x88, 0x13, 0x7C, 0x01, 0x00, 0x00];
    c.bench_function("Tpdo2 decode (4 x u16)", |b| {
        b.iter(|| pdo::Tpdo2::from_slice(black_box(&frame)))
    });
    let words = [1u16, 0, 5000, 0];
    c.bench_function("baseline: 4 x u16 to_le_bytes by hand", |b| {
        b.iter(|| {
            let w = black_box(&words);
            let mut out = [0u8; 8];
            for (chunk, word) in out.chunks_exact_mut(2).zip(w) {
                chunk.copy_from_slice(&word.to_le_bytes());
            }
            out
        })
    });
    c.bench_function("baseline: 4 x u16 from_le_bytes by hand", |b| {
        b.iter(|| {
            let f = black_box(&frame);
            let mut words = [0u16; 4];
            for (word, chunk) in words.iter_mut().zip(f.chunks_exact(2)) {
                *word = u16::from_le_bytes([chunk[0], chunk[1]]);
            }
            words
        })
    });
    let t3 = pdo::Tpdo3 {
        nibble: 5,
        signed_24: -2,
        type_: 3,
        flag: true,
    };
    c.bench_function("Tpdo3 encode (bit-packed)", |b| {
        b.iter(|| black_box(&t3).to_bytes())
    });
}

fn od_access(c: &mut Criterion) {
    let mut od = Od::new(3);
    c.bench_function("OD write u16 6040h", |b| {
        b.iter(|| od.write(black_box(0x6040), black_box(0), black_box(&[0x0F, 0x00])))
    });
    c.bench_function("OD read u32 1018h:01", |b| {
        let mut buf = [0u8; 8];
        b.iter(|| od.read(black_box(0x1018), black_box(1), 0, &mut buf))
    });
    c.bench_function("OD write with limits 2102h", |b| {
        b.iter(|| od.write(black_box(0x2102), black_box(0), black_box(&[0x64, 0x00])))
    });
    // The application's typed access by a constant address (no search: the position is known).
    c.bench_function("typed get od::CONTROLWORD", |b| {
        b.iter(|| black_box(&od).get(address::CONTROLWORD))
    });
    c.bench_function("typed set od::CONTROLWORD", |b| {
        b.iter(|| black_box(&mut od).set(address::CONTROLWORD, black_box(0x0F)))
    });
    // The same accesses as a hand-written match, with no access, length or limit checks.
    let mut fields = HandWritten::default();
    c.bench_function("baseline: plain field load u16", |b| {
        b.iter(|| black_box(&fields).controlword)
    });
    c.bench_function("baseline: hand-written write u16", |b| {
        b.iter(|| fields.write(black_box(0x6040), black_box(0), black_box(&[0x0F, 0x00])))
    });
    c.bench_function("baseline: hand-written read u32", |b| {
        let mut buf = [0u8; 8];
        b.iter(|| fields.read(black_box(0x1018), black_box(1), &mut buf))
    });
}

/// Three entries served by a hand-written match: the floor any object dictionary pays.
#[derive(Default)]
struct HandWritten {
    controlword: u16,
    vendor_id: u32,
    setting: u16,
}

impl HandWritten {
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> bool {
        match (index, sub, data) {
            (0x6040, 0, &[a, b]) => self.controlword = u16::from_le_bytes([a, b]),
            (0x2102, 0, &[a, b]) => self.setting = u16::from_le_bytes([a, b]),
            _ => return false,
        }
        true
    }

    fn read(&self, index: u16, sub: u8, buf: &mut [u8; 8]) -> usize {
        match (index, sub) {
            (0x1018, 1) => {
                buf[..4].copy_from_slice(&self.vendor_id.to_le_bytes());
                4
            }
            (0x6040, 0) => {
                buf[..2].copy_from_slice(&self.controlword.to_le_bytes());
                2
            }
            _ => 0,
        }
    }
}

criterion_group!(benches, generation, pdos, od_access);
criterion_main!(benches);
