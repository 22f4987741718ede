//! LSS (CiA 305) end to end: `edsgen simulate` with three unconfigured devices (`@255`: two of
//! one kind, CANopenSocket's basicDevice, which get serial numbers 0 and 1, and CANopenDemo's
//! demoDevice; both files say `LSS_Supported=1`) on a socketcand hub, configured by python
//! `canopen` 2.4.1's LSS master (`scripts/lss_master.py`: fastscan, configure node-ID, store,
//! switch, inquire, bit timing) and by `edsgen lss`; each device then boots up and answers SDO
//! at its new node-ID. The bundled cards say `LSS_Supported=0`: `@255` is refused for them.

mod process_support;

use std::time::Duration;

use edsgen_host::hub::{Hub, HubOptions};
use process_support::{corpus_file, python, Process, EDSGEN, START_TIMEOUT};

/// One fastscan at a time: python `canopen` waits 10 ms after a probe's first answer for the
/// other slaves' answers, and two scans at once (each with its hub, simulator and master) on
/// this machine's two cores can delay an answer past that, so that it counts for the next probe.
static ONE_SCAN_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

const BASIC: &str = "CANopenNode__CANopenSocket/examples__basicDevice__basicDevice.eds";
const DEMO: &str = "CANopenNode__CANopenDemo/demo__demoDevice.eds";

/// A hub and `edsgen simulate` with the three unconfigured devices on it; the hub's address
/// and the simulator's announcements of their LSS addresses.
fn three_unconfigured() -> Option<(Hub, Process, String, Vec<String>)> {
    let basic = corpus_file(BASIC)?;
    let demo = corpus_file(DEMO)?;
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).expect("the hub starts");
    let addr = hub.local_addr().to_string();
    let (basic, demo) = (
        format!("{}@255", basic.display()),
        format!("{}@255", demo.display()),
    );
    let sim = Process::edsgen(&["simulate", &basic, &basic, &demo, "--bus", &addr]);
    // Each device's LSS address, then its start.
    let mut announced = Vec::new();
    for _ in 0..3 {
        announced.push(sim.stderr_line(|l| l.starts_with("unconfigured node"), START_TIMEOUT));
        sim.stderr_line(
            |l| l.starts_with("simulating unconfigured node"),
            START_TIMEOUT,
        );
    }
    Some((hub, sim, addr, announced))
}

fn edsgen(args: &[&str]) -> (Option<i32>, String, String) {
    let out = std::process::Command::new(EDSGEN)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn python_canopen_configures_every_unconfigured_device_by_fastscan() {
    let _scan = ONE_SCAN_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some(python) = python() else { return };
    let Some((_hub, _sim, addr, announced)) = three_unconfigured() else {
        return;
    };
    let announced: Vec<&str> = announced
        .iter()
        .map(|l| l.split(['(', ')']).nth(1).unwrap())
        .collect();
    assert_eq!(
        announced,
        [
            "LSS address 0x00000000:0x00000000:0x00000000:0x00000000",
            "LSS address 0x00000000:0x00000000:0x00000000:0x00000001",
            "LSS address 0x00000000:0x00000001:0x00000000:0x00000003",
        ]
    );
    let (host, port) = addr.rsplit_once(':').unwrap();
    let master = Process::python(&python, "scripts/lss_master.py", &[host, port, "10"]);
    let exited = master.finish(Duration::from_secs(90));
    assert_eq!(exited.code, Some(0), "{}\n{}", exited.stdout, exited.stderr);
    let lines: Vec<&str> = exited.stdout.lines().collect();
    assert_eq!(
        lines,
        [
            "found 0x00000000:0x00000000:0x00000000:0x00000000 node 10 boot-up serial 0x00000000",
            "found 0x00000000:0x00000000:0x00000000:0x00000001 node 11 boot-up serial 0x00000001",
            "found 0x00000000:0x00000001:0x00000000:0x00000003 node 12 boot-up serial 0x00000003",
            "3 found",
            "selected node-ID 10 serial 0x00000000",
            "bit timing 250 kbit/s accepted",
            "bit timing table entry 5 refused: LSS Error: 1",
            "node-ID 0 refused: LSS Error: 1",
        ]
    );
    // The IDs are the devices' now: edsgen sees them as any node.
    let (code, stdout, _) = edsgen(&["scan", "--bus", &addr, "--timeout", "500"]);
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("3 node(s) found"), "{stdout}");
    assert!(!stdout.contains("unconfigured"), "{stdout}");
    // A reset node keeps the stored ID.
    let (code, stdout, _) = edsgen(&["nmt", "reset", "11", "--bus", &addr]);
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("boot-up"), "{stdout}");
}

