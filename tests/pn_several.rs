//! Two simulated Goodrive350 PROFINET cards on one interface (`simulate --profinet IFACE --card
//! goodrive350-pn@line-a --card goodrive350-pn@line-b`), a bridge in a private network
//! namespace with a veth to each of two controllers' namespaces, the bridge with two addresses
//! that the cards take in order:
//! pnio-dcp (a third-party DCP client) finds both with their names, IPs and MACs and names
//! them anew; `edsgen pn list` lists both; then two controllers at once, each on one card:
//! `edsgen pn io` on drive-a while profinet-py's `profinet cyclic` runs drive-b, then the other
//! way round; each card prints its own ARs after its name. Needs root (namespaces, raw
//! sockets): without it the test says so and passes, except under `CI=true`.

mod process_support;

use std::process::Command;
use std::time::Duration;

use edsgen_demo::netns::{is_root, End, Network};
use process_support::{python, skip, Process, EDSGEN};

/// pnio-dcp: identify all (sorted by name), rename each device in that order to the names
/// given, identify all again.
const PNIO_DCP: &str = r#"
import sys
import pnio_dcp
dcp = pnio_dcp.DCP(sys.argv[1])
def found():
    return sorted(dcp.identify_all(timeout=2), key=lambda d: d.name_of_station)
before = found()
for d in before:
    print("found", d.name_of_station, d.IP, d.MAC, flush=True)
for d, new in zip(before, sys.argv[2:]):
    print("set", d.MAC, new, dcp.set_name_of_station(d.MAC, new).code, flush=True)
for d in found():
    print("found", d.name_of_station, d.IP, d.MAC, flush=True)
"#;

/// Twenty zero bytes in hex: the rest of a PZD mapping record.
const ZEROS_20: &str = "0000000000000000000000000000000000000000";

