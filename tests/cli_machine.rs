//! `edsgen simulate --machine FILE`: bad machine files refused before anything starts, each
//! problem at its line; a machine of two buses (CANopen cards on an edsgen bus, a Goodrive350
//! EtherNet/IP adapter on 127.0.0.1) brought up, answering its masters, routing faults by name
//! and stopping cleanly on SIGTERM.

mod process_support;

use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};

use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::CanFrame;

use process_support::{Process, EDSGEN};

/// How long a line or an exit may take.
const WAIT: Duration = Duration::from_secs(15);

/// `text` as `NAME` in a folder of this test's own, beside an EDS `vendor.eds` (a copy of the
/// bundled CP301's, for the relative paths).
fn machine_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("edsgen-machine-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/eds/cp301.eds"),
        dir.join("vendor.eds"),
    )
    .unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// `edsgen simulate --machine PATH`'s exit code and standard error, for a file refused at once.
fn refused(path: &PathBuf) -> (Option<i32>, String) {
    let out = Command::new(EDSGEN)
        .args(["simulate", "--machine"])
        .arg(path)
        .output()
        .unwrap();
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "",
        "nothing is started"
    );
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_machine_files_are_refused_with_their_lines_before_anything_starts() {
    let path = machine_file(
        "bad.toml",
        r#"[[canopen]]
bus = "127.0.0.1:1"
devices = ["cp302@2", "goodrive350@3", "cp301@3", "missing.eds@9", "vendor.eds"]

[[ethercat]]
devices = ["ec-tx508"]

[[enip]]
devices = [{ device = "goodrive350-enip", address = "10.0.0.21" }, { device = "goodrive350-enip", address = "10.0.0.21", name = "b" }]

[[profinet]]
interface = "veth9"
devices = ["goodrive350-pn@port-001"]

[[profibuss]]
tty = "/dev/ttyS1"
"#,
    );
    let (code, stderr) = refused(&path);
    let p = path.display();
    assert_eq!(code, Some(2));
    assert_eq!(
        stderr,
        format!(
            "error: {p}:3:12: no canopen card `cp302` (did you mean `cp301`?): the bundled ones are cp301, ms300, goodrive350, rd11, hd1e; a file is a path (`vendor/drive.eds`)
error: {p}:3:40: node 3 on bus 127.0.0.1:1 is taken by an earlier device
error: {p}:3:51: no file `{dir}/missing.eds` (relative to the machine file)
error: {p}:3:68: `vendor.eds` needs its node-ID: `vendor.eds@ID`
error: {p}:5:1: [[ethercat]] without its `interface`
error: {p}:9:68: IP address 10.0.0.21 is taken by an earlier device
error: {p}:13:12: `port-001` is not a PROFINET name of station: a first label of the form `port-xyz` or `port-xyz-abcde`, which names a port
error: {p}:15:3: unknown table `profibuss` (did you mean `[[profibus]]`?): a machine file has [[canopen]], [[ethercat]], [[profibus]], [[profinet]] and [[enip]]
error: {p}: 8 problem(s); nothing was started
",
            dir = path.parent().unwrap().display()
        )
    );
}

#[test]
fn a_machine_file_that_is_not_toml_or_has_unknown_keys_is_refused() {
    let path = machine_file("syntax.toml", "[[canopen]\nbus = 1\n");
    let (code, stderr) = refused(&path);
    assert_eq!(code, Some(2));
    assert!(
        stderr.starts_with(&format!("error: {}:1:", path.display())) && stderr.contains("not TOML"),
        "{stderr}"
    );
    let path = machine_file(
        "keys.toml",
        "[[profibus]]\ntty = \"/dev/ttyS1\"\nbaud = 19200\ndevices = [\"goodrive350-dp@126\"]\n\n[[canopen]]\nsocketcan = \"can0\"\ndevices = [\"cp301\", \"vendor.eds@2\", { device = \"ms300\", name = \"cp301\" }, { device = \"hd1e\", ip = \"10.0.0.1\" }]\n",
    );
    let (code, stderr) = refused(&path);
    let p = path.display();
    assert_eq!(code, Some(2));
    assert_eq!(
        stderr,
        format!(
            "error: {p}:3:1: unknown key `baud` in [[profibus]] (it takes `tty`, `devices`)
error: {p}:4:12: bad station address `126` in `goodrive350-dp@126` (0 to 125)
error: {p}:8:21: node 2 on SocketCAN can0 is taken by an earlier device
error: {p}:8:37: a second device named `cp301`: faults on standard input name one device; give each its own `name`
error: {p}:8:94: unknown key `ip` in a canopen device (it takes `device`, `name`)
error: {p}: 5 problem(s); nothing was started
"
        )
    );
}

/// A free TCP port on 127.0.0.1 (for the EtherNet/IP adapter, beside other tests' adapters).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

