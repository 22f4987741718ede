//! `edsgen simulate --machine FILE`: a whole machine from one file (`docs/machine.md`). The file
//! is read and checked as a whole first ([`file`]); then each bus table is served by an
//! `edsgen simulate` of this same binary for that bus (one per EtherNet/IP adapter), whose lines
//! are printed prefixed with the bus. `fault NAME` and `clear NAME` on standard input reach the
//! device named; SIGINT, SIGTERM or SIGHUP stop every bus, and so does any bus that stops.

pub mod file;
pub mod model;
mod modules;

use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, Command, ExitCode, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use model::{Address, Bus, Machine, Place, Planned, Source};

use super::{fail, signals};
use edsgen_model::lint::Policy;

/// How long the buses have to stop after SIGTERM before they are killed.
const STOP_GRACE: Duration = Duration::from_secs(3);

/// Runs the machine file at `path`; each bus serves descriptions with errors of the rules in
/// `allow` (`--allow CODE`), as `simulate` does.
pub fn run(path: &Path, allow: &[String], policy: &Policy) -> ExitCode {
    let machine = match file::read(path) {
        Ok(machine) => machine,
        Err(problems) => {
            for p in &problems {
                if p.line == 0 {
                    eprintln!("error: {}: {}", path.display(), p.message);
                } else {
                    eprintln!(
                        "error: {}:{}:{}: {}",
                        path.display(),
                        p.line,
                        p.column,
                        p.message
                    );
                }
            }
            return fail(format!(
                "{}: {} problem(s); nothing was started",
                path.display(),
                problems.len()
            ));
        }
    };
    if machine.sections.is_empty() {
        return fail(format!(
            "{}: no bus table, nothing to start",
            path.display()
        ));
    }
    // Every description judged before anything starts, as each bus would judge it.
    for device in machine.sections.iter().flat_map(|s| &s.devices) {
        if let Source::File(file, pick) = &device.source {
            let pick = pick.as_deref().map(device_choice);
            if let Err(message) = super::simulate::load_servable(file, pick.as_deref(), policy) {
                return fail(format!(
                    "{}: {message}; nothing was started",
                    path.display()
                ));
            }
        }
    }
    if let Err(message) = signals::install() {
        return fail(message);
    }
    print_plan(&machine);
    let exe = match std::env::current_exe() {
        Ok(exe) => exe,
        Err(e) => return fail(format!("cannot find this program to start the buses: {e}")),
    };
    let (lines_tx, lines_rx) = mpsc::channel::<Heard>();
    let mut buses: Vec<Running> = Vec::new();
    for mut launch in launches(&machine) {
        for code in allow {
            launch.args.extend(["--allow".to_owned(), code.clone()]);
        }
        match launch.start(&exe, &lines_tx) {
            Ok(running) => buses.push(running),
            Err(e) => {
                eprintln!("error: cannot start {}: {e}", launch.label);
                stop(&mut buses);
                return ExitCode::from(1);
            }
        }
    }
    stdin_lines(lines_tx);
    let code = supervise(&mut buses, &lines_rx);
    stop(&mut buses);
    while let Ok(heard) = lines_rx.try_recv() {
        if let Heard::Line(line) = heard {
            line.print();
        }
    }
    eprintln!("stopped: machine {}", path.display());
    code
}

/// Every device with its bus and address, before anything starts.
fn print_plan(machine: &Machine) {
    for section in &machine.sections {
        for device in &section.devices {
            let what = match &device.source {
                Source::Card(card) => format!("card {card}"),
                Source::File(path, None) => path.display().to_string(),
                Source::File(path, Some(pick)) => format!("{}#{pick}", path.display()),
            };
            let mut plugged = String::new();
            if let Some(access_point) = &device.access_point {
                plugged.push_str(&format!(", access point {access_point:?}"));
            }
            if !device.modules.is_empty() {
                let modules: Vec<String> =
                    device.modules.iter().map(|m| format!("{m:?}")).collect();
                plugged.push_str(&format!(", modules {}", modules.join(", ")));
            }
            println!(
                "{:<9} {:<24} {:<32} {} on {}{plugged}",
                section.bus.table(),
                device.name,
                what,
                device.address,
                section.place
            );
        }
    }
}

