//! `edsgen demo --enip`: the EtherNet/IP card's steps ([`super::enip::workflow`]) over real TCP
//! 44818 and UDP 2222. As root, two private network namespaces joined by a veth pair: `edsgen
//! simulate --enip 192.168.250.1 --card goodrive350-enip` in one; in the other this same
//! binary again as the demo's scanner (`edsgen demo --enip-scanner ADDR`, [`scan`]: a process
//! enters a namespace only by being started in it), which prints its report as JSON for this
//! process to take into its trace, with the adapter's own log lines. Namespaces, pair and
//! programs go when the section ends (or on Ctrl-C, [`crate::netns`]). Not root: said on
//! standard error, and run in this process.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpStream, UdpSocket};
use std::process::Stdio;
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

use edsgen_sim::enip::driver::IO_PORT;
use edsgen_sim::enip::wire::{item, parse_items};

use super::enip::{workflow, Scanner, Stopped, RPI_US};
use super::{Report, Step, Trace};
use crate::netns::{self, End, Network};

/// The adapter's address (namespace 0) and the scanner's (namespace 1), on a /24.
const ADAPTER: Ipv4Addr = Ipv4Addr::new(192, 168, 250, 1);
const SCANNER: Ipv4Addr = Ipv4Addr::new(192, 168, 250, 2);
/// How long the adapter may take to say it serves, and the scanner to finish its steps.
const START: Duration = Duration::from_secs(20);
const STEPS: Duration = Duration::from_secs(60);
/// How long a TCP exchange with the adapter may take.
const TCP_TIMEOUT: Duration = Duration::from_secs(5);

fn rpi() -> Duration {
    Duration::from_micros(RPI_US)
}

/// Runs the card's section between two namespaces where this process can, else in process.
pub(super) fn run(trace: &mut Trace) {
    if !netns::is_root() {
        eprintln!(
            "{}; the EtherNet/IP card runs in this process instead",
            netns::not_root("demo --enip")
        );
        super::enip::run(trace);
        return;
    }
    trace.heading(
        "Goodrive350 EtherNet/IP card: a class-1 scanner from the generated images, over TCP \
         44818 and UDP 2222 between two network namespaces",
    );
    let mut net = match Network::create("enip", 2) {
        Ok(net) => net,
        Err(problem) => {
            trace.step("two network namespaces and a veth pair", Err(problem));
            return;
        }
    };
    let said = match on_wire(trace, &mut net) {
        Ok(said) => said,
        Err((problem, said)) => {
            trace.step("Goodrive350 EtherNet/IP workflow", Err(problem));
            said
        }
    };
    drop(net);
    for line in said {
        trace.line(None, format!("adapter: {line}"));
    }
}

