//! A machine file with all five buses, brought up by `edsgen simulate --machine` in a private
//! network namespace (root only; a visible skip otherwise, a failure under `CI=true`), each bus
//! checked from the other side of its wire:
//! - CANopen: `edsgen scan` on the machine's `edsgen bus` finds the CP301 and the Goodrive350;
//! - EtherCAT: SOEM (python `pysoem`, scripts/soem_segment.py) takes a segment of two EC-TX508s
//!   to Op and drives each to its own speed;
//! - PROFINET: `edsgen pn list` finds two Goodrive350 PROFINET cards on one interface, each by
//!   its name of station and IP;
//! - EtherNet/IP: `edsgen enip list` finds the Goodrive350 EtherNet/IP card at its address;
//! - PROFIBUS-DP: `edsgen dp scan` finds the DP card on a pseudo-terminal line.
//!
//! Then SIGTERM stops the whole machine.

mod process_support;

use std::process::Command;
use std::time::Duration;

use edsgen_demo::netns::{self, End, Network};
use process_support::{python, root, skip, Process, EDSGEN};

const WAIT: Duration = Duration::from_secs(30);

#[test]
fn a_machine_of_five_buses_answers_on_each() {
    if !netns::is_root() {
        return skip::<()>(netns::not_root("the five-bus machine test")).unwrap_or(());
    }
    let Some(python) = python() else { return };
    // Namespace 0 runs the machine (and its CAN hub); namespace 1 the masters.
    let mut net = Network::create("machine", 2).expect("namespaces");
    let (ecat_dev, ecat_master) = net
        .veth(End::Namespace(0), End::Namespace(1))
        .expect("the EtherCAT link");
    let (pn_dev, pn_master) = net
        .veth(End::Namespace(0), End::Namespace(1))
        .expect("the PROFINET link");
    let (ip_dev, ip_master) = net
        .veth(End::Namespace(0), End::Namespace(1))
        .expect("the EtherNet/IP link");
    net.address(0, &ip_dev, "10.231.7.2/24")
        .expect("an address");
    for address in ["10.231.8.2/24", "10.231.8.3/24"] {
        net.address(0, &pn_dev, address).expect("an address");
    }
    net.address(1, &ip_master, "10.231.7.1/24")
        .expect("an address");
    let pair = Process::python(&python, "scripts/pty_pair.py", &[]);
    let line = pair.stdout_line(|l| l.starts_with("PTY "), WAIT);
    let ends: Vec<&str> = line.split(' ').skip(1).collect();
    let (dp_master, dp_dev) = (ends[0].to_owned(), ends[1].to_owned());

    let in_ns = |n: usize, program: &str, args: &[&str]| {
        let mut command = net.command(n, program).expect("a command");
        command.args(args).current_dir(root());
        command
    };
    let hub = Process::start(&mut in_ns(
        0,
        EDSGEN,
        &["bus", "--listen", "127.0.0.1:29536"],
    ));
    hub.stdout_line(|l| l.contains("listening on 127.0.0.1:29536"), WAIT);

    let dir = std::env::temp_dir().join(format!("edsgen-machine-wire-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("machine.toml");
    std::fs::write(
        &file,
        format!(
            r#"[[canopen]]
bus = "127.0.0.1:29536"
devices = ["cp301@2", "goodrive350@3"]

[[ethercat]]
interface = "{ecat_dev}"
devices = ["ec-tx508", "ec-tx508"]

[[profibus]]
tty = "{dp_dev}"
devices = ["goodrive350-dp@2"]

[[profinet]]
interface = "{pn_dev}"
devices = [
    {{ device = "goodrive350-pn", name = "drive-a", ip = "10.231.8.2/24" }},
    {{ device = "goodrive350-pn", name = "drive-b", ip = "10.231.8.3/24" }},
]

[[enip]]
devices = [{{ device = "goodrive350-enip", address = "10.231.7.2" }}]
"#
        ),
    )
    .unwrap();
    let mut machine = Process::start(&mut in_ns(
        0,
        EDSGEN,
        &["simulate", "--machine", file.to_str().unwrap()],
    ));
    // Every bus up: each says so on its standard error, prefixed with the bus.
    let mut waiting = vec![
        "[canopen bus 127.0.0.1:29536] simulating node 3 ".to_owned(),
        "[enip 10.231.7.2] serving ".to_owned(),
        "[profibus line ".to_owned(),
    ];
    while !waiting.is_empty() {
        let line = machine.stderr_line(|l| waiting.iter().any(|w| l.starts_with(w)), WAIT);
        waiting.retain(|w| !line.starts_with(w.as_str()));
    }
    std::thread::sleep(Duration::from_millis(500));

    // CANopen.
    let scan = Process::start(&mut in_ns(0, EDSGEN, &["scan"])).finish(WAIT);
    assert_eq!(scan.code, Some(0), "{scan:?}");
    let nodes: Vec<&str> = scan
        .stdout
        .lines()
        .skip(1)
        .take(2)
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert_eq!(nodes, ["2", "3"], "{scan:?}");
    assert!(
        scan.stdout.contains("\n2 node(s) found on can0\n"),
        "{scan:?}"
    );
    // EtherCAT, by SOEM: a segment of two EC-TX508s, each driven to its own speed.
    let script = root().join("scripts/soem_segment.py");
    let soem = Process::start(&mut in_ns(
        1,
        python.to_str().unwrap(),
        &[script.to_str().unwrap(), &ecat_master],
    ))
    .finish(Duration::from_secs(90));
    let lines: Vec<&str> = soem.stdout.lines().collect();
    assert_eq!(
        lines[..3],
        [
            "found 2",
            "0 identity 0x000004d8 0x00009252 0x00000001 name EC-TX508 images 21/23",
            "1 identity 0x000004d8 0x00009252 0x00000001 name EC-TX508 images 21/23",
        ],
        "{soem:?}"
    );
    assert_eq!(lines[3..4], ["op True"], "{soem:?}");
    assert_eq!(lines[5..], ["speeds 300 150", "done"], "{soem:?}");
    let (got, expected) = lines[4]
        .strip_prefix("wkc ")
        .and_then(|w| w.split_once(" expected "))
        .unwrap_or_else(|| panic!("{soem:?}"));
    assert_eq!(got, expected, "{soem:?}");
    // PROFINET.
    let pn = Process::start(&mut in_ns(1, EDSGEN, &["pn", "list", &pn_master])).finish(WAIT);
    assert_eq!(pn.code, Some(0), "{pn:?}");
    for (name, ip) in [("drive-a", "10.231.8.2"), ("drive-b", "10.231.8.3")] {
        let line = pn.stdout.lines().find(|l| l.contains(name));
        assert!(line.is_some_and(|l| l.contains(ip)), "{name}: {pn:?}");
    }
    // A fault for one of the two, by its name, reaches that one.
    machine.send_line("fault drive-b");
    let raised = machine.stdout_line(|l| l.contains("drive fault"), WAIT);
    assert!(
        raised.starts_with(&format!(
            "[profinet interface {pn_dev}] drive-b: drive fault "
        )) && raised.ends_with(" (OC1) raised"),
        "{raised}"
    );
    // EtherNet/IP.
    let enip = Process::start(&mut in_ns(1, EDSGEN, &["enip", "list", "10.231.7.2"])).finish(WAIT);
    assert_eq!(enip.code, Some(0), "{enip:?}");
    assert!(enip.stdout.contains("10.231.7.2"), "{enip:?}");
    // PROFIBUS-DP.
    let dp = Process::edsgen(&["dp", "scan", &dp_master]).finish(WAIT);
    assert_eq!(dp.code, Some(0), "{dp:?}");
    assert_eq!(dp.stdout, "station 2: Ident_Number 0350h, no master\n");

    // SIGTERM stops every bus, then the machine.
    let term = Command::new("kill")
        .args(["-TERM", &machine.id().to_string()])
        .status()
        .unwrap();
    assert!(term.success());
    let exited = machine.finish(WAIT);
    assert_eq!(exited.code, Some(0), "{exited:?}");
    assert!(
        exited
            .stderr
            .ends_with(&format!("stopped: machine {}\n", file.display())),
        "{exited:?}"
    );
    drop(hub);
    drop(pair);
}
