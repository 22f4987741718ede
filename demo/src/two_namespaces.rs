//! The scaffolding of the demo's sections on a real wire: the fall-back to this process when not
//! root, a simulator program serving in a namespace whose log is collected, this same binary
//! re-executed as a hidden client role in another namespace (a process enters a namespace only
//! by being started in it), and the JSON report that client prints, merged into the trace.

use std::io::{BufRead, BufReader, Read};
use std::net::Ipv4Addr;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::Duration;

use super::{Report, Step, Trace};
use crate::netns::{self, ChildId, End, Network};

/// How long a simulator may take to say it serves.
const START: Duration = Duration::from_secs(20);

/// What a section on the wire gives back: the simulator's log, with the problem if any.
pub(super) type Outcome = Result<Vec<String>, (String, Vec<String>)>;

/// When this process cannot make namespaces, says so on standard error (`option` names the
/// demo's flag, `who` what runs instead), runs `in_process`, and returns false.
pub(super) fn as_root(
    option: &str,
    who: &str,
    trace: &mut Trace,
    in_process: fn(&mut Trace),
) -> bool {
    if netns::is_root() {
        return true;
    }
    eprintln!(
        "{}; {who} runs in this process instead",
        netns::not_root(option)
    );
    in_process(trace);
    false
}

/// What a section's two namespaces hold for it: a veth pair's ends (namespace 0's, then
/// namespace 1's) with their addresses, the namespaces' names, and this program, to start there.
pub(super) struct Pair {
    pub(super) ends: [String; 2],
    pub(super) namespaces: [String; 2],
    pub(super) exe: PathBuf,
}

/// Two namespaces tagged `tag` joined by a veth pair with `addresses` (/24) on its ends, the
/// section `on_wire` in them, a failure of it as the step `workflow`; then, the namespaces
/// gone, the simulator's log, each line after `speaker`.
pub(super) fn between_two(
    trace: &mut Trace,
    tag: &str,
    addresses: [Ipv4Addr; 2],
    workflow: &str,
    speaker: &str,
    on_wire: impl FnOnce(&mut Trace, &mut Network, &Pair) -> Outcome,
) {
    let mut net = match Network::create(tag, 2) {
        Ok(net) => net,
        Err(problem) => {
            trace.step("two network namespaces and a veth pair", Err(problem));
            return;
        }
    };
    let outcome = match join(&mut net, addresses) {
        Ok(pair) => on_wire(trace, &mut net, &pair),
        Err(problem) => Err((problem, Vec::new())),
    };
    let said = match outcome {
        Ok(said) => said,
        Err((problem, said)) => {
            trace.step(workflow, Err(problem));
            said
        }
    };
    drop(net);
    for line in said {
        trace.line(None, format!("{speaker}: {line}"));
    }
}

/// Namespaces 0 and 1 of `net` joined by a veth pair with `addresses` on its ends.
fn join(net: &mut Network, addresses: [Ipv4Addr; 2]) -> Result<Pair, String> {
    let (a, b) = net.veth(End::Namespace(0), End::Namespace(1))?;
    net.address(0, &a, &format!("{}/24", addresses[0]))?;
    net.address(1, &b, &format!("{}/24", addresses[1]))?;
    let exe = std::env::current_exe().map_err(|e| format!("this program: {e}"))?;
    let ns = |n: usize| net.namespace(n).unwrap_or_default().to_owned();
    Ok(Pair {
        ends: [a, b],
        namespaces: [ns(0), ns(1)],
        exe,
    })
}

/// A child's standard stream, line by line, from a thread.
fn lines_of(stream: impl Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stream).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// A simulator program serving in a namespace: its log is the stream its ready line came on
/// (standard output when piped, else standard error), then its standard error if both are.
pub(super) struct Server {
    /// The program, in the [`Network`] that runs it.
    pub(super) id: ChildId,
    log: Receiver<String>,
    errors: Option<Receiver<String>>,
    said: Vec<String>,
}

impl Server {
    /// Spawns `command` (`shown` in `trace`, `who` in problems) and waits for its line that
    /// starts with `ready` (kept in its log when `keep_ready`).
    pub(super) fn start(
        trace: &mut Trace,
        net: &mut Network,
        command: &mut Command,
        shown: String,
        who: &str,
        (ready, keep_ready): (&str, bool),
    ) -> Result<Server, (String, Vec<String>)> {
        let bare = |problem: String| (problem, Vec::new());
        trace.line(None, shown);
        let id = net.spawn(command).map_err(bare)?;
        let child = net.child(id).ok_or_else(|| bare(who.to_owned()))?;
        let (log, errors) = match (child.stdout.take(), child.stderr.take()) {
            (Some(stdout), stderr) => (lines_of(stdout), stderr.map(lines_of)),
            (None, Some(stderr)) => (lines_of(stderr), None),
            (None, None) => return Err(bare(format!("{who}'s standard streams"))),
        };
        let mut server = Server {
            id,
            log,
            errors,
            said: Vec::new(),
        };
        loop {
            match server.log.recv_timeout(START) {
                Ok(line) if line.starts_with(ready) => {
                    if keep_ready {
                        server.said.push(line);
                    }
                    return Ok(server);
                }
                Ok(line) => server.said.push(line),
                Err(_) => {
                    let mut said = server.said;
                    said.extend(server.errors.iter().flat_map(Receiver::try_iter));
                    return Err((format!("{who} did not start in {START:?}"), said));
                }
            }
        }
    }

