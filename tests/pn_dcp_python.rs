//! The simulated Goodrive350 PROFINET card against pnio-dcp (a third-party DCP client, pinned in
//! scripts/python-venv.sh), over a veth pair joining two private network namespaces: the
//! controller finds the card by its GSDML's name of station, VendorID and DeviceID, sets a new
//! name and reads it back, sets an IP and reads it back, and flashes the LED; the device prints
//! each change; then `edsgen pn list` and `edsgen pn set-name` do the same from the controller's
//! side. Needs root (namespaces, raw sockets): without it the test says so and passes,
//! except under `CI=true`.

mod process_support;

use std::process::Command;
use std::time::Duration;

use process_support::{python, skip, Process, EDSGEN};

/// Two namespaces and the veth pair between them, deleted on drop (also when the test fails).
struct Link {
    device_ns: String,
    controller_ns: String,
}

fn ip(args: &[&str]) {
    let status = Command::new("ip").args(args).status().expect("ip runs");
    assert!(status.success(), "ip {args:?} failed");
}

impl Link {
    fn new() -> Link {
        let pid = std::process::id();
        let link = Link {
            device_ns: format!("pn-dev-{pid}"),
            controller_ns: format!("pn-ctl-{pid}"),
        };
        ip(&["netns", "add", &link.device_ns]);
        ip(&["netns", "add", &link.controller_ns]);
        let (dev, ctl) = (format!("pnd{pid}"), format!("pnc{pid}"));
        ip(&["link", "add", &dev, "type", "veth", "peer", "name", &ctl]);
        ip(&["link", "set", &dev, "netns", &link.device_ns]);
        ip(&["link", "set", &ctl, "netns", &link.controller_ns]);
        ip(&["-n", &link.device_ns, "link", "set", &dev, "up"]);
        ip(&["-n", &link.controller_ns, "link", "set", &ctl, "up"]);
        // pnio-dcp finds its interface by IP address.
        ip(&[
            "-n",
            &link.controller_ns,
            "addr",
            "add",
            "10.77.0.1/24",
            "dev",
            &ctl,
        ]);
        link
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        // Deleting a namespace deletes the veth end inside it, and so the pair.
        for ns in [&self.device_ns, &self.controller_ns] {
            let _ = Command::new("ip").args(["netns", "del", ns]).status();
        }
    }
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

#[test]
fn pnio_dcp_finds_names_and_addresses_the_simulated_card() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for the PROFINET test");
        return;
    }
    let Some(python) = python() else { return };
    let link = Link::new();
    let pid = std::process::id();
    let device = Process::start(Command::new("ip").args([
        "netns",
        "exec",
        &link.device_ns,
        EDSGEN,
        "simulate",
        "--profinet",
        &format!("pnd{pid}"),
        "--card",
        "goodrive350-pn",
    ]));
    let started = device.stdout_line(
        |l| l.starts_with("PROFINET device"),
        Duration::from_secs(10),
    );
    assert!(
        started.starts_with(&format!(
            "PROFINET device `goodrive350-pn` (VendorID 0x0350, DeviceID 0x0350) on pnd{pid}, MAC "
        )),
        "{started}"
    );
    let controller = Process::start(
        Command::new("ip").args([
            "netns",
            "exec",
            &link.controller_ns,
            python.to_str().expect("a UTF-8 path"),
            process_support::root()
                .join("scripts/pn_dcp_controller.py")
                .to_str()
                .expect("a UTF-8 path"),
            "10.77.0.1",
            &format!("pnc{pid}"),
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
    let ctl = format!("pnc{pid}");
    let pn = |args: &[&str]| {
        let mut all = vec!["netns", "exec", &link.controller_ns, EDSGEN, "pn"];
        all.extend_from_slice(args);
        Process::start(Command::new("ip").args(&all)).finish(Duration::from_secs(20))
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
    drop(link);
}
