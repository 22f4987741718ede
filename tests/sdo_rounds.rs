//! 10,000 SDO transactions, python `canopen` 2.4.1 master → `edsgen simulate` (CP301 at node 3)
//! through the socketcand hub, without a failure; the same against python canopen's own
//! LocalNode in the same run, for the median round trip beside it. The figures are printed
//! (`cargo test --release --test sdo_rounds -- --nocapture`); the test asserts no failure.
//! (`examples/socketcand_bench` measures the generated CP301 node and the hub's relay rate.)

mod process_support;

use std::path::Path;
use std::time::{Duration, Instant};

use edsgen_host::hub::{Hub, HubOptions};
use process_support::{edsgen_simulate, python, Process, START_TIMEOUT};

const ROUNDS: &str = "10000";

/// `sdo_rounds.py master` against node `node_id`: (failures, median round trip in µs).
fn master(python: &Path, addr: &str, node_id: &str) -> (u64, u64) {
    let (host, port) = addr.rsplit_once(':').unwrap();
    let master = Process::python(
        python,
        "scripts/sdo_rounds.py",
        &["master", host, port, node_id, ROUNDS],
    );
    let exited = master.finish(Duration::from_secs(300));
    let out = exited.stdout;
    assert_eq!(exited.code, Some(0), "{out}\n{}", exited.stderr);
    let value = |key: &str| -> u64 {
        out.lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or_else(|| panic!("no {key} in {out}"))
    };
    (value("failures"), value("median_us"))
}

#[test]
fn ten_thousand_sdo_transactions_through_the_hub_without_a_failure() {
    let Some(python) = python() else { return };
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let addr = hub.local_addr().to_string();

    let (sim, _) = edsgen_simulate(&["eds/cp301.eds@3", "--bus", &addr], 1);
    let started = Instant::now();
    let relayed_before = hub.frames_relayed();
    let (failures, simulated_us) = master(&python, &addr, "3");
    let relayed = hub.frames_relayed() - relayed_before;
    let elapsed = started.elapsed();
    drop(sim);
    assert_eq!(failures, 0);

    let eds = process_support::root().join("eds/cp301.eds");
    let port = addr.rsplit_once(':').unwrap().1;
    let local = Process::python(
        &python,
        "scripts/sdo_rounds.py",
        &["serve", "127.0.0.1", port, "4", eds.to_str().unwrap()],
    );
    local.stdout_line(|l| l.starts_with("serving"), START_TIMEOUT);
    let (local_failures, local_us) = master(&python, &addr, "4");
    drop(local);
    eprintln!(
        "{ROUNDS} SDO uploads: edsgen simulate median {simulated_us} µs ({relayed} frames relayed in {:.1} s), python LocalNode median {local_us} µs ({local_failures} failures)",
        elapsed.as_secs_f64()
    );
}
