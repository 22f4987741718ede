//! `edsgen pn`'s bench verbs over a veth pair joining two private network namespaces: `list`
//! (its window said, the card's line), `set-ip` by name and by MAC (permanent and temporary,
//! the device taking datagrams at its new address), `blink`, `im` (I&M0 in words) and `record`
//! (a hex dump, and a refused index in words) against the simulated Goodrive350 card; `im`
//! against p-net's Linux sample (`../shared/peers/p-net/pn_dev_veth`), a device nobody here
//! wrote. Needs root (namespaces, raw sockets) and, for p-net, the peers folder: without them
//! the tests say so and pass, except under `CI=true`.

mod process_support;

use std::path::PathBuf;
use std::time::Duration;

use process_support::netns::{is_root, VethPair};
use process_support::{skip, Exited, Process, EDSGEN};

impl VethPair {
    /// `edsgen pn ARGS` in the controller's namespace, to its end.
    fn pn(&self, args: &[&str]) -> Exited {
        Process::start(self.inside(1, EDSGEN).arg("pn").args(args)).finish(WAIT)
    }
}

const WAIT: Duration = Duration::from_secs(20);

/// What an `edsgen` run said: (exit code, standard output, standard error).
fn said(exited: &Exited) -> (Option<i32>, &str, &str) {
    (exited.code, exited.stdout.as_str(), exited.stderr.as_str())
}

#[test]
fn the_bench_verbs_list_address_blink_and_read_the_simulated_card() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for `pn`");
        return;
    }
    let net = VethPair::new(
        "pn-bench",
        &["10.83.0.2/24", "10.83.0.9/24"],
        &["10.83.0.1/24"],
    );
    let ctl = net.master_if.as_str();
    let device = Process::start(net.inside(0, EDSGEN).args([
        "simulate",
        "--profinet",
        &net.device_if,
        "--card",
        "goodrive350-pn@drive-7",
    ]));
    let started = device.stdout_line(|l| l.starts_with("PROFINET device"), WAIT);
    let mac = started.rsplit(' ').next().expect("the MAC").to_owned();

    let listed = net.pn(&["list", ctl, "--window", "300"]);
    assert_eq!(
        said(&listed),
        (
            Some(0),
            format!("{mac}\tdrive-7\t0350:0350\t10.83.0.2\tINVT Goodrive350\n").as_str(),
            format!(
                "listening 0.8 s for DCP Identify answers on {ctl} (ResponseDelayFactor 30: devices answer within 0.30 s)\n"
            )
            .as_str()
        )
    );

    // A new permanent IP by name, with a gateway: the device takes RPC there (I&M0 below).
    let set = net.pn(&["set-ip", ctl, "drive-7", "10.83.0.9/24", "10.83.0.1"]);
    assert_eq!(
        said(&set),
        (
            Some(0),
            format!(
                "{mac}: IP set to 10.83.0.9 mask 255.255.255.0 gateway 10.83.0.1 (permanent)\n"
            )
            .as_str(),
            ""
        )
    );
    let expected = "IP set to 10.83.0.9 mask 255.255.255.0 gateway 10.83.0.1";
    assert_eq!(device.stdout_line(|l| l == expected, WAIT), expected);
    let im = net.pn(&["im", ctl, "drive-7"]);
    assert_eq!(
        said(&im),
        (
            Some(0),
            "vendor ID: 0x0350\n\
             order ID: INVT Goodrive350\n\
             serial number: 0001\n\
             hardware revision: 1\n\
             software revision: V1.0.0\n\
             revision counter: 0\n\
             profile: 0x0000, specific type 0x0000\n\
             I&M version: 1.1, records: I&M0\n",
            ""
        )
    );

    // Back to the first address by MAC, temporarily; the record by its new address.
    let set = net.pn(&["set-ip", ctl, &mac, "10.83.0.2/24", "--temporary"]);
    assert_eq!(
        said(&set),
        (
            Some(0),
            format!("{mac}: IP set to 10.83.0.2 mask 255.255.255.0 gateway 0.0.0.0 (temporary)\n")
                .as_str(),
            ""
        )
    );
    // Record 256 of the drive's subslot: P16.32 to P16.42, what each PZD output word sets
    // (by default PZD2 the frequency reference, P16.32 = 1).
    let record = net.pn(&[
        "record",
        ctl,
        "drive-7",
        "--slot",
        "1",
        "--subslot",
        "1",
        "--index",
        "256",
    ]);
    assert_eq!(
        said(&record),
        (
            Some(0),
            "record 0x0100 of slot 1 subslot 0x0001: 22 bytes\n\
             0000  00 01 00 00 00 00 00 00 00 00 00 00 00 00 00 00\n\
             0010  00 00 00 00 00 00\n",
            ""
        )
    );
    let refused = net.pn(&[
        "record",
        ctl,
        "drive-7",
        "--slot",
        "1",
        "--subslot",
        "0x0001",
        "--index",
        "0x03e7",
    ]);
    assert_eq!(
        said(&refused),
        (
            Some(1),
            "",
            "`drive-7` refused the read of record 0x03e7 of slot 1 subslot 0x0001: PNIOStatus de 80 b0 00 (invalid index)\n"
        )
    );

    let blink = net.pn(&["blink", ctl, "drive-7"]);
    assert_eq!(
        said(&blink),
        (
            Some(0),
            format!("{mac}: flashing its LED (DCP Control Signal)\n").as_str(),
            ""
        )
    );
    let expected = "signal: flashing the LED";
    assert_eq!(device.stdout_line(|l| l == expected, WAIT), expected);

    let missing = net.pn(&["im", ctl, "nobody"]);
    assert_eq!(
        said(&missing),
        (
            Some(1),
            "",
            format!("no device named `nobody` answered on {ctl} within 2 s\n").as_str()
        )
    );
    let bad = net.pn(&["set-ip", ctl, "drive-7", "10.83.0.9"]);
    assert_eq!(
        said(&bad),
        (
            Some(2),
            "",
            "error: `10.83.0.9` is not ADDR/PREFIX (such as 10.0.0.5/24)\n"
        )
    );
    drop(device);
}