/// One `edsgen simulate` to start.
struct Launch {
    label: String,
    args: Vec<String>,
    /// The devices it serves whose faults come from standard input.
    faulted: Vec<Faulted>,
}

/// A device whose faults come from its bus's standard input.
#[derive(Debug, Clone)]
struct Faulted {
    /// Its name in the machine file.
    name: String,
    /// What its bus calls it after `fault`/`clear` when the bus serves several (an EtherCAT
    /// position, a PROFINET name of station); nothing when it is the bus's only drive.
    target: Option<String>,
}

/// The `edsgen simulate` runs that serve `machine`: one per bus table, one per EtherNet/IP
/// adapter.
fn launches(machine: &Machine) -> Vec<Launch> {
    let mut out = Vec::new();
    for section in &machine.sections {
        let bus = section.bus;
        let place = match &section.place {
            Place::CanBus(addr) => vec!["--bus".to_owned(), addr.clone()],
            Place::SocketCan(iface) => vec!["--socketcan".to_owned(), iface.clone()],
            Place::Interface(iface) if bus == Bus::EtherCat => {
                vec!["--ethercat".to_owned(), iface.clone()]
            }
            Place::Interface(iface) => vec!["--profinet".to_owned(), iface.clone()],
            Place::Tty(tty) => vec!["--profibus".to_owned(), tty.clone()],
            Place::Host => Vec::new(),
        };
        if bus == Bus::Enip {
            for device in &section.devices {
                let Address::Ip(ip) = &device.address else {
                    continue;
                };
                let mut args = vec!["simulate".to_owned(), "--enip".to_owned(), ip.clone()];
                args.extend(device_args(bus, device));
                out.push(Launch {
                    label: format!("enip {ip}"),
                    args,
                    faulted: Vec::new(),
                });
            }
            continue;
        }
        let mut args = vec!["simulate".to_owned()];
        args.extend(place);
        let mut faulted = Vec::new();
        // PROFINET gives `--ip` in its devices' order, the cards first, then the files.
        let mut devices: Vec<&Planned> = section.devices.iter().collect();
        if bus == Bus::Profinet {
            devices.sort_by_key(|d| !matches!(d.source, Source::Card(_)));
        }
        for (position, device) in devices.iter().enumerate() {
            args.extend(device_args(bus, device));
            if takes_faults(bus, device) {
                faulted.push(Faulted {
                    name: device.name.clone(),
                    target: fault_target(bus, device, position),
                });
            }
        }
        if bus == Bus::Profinet && devices.iter().any(|d| pn_ip(d).is_some()) {
            for device in &devices {
                let ip = pn_ip(device).unwrap_or("-");
                args.extend(["--ip".to_owned(), ip.to_owned()]);
            }
        }
        if faulted.len() == 1 && section.devices.len() == 1 {
            faulted[0].target = None;
        }
        if !faulted.is_empty() {
            args.push("--faults-on-stdin".to_owned());
        }
        out.push(Launch {
            label: format!("{} {}", bus.table(), section.place),
            args,
            faulted,
        });
    }
    out
}

/// A device's arguments to `edsgen simulate`.
fn device_args(bus: Bus, device: &Planned) -> Vec<String> {
    let suffix = match &device.address {
        Address::NodeId(id) | Address::Station(id) => format!("@{id}"),
        Address::Pn { name: Some(n), .. } => format!("@{n}"),
        _ => String::new(),
    };
    let mut args = match &device.source {
        Source::Card(card) => vec!["--card".to_owned(), format!("{card}{suffix}")],
        Source::File(path, _) => vec![format!("{}{suffix}", path.display())],
    };
    if let (Bus::EtherCat, Source::File(_, Some(pick))) = (bus, &device.source) {
        args.extend(["--device".to_owned(), device_choice(pick)]);
    }
    for module in &device.modules {
        args.extend(["--module".to_owned(), module.clone()]);
    }
    if let Some(access_point) = &device.access_point {
        args.extend(["--access-point".to_owned(), access_point.clone()]);
    }
    args
}