#[test]
fn a_machine_of_two_buses_comes_up_answers_routes_faults_and_stops_on_sigterm() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let bus = hub.local_addr().to_string();
    let enip = format!("127.0.0.1:{}", free_port());
    let path = machine_file(
        "line.toml",
        &format!(
            r#"[[canopen]]
bus = "{bus}"
devices = ["goodrive350@3", "vendor.eds@9"]

[[enip]]
devices = [{{ device = "goodrive350-enip", address = "{enip}", name = "fan-1" }}]
"#
        ),
    );
    let mut machine = Process::edsgen(&["simulate", "--machine", path.to_str().unwrap()]);
    // The plan first: every device with its bus and address.
    let dir = path.parent().unwrap().display().to_string();
    let first = machine.stdout_line(|l| l.starts_with("canopen"), WAIT);
    assert_eq!(
        first,
        format!(
            "{:<9} {:<24} {:<32} node 3 on bus {bus}",
            "canopen", "goodrive350@3", "card goodrive350"
        )
    );
    let second = machine.stdout_line(|l| l.starts_with("canopen"), WAIT);
    assert_eq!(
        second,
        format!(
            "{:<9} {:<24} {:<32} node 9 on bus {bus}",
            "canopen",
            "vendor.eds@9",
            format!("{dir}/vendor.eds")
        )
    );
    let third = machine.stdout_line(|l| l.starts_with("enip"), WAIT);
    assert_eq!(
        third,
        format!(
            "{:<9} {:<24} {:<32} address {enip} on this host",
            "enip", "fan-1", "card goodrive350-enip"
        )
    );
    // Each bus's own lines, prefixed with the bus (the buses start side by side: in any order).
    let mut waiting = vec![
        format!("[canopen bus {bus}] simulating node 3 (card goodrive350) on {bus}"),
        format!("[canopen bus {bus}] simulating node 9 ({dir}/vendor.eds) on {bus}"),
        format!("[enip {enip}] serving card goodrive350-enip on {enip} "),
    ];
    while !waiting.is_empty() {
        let line = machine.stderr_line(|l| waiting.iter().any(|w| l.starts_with(w)), WAIT);
        waiting.retain(|w| !line.starts_with(w));
    }
    // The CANopen devices answer their SDOs: 1018h:01 (vendor-ID) of both.
    let mut master = SocketcandClient::connect(&bus, "can0", Duration::from_secs(3)).unwrap();
    std::thread::sleep(Duration::from_millis(100));
    for node in [3u16, 9] {
        master
            .send(&CanFrame::new(0x600 + node, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]).unwrap())
            .unwrap();
        let deadline = Instant::now() + WAIT;
        loop {
            assert!(Instant::now() < deadline, "node {node} did not answer");
            if let Some(frame) = master.recv_timeout(Duration::from_millis(50)).unwrap() {
                if frame.std_id() == Some(0x580 + node) {
                    assert_eq!(frame.data()[..4], [0x43, 0x18, 0x10, 0x01]);
                    break;
                }
            }
        }
    }
    // The adapter answers Get_Attributes_All of its Identity.
    let identity = Command::new(EDSGEN)
        .args(["enip", "get", &enip, "@1/1"])
        .output()
        .unwrap();
    assert!(identity.status.success(), "{identity:?}");
    // Faults by name: these devices take none from standard input, and the machine says so.
    machine.send_line("fault fan-1");
    machine.stderr_line(
        |l| l == "machine: no device `fan-1` takes faults from standard input (none of this machine's devices does)",
        WAIT,
    );
    // SIGTERM stops every bus, then the machine.
    let term = Command::new("kill")
        .args(["-TERM", &machine.id().to_string()])
        .status()
        .unwrap();
    assert!(term.success());
    let exited = machine.finish(WAIT);
    assert_eq!(exited.code, Some(0), "{}", exited.stderr);
    assert!(
        exited
            .stderr
            .ends_with(&format!("stopped: machine {}\n", path.display())),
        "{}",
        exited.stderr
    );
    assert!(
        exited.stderr.contains(&format!("[enip {enip}] stopped: ")),
        "{}",
        exited.stderr
    );
}

#[test]
fn no_bus_outlives_a_machine_that_is_killed() {
    let enip = format!("127.0.0.1:{}", free_port());
    let path = machine_file(
        "killed.toml",
        &format!(
            "[[enip]]\ndevices = [{{ device = \"goodrive350-enip\", address = \"{enip}\" }}]\n"
        ),
    );
    let machine = Process::edsgen(&["simulate", "--machine", path.to_str().unwrap()]);
    machine.stderr_line(|l| l.starts_with(&format!("[enip {enip}] serving ")), WAIT);
    let killed = Command::new("kill")
        .args(["-KILL", &machine.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    // The adapter stops with its machine: its TCP port is free again.
    let deadline = Instant::now() + WAIT;
    while std::net::TcpListener::bind(&enip).is_err() {
        assert!(
            Instant::now() < deadline,
            "the adapter on {enip} outlived its machine"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}