/// A child's standard stream, line by line, from a thread.
pub(super) fn lines_of(stream: impl Read + Send + 'static) -> Receiver<String> {
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

/// The adapter and the scanner in their namespaces, the scanner's report taken into `trace`;
/// the adapter's log once it is stopped (with the problem, if any).
fn on_wire(trace: &mut Trace, net: &mut Network) -> Result<Vec<String>, (String, Vec<String>)> {
    let bare = |problem: String| (problem, Vec::new());
    let (adapter_end, scanner_end) = net
        .veth(End::Namespace(0), End::Namespace(1))
        .map_err(bare)?;
    net.address(0, &adapter_end, &format!("{ADAPTER}/24"))
        .map_err(bare)?;
    net.address(1, &scanner_end, &format!("{SCANNER}/24"))
        .map_err(bare)?;
    let exe = std::env::current_exe().map_err(|e| bare(format!("this program: {e}")))?;
    let ns = |n: usize| net.namespace(n).unwrap_or_default().to_owned();
    let (adapter_ns, scanner_ns) = (ns(0), ns(1));

    let mut command = net.command(0, &exe).map_err(bare)?;
    command
        .args(["simulate", "--enip", &ADAPTER.to_string()])
        .args(["--card", "goodrive350-enip"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    trace.line(
        None,
        format!(
            "ip netns exec {adapter_ns} edsgen simulate --enip {ADAPTER} --card goodrive350-enip"
        ),
    );
    let adapter = net.spawn(&mut command).map_err(bare)?;
    let stderr = net
        .child(adapter)
        .and_then(|c| c.stderr.take())
        .ok_or_else(|| bare("the adapter's standard error".into()))?;
    let log = lines_of(stderr);
    let mut said = Vec::new();
    loop {
        match log.recv_timeout(START) {
            Ok(line) if line.starts_with("serving ") => break,
            Ok(line) => said.push(line),
            Err(_) => return Err((format!("the adapter did not start in {START:?}"), said)),
        }
    }

    let mut command = net.command(1, &exe).map_err(bare)?;
    command
        .args(["demo", "--enip-scanner", &ADAPTER.to_string()])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    trace.line(
        None,
        format!(
            "ip netns exec {scanner_ns} edsgen demo --enip-scanner {ADAPTER} (the scanner, at \
             {SCANNER})"
        ),
    );
    let scanner = net.spawn(&mut command).map_err(bare)?;
    let child = net
        .child(scanner)
        .ok_or_else(|| bare("the scanner".into()))?;
    let (Some(stdout), Some(stderr)) = (child.stdout.take(), child.stderr.take()) else {
        return Err(bare("the scanner's standard streams".into()));
    };
    let (stdout, stderr) = (lines_of(stdout), lines_of(stderr));
    let finished = net.wait(scanner, STEPS);
    let result = match finished {
        None => Err(format!("the scanner did not finish in {STEPS:?}")),
        Some(status) if !status.success() => Err(format!(
            "the scanner exited with {status}: {}",
            stderr.try_iter().collect::<Vec<_>>().join(" / ")
        )),
        Some(_) => {
            let json: Vec<String> = stdout.iter().collect();
            Report::from_json(&json.join("\n")).map(|report| trace.merge(report))
        }
    };
    // The adapter runs until stopped.
    net.stop(adapter, Duration::from_secs(2));
    said.extend(log.iter());
    match result {
        Ok(()) => Ok(said),
        Err(problem) => Err((problem, said)),
    }
}

/// `edsgen demo --enip-scanner ADDR`, run inside the scanner's namespace by `--enip`: the card's
/// steps against the adapter at `addr` (TCP 44818, UDP 2222), the report to print as JSON.
pub fn scan(addr: Ipv4Addr) -> Report {
    let mut trace = Trace::new(Report::default());
    match Wire::connect(addr) {
        Ok(mut wire) => {
            if let Err(problem) = workflow(&mut trace, &mut wire) {
                trace.step("Goodrive350 EtherNet/IP workflow", Err(problem));
            }
        }
        Err(problem) => trace.step("connect to the adapter", Err(problem)),
    }
    trace.finish()
}

/// The scanner's sockets: TCP 44818 to the adapter, UDP 2222 both ways.
struct Wire {
    tcp: TcpStream,
    udp: UdpSocket,
    adapter: SocketAddr,
    /// The last T→O image, and when it came.
    last: Option<(Vec<u8>, Instant)>,
    /// When the last O→T datagram went.
    sent: Option<Instant>,
    /// When the current RPI ends.
    next: Instant,
}

impl Wire {
    fn connect(addr: Ipv4Addr) -> Result<Wire, String> {
        let tcp = TcpStream::connect_timeout(&SocketAddr::from((addr, 44818)), TCP_TIMEOUT)
            .map_err(|e| format!("TCP {addr}:44818: {e}"))?;
        tcp.set_read_timeout(Some(TCP_TIMEOUT))
            .and_then(|()| tcp.set_write_timeout(Some(TCP_TIMEOUT)))
            .and_then(|()| tcp.set_nodelay(true))
            .map_err(|e| format!("TCP {addr}:44818: {e}"))?;
        let udp = UdpSocket::bind((Ipv4Addr::UNSPECIFIED, IO_PORT))
            .map_err(|e| format!("UDP {IO_PORT}: {e}"))?;
        Ok(Wire {
            tcp,
            udp,
            adapter: SocketAddr::from((addr, IO_PORT)),
            last: None,
            sent: None,
            next: Instant::now(),
        })
    }

    /// Takes T→O datagrams until `until`, keeping the last image.
    fn receive_until(&mut self, until: Instant) -> Result<(), String> {
        let mut buf = [0u8; 1500];
        loop {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(());
            }
            self.udp
                .set_read_timeout(Some(left))
                .map_err(|e| format!("UDP {IO_PORT}: {e}"))?;
            let Ok((n, from)) = self.udp.recv_from(&mut buf) else {
                continue;
            };
            if from.ip() != self.adapter.ip() {
                continue;
            }
            // Sequenced address, then connected data: its 16-bit sequence count, the image.
            let image = parse_items(&buf[..n]).and_then(|items| {
                items
                    .iter()
                    .find(|(kind, _)| *kind == item::CONNECTED_DATA)
                    .and_then(|(_, data)| data.get(2..))
                    .map(<[u8]>::to_vec)
            });
            if let Some(image) = image {
                self.last = Some((image, Instant::now()));
            }
        }
    }

    /// The end of the next RPI (from now, if the last ended long ago).
    fn next_rpi(&mut self) -> Instant {
        let now = Instant::now();
        self.next = (self.next + rpi()).max(now + rpi() / 2);
        self.next
    }
}

impl Scanner for Wire {
    fn request(&mut self, message: &[u8]) -> Result<Vec<u8>, String> {
        let tcp = |e: std::io::Error| format!("TCP 44818: {e}");
        self.tcp.write_all(message).map_err(tcp)?;
        let mut reply = vec![0u8; 24];
        self.tcp.read_exact(&mut reply).map_err(tcp)?;
        let length = usize::from(u16::from_le_bytes([reply[2], reply[3]]));
        reply.resize(24 + length, 0);
        self.tcp.read_exact(&mut reply[24..]).map_err(tcp)?;
        Ok(reply)
    }

    fn rpi(&mut self, datagram: &[u8]) -> Result<Vec<u8>, String> {
        self.udp
            .send_to(datagram, self.adapter)
            .map_err(|e| format!("UDP {}: {e}", self.adapter))?;
        self.sent = Some(Instant::now());
        let until = self.next_rpi();
        self.receive_until(until)?;
        // The first T→O datagram may take the adapter's own RPI to come.
        if self.last.is_none() {
            let until = self.next_rpi();
            self.receive_until(until)?;
        }
        self.last
            .as_ref()
            .map(|(image, _)| image.clone())
            .ok_or_else(|| "no T→O datagram from the adapter".to_owned())
    }

    /// Closed: no T→O datagram in the last two RPIs, the last one at least two RPIs after the
    /// last O→T (the adapter waits 4 × RPI, and produces every RPI).
    fn stop_producing(&mut self, rpis: u32) -> Result<Stopped, String> {
        for _ in 0..rpis {
            let until = self.next_rpi();
            self.receive_until(until)?;
        }
        let last = self.last.as_ref().map(|(_, at)| *at);
        let quiet = last.map_or(Duration::MAX, |at| at.elapsed());
        let after = match (last, self.sent) {
            (Some(last), Some(sent)) => last.saturating_duration_since(sent),
            _ => Duration::ZERO,
        };
        let after = after.as_millis();
        Ok(Stopped {
            closed: quiet >= 2 * rpi() && after >= 2 * rpi().as_millis(),
            image: None,
            log: None,
            seen: format!(
                "the adapter's T→O datagrams stopped {after} ms after the scanner's last O→T"
            ),
        })
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