#[test]
fn two_cards_on_one_interface_are_found_named_and_driven_each_by_its_own_controller() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for the PROFINET test");
        return;
    }
    let Some(python) = python() else { return };
    // The device's namespace (0) bridges a veth to each controller's (1 and 2): two hosts
    // on the devices' segment, each with its own UDP 34964.
    let mut net = Network::create("pn-two", 3).expect("three namespaces");
    let (to_1, ctl) = net
        .veth(End::Namespace(0), End::Namespace(1))
        .expect("a veth pair");
    let (to_2, ctl_2) = net
        .veth(End::Namespace(0), End::Namespace(2))
        .expect("a veth pair");
    let device_if = format!("br{}", std::process::id());
    let ns0 = net.namespace(0).expect("namespace 0").to_owned();
    for args in [
        vec!["link", "add", &device_if, "type", "bridge"],
        vec!["link", "set", &to_1, "master", &device_if],
        vec!["link", "set", &to_2, "master", &device_if],
        vec!["link", "set", &device_if, "up"],
    ] {
        let done = Command::new("ip")
            .args(["-n", &ns0])
            .args(&args)
            .status()
            .expect("ip runs");
        assert!(done.success(), "ip {args:?}");
    }
    net.address(0, &device_if, "10.82.0.2/24")
        .expect("an address");
    net.address(0, &device_if, "10.82.0.3/24")
        .expect("an address");
    net.address(1, &ctl, "10.82.0.1/24").expect("an address");
    net.address(2, &ctl_2, "10.82.0.4/24").expect("an address");
    let inside =
        |n: usize, program: &str| -> Command { net.command(n, program).expect("a namespace") };
    let device = Process::start(inside(0, EDSGEN).args([
        "simulate",
        "--profinet",
        &device_if,
        "--card",
        "goodrive350-pn@line-a",
        "--card",
        "goodrive350-pn@line-b",
    ]));
    let wait = Duration::from_secs(10);
    let mut started = Vec::new();
    for _ in 0..4 {
        started.push(device.next_line(wait).expect("the start lines"));
    }
    let mac_of = |line: &str| line.rsplit(' ').next().expect("a MAC").to_owned();
    let (mac_a, mac_b) = (mac_of(&started[0]), mac_of(&started[2]));
    assert_eq!(
        started,
        [
            format!("PROFINET device `line-a` (VendorID 0x0350, DeviceID 0x0350) on {device_if}, MAC {mac_a}"),
            format!("RPC on UDP 34964 at 10.82.0.2 mask 255.255.255.0 ({device_if}'s address)"),
            format!("PROFINET device `line-b` (VendorID 0x0350, DeviceID 0x0350) on {device_if}, MAC {mac_b}"),
            format!("RPC on UDP 34964 at 10.82.0.3 mask 255.255.255.0 ({device_if}'s address)"),
        ]
    );
    // The second card's MAC: the first's (the interface's), locally administered, plus one.
    let bytes = |mac: &str| -> Vec<u8> {
        mac.split(':')
            .map(|b| u8::from_str_radix(b, 16).expect("hex"))
            .collect()
    };
    let (a, b) = (bytes(&mac_a), bytes(&mac_b));
    let low = |m: &[u8]| u32::from_be_bytes([0, m[3], m[4], m[5]]);
    assert_eq!(b[0], (a[0] | 0x02) & !0x01);
    assert_eq!(b[1..3], a[1..3]);
    assert_eq!(low(&b), (low(&a) + 1) & 0x00FF_FFFF);

    // pnio-dcp finds both, names them, and finds them by their new names.
    let dcp = Process::start(inside(1, python.to_str().expect("a UTF-8 path")).args([
        "-c",
        PNIO_DCP,
        "10.82.0.1",
        "drive-a",
        "drive-b",
    ]));
    let done = dcp.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{}", done.stderr);
    assert_eq!(
        done.stdout.lines().collect::<Vec<_>>(),
        [
            format!("found line-a 10.82.0.2 {mac_a}"),
            format!("found line-b 10.82.0.3 {mac_b}"),
            format!("set {mac_a} drive-a 0"),
            format!("set {mac_b} drive-b 0"),
            format!("found drive-a 10.82.0.2 {mac_a}"),
            format!("found drive-b 10.82.0.3 {mac_b}"),
        ]
    );
    // Each line names its device as it is after the event.
    for expected in [
        "drive-a: name of station set to `drive-a`",
        "drive-b: name of station set to `drive-b`",
    ] {
        assert_eq!(device.stdout_line(|l| l == expected, wait), expected);
    }
    let listed = Process::start(inside(1, EDSGEN).args(["pn", "list", &ctl]))
        .finish(Duration::from_secs(20));
    assert_eq!(listed.code, Some(0), "{}", listed.stderr);
    let mut lines: Vec<&str> = listed.stdout.lines().collect();
    lines.sort_unstable();
    let mut expected = [
        format!("{mac_a}\tdrive-a\t0350:0350\t10.82.0.2\tINVT Goodrive350"),
        format!("{mac_b}\tdrive-b\t0350:0350\t10.82.0.3\tINVT Goodrive350"),
    ];
    expected.sort_unstable();
    assert_eq!(lines, expected);

    // Two controllers at once, one per card, then the other way round.
    let gsdml = process_support::root().join("eds/goodrive350-pn.xml");
    let gsdml = gsdml.to_str().expect("a UTF-8 path");
    let profinet = python.with_file_name("profinet");
    for (by_pn_io, by_profinet_py, profinet_py_ip) in [
        ("drive-a", "drive-b", "10.82.0.3"),
        ("drive-b", "drive-a", "10.82.0.2"),
    ] {
        // PZD2 out is the frequency reference (P16.32 = 1), PZD2 in the running frequency
        // (P16.43 = 1).
        let pn_io = Process::start(inside(2, EDSGEN).args([
            "pn",
            "io",
            &ctl_2,
            by_pn_io,
            "--gsdml",
            gsdml,
            "--record",
            &format!("1.1.256=0001{ZEROS_20}"),
            "--record",
            &format!("1.1.257=0001{ZEROS_20}"),
            "CW=1",
            "PZD2=500",
        ]));
        let ready = pn_io.stdout_line(
            |l| l.starts_with("application ready"),
            Duration::from_secs(30),
        );
        assert_eq!(ready, "application ready: exchanging data");
        let py = Process::start(inside(1, profinet.to_str().expect("a UTF-8 path")).args([
            "-i",
            &ctl,
            "cyclic",
            by_profinet_py,
            "--gsdml",
            gsdml,
            "--cycle-ms",
            "8",
            "--duration",
            "2",
        ]))
        .finish(Duration::from_secs(60));
        assert_eq!(py.code, Some(0), "{}\n{}", py.stdout, py.stderr);
        let connecting = format!("Connecting to {by_profinet_py} ({profinet_py_ip})...");
        assert!(py.stdout.lines().any(|l| l == connecting), "{}", py.stdout);
        let received: u32 = py
            .stdout
            .lines()
            .find_map(|l| l.strip_prefix("Stopped. TX="))
            .and_then(|l| l.split("RX=").nth(1))
            .and_then(|r| r.split(' ').next())
            .and_then(|n| n.parse().ok())
            .expect("RX=N");
        assert!(received > 0, "{}", py.stdout);
        // pn io's card runs its drive on CW 1 to 5.00 Hz, and its AR lasts until released
        // (a lost device ends `pn io` with exit 1).
        let running = pn_io.stdout_line(
            |l| l.starts_with("inputs 1.1:") && l.contains(" PZD2=500 "),
            Duration::from_secs(30),
        );
        assert!(running.contains(" SW=0x"), "{running}");
        let stopped = Command::new("kill")
            .args(["-TERM", &pn_io.id().to_string()])
            .status()
            .expect("kill");
        assert!(stopped.success());
        let done = pn_io.finish(Duration::from_secs(10));
        assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
        let last = done.stdout.lines().last().unwrap_or_default();
        assert!(
            last.starts_with("released the AR after "),
            "{}",
            done.stdout
        );
        // Each card tells its own ARs apart.
        for (name, ar) in [
            (by_pn_io, "AR connected (ARType 0x0001): input FrameID 0xc001, output FrameID 0xc102, every 8000 us"),
            (by_profinet_py, "ApplicationReady confirmed: cyclic data exchange"),
            (by_pn_io, "AR released"),
        ] {
            let expected = format!("{name}: {ar}");
            assert_eq!(device.stdout_line(|l| l == expected, wait), expected);
        }
    }
    drop(device);
    drop(net);
}