#[test]
fn edsgen_lss_lists_assigns_and_inquires() {
    let _scan = ONE_SCAN_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some((_hub, _sim, addr, _)) = three_unconfigured() else {
        return;
    };
    let bus = ["--bus", addr.as_str()];
    let (code, stdout, _) = edsgen(&[&["scan"][..], &bus, &["--timeout", "300"]].concat());
    assert_eq!(code, Some(0));
    assert!(
        stdout.contains("unconfigured node(s) on the bus"),
        "{stdout}"
    );
    let (code, stdout, _) = edsgen(&[&["lss", "inquire"][..], &bus].concat());
    assert_eq!(
        (code, stdout.as_str()),
        (Some(1), "no LSS answer\n"),
        "no node is in configuration"
    );
    let (code, stdout, stderr) = edsgen(&[&["lss", "scan"][..], &bus].concat());
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(
        stdout,
        "0x00000000:0x00000000:0x00000000:0x00000000\n\
         0x00000000:0x00000000:0x00000000:0x00000001\n\
         0x00000000:0x00000001:0x00000000:0x00000003\n\
         3 unconfigured node(s) found on can0\n"
    );
    let (code, stdout, _) = edsgen(
        &[
            &[
                "lss",
                "set-id",
                "0x00000000:0x00000001:0x00000000:0x00000003",
                "7",
            ][..],
            &bus,
            &["--store"],
        ]
        .concat(),
    );
    assert_eq!(code, Some(0), "{stdout}");
    assert_eq!(
        stdout,
        "0x00000000:0x00000001:0x00000000:0x00000003: node-ID 7, stored\n"
    );
    let read = |entry: &str| {
        let args = [&["sdo", "read", "7", entry, "--type", "u32"][..], &bus].concat();
        edsgen(&args)
    };
    let (code, stdout, _) = read("1018:4");
    assert_eq!(
        (code, stdout.as_str()),
        (Some(0), "1018h:04h = 3 (0x00000003)\n")
    );
    // The $NODEID defaults follow the new node-ID: the EMCY COB-ID is 80h + 7.
    let (code, stdout, _) = read("1014");
    assert_eq!(
        (code, stdout.as_str()),
        (Some(0), "1014h:00h = 135 (0x00000087)\n")
    );
    // Absent identity: no answer, exit 1; a node-ID out of range: usage, exit 2.
    let absent = "0x00000000:0x00000000:0x00000000:0x00000009";
    let (code, stdout, _) = edsgen(&[&["lss", "set-id", absent, "8"][..], &bus].concat());
    assert_eq!((code, stdout.as_str()), (Some(1), "no LSS answer\n"));
    let (code, _, stderr) = edsgen(&[&["lss", "set-id", absent, "128"][..], &bus].concat());
    assert_eq!(code, Some(2), "{stderr}");
    let (code, _, _) = edsgen(&[&["lss", "switch", "global", "configuration"][..], &bus].concat());
    assert_eq!(code, Some(0));
    let (code, stdout, _) = edsgen(&[&["lss", "set-bitrate", "100"][..], &bus].concat());
    assert_eq!(code, Some(2), "100 kbit/s is not in table 0: {stdout}");
    let (code, stdout, _) = edsgen(&[&["lss", "set-bitrate", "125"][..], &bus].concat());
    assert_eq!(code, Some(0), "{stdout}");
    let (code, _, _) = edsgen(&[&["lss", "switch", "global", "waiting"][..], &bus].concat());
    assert_eq!(code, Some(0));
    let (code, stdout, _) = edsgen(&[&["lss", "scan"][..], &bus].concat());
    assert_eq!(code, Some(0));
    assert!(
        stdout.ends_with("2 unconfigured node(s) found on can0\n"),
        "{stdout}"
    );
}

#[test]
fn a_card_whose_eds_says_lss_supported_0_cannot_start_unconfigured() {
    let (code, _, stderr) = edsgen(&["simulate", "--card", "cp301@255", "--bus", "127.0.0.1:1"]);
    assert_eq!(code, Some(2));
    assert_eq!(
        stderr,
        "error: --card cp301@255: eds/cp301.eds says LSS_Supported=0: the device cannot be \
         configured by LSS (CiA 305), so it cannot start unconfigured (@255); give it a \
         node-ID 1..=127\n"
    );
}
