//! How far one EtherCAT segment scales (issue 31): `edsgen simulate --ethercat` serving N
//! EC-TX508s on one end of a veth pair in a private network namespace, ethercrab on the other
//! bringing them to Op and running CYCLES cycles at a 1 ms period. Per N: the cycles missed (a
//! `tx_rx` that fails, comes back with a working counter other than the first cycle's, which
//! must be 3 per SubDevice at least, or takes longer than the 1 ms period), the p50/p99/worst
//! cycle time, and the simulator's resident memory; then the memory per SubDevice (between the
//! smallest and largest N) and the longest chain of those tried with no missed cycle.
//!
//! Just before each chain, in the same namespace, the same number of cycles of a baseline with
//! neither the simulator nor ethercrab ([`echo`]: a frame echoed across the veth pair every
//! period), and for both what the machine did meanwhile ([`host`]: steal time, run-queue wait,
//! interrupts). Prints the load average first and last: on a shared machine the figures are as
//! quiet as it was. Needs root; release builds:
//!
//! ```sh
//! cargo build --release --features ethercrab --bin edsgen --example ethercat_scale
//! sudo target/release/examples/ethercat_scale [CYCLES (10000)] [N...] (1 16 64 96 128 192 256)
//! ```
//!
//! The programs run under `SCHED_FIFO` at priority 50 ([`fifo_priority`] says why;
//! `EDSGEN_SCALE_FIFO=PRIORITY` or `off`). `EDSGEN_SCALE_TXRX=tokio`, `EDSGEN_SCALE_PDU=1100`
//! and `EDSGEN_SCALE_FIFO=off` measure the MainDevice as it was set up before (ethercrab's
//! README setup), against the defaults ([`maindevice`] says why).
//!
//! The namespace, its veth pair and the simulator are removed at the end, also on failure.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod echo;
mod host;
mod maindevice;
mod wire;

use host::Host;

