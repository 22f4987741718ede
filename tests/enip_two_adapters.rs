//! Two EtherNet/IP adapters in one process (`edsgen simulate --enip A,B --card
//! goodrive350-enip`, issue 31) driven at once by a real class-1 scanner: PyPI `ethernetip`
//! 1.2.0 (pinned), `scripts/enip_two_adapters.py`, one UDP 2222 socket for both connections.
//! The adapters have two addresses of one namespace, the scanner another namespace across a
//! veth pair (names with this test's pid, deleted by a guard, also on failure). Needs root:
//! outside root the test says so and passes; under `CI=true` it fails instead.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::netns::{is_root, VethPair};
use process_support::{python, root, skip, Process, EDSGEN};
use serde_json::Value;

fn bytes(line: &Value, key: &str) -> Vec<u64> {
    line[key]
        .as_array()
        .unwrap_or_else(|| panic!("{line}: no {key}"))
        .iter()
        .map(|b| b.as_u64().expect("a byte"))
        .collect()
}

/// 32 bytes: `words` little-endian, then zeros.
fn image(words: &[u16]) -> Vec<u64> {
    let mut out = vec![0u64; 32];
    for (n, w) in words.iter().enumerate() {
        out[2 * n] = u64::from(w & 0xFF);
        out[2 * n + 1] = u64::from(w >> 8);
    }
    out
}

#[test]
fn ethernetip_opens_class_1_connections_to_two_adapters() {
    if !is_root() {
        skip::<()>("not root: no network namespaces for the two-adapter ethernetip test");
        return;
    }
    let Some(python) = python() else { return };
    let ns = VethPair::new(
        "e2",
        &["10.232.0.1/24", "10.232.0.3/24"],
        &["10.232.0.2/24"],
    );
    let (a, b) = ("10.232.0.1", "10.232.0.3");
    let adapters = Process::start(Command::new("ip").args([
        "netns",
        "exec",
        ns.devices(),
        EDSGEN,
        "simulate",
        "--enip",
        &format!("{a},{b}"),
        "--card",
        "goodrive350-enip",
    ]));
    for _ in 0..2 {
        adapters.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
    }
    let scanner = Process::start(
        Command::new("ip")
            .args(["netns", "exec", ns.master()])
            .arg(&python)
            .arg(root().join("scripts/enip_two_adapters.py"))
            .args([a, b]),
    );
    let done = scanner.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
    let lines: Vec<Value> = done
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    let opened: Vec<(&str, &Value)> = lines
        .iter()
        .filter(|l| l.get("forward_open").is_some())
        .map(|l| {
            (
                l["address"].as_str().expect("an address"),
                &l["forward_open"],
            )
        })
        .collect();
    assert_eq!(opened, [(a, &Value::from(0)), (b, &Value::from(0))]);
    let last = |address: &str| -> &Value {
        lines
            .iter()
            .find(|l| l["address"] == address && l.get("input").is_some())
            .unwrap_or_else(|| panic!("no exchange with {address} in {}", done.stdout))
    };
    // Each adapter got its own outputs: PKW task 1 (read) of P00.10 to A, of P00.11 to B.
    // Each answered its own: response 1, the parameter, and its value (P00.10 50.00 Hz, P00.11
    // 10.0 s), with SW 0x4103 (stopped, ready) in PZD1.
    for (address, parameter, value) in [(a, 0x000A, 5000), (b, 0x000B, 100)] {
        let line = last(address);
        assert_eq!(bytes(line, "output"), image(&[1, parameter]), "{address}");
        assert_eq!(
            bytes(line, "input"),
            image(&[1, parameter, 0, value, 0x4103]),
            "{address}"
        );
        assert_eq!(line["forward_close"], 0, "{address}");
    }
}
