//! 10,000 SDO transactions, python `canopen` 2.4.1 master → `edsgen simulate` (CP301 at node 3)
//! through the socketcand hub, without a failure; the same against python canopen's own
//! LocalNode in the same run, for the median round trip beside it. The figures are printed
//! (`cargo test --release --test sdo_rounds -- --nocapture`); the test asserts no failure.
//! (`examples/socketcand_bench` measures the generated CP301 node and the hub's relay rate.)

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use edsgen_runtime::transport::hub::{Hub, HubOptions};

const EDSGEN: &str = env!("CARGO_BIN_EXE_edsgen");
const ROUNDS: &str = "10000";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The venv's python (`scripts/python-venv.sh` makes it on first use); `None` (a skip) where
/// python is missing, except under `CI=true`.
fn python() -> Option<PathBuf> {
    static PYTHON: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    let found = PYTHON.get_or_init(|| {
        let out = Command::new(root().join("scripts/python-venv.sh"))
            .output()
            .map_err(|e| format!("cannot run scripts/python-venv.sh: {e}"))?;
        if !out.status.success() {
            return Err(String::from_utf8_lossy(&out.stderr).into_owned());
        }
        Ok(root().join(".venv/bin/python"))
    });
    match found {
        Ok(python) => Some(python.clone()),
        Err(why) => {
            assert!(std::env::var("CI").as_deref() != Ok("true"), "{why}");
            eprintln!("skipping: {why}");
            None
        }
    }
}

/// A child process killed (and reaped) when dropped.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Waits (at most 20 s) for the first line of `child`'s standard output or error starting
/// with `prefix`.
fn wait_for_line(reader: impl Read + Send + 'static, prefix: &'static str) {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(reader).lines().map_while(Result::ok) {
            if line.starts_with(prefix) {
                let _ = tx.send(());
                break;
            }
        }
    });
    rx.recv_timeout(Duration::from_secs(20))
        .unwrap_or_else(|_| panic!("no `{prefix}` line"));
}

/// `sdo_rounds.py master` against node `node_id`: (failures, median round trip in µs).
fn master(python: &Path, addr: &str, node_id: &str) -> (u64, u64) {
    let (host, port) = addr.rsplit_once(':').unwrap();
    let mut child = Killed(
        Command::new(python)
            .arg(root().join("scripts/sdo_rounds.py"))
            .args(["master", host, port, node_id, ROUNDS])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let deadline = Instant::now() + Duration::from_secs(300);
    let status = loop {
        if let Some(status) = child.0.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "the master timed out");
        std::thread::sleep(Duration::from_millis(50));
    };
    let (mut out, mut err) = (String::new(), String::new());
    child
        .0
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    child
        .0
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(status.success(), "{out}\n{err}");
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

    let mut sim = Killed(
        Command::new(EDSGEN)
            .args(["simulate", "eds/cp301.eds@3", "--bus", &addr])
            .current_dir(root())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    wait_for_line(sim.0.stderr.take().unwrap(), "simulating node 3");
    let started = Instant::now();
    let relayed_before = hub.frames_relayed();
    let (failures, simulated_us) = master(&python, &addr, "3");
    let relayed = hub.frames_relayed() - relayed_before;
    let elapsed = started.elapsed();
    drop(sim);
    assert_eq!(failures, 0);

    let mut local = Killed(
        Command::new(&python)
            .arg(root().join("scripts/sdo_rounds.py"))
            .args(["serve", "127.0.0.1", addr.rsplit_once(':').unwrap().1, "4"])
            .arg(root().join("eds/cp301.eds"))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    wait_for_line(local.0.stdout.take().unwrap(), "serving");
    let (local_failures, local_us) = master(&python, &addr, "4");
    drop(local);
    eprintln!(
        "{ROUNDS} SDO uploads: edsgen simulate median {simulated_us} µs ({relayed} frames relayed in {:.1} s), python LocalNode median {local_us} µs ({local_failures} failures)",
        elapsed.as_secs_f64()
    );
}
