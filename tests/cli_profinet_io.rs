//! `edsgen pn io`, the PROFINET IO controller at the bench, over a veth pair joining two
//! private network namespaces: against `edsgen simulate --profinet --card goodrive350-pn` (the
//! device taking its interface's address, the drive run to 5.00 Hz and a PKW read of P00.11 by name, a drive fault's Diagnosis alarm
//! printed and acknowledged, the AR released on SIGTERM), and against p-net's Linux sample
//! (`../shared/peers/p-net/pn_dev_veth`, a device nobody here wrote: its echo module's gain
//! set by a parameter record, its inputs the outputs times the gain). Needs root (namespaces,
//! raw sockets) and, for p-net, the peers folder: without them the tests say so and pass,
//! except under `CI=true`.

mod process_support;

use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

use process_support::netns::{is_root, VethPair};
use process_support::{skip, Process, EDSGEN};

/// Reads `process`'s standard output into `said` up to the line `wanted` accepts.
fn lines_until(process: &Process, wanted: impl Fn(&str) -> bool, said: &mut Vec<String>) -> String {
    loop {
        let Some(line) = process.next_line(Duration::from_secs(30)) else {
            panic!("the line wanted did not come within 30 s; it said {said:#?}");
        };
        said.push(line.clone());
        if wanted(&line) {
            return line;
        }
    }
}

const ZEROS_20: &str = "0000000000000000000000000000000000000000";

#[test]
fn pn_io_runs_the_simulated_goodrive350_by_name_and_acknowledges_its_alarm() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for `pn io`");
        return;
    }
    let net = VethPair::new("pn-io", &["10.78.0.2/24"], &["10.78.0.1/24"]);
    let mut device = Process::start(net.inside(0, EDSGEN).args([
        "simulate",
        "--profinet",
        &net.device_if,
        "--card",
        "goodrive350-pn",
        "--faults-on-stdin",
    ]));
    // Without --ip, the device takes its interface's address.
    assert_eq!(
        device.stdout_line(|l| l.starts_with("RPC on"), Duration::from_secs(10)),
        format!(
            "RPC on UDP 34964 at 10.78.0.2 mask 255.255.255.0 ({}'s address)",
            net.device_if
        )
    );
    let gsdml = process_support::root().join("eds/goodrive350-pn.xml");
    // PZD2 out is the frequency reference (P16.32 = 1), PZD2 in the running frequency
    // (P16.43 = 1); PKW task 1 reads P00.11 (acceleration time, 10.0 s).
    let reference = format!("1.1.256=0001{ZEROS_20}");
    let actual = format!("1.1.257=0001{ZEROS_20}");
    let controller = Process::start(net.inside(1, EDSGEN).args([
        "pn",
        "io",
        &net.master_if,
        "goodrive350-pn",
        "--gsdml",
        gsdml.to_str().expect("a UTF-8 path"),
        "--record",
        &reference,
        "--record",
        &actual,
        "CW=1",
        "PZD2=500",
        "PKW1=1",
        "PKW2=0x000B",
    ]));
    let mut said = Vec::new();
    let found = lines_until(&controller, |l| l.starts_with("device "), &mut said);
    assert!(
        found.starts_with("device `goodrive350-pn` at ")
            && found.ends_with(", IP 10.78.0.2, VendorID 0x0350, DeviceID 0x0350"),
        "{found}"
    );
    said.clear();
    lines_until(
        &controller,
        |l| l.starts_with("application ready"),
        &mut said,
    );
    assert_eq!(
        said,
        [
            "connected: input frame 0xc001, output frame 0xc102, every 8 ms",
            "wrote record 256 of slot 1 subslot 1 (22 bytes)",
            "wrote record 257 of slot 1 subslot 1 (22 bytes)",
            "application ready: exchanging data",
        ]
    );
    let running = "inputs 1.1: PKW1=1 PKW2=11 PKW3=0 PKW4=100 SW=0x4101 PZD2=500 PZD3=0 PZD4=0 \
                   PZD5=0 PZD6=0 PZD7=0 PZD8=0 PZD9=0 PZD10=0 PZD11=0 PZD12=0";
    lines_until(&controller, |l| l == running, &mut said);
    device.send_line("fault");
    let alarm = lines_until(&controller, |l| l.starts_with("alarm"), &mut said);
    assert_eq!(
        alarm,
        "alarm: Diagnosis (0x0001) in slot 1 subslot 1, sequence 0, low priority: acknowledged"
    );
    assert_eq!(
        device.stdout_line(|l| l.starts_with("alarm"), Duration::from_secs(5)),
        "alarm 0x0001 of slot 1 subslot 1 acknowledged (sequence 0, PNIOStatus 00000000)"
    );
    let stopped = Command::new("kill")
        .args(["-TERM", &controller.id().to_string()])
        .status()
        .expect("kill");
    assert!(stopped.success());
    let done = controller.finish(Duration::from_secs(10));
    assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
    let last = done.stdout.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("released the AR after ") && last.ends_with(" cycles"),
        "{}",
        done.stdout
    );
    assert_eq!(
        device.stdout_line(|l| l == "AR released", Duration::from_secs(5)),
        "AR released"
    );
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
fn pn_io_exchanges_data_with_p_nets_sample_device() {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for `pn io`");
        return;
    }
    let Some(peer) = p_net() else { return };
    let net = VethPair::new("pn-pnet", &["10.77.0.2/24"], &["10.77.0.1/24"]);
    let storage = std::env::temp_dir().join(format!("edsgen-pn-io-{}", std::process::id()));
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
    device.stdout_line(
        |l| l.starts_with("Network script for"),
        Duration::from_secs(20),
    );
    std::thread::sleep(Duration::from_millis(500));
    let gsdml = peer.join("GSDML-V2.4-RT-Labs-P-Net-Sample-App-20220324.xml");
    let controller = Process::start(net.inside(1, EDSGEN).args([
        "pn",
        "io",
        &net.master_if,
        "rt-labs-dev",
        "--gsdml",
        gsdml.to_str().expect("a UTF-8 path"),
        "--module",
        "1=IDM_40",
        "--module",
        "2=IDM_31",
        "--record",
        "1.1.125=00000003",
        "--cycles",
        "150",
        "Output int from controller=7",
        "Output float from controller=1.5",
        "Output 8 bits=0x81",
    ]));
    let done = controller.finish(Duration::from_secs(30));
    drop(device);
    let _ = std::fs::remove_dir_all(&storage);
    assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
    let lines: Vec<&str> = done.stdout.lines().collect();
    assert!(
        lines[0].starts_with("device `rt-labs-dev` at ")
            && lines[0].ends_with(", IP 10.77.0.2, VendorID 0x0493, DeviceID 0x0002"),
        "{}",
        done.stdout
    );
    assert_eq!(
        lines[1..],
        [
            "connected: input frame 0xc001, output frame 0xc000, every 8 ms",
            "wrote record 125 of slot 1 subslot 1 (4 bytes)",
            "application ready: exchanging data",
            "inputs 1.1: Input float to controller=0 Input int to controller=0",
            "inputs 1.1: Input float to controller=4.5 Input int to controller=21",
            "released the AR after 150 cycles",
        ],
        "{}",
        done.stdout
    );
}