    /// Stops the program (it runs until stopped; `grace` to end on SIGTERM), with `result`, the
    /// section's own, its whole log.
    pub(super) fn stop(
        self,
        net: &mut Network,
        grace: Duration,
        result: Result<(), String>,
    ) -> Outcome {
        net.stop(self.id, grace);
        let mut said = self.said;
        said.extend(self.log.iter());
        said.extend(self.errors.iter().flat_map(Receiver::iter));
        match result {
            Ok(()) => Ok(said),
            Err(problem) => Err((problem, said)),
        }
    }
}

/// Runs `command`, this program again in a client role (`shown` in `trace`, `who` in problems),
/// for up to `steps`, its standard output and error piped, and merges the report it prints as
/// JSON into `trace`.
pub(super) fn client(
    trace: &mut Trace,
    net: &mut Network,
    command: &mut Command,
    shown: String,
    who: &str,
    steps: Duration,
) -> Result<(), String> {
    trace.line(None, shown);
    command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let id = net.spawn(command)?;
    let child = net.child(id).ok_or_else(|| who.to_owned())?;
    let (Some(stdout), Some(stderr)) = (child.stdout.take(), child.stderr.take()) else {
        return Err(format!("{who}'s standard streams"));
    };
    let (stdout, stderr) = (lines_of(stdout), lines_of(stderr));
    match net.wait(id, steps) {
        None => Err(format!("{who} did not finish in {steps:?}")),
        Some(status) if !status.success() => Err(format!(
            "{who} exited with {status}: {}",
            stderr.try_iter().collect::<Vec<_>>().join(" / ")
        )),
        Some(_) => {
            let json: Vec<String> = stdout.iter().collect();
            Report::from_json(&json.join("\n")).map(|report| trace.merge(report))
        }
    }
}

impl Report {
    /// The report as one JSON object (`lines`, and `steps` with `name` and `ok` or `err`), for
    /// a section run in another process.
    pub fn to_json(&self) -> String {
        let steps: Vec<serde_json::Value> = self
            .steps
            .iter()
            .map(|step| match &step.outcome {
                Ok(seen) => serde_json::json!({ "name": step.name, "ok": seen }),
                Err(problem) => serde_json::json!({ "name": step.name, "err": problem }),
            })
            .collect();
        serde_json::json!({ "lines": self.lines, "steps": steps }).to_string()
    }

    /// The report [`Report::to_json`] wrote.
    pub fn from_json(text: &str) -> Result<Report, String> {
        let bad = || format!("not a report: {text:?}");
        let value: serde_json::Value = serde_json::from_str(text).map_err(|_| bad())?;
        let lines = value["lines"]
            .as_array()
            .ok_or_else(bad)?
            .iter()
            .map(|line| line.as_str().map(str::to_owned).ok_or_else(bad))
            .collect::<Result<Vec<_>, _>>()?;
        let steps = value["steps"]
            .as_array()
            .ok_or_else(bad)?
            .iter()
            .map(|step| {
                let name = step["name"].as_str().ok_or_else(bad)?.to_owned();
                let outcome = match (step["ok"].as_str(), step["err"].as_str()) {
                    (Some(seen), None) => Ok(seen.to_owned()),
                    (None, Some(problem)) => Err(problem.to_owned()),
                    _ => return Err(bad()),
                };
                Ok(Step { name, outcome })
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(Report { lines, steps })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_report_goes_through_json_unchanged() {
        let report = Report {
            lines: vec!["== a".into(), "  ok    b: c \"d\"".into()],
            steps: vec![
                Step {
                    name: "b".into(),
                    outcome: Ok("c \"d\"".into()),
                },
                Step {
                    name: "e".into(),
                    outcome: Err("f".into()),
                },
            ],
        };
        let back = Report::from_json(&report.to_json()).expect("a report");
        assert_eq!((back.lines, back.steps), (report.lines, report.steps));
        assert!(Report::from_json("{\"lines\": []}").is_err());
        assert!(Report::from_json("").is_err());
    }
}
