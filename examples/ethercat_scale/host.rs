//! What the machine did around a run, from `/proc`: the time the hypervisor gave other guests
//! (steal, `/proc/stat`), the time some runnable task waited for a CPU (`/proc/pressure/cpu`;
//! this kernel has no `/proc/schedstat`) and the interrupts taken (`/proc/interrupts`), as
//! deltas over the run; and how long one process's own threads waited for a CPU
//! ([`waited_for_cpu`], from `/proc/PID/task/*/schedstat`).

/// One reading of the counters.
#[derive(Debug, Default)]
pub struct Host {
    /// `/proc/stat`'s all-CPU line: steal and the sum of every state, in clock ticks.
    steal: u64,
    total: u64,
    /// Microseconds during which some runnable task waited for a CPU.
    pressure_us: u64,
    /// When it was read.
    at: Option<std::time::Instant>,
    /// Each interrupt line's count, summed over the CPUs, with its name.
    interrupts: Vec<(String, u64)>,
}

impl Host {
    /// Reads the counters now (a counter that cannot be read stays 0).
    pub fn read() -> Self {
        let mut host = Host::default();
        if let Ok(stat) = std::fs::read_to_string("/proc/stat") {
            if let Some(cpu) = stat.lines().find(|l| l.starts_with("cpu ")) {
                // user nice system idle iowait irq softirq steal (guest time is in user).
                let ticks: Vec<u64> = cpu
                    .split_whitespace()
                    .skip(1)
                    .take(8)
                    .filter_map(|t| t.parse().ok())
                    .collect();
                host.total = ticks.iter().sum();
                host.steal = ticks.get(7).copied().unwrap_or(0);
            }
        }
        if let Ok(pressure) = std::fs::read_to_string("/proc/pressure/cpu") {
            // some avg10=.. avg60=.. avg300=.. total=MICROSECONDS
            host.pressure_us = pressure
                .lines()
                .find(|l| l.starts_with("some "))
                .and_then(|l| l.split("total=").nth(1)?.trim().parse().ok())
                .unwrap_or(0);
        }
        host.at = Some(std::time::Instant::now());
        if let Ok(interrupts) = std::fs::read_to_string("/proc/interrupts") {
            let cpus = interrupts
                .lines()
                .next()
                .map_or(0, |l| l.split_whitespace().count());
            for line in interrupts.lines().skip(1) {
                let mut fields = line.split_whitespace();
                let Some(name) = fields.next() else { continue };
                let words: Vec<&str> = fields.collect();
                let count = words
                    .iter()
                    .take(cpus)
                    .filter_map(|c| c.parse::<u64>().ok());
                let label = match words.get(cpus..) {
                    Some(rest) if !rest.is_empty() => format!("{name} {}", rest.join(" ")),
                    _ => name.to_owned(),
                };
                host.interrupts.push((label, count.sum()));
            }
        }
        host
    }

    /// What happened between `self` (before) and `after`, as one line.
    pub fn since(&self, after: &Host) -> String {
        let total = after.total.saturating_sub(self.total).max(1);
        let steal = after.steal.saturating_sub(self.steal);
        let pressure = after.pressure_us.saturating_sub(self.pressure_us) as f64 / 1e3;
        let wall = match (self.at, after.at) {
            (Some(a), Some(b)) => b.duration_since(a).as_secs_f64() * 1e3,
            _ => 0.0,
        };
        let mut interrupts: Vec<(&str, u64)> = after
            .interrupts
            .iter()
            .filter_map(|(label, count)| {
                let before = self.interrupts.iter().find(|(l, _)| l == label)?.1;
                Some((label.as_str(), count.saturating_sub(before)))
            })
            .filter(|(_, n)| *n > 0)
            .collect();
        interrupts.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
        let top: Vec<String> = interrupts
            .iter()
            .take(4)
            .map(|(label, n)| format!("{label} {n}"))
            .collect();
        format!(
            "steal {:.1} % ({steal} of {total} ticks), some task waiting for a CPU {pressure:.0} of \
             {wall:.0} ms, interrupts: {}",
            100.0 * steal as f64 / total as f64,
            top.join(", ")
        )
    }
}

/// How long the threads of process `pid` (`"self"` for this one) have waited on a run queue,
/// runnable but not running, in all (`/proc/PID/task/*/schedstat`'s second field), leaving
/// out the threads named `except`.
pub fn waited_for_cpu(pid: &str, except: Option<&str>) -> std::time::Duration {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return std::time::Duration::ZERO;
    };
    let ns: u64 = tasks
        .filter_map(|task| task.ok())
        .filter(|task| {
            let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
            except != Some(comm.trim())
        })
        .filter_map(|task| std::fs::read_to_string(task.path().join("schedstat")).ok())
        .filter_map(|stat| stat.split_whitespace().nth(1)?.parse::<u64>().ok())
        .sum();
    std::time::Duration::from_nanos(ns)
}
