//! `edsgen demo`, the README's main job: every step passes, the trace shows the manuals' frames
//! decoded by name, and the command's exit code and summary say so; with `--bus`, the same
//! workflows against `edsgen simulate --card` through a hub, in real time.

mod process_support;

use std::process::Command;

use edsgen_runtime::transport::hub::{Hub, HubOptions};
use process_support::edsgen_simulate;

#[test]
fn every_step_of_the_demo_behaves_as_the_manuals_say() {
    let report = edsgen::demo::run();
    let failed: Vec<_> = report.steps.iter().filter(|s| s.outcome.is_err()).collect();
    assert_eq!(failed, Vec::<&edsgen::demo::Step>::new());
    assert_eq!(report.steps.len(), 26);
    // The Goodrive350 manual's PDO2 Tx (§3.5.4), 283: 01 01 88 13 7C 01 00 00, decoded.
    let pdo2 = "7.100000  283  TPDO2      node 3 Status word = 257 (0x0101), Monitoring data: \
                Returned value 1 = 5000 (0x1388), Monitoring data: Returned value 2 = 380 \
                (0x017C), Monitoring data: Returned value 3 = 0";
    assert!(report.lines.iter().any(|l| l.trim() == pdo2), "{pdo2}");
    // The CP301's speed read back while ramping (§5.3).
    let ramping = "0.500000  582  SDO        node 2 read 6044:00 vl velocity actual value = 750";
    assert!(
        report.lines.iter().any(|l| l.trim() == ramping),
        "{ramping}"
    );
}

#[test]
fn the_demo_command_exits_0_with_its_summary() {
    let output = Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .arg("demo")
        .output()
        .expect("edsgen runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.ends_with("\n26 step(s): 26 as the manuals say, 0 not\n"),
        "{stdout}"
    );
}

#[test]
fn the_demo_drives_simulated_cards_on_a_bus() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).expect("a hub on loopback");
    let addr = hub.local_addr().to_string();
    let _simulate = edsgen_simulate(
        &["--card", "cp301@2", "--card", "goodrive350", "--bus", &addr],
        2,
    );
    let output = Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .args(["demo", "--bus", &addr])
        .output()
        .expect("edsgen demo runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    // The fault cannot be injected into a drive in another process: that step says so.
    assert!(
        stdout.contains(
            "ok    fault OUT1 injected, and its reset: not run: the drive is not in this process"
        ),
        "{stdout}"
    );
    assert!(
        stdout.ends_with("\n25 step(s): 25 as the manuals say, 0 not\n"),
        "{stdout}"
    );
}
