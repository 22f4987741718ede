//! The Goodrive350 EtherNet/IP card (`edsgen simulate --enip ADDR --card goodrive350-enip`)
//! driven by a real class-1 scanner: PyPI `ethernetip` 1.2.0 (pinned), `scripts/enip_scanner.py`.
//! Both bind UDP 2222, so they run in two private network namespaces joined by a veth pair
//! (names with this test's pid, deleted afterwards by a guard, also on failure). Needs root:
//! outside root the test says so and passes; under `CI=true` it fails instead.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::netns::{is_root, VethPair};
use process_support::{python, root, skip, Process, EDSGEN};
use serde_json::Value;

fn words(step: &Value, key: &str) -> Vec<u64> {
    step[key]
        .as_array()
        .unwrap_or_else(|| panic!("{step}: no {key}"))
        .iter()
        .map(|w| w.as_u64().expect("a word"))
        .collect()
}

#[test]
fn ethernetip_scanner_drives_the_card() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the ethernetip scanner test");
        return;
    }
    let Some(python) = python() else { return };
    let ns = VethPair::new("ee", &["10.231.0.1/24"], &["10.231.0.2/24"]);
    let adapter = Process::start(Command::new("ip").args([
        "netns",
        "exec",
        ns.devices(),
        EDSGEN,
        "simulate",
        "--enip",
        "10.231.0.1",
        "--card",
        "goodrive350-enip",
    ]));
    adapter.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
    let scanner = Process::start(
        Command::new("ip")
            .args(["netns", "exec", ns.master()])
            .arg(&python)
            .arg(root().join("scripts/enip_scanner.py"))
            .arg("10.231.0.1"),
    );
    let done = scanner.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
    let steps: Vec<Value> = done
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    let step = |name: &str| -> &Value {
        steps
            .iter()
            .find(|s| s["step"] == name)
            .unwrap_or_else(|| panic!("no step {name} in {}", done.stdout))
    };
    assert_eq!(step("forward_open")["status"], 0);
    // At rest: SW 0x4103 (stopped, ready, communication control: P00.01 = 2).
    assert_eq!(words(step("idle"), "words")[4], 0x4103);
    // PKW writes (task 4) answered with response 1 and the value.
    assert_eq!(words(step("p16_32"), "words")[..4], [1, 0x1020, 0, 1]);
    assert_eq!(words(step("p16_43"), "words")[..4], [1, 0x102B, 0, 1]);
    // P00.10, the keypad frequency: 50.00 Hz by default.
    assert_eq!(words(step("p00_10"), "words")[..4], [1, 10, 0, 5000]);
    // P07.27 is read only: response 3, error 7 (Table 5-12).
    assert_eq!(words(step("read_only"), "words")[..4], [3, 0x071B, 7, 0]);
    // Running forward (SW state 1), the transmitted PZD2 (running frequency) ramping to 25.00 Hz.
    let running = step("running");
    let (first, later) = (words(running, "first"), words(running, "later"));
    assert_eq!(later[4] & 0xFF, 1, "SW {:#06x}", later[4]);
    assert!(
        first[5] > 0 && later[5] > first[5] && later[5] <= 2500,
        "{first:?} {later:?}"
    );
    assert_eq!(step("forward_close")["status"], 0);
    assert_eq!(step("stopped_producing")["status"], 0);
    // The adapter timed the second connection out and the drive tripped with E-EIP.
    adapter.stderr_line(|l| l.contains("timed out"), Duration::from_secs(5));
    adapter.stderr_line(|l| l == "drive fault E-EIP", Duration::from_secs(5));
    drop(adapter);
    drop(ns);
}
