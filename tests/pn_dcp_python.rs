//! The simulated Goodrive350 PROFINET card against pnio-dcp (a third-party DCP client, pinned in
//! scripts/python-venv.sh), over a veth pair joining two private network namespaces: the
//! controller finds the card by its GSDML's name of station, VendorID and DeviceID, sets a new
//! name and reads it back, sets an IP and reads it back, and flashes the LED; the device prints
//! each change; then `edsgen pn list` and `edsgen pn set-name` do the same from the controller's
//! side. Needs root (namespaces, raw sockets): without it the test says so and passes,
//! except under `CI=true`.

mod process_support;

use std::time::Duration;

use edsgen_demo::netns::{is_root, End, Network};
use process_support::{python, skip, Process, EDSGEN};

#[test]
fn pnio_dcp_finds_names_and_addresses_the_simulated_card() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for the PROFINET test");
        return;
    }
    let Some(python) = python() else { return };
    // pnio-dcp finds its interface by IP address.
    // The device in namespace 0, the controller in namespace 1.
    let mut net = Network::create("pn-dcp", 2).expect("two namespaces");
    let (device_if, ctl) = net
        .veth(End::Namespace(0), End::Namespace(1))
        .expect("a veth pair");
    net.address(1, &ctl, "10.77.0.1/24").expect("an address");
    let inside = |n: usize, program: &str| net.command(n, program).expect("a namespace");
    let device = Process::start(inside(0, EDSGEN).args([
        "simulate",
        "--profinet",
        &device_if,
        "--card",
        "goodrive350-pn",
    ]));
    let started = device.stdout_line(
        |l| l.starts_with("PROFINET device"),
        Duration::from_secs(10),
    );
    assert!(
        started.starts_with(&format!(
            "PROFINET device `goodrive350-pn` (VendorID 0x0350, DeviceID 0x0350) on {device_if}, MAC "
        )),
        "{started}"
    );
    let controller = Process::start(
        inside(1, python.to_str().expect("a UTF-8 path")).args([
            process_support::root()
                .join("scripts/pn_dcp_controller.py")
                .to_str()
                .expect("a UTF-8 path"),
            "10.77.0.1",
            &ctl,
            "goodrive350-pn",
            "drive-7",
        ]),
    );
    let done = controller.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{}", done.stderr);
    assert_eq!(
        done.stdout.lines().collect::<Vec<_>>(),
        vec![
            "found 1 named goodrive350-pn",
            "vendor 0350 device 0350",
            "set name 0",
            "get name drive-7",
            "identify name drive-7",
            "set ip 0",
            "get ip 10.77.0.2",
            "blink 0",
        ]
    );
    for expected in [
        "name of station set to `drive-7`",
        "IP set to 10.77.0.2 mask 255.255.255.0 gateway 0.0.0.0",
        "signal: flashing the LED",
    ] {
        assert_eq!(
            device.stdout_line(|l| l == expected, Duration::from_secs(5)),
            expected
        );
    }
    // edsgen's own bench verbs, from the controller's namespace: the name pnio-dcp set, the
    // IP, the GSDML matched by its IDs; then a new name, seen again.
    let mac = started.rsplit(' ').next().expect("the MAC").to_owned();
    let gsdml = process_support::root().join("eds/goodrive350-pn.xml");
    let gsdml = gsdml.to_str().expect("a UTF-8 path");
    let pn = |args: &[&str]| {
        Process::start(inside(1, EDSGEN).arg("pn").args(args)).finish(Duration::from_secs(20))
    };
    let listed = pn(&["list", &ctl, "--gsdml", gsdml]);
    assert_eq!(listed.code, Some(0), "{}", listed.stderr);
    assert_eq!(
        listed.stdout,
        format!("{mac}\tdrive-7\t0350:0350\t10.77.0.2\tINVT Goodrive350\t{gsdml}\n")
    );
    let set = pn(&["set-name", &ctl, &mac, "line-2.gd350"]);
    assert_eq!(set.code, Some(0), "{}", set.stderr);
    assert_eq!(
        set.stdout,
        format!("{mac}: name of station set to `line-2.gd350`\n")
    );
    let listed = pn(&["list", &ctl]);
    assert_eq!(
        listed.stdout,
        format!("{mac}\tline-2.gd350\t0350:0350\t10.77.0.2\tINVT Goodrive350\n")
    );
    let refused = pn(&["set-name", &ctl, &mac, "Not_A_Name"]);
    assert_eq!(refused.code, Some(2));
    drop(device);
    drop(net);
}
