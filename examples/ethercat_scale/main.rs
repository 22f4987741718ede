//! How far one EtherCAT segment scales (issue 31): `edsgen simulate --ethercat` serving N
//! EC-TX508s on one end of a veth pair in a private network namespace, ethercrab on the other
//! bringing them to Op and running CYCLES cycles at a 1 ms period. Per N: the cycles missed (a
//! `tx_rx` that fails, comes back with a working counter other than the first cycle's, which
//! must be 3 per SubDevice at least, or takes longer than the 1 ms period), the p50/p99/worst cycle time, and the simulator's resident
//! memory; then the memory per SubDevice (between the smallest and largest N) and the longest
//! chain of those tried with no missed cycle. Prints the load average first and last: on a
//! shared machine the figures are as quiet as it was. Needs root; release builds:
//!
//! ```sh
//! cargo build --release --features ethercrab --bin edsgen --example ethercat_scale
//! sudo target/release/examples/ethercat_scale [CYCLES (10000)] [N...] (1 16 64 96 128 192 256)
//! ```
//!
//! The namespace, its veth pair and the simulator are removed at the end, also on failure.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

/// The variable carrying the chain's length to this program run as the MainDevice.
const ROLE: &str = "EDSGEN_SCALE_SUBDEVICES";
/// The cycle period.
const PERIOD: Duration = Duration::from_millis(1);
/// The longest chain the MainDevice takes.
const MAX_SUBDEVICES: usize = 256;
/// Each EC-TX508's images: 21 bytes of outputs, 23 of inputs.
const IMAGE: usize = 44;

const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
static PDU_STORAGE: PduStorage<32, MAX_PDU_DATA> = PduStorage::new();

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let cycles: usize = match args.next() {
        Some(n) => n
            .parse()
            .map_err(|_| format!("CYCLES: `{n}` is not a number"))?,
        None => 10_000,
    };
    if let Ok(n) = std::env::var(ROLE) {
        let n: usize = n.parse().map_err(|_| "the chain's length".to_owned())?;
        return maindevice(n, cycles);
    }
    let mut sizes: Vec<usize> = args
        .map(|n| n.parse().map_err(|_| format!("N: `{n}` is not a number")))
        .collect::<Result<_, _>>()?;
    if sizes.is_empty() {
        sizes = vec![1, 16, 64, 96, 128, 192, 256];
    }
    if let Some(n) = sizes.iter().find(|&&n| n == 0 || n > MAX_SUBDEVICES) {
        return Err(format!("N: {n} is not 1 to {MAX_SUBDEVICES}"));
    }
    let edsgen = std::env::current_exe()
        .ok()
        .and_then(|me| Some(me.parent()?.parent()?.join("edsgen")))
        .filter(|p| p.is_file())
        .ok_or("no edsgen next to this example: cargo build --release --bin edsgen")?;
    println!("load average before: {}", load_average());
    println!("{cycles} cycles at a 1 ms period per chain of N EC-TX508s");
    let mut memory = Vec::new();
    let mut longest = None;
    for n in sizes {
        let ns = Namespace::new()?;
        let figures = ns.run(&edsgen, n, cycles)?;
        println!("N {n:>3}: {figures}");
        if let Some(rss) = figures.rss_kib {
            memory.push((n, rss));
        }
        if figures.missed == 0 {
            longest = Some(n);
        }
    }
    if let (Some(&(n0, m0)), Some(&(n1, m1))) = (memory.first(), memory.last()) {
        if n1 > n0 {
            let per = (m1 as f64 - m0 as f64) / (n1 - n0) as f64;
            println!(
                "resident memory per SubDevice: {per:.0} KiB (N {n0}: {m0} KiB, N {n1}: {m1} KiB)"
            );
        }
    }
    match longest {
        Some(n) => println!("longest chain with no missed cycle: {n}"),
        None => println!("longest chain with no missed cycle: none of those tried"),
    }
    println!("load average after: {}", load_average());
    Ok(())
}

/// `/proc/loadavg`'s three averages.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split(' ').take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".to_owned())
}

/// What one chain did.
#[derive(Debug)]
struct Figures {
    missed: usize,
    line: String,
    rss_kib: Option<u64>,
}

impl std::fmt::Display for Figures {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.line)?;
        match self.rss_kib {
            Some(rss) => write!(f, ", simulator resident {rss} KiB"),
            None => Ok(()),
        }
    }
}

/// A private network namespace with a veth pair `ecm` (MainDevice) / `ecs` (SubDevices),
/// deleted when dropped.
struct Namespace {
    name: String,
}

impl Namespace {
    fn new() -> Result<Self, String> {
        let ns = Namespace {
            name: format!("edsgen-scale-{}", std::process::id()),
        };
        ip(&["netns", "add", &ns.name])?;
        for args in [
            &["link", "add", "ecm", "type", "veth", "peer", "name", "ecs"][..],
            &["link", "set", "ecm", "up"],
            &["link", "set", "ecs", "up"],
        ] {
            ip(&[&["-n", &ns.name][..], args].concat())?;
        }
        Ok(ns)
    }

    fn exec(&self, program: &std::path::Path) -> Command {
        let mut command = Command::new("ip");
        command.args(["netns", "exec", &self.name]).arg(program);
        command
    }