/// A PROFINET device's `ip`, if the machine file gives one.
fn pn_ip(device: &Planned) -> Option<&str> {
    match &device.address {
        Address::Pn { ip: Some(ip), .. } => Some(ip),
        _ => None,
    }
}

/// What the bus's `fault`/`clear` lines call a device among several: its position in an
/// EtherCAT segment, its name of station on a PROFINET interface.
fn fault_target(bus: Bus, device: &Planned, position: usize) -> Option<String> {
    match (bus, &device.address) {
        (Bus::EtherCat, _) => Some(position.to_string()),
        (
            Bus::Profinet,
            Address::Pn {
                name: Some(name), ..
            },
        ) => Some(name.clone()),
        _ => None,
    }
}

/// `FILE.xml#xCODE` or `FILE.xml#NAME` in a machine file: the `--device` choice, `#xCODE` for a
/// product code, the name as written otherwise.
fn device_choice(pick: &str) -> String {
    let code = pick
        .strip_prefix('x')
        .filter(|hex| !hex.is_empty() && hex.chars().all(|c| c.is_ascii_hexdigit()));
    match code {
        Some(_) => format!("#{pick}"),
        None => pick.to_owned(),
    }
}

/// Whether the device's simulator takes `fault`/`clear` lines (the drives that do today).
fn takes_faults(bus: Bus, device: &Planned) -> bool {
    matches!(
        (bus, &device.source),
        (Bus::EtherCat, Source::Card("ec-tx508")) | (Bus::Profinet, Source::Card("goodrive350-pn"))
    )
}

/// A started bus.
struct Running {
    label: String,
    child: Child,
    stdin: Option<ChildStdin>,
    faulted: Vec<Faulted>,
}

impl Launch {
    fn start(&self, exe: &Path, lines: &mpsc::Sender<Heard>) -> std::io::Result<Running> {
        let mut child = Command::new(exe)
            .args(&self.args)
            .env(signals::PARENT_VARIABLE, std::process::id().to_string())
            .stdin(if self.faulted.is_empty() {
                Stdio::null()
            } else {
                Stdio::piped()
            })
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        if let Some(out) = child.stdout.take() {
            prefix_lines(out, format!("[{}] ", self.label), false, lines.clone());
        }
        if let Some(err) = child.stderr.take() {
            prefix_lines(err, format!("[{}] ", self.label), true, lines.clone());
        }
        Ok(Running {
            label: self.label.clone(),
            stdin: child.stdin.take(),
            child,
            faulted: self.faulted.clone(),
        })
    }
}

/// What the machine hears, in the order it comes: a bus's line, or a command on standard input.
enum Heard {
    Line(Line),
    Command(String),
}

/// A line a bus printed, prefixed with the bus.
struct Line {
    text: String,
    /// Whether the bus wrote it on its standard error (it goes to ours).
    error: bool,
}

impl Line {
    fn print(&self) {
        if self.error {
            eprintln!("{}", self.text);
        } else {
            println!("{}", self.text);
        }
    }
}

/// Forwards each line of `from`, prefixed, to `to`.
fn prefix_lines(
    from: impl Read + Send + 'static,
    prefix: String,
    error: bool,
    to: mpsc::Sender<Heard>,
) {
    std::thread::spawn(move || {
        for line in BufReader::new(from).lines() {
            let Ok(line) = line else { break };
            let text = format!("{prefix}{line}");
            if to.send(Heard::Line(Line { text, error })).is_err() {
                break;
            }
        }
    });
}

