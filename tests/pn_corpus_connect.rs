//! Every GSDML corpus file that `edsgen simulate --profinet FILE` accepts (read as GSDML without
//! errors) gives a device whose connection management accepts the Connect of its own default
//! configuration (an IO AR with the IOCRs, AlarmCR and expected submodules a controller builds
//! from it, at the first send clock and the smallest reduction ratio its MinDeviceInterval
//! allows) without a module difference, answers PrmEnd and sends ApplicationReady. A corpus
//! test: skipped with a line when the corpus is absent, a failure under `CI=true`.

mod emit_common;
mod process_support;

use edsgen_model::diag::Severity;
use edsgen_model::{read, validate};
use edsgen_runtime::Instant;
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::ar::Cm;
use edsgen_sim::profinet::controller::{connected, response, Controller};
use emit_common::corpus_files;
use process_support::gsdml_corpus_dir;

#[test]
fn every_simulable_corpus_gsdml_accepts_the_connect_of_its_default_configuration() {
    let Some(dir) = gsdml_corpus_dir() else {
        return;
    };
    let mut served = 0;
    let mut problems = Vec::new();
    for (name, path) in corpus_files(&dir) {
        let bytes = std::fs::read(&path).expect("a corpus file");
        let read = read::read_bytes(&path, &bytes);
        let errors = read
            .diagnostics
            .iter()
            .chain(&validate::validate(&read.device))
            .any(|d| d.severity == Severity::Error);
        let Some(pn) = read.device.profinet().filter(|_| !errors) else {
            continue;
        };
        let config = DeviceConfig::from_gsdml(pn);
        let scf = config.send_clocks[0];
        let Some(rr) = config
            .reduction_ratios
            .iter()
            .copied()
            .filter(|rr| u32::from(scf) * u32::from(*rr) >= config.min_device_interval)
            .min()
        else {
            problems.push(format!(
                "{name}: no reduction ratio reaches the MinDeviceInterval"
            ));
            continue;
        };
        let mac = [2, 0, 0, 0, 0, 2];
        let mut cm = Cm::new(config.clone(), mac, (1, 1, 1), "corpus");
        let mut ctl = Controller::new([2, 0, 0, 0, 0, 1], cm.object(), 1);
        let blocks = ctl.connect_blocks(&config, scf, rr, 3);
        let now = Instant::from_millis(0);
        let from = ([10, 0, 0, 1], 49152);
        let answer = cm
            .handle_datagram(now, from, &ctl.connect(&blocks))
            .and_then(|a| response(&a));
        match answer {
            Some((status, args)) if status.is_ok() => {
                if connected(&args).is_none_or(|c| c.diff.is_some()) {
                    problems.push(format!("{name}: no IOCRs, or a module difference"));
                    continue;
                }
            }
            other => {
                problems.push(format!("{name}: Connect answered {other:02x?}"));
                continue;
            }
        }
        let prm_end = cm
            .handle_datagram(now, from, &ctl.prm_end())
            .and_then(|a| response(&a));
        if !prm_end.is_some_and(|(s, _)| s.is_ok()) || cm.poll_datagram().is_none() {
            problems.push(format!("{name}: no PrmEnd or ApplicationReady"));
            continue;
        }
        served += 1;
    }
    assert_eq!(problems, Vec::<String>::new());
    // The corpus files that read as GSDML without errors (tests/gsdml_corpus_compile.rs pins
    // the others with their diagnostics).
    assert_eq!(served, 17);
}