    /// A chain of `n` EC-TX508s served and driven for `cycles` cycles.
    fn run(&self, edsgen: &std::path::Path, n: usize, cycles: usize) -> Result<Figures, String> {
        let mut command = self.exec(edsgen);
        command.args(["simulate", "--ethercat", "ecs"]);
        for _ in 0..n {
            command.args(["--card", "ec-tx508"]);
        }
        let mut sim = Killed(
            command
                .stderr(Stdio::piped())
                .spawn()
                .map_err(|e| format!("edsgen: {e}"))?,
        );
        let lines = sim
            .0
            .stderr
            .take()
            .ok_or("the simulator's standard error")?;
        let mut lines = BufReader::new(lines).lines();
        loop {
            match lines.next() {
                Some(Ok(line)) if line.starts_with("serving ") => break,
                Some(Ok(_)) => {}
                _ => return Err(format!("N {n}: the simulator did not start")),
            }
        }
        // Its later lines (the stop) still have a reader.
        std::thread::spawn(move || lines.for_each(drop));
        // `ip netns exec` runs the program in its own place: the child is the simulator.
        let pid = sim.0.id();
        let me = std::env::current_exe().map_err(|e| e.to_string())?;
        let output = self
            .exec(&me)
            .arg(cycles.to_string())
            .env(ROLE, n.to_string())
            .output()
            .map_err(|e| format!("the MainDevice: {e}"))?;
        let rss_kib = resident_kib(pid);
        let stdout = String::from_utf8_lossy(&output.stdout);
        let line = stdout.lines().last().unwrap_or_default().to_owned();
        if !output.status.success() {
            return Ok(Figures {
                missed: cycles,
                line: format!(
                    "not in Op: {}",
                    String::from_utf8_lossy(&output.stderr).trim()
                ),
                rss_kib,
            });
        }
        let missed = line
            .split_once("missed ")
            .and_then(|(_, m)| m.split(',').next()?.parse().ok())
            .ok_or_else(|| format!("N {n}: the MainDevice said `{line}`"))?;
        Ok(Figures {
            missed,
            line,
            rss_kib,
        })
    }
}

impl Drop for Namespace {
    fn drop(&mut self) {
        let _ = ip(&["netns", "del", &self.name]);
    }
}

/// A child killed and waited for when dropped.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .args(["-TERM", &self.0.id().to_string()])
            .status();
        let _ = self.0.wait();
    }
}

fn ip(args: &[&str]) -> Result<(), String> {
    let status = Command::new("ip")
        .args(args)
        .status()
        .map_err(|e| format!("ip: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("ip {args:?} failed (root?)"))
    }
}

/// A process's resident memory (VmRSS), in KiB.
fn resident_kib(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The MainDevice, in the namespace: `n` SubDevices to Op, then `cycles` cycles at [`PERIOD`],
/// one line of figures.
fn maindevice(n: usize, cycles: usize) -> Result<(), String> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| e.to_string())?;
    runtime.block_on(async {
        let (tx, rx, pdu_loop) = PDU_STORAGE
            .try_split()
            .map_err(|_| "the PDU storage is split once")?;
        let timeouts = Timeouts {
            pdu: Duration::from_millis(500),
            state_transition: Duration::from_secs(30),
            mailbox_response: Duration::from_secs(2),
            eeprom: Duration::from_secs(2),
            ..Timeouts::default()
        };
        let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
        tokio::spawn(tx_rx_task("ecm", tx, rx).map_err(|e| format!("ecm: {e}"))?);
        let group = maindevice
            .init_single_group::<MAX_SUBDEVICES, { MAX_SUBDEVICES * IMAGE }>(ethercat_now)
            .await
            .map_err(|e| format!("discovery: {e:?}"))?;
        if group.len() != n {
            return Err(format!("{} SubDevices found, {n} served", group.len()));
        }
        let group = group
            .into_op(&maindevice)
            .await
            .map_err(|e| format!("Op: {e:?}"))?;
        // Every SubDevice counts 3 on each LRW that reaches its images: once, or twice when
        // ethercrab's chunks of the image (a frame's worth each) split its images.
        let expected = group
            .tx_rx(&maindevice)
            .await
            .map_err(|e| format!("the first cycle: {e:?}"))?
            .working_counter;
        if usize::from(expected) < 3 * n {
            return Err(format!("working counter {expected} of {n} SubDevices"));
        }
        let mut interval = tokio::time::interval(PERIOD);
        interval.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        let mut times = Vec::with_capacity(cycles);
        let mut missed = 0;
        for _ in 0..cycles {
            interval.tick().await;
            let start = Instant::now();
            let answer = group.tx_rx(&maindevice).await;
            let took = start.elapsed();
            let counted = answer.is_ok_and(|a| a.working_counter == expected);
            if !counted || took > PERIOD {
                missed += 1;
            }
            times.push(took);
        }
        times.sort();
        let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize];
        println!(
            "missed {missed}, cycle time p50 {} µs, p99 {} µs, worst {} µs",
            at(0.5).as_micros(),
            at(0.99).as_micros(),
            at(1.0).as_micros()
        );
        Ok(())
    })
}