/// The variable carrying the chain's length (or `echo`, for the baseline) to this program run
/// in the namespace.
const ROLE: &str = "EDSGEN_SCALE_SUBDEVICES";
/// The cycle period.
const PERIOD: Duration = Duration::from_millis(1);
/// The longest chain the MainDevice takes.
const MAX_SUBDEVICES: usize = 256;
/// Each EC-TX508's images: 21 bytes of outputs, 23 of inputs.
const IMAGE: usize = 44;

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let cycles: usize = match args.next() {
        Some(n) => n
            .parse()
            .map_err(|_| format!("CYCLES: `{n}` is not a number"))?,
        None => 10_000,
    };
    match std::env::var(ROLE).as_deref() {
        Ok("echo") => return echo::baseline(cycles),
        Ok(n) => {
            let n: usize = n.parse().map_err(|_| "the chain's length".to_owned())?;
            return maindevice::run(n, cycles);
        }
        Err(_) => {}
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
    println!("{}", maindevice::describe(maindevice::setup()?));
    match fifo_priority() {
        Some(priority) => println!(
            "the simulator, the MainDevice and the baseline under SCHED_FIFO, priority {priority}"
        ),
        None => println!("the simulator, the MainDevice and the baseline under SCHED_OTHER"),
    }
    let mut memory = Vec::new();
    let mut longest = None;
    for n in sizes {
        let ns = Namespace::new()?;
        // The baseline first, in the same namespace, just before the chain: side by side.
        let before = Host::read();
        let baseline = ns.baseline(cycles)?;
        let between = Host::read();
        let figures = ns.run(&edsgen, n, cycles)?;
        let after = Host::read();
        println!("N {n:>3}: {figures}");
        println!("       host meanwhile: {}", between.since(&after));
        println!("       {baseline}");
        println!("       host meanwhile: {}", before.since(&between));
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

/// The real-time priority the programs run at: 50 unless `EDSGEN_SCALE_FIFO` gives another,
/// or `off` (the ordinary policy).
///
/// Why real time: on this shared 2-core machine, under the ordinary policy the MainDevice and
/// the simulator (each woken three times a cycle at 64 SubDevices) wait behind the other jobs'
/// processes for a CPU, and such a wait can last to the scheduler's next tick, 4 ms here
/// (HZ=250): the stalls of 4 to 8 ms are one or two ticks. The echo baseline, which hardly uses the CPU, does not wait. Measured
/// at load 9 to 11, 64 SubDevices, 3,000 cycles, three runs: 73 to 104 cycles over 1 ms (21 to
/// 25 over 4 ms), the MainDevice's threads 3.5 to 3.8 s waiting for a CPU, against 0 to 1 over
/// 1 ms and 0.2 to 0.3 s for the baseline beside it; under `SCHED_FIFO` (with async-io's thread
/// back on the ordinary policy, see `maindevice`), 3 to 5 over 1 ms and none over 4 ms, the
/// baseline 1 to 3. This is what ethercrab's examples do for their TX/RX
/// thread (`thread_priority`, `SCHED_FIFO`).
pub fn fifo_priority() -> Option<String> {
    match std::env::var("EDSGEN_SCALE_FIFO") {
        Err(_) => Some("50".to_owned()),
        Ok(off) if off == "off" => None,
        Ok(priority) => Some(priority),
    }
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

    /// `program` in the namespace, under `SCHED_FIFO` ([`fifo_priority`]; the simulator, the
    /// MainDevice and the baseline alike: `chrt` runs `ip`, which runs the program, and the
    /// policy is inherited).
    fn exec(&self, program: &std::path::Path) -> Command {
        let mut command = match fifo_priority() {
            Some(priority) => {
                let mut chrt = Command::new("chrt");
                chrt.args(["-f", &priority, "ip"]);
                chrt
            }
            None => Command::new("ip"),
        };
        command.args(["netns", "exec", &self.name]).arg(program);
        command
    }

    /// The echo baseline ([`echo::baseline`]) for `cycles` cycles: its line of figures.
    fn baseline(&self, cycles: usize) -> Result<String, String> {
        let me = std::env::current_exe().map_err(|e| e.to_string())?;
        let output = self
            .exec(&me)
            .arg(cycles.to_string())
            .env(ROLE, "echo")
            .output()
            .map_err(|e| format!("the echo baseline: {e}"))?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        match stdout.lines().last() {
            Some(line) if output.status.success() => Ok(line.to_owned()),
            _ => Err(format!(
                "the echo baseline: {}",
                String::from_utf8_lossy(&output.stderr).trim()
            )),
        }
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
        let sim_waited_before = host::waited_for_cpu(&pid.to_string(), None);
        let me = std::env::current_exe().map_err(|e| e.to_string())?;
        let output = self
            .exec(&me)
            .arg(cycles.to_string())
            .env(ROLE, n.to_string())
            .output()
            .map_err(|e| format!("the MainDevice: {e}"))?;
        let rss_kib = resident_kib(pid);
        let sim_waited =
            host::waited_for_cpu(&pid.to_string(), None).saturating_sub(sim_waited_before);
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
            line: format!("{line}, the simulator's {} ms", sim_waited.as_millis()),
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

/// The cycle's timer: absolute deadlines one [`PERIOD`] apart, slept to with `nanosleep`
/// (high-resolution, unlike tokio's millisecond wheel); a deadline already passed moves the
/// next ones (no burst of catch-up cycles).
struct Ticker {
    next: Instant,
}

impl Ticker {
    fn new() -> Self {
        Ticker {
            next: Instant::now() + PERIOD,
        }
    }

    /// Sleeps until the next deadline; returns how late it woke.
    fn tick(&mut self) -> Duration {
        let now = Instant::now();
        if now < self.next {
            std::thread::sleep(self.next - now);
        }
        let woke = Instant::now();
        let late = woke.saturating_duration_since(self.next);
        self.next = if late > PERIOD {
            woke + PERIOD
        } else {
            self.next + PERIOD
        };
        late
    }
}

/// Round-trip or cycle times, for their quantiles.
struct Times(Vec<Duration>);

impl Times {
    fn with_capacity(n: usize) -> Self {
        Times(Vec::with_capacity(n))
    }

    fn push(&mut self, time: Duration) {
        self.0.push(time);
    }

    fn total(&self) -> Duration {
        self.0.iter().sum()
    }

    /// p50/p99/worst, how many took longer than `period` and over 4 ms (the stalls), and `late`,
    /// the timer's wake-ups more than a period late.
    fn summary(&mut self, period: Duration, late: usize) -> String {
        let times = &mut self.0;
        if times.is_empty() {
            return "no cycles".to_owned();
        }
        times.sort();
        let over = times.iter().filter(|&&t| t > period).count();
        let stalls = times.iter().filter(|&&t| t > 4 * period).count();
        let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize].as_micros();
        format!(
            "p50 {} µs, p99 {} µs, worst {} µs, over 1 ms {over} (over 4 ms {stalls}), \
             timer over 1 ms late {late}",
            at(0.5),
            at(0.99),
            at(1.0)
        )
    }
}