/// The lines of standard input, as they come, to `to`.
fn stdin_lines(to: mpsc::Sender<Heard>) {
    std::thread::spawn(move || {
        for line in std::io::stdin().lock().lines() {
            let Ok(line) = line else { break };
            if to.send(Heard::Command(line)).is_err() {
                break;
            }
        }
    });
}

/// Prints the buses' lines and routes faults, each as it comes, until a stop is asked for or
/// a bus stops.
fn supervise(buses: &mut [Running], heard: &mpsc::Receiver<Heard>) -> ExitCode {
    loop {
        match heard.recv_timeout(Duration::from_millis(20)) {
            Ok(Heard::Line(line)) => line.print(),
            Ok(Heard::Command(command)) => fault_command(buses, command.trim()),
            Err(_) => {}
        }
        if signals::requested() {
            return ExitCode::SUCCESS;
        }
        for bus in buses.iter_mut() {
            if let Ok(Some(status)) = bus.child.try_wait() {
                while let Ok(heard) = heard.recv_timeout(Duration::from_millis(50)) {
                    if let Heard::Line(line) = heard {
                        line.print();
                    }
                }
                eprintln!(
                    "error: {} stopped ({status}); stopping the machine",
                    bus.label
                );
                return ExitCode::from(1);
            }
        }
    }
}

/// `fault NAME` or `clear NAME`, to the bus serving NAME.
fn fault_command(buses: &mut [Running], command: &str) {
    if command.is_empty() {
        return;
    }
    let Some((verb, name)) = command
        .split_once(char::is_whitespace)
        .map(|(v, n)| (v, n.trim()))
        .filter(|(v, _)| matches!(*v, "fault" | "clear"))
    else {
        eprintln!("machine: `{command}`: standard input takes `fault NAME` and `clear NAME`");
        return;
    };
    let found = buses.iter_mut().find_map(|b| {
        let target = b.faulted.iter().find(|f| f.name == name)?.target.clone();
        Some((b, target))
    });
    let Some((bus, target)) = found else {
        let names: Vec<&str> = buses
            .iter()
            .flat_map(|b| b.faulted.iter().map(|f| f.name.as_str()))
            .collect();
        let list = if names.is_empty() {
            "none of this machine's devices does".to_owned()
        } else {
            format!("the drives that do: {}", names.join(", "))
        };
        eprintln!("machine: no device `{name}` takes faults from standard input ({list})");
        return;
    };
    if let Some(stdin) = &mut bus.stdin {
        let line = match target {
            Some(target) => format!("{verb} {target}"),
            None => verb.to_owned(),
        };
        if writeln!(stdin, "{line}")
            .and_then(|()| stdin.flush())
            .is_err()
        {
            eprintln!("machine: {} does not listen for faults any more", bus.label);
        }
    }
}

/// SIGTERM to every bus still running, then SIGKILL to those still there after a grace time.
fn stop(buses: &mut [Running]) {
    for bus in buses.iter_mut() {
        if let Ok(None) = bus.child.try_wait() {
            terminate(&bus.child);
        }
    }
    let end = Instant::now() + STOP_GRACE;
    for bus in buses.iter_mut() {
        loop {
            match bus.child.try_wait() {
                Ok(Some(_)) | Err(_) => break,
                Ok(None) if Instant::now() >= end => {
                    let _ = bus.child.kill();
                    let _ = bus.child.wait();
                    break;
                }
                Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            }
        }
    }
}

/// Asks a bus to stop as Ctrl-C would (each simulator stops cleanly on SIGTERM).
fn terminate(child: &Child) {
    let Ok(pid) = i32::try_from(child.id()) else {
        return;
    };
    let _ = nix::sys::signal::kill(nix::unistd::Pid::from_raw(pid), nix::sys::signal::SIGTERM);
}

#[cfg(test)]
mod tests;
