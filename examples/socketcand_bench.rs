//! Measures SDO round trips of python `canopen` 2.4.1 through the socketcand hub, against the
//! generated CP301 node on the runtime's driver and, in the same run, against python canopen's
//! own `LocalNode`; then the hub's relay rate when flooded by one client. Not a test: run once,
//! in release mode, on an idle machine:
//!
//! ```text
//! cargo run --release --example socketcand_bench [TRANSACTIONS]
//! ```
//!
//! The python side is `scripts/bench_socketcand.py`, in the venv of `scripts/python-venv.sh`.

mod venv;

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::node::Node;
use edsgen_runtime::CanFrame;
use edsgen_sim::cards::cp301;

const TIMEOUT: Duration = Duration::from_secs(5);

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A python process, killed when dropped.
struct Python(Child);

impl Drop for Python {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn bench_script(python: &Path, args: &[&str]) -> Python {
    let child = Command::new(python)
        .arg(root().join("scripts/bench_socketcand.py"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("run scripts/bench_socketcand.py");
    Python(child)
}

/// The first line of the script's output that starts with `prefix`, without it.
fn line_starting(script: &mut Python, prefix: &str) -> String {
    let stdout = script.0.stdout.as_mut().unwrap();
    for line in BufReader::new(stdout).lines() {
        let line = line.unwrap();
        if let Some(rest) = line.strip_prefix(prefix) {
            return rest.to_owned();
        }
    }
    panic!("bench_socketcand.py ended before {prefix}");
}

/// Runs the python master against `node_id`; prints and returns its result line.
fn measure(python: &Path, hub: &Hub, node_id: &str, transactions: &str, label: &str) {
    let port = hub.local_addr().port().to_string();
    let eds = root().join("eds/cp301.eds");
    let relayed_before = hub.frames_relayed();
    let start = Instant::now();
    let mut master = bench_script(
        python,
        &[
            "master",
            &port,
            eds.to_str().unwrap(),
            node_id,
            transactions,
        ],
    );
    let result: serde_json::Value =
        serde_json::from_str(&line_starting(&mut master, "RESULT ")).unwrap();
    let elapsed = start.elapsed().as_secs_f64();
    let frames = hub.frames_relayed() - relayed_before;
    println!(
        "{label:<32} {:>6} transactions, {} failures, median round trip {} µs (p99 {} µs), \
         {:.2} s; hub relayed {frames} frames, {:.0} frames/s over the run",
        result["transactions"],
        result["failures"],
        result["median_us"],
        result["p99_us"],
        result["seconds"].as_f64().unwrap(),
        frames as f64 / elapsed,
    );
}

/// One client floods the hub, another reads every frame: the hub's relay rate.
fn flood(hub: &Hub, frames: u32) {
    let mut sender = SocketcandClient::connect(hub.local_addr(), "can0", TIMEOUT).unwrap();
    let mut receiver = SocketcandClient::connect(hub.local_addr(), "can0", TIMEOUT).unwrap();
    // Past the receiver's quiet period, so that the clock measures relaying only.
    std::thread::sleep(Duration::from_millis(100));
    let start = Instant::now();
    let reader = std::thread::spawn(move || {
        for n in 0..frames {
            let frame = receiver.recv_timeout(TIMEOUT).unwrap();
            assert_eq!(frame, CanFrame::new(0x181, &n.to_le_bytes()));
        }
    });
    for n in 0..frames {
        sender
            .send(&CanFrame::new(0x181, &n.to_le_bytes()).unwrap())
            .unwrap();
    }
    reader.join().unwrap();
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "{:<32} {frames} frames from one client to another in {elapsed:.2} s: {:.0} frames/s",
        "hub flooded (Rust clients)",
        f64::from(frames) / elapsed
    );
}

fn main() {
    let transactions = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "10000".to_owned());
    let python = venv::python().unwrap_or_else(|why| panic!("{why}"));
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let port = hub.local_addr().port().to_string();

    let transport = SocketcandClient::connect(hub.local_addr(), "can0", TIMEOUT).unwrap();
    let clock = MonotonicClock::new();
    let node = Node::new(cp301::Od::new(5), 5, clock.now()).unwrap();
    let device = Driver::with_clock(transport, node, clock).spawn().unwrap();
    measure(
        &python,
        &hub,
        "5",
        &transactions,
        "edsgen CP301 node (driver)",
    );

    let eds = root().join("eds/cp301.eds");
    let mut local = bench_script(&python, &["serve", &port, eds.to_str().unwrap(), "6"]);
    line_starting(&mut local, "READY");
    measure(
        &python,
        &hub,
        "6",
        &transactions,
        "python canopen LocalNode",
    );
    let _ = local.0.stdin.take().map(|mut stdin| stdin.flush());

    flood(&hub, 200_000);
    let (ended, _, _) = device.stop();
    ended.unwrap();
}
