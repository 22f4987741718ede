//! `edsgen demo --machine`: the bundled cards as one machine. As root, the demo writes a machine
//! file naming every bus's card, `edsgen simulate --machine` brings it up in a private network
//! namespace, and each bus is driven from the far side of its wire by the demo's master for it:
//! the CANopen workflows over socketcand (an `edsgen bus` beside the machine, the master a role
//! in the machine's namespace), the EC-TX508 by ethercrab over a veth pair from this process
//! (feature `ethercrab`; its fault raised and cleared through the machine's standard input, by
//! name), the EtherNet/IP scanner and the PROFINET controller in a second namespace, and
//! profirust's DP master in this process on a pseudo-terminal line to the DP card.
//! SIGTERM then stops the machine, which must say every bus stopped.

use std::io::{BufRead, BufReader, Read};
use std::process::{ChildStdin, Stdio};
use std::sync::mpsc::{self, Receiver, Sender};
use std::time::{Duration, Instant};

use super::two_namespaces::{self, Server};
use super::{enip_wire, profinet_wire, Trace};
use crate::netns::{ChildId, End, Network};

/// The socketcand hub the machine's CANopen drives join, inside the machine's namespace.
const CAN_BUS: &str = "127.0.0.1:29536";
/// How long the machine may take until every bus serves.
const START: Duration = Duration::from_secs(30);
/// How long the CANopen master may take for both drives' workflows, in real time.
const CANOPEN_STEPS: Duration = Duration::from_secs(90);

/// The starts of the lines the machine's buses print once they serve (each after its bus).
fn ready_lines(links: &Links) -> Vec<String> {
    let mut lines = vec![
        format!("[canopen bus {CAN_BUS}] simulating node 2 "),
        format!("[canopen bus {CAN_BUS}] simulating node 3 "),
        format!("[enip {}] serving ", enip_wire::ADAPTER),
        format!(
            "[profinet interface {}] RPC on UDP 34964 ",
            links.profinet.0
        ),
    ];
    if let Some((device, _)) = &links.ethercat {
        lines.push(format!("[ethercat interface {device}] serving "));
    }
    lines
}

/// Runs the machine section (root: the caller checked).
pub(super) fn run(trace: &mut Trace) {
    let ethercat = cfg!(feature = "ethercrab");
    if !ethercat {
        eprintln!(
            "demo --machine drives the EC-TX508 with ethercrab, which needs edsgen built with the \
             `ethercrab` feature (cargo build --features ethercrab); the EC-TX508 runs in this \
             process instead"
        );
    }
    trace.heading(
        "the bundled cards as one machine: `edsgen simulate --machine` in a network namespace, \
         each bus driven from the far side of its wire",
    );
    let mut net = match Network::create("machine", 2) {
        Ok(net) => net,
        Err(problem) => {
            trace.step("two network namespaces", Err(problem));
            return;
        }
    };
    let said = match on_wire(trace, &mut net, ethercat) {
        Ok(said) => said,
        Err((problem, said)) => {
            trace.step("the machine", Err(problem));
            said
        }
    };
    drop(net);
    trace.heading("what the machine said");
    for line in said {
        trace.line(None, format!("machine: {line}"));
    }
    if !ethercat {
        super::ethercat::run(trace);
    }
}

/// The links the machine's buses use (veth pairs, the machine's end first) that the demo needs
/// again; the EtherNet/IP pair needs only its addresses.
struct Links {
    /// The EC-TX508's end and ethercrab's (in this process's namespace), with ethercrab.
    ethercat: Option<(String, String)>,
    profinet: (String, String),
    /// The PROFIBUS line: the master's end, then the card's.
    dp: crate::pty::Line,
}

fn links(net: &mut Network, ethercat: bool) -> Result<Links, String> {
    let ethercat = if ethercat {
        let (master, device) = net.veth(End::Host, End::Namespace(0))?;
        Some((device, master))
    } else {
        None
    };
    let enip = net.veth(End::Namespace(0), End::Namespace(1))?;
    net.address(0, &enip.0, &format!("{}/24", enip_wire::ADAPTER))?;
    net.address(1, &enip.1, &format!("{}/24", enip_wire::SCANNER))?;
    let profinet = net.veth(End::Namespace(0), End::Namespace(1))?;
    net.address(0, &profinet.0, &format!("{}/24", profinet_wire::CARD))?;
    net.address(1, &profinet.1, &format!("{}/24", profinet_wire::CONTROLLER))?;
    let dp = crate::pty::line()?;
    Ok(Links {
        ethercat,
        profinet,
        dp,
    })
}