/// p-net's peer folder, or a skip.
fn p_net() -> Option<PathBuf> {
    let dir = process_support::root().join("../shared/peers/p-net");
    if dir.join("pn_dev_veth").is_file() {
        Some(dir)
    } else {
        skip(format!("no p-net peer at {}", dir.display()))
    }
}

#[test]
fn pn_im_reads_p_nets_sample_device() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for `pn im`");
        return;
    }
    let Some(peer) = p_net() else { return };
    let net = VethPair::new("pn-im", &["10.84.0.2/24"], &["10.84.0.1/24"]);
    let storage = std::env::temp_dir().join(format!("edsgen-pn-im-{}", std::process::id()));
    std::fs::create_dir_all(&storage).expect("a storage folder");
    let binary = peer.join("pn_dev_veth");
    let mut command = net.inside(0, binary.to_str().expect("a UTF-8 path"));
    command
        .args([
            "-i",
            &net.device_if,
            "-p",
            storage.to_str().expect("a UTF-8 path"),
        ])
        .current_dir(&peer);
    let device = Process::start(&mut command);
    device.stdout_line(|l| l.starts_with("Network script for"), WAIT);
    std::thread::sleep(Duration::from_millis(500));
    let im = net.pn(&["im", &net.master_if, "rt-labs-dev"]);
    let _ = std::fs::remove_dir_all(&storage);
    // The sample application's own identity (its I&M0 data, in p-net's sample sources),
    // I&M1 to I&M3 supported beside I&M0.
    assert_eq!(
        said(&im),
        (
            Some(0),
            "vendor ID: 0x0493\n\
             order ID: 12345 Abcdefghijk\n\
             serial number: 007\n\
             hardware revision: 3\n\
             software revision: V0.2.0\n\
             revision counter: 0\n\
             profile: 0x1234, specific type 0x5678\n\
             I&M version: 1.1, records: I&M0, I&M1, I&M2, I&M3\n",
            ""
        )
    );
    drop(device);
}