/// The machine file: every bundled card, each on its link.
fn machine_file(links: &Links) -> String {
    let mut text = format!(
        "[[canopen]]\nbus = \"{CAN_BUS}\"\ndevices = [\"cp301@2\", \"goodrive350@3\"]\n\n\
         [[enip]]\ndevices = [{{ device = \"goodrive350-enip\", address = \"{}\" }}]\n\n\
         [[profinet]]\ninterface = \"{}\"\n\
         devices = [{{ device = \"goodrive350-pn\", ip = \"{}/24\" }}]\n",
        enip_wire::ADAPTER,
        links.profinet.0,
        profinet_wire::CARD,
    );
    text.push_str(&format!(
        "\n[[profibus]]\ntty = \"{}\"\ndevices = [\"goodrive350-dp@2\"]\n",
        links.dp.ends[1].display()
    ));
    if let Some((device, _)) = &links.ethercat {
        text.push_str(&format!(
            "\n[[ethercat]]\ninterface = \"{device}\"\ndevices = [\"ec-tx508\"]\n"
        ));
    }
    text
}

/// The machine and its masters; the machine's lines once it is stopped (with the problem, if
/// any).
fn on_wire(trace: &mut Trace, net: &mut Network, ethercat: bool) -> two_namespaces::Outcome {
    let bare = |problem: String| (problem, Vec::new());
    let links = links(net, ethercat).map_err(bare)?;
    let exe = std::env::current_exe().map_err(|e| bare(format!("this program: {e}")))?;
    let machine_ns = net.namespace(0).unwrap_or_default().to_owned();
    let masters_ns = net.namespace(1).unwrap_or_default().to_owned();

    let mut hub = net.command(0, &exe).map_err(bare)?;
    hub.args(["bus", "--listen", CAN_BUS])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let shown = format!("ip netns exec {machine_ns} edsgen bus --listen {CAN_BUS}");
    let ready = ("edsgen bus: socketcand hub listening on", false);
    let hub = Server::start(trace, net, &mut hub, shown, "the CAN hub", ready)?;

    let dir = std::env::temp_dir().join(format!("edsgen-demo-machine-{}", std::process::id()));
    let file = dir.join("machine.toml");
    let text = machine_file(&links);
    std::fs::create_dir_all(&dir)
        .and_then(|()| std::fs::write(&file, &text))
        .map_err(|e| bare(format!("{}: {e}", file.display())))?;
    for line in text.lines().filter(|l| !l.is_empty()) {
        trace.line(None, format!("machine.toml: {line}"));
    }
    let mut command = net.command(0, &exe).map_err(bare)?;
    command
        .arg("simulate")
        .arg("--machine")
        .arg(&file)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    trace.line(
        None,
        format!("ip netns exec {machine_ns} edsgen simulate --machine machine.toml"),
    );
    let id = net.spawn(&mut command).map_err(bare)?;
    let mut machine = Machine::watch(net, id).map_err(bare)?;
    let result = machine.wait_ready(&ready_lines(&links)).and_then(|()| {
        drive(
            trace,
            net,
            &exe,
            [&machine_ns, &masters_ns],
            &links,
            &mut machine,
        )
    });
    let stopped = machine.stop(net);
    // The hub's log says nothing the demo checks.
    let _ = hub.stop(net, Duration::from_secs(2), Ok(()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut said = machine.said;
    said.extend(machine.lines.try_iter());
    let stopped_line = said.iter().any(|l| l.starts_with("stopped: machine "));
    if result.is_ok() {
        trace.step(
            "SIGTERM stops the machine: every bus, then `stopped: machine`",
            match (stopped, stopped_line) {
                (Some(status), true) if status.success() => Ok(format!("{status}")),
                (status, line) => Err(format!(
                    "exit {status:?}, `stopped: machine` {}",
                    if line { "said" } else { "not said" }
                )),
            },
        );
    }
    match result {
        Ok(()) => Ok(said),
        Err(problem) => Err((problem, said)),
    }
}

/// Each bus's master against the machine.
fn drive(
    trace: &mut Trace,
    net: &mut Network,
    exe: &std::path::Path,
    [machine_ns, masters_ns]: [&str; 2],
    links: &Links,
    machine: &mut Machine,
) -> Result<(), String> {
    trace.heading("CP301 and Goodrive350 on the machine's CANopen bus, from its namespace");
    let mut command = net.command(0, exe)?;
    command.args(["demo-role", "canopen-master", CAN_BUS]);
    let shown = format!("ip netns exec {machine_ns} edsgen demo-role canopen-master {CAN_BUS}");
    two_namespaces::client(
        trace,
        net,
        &mut command,
        shown,
        "the CANopen master",
        CANOPEN_STEPS,
    )?;

    ethercat(trace, links, machine);

    trace.heading("Goodrive350 EtherNet/IP card on the machine, from the masters' namespace");
    let adapter = enip_wire::ADAPTER.to_string();
    let mut command = net.command(1, exe)?;
    command.args(["demo-role", "enip-scanner", &adapter]);
    let shown = format!("ip netns exec {masters_ns} edsgen demo-role enip-scanner {adapter}");
    two_namespaces::client(
        trace,
        net,
        &mut command,
        shown,
        "the scanner",
        enip_wire::STEPS,
    )?;

    trace.heading("Goodrive350 PROFINET card on the machine, from the masters' namespace");
    let card = profinet_wire::CARD.to_string();
    let end = &links.profinet.1;
    let mut command = net.command(1, exe)?;
    command.args(["demo-role", "profinet-controller", end, &card]);
    let shown =
        format!("ip netns exec {masters_ns} edsgen demo-role profinet-controller {end} {card}");
    two_namespaces::client(
        trace,
        net,
        &mut command,
        shown,
        "the controller",
        profinet_wire::STEPS,
    )?;

    super::dp_line::run(trace, &links.dp.ends[0]);
    Ok(())
}

/// The EC-TX508 by ethercrab from this process, its fault raised and cleared through the
/// machine's standard input by the device's name.
#[cfg(feature = "ethercrab")]
fn ethercat(trace: &mut Trace, links: &Links, machine: &mut Machine) {
    if let (Some((_, master)), Some(stdin)) = (&links.ethercat, machine.stdin.take()) {
        trace.heading(&format!(
            "EC-TX508 on the machine's EtherCAT link: ethercrab on {master}, 1 ms cycle"
        ));
        let faults = super::ethercat_wire::Faults::named(stdin, "ec-tx508");
        if let Err(problem) = super::ethercat_wire::drive_machine(trace, master, faults) {
            trace.step("EC-TX508 over EtherCAT", Err(problem));
        }
    }
}

/// Without ethercrab the machine has no EtherCAT link (the EC-TX508 runs in this process).
#[cfg(not(feature = "ethercrab"))]
fn ethercat(_: &mut Trace, _: &Links, _: &mut Machine) {}

/// The running machine: its standard input (faults by name) and its lines, both streams in the
/// order they came.
struct Machine {
    id: ChildId,
    stdin: Option<ChildStdin>,
    lines: Receiver<String>,
    said: Vec<String>,
}

impl Machine {
    fn watch(net: &mut Network, id: ChildId) -> Result<Machine, String> {
        let child = net.child(id).ok_or("the machine")?;
        let (tx, lines) = mpsc::channel();
        if let Some(out) = child.stdout.take() {
            forward(out, tx.clone());
        }
        if let Some(err) = child.stderr.take() {
            forward(err, tx);
        }
        Ok(Machine {
            id,
            stdin: child.stdin.take(),
            lines,
            said: Vec::new(),
        })
    }

    /// Waits until the machine has said each of `ready` (line starts).
    fn wait_ready(&mut self, ready: &[String]) -> Result<(), String> {
        let mut waiting: Vec<&String> = ready.iter().collect();
        let end = Instant::now() + START;
        while !waiting.is_empty() {
            let left = end.saturating_duration_since(Instant::now());
            let Ok(line) = self.lines.recv_timeout(left) else {
                return Err(format!(
                    "the machine did not serve in {START:?}: still waiting for {waiting:?}"
                ));
            };
            waiting.retain(|w| !line.starts_with(w.as_str()));
            self.said.push(line);
        }
        Ok(())
    }

    /// SIGTERM (its buses stop first); its exit status.
    fn stop(&mut self, net: &mut Network) -> Option<std::process::ExitStatus> {
        drop(self.stdin.take());
        let status = net.stop(self.id, Duration::from_secs(10));
        // Its last lines, until both streams end (or a second passes without one).
        while let Ok(line) = self.lines.recv_timeout(Duration::from_secs(1)) {
            self.said.push(line);
        }
        status
    }
}

fn forward(stream: impl Read + Send + 'static, to: Sender<String>) {
    std::thread::spawn(move || {
        for line in BufReader::new(stream).lines() {
            let Ok(line) = line else { break };
            if to.send(line).is_err() {
                break;
            }
        }
    });
}
