//! `edsgen demo`, the README's main job: every step passes, the trace shows the manuals' frames
//! and the EC-TX508's process images decoded by name, and the command's exit code and summary
//! say so; with `--bus`, the same CANopen workflows against `edsgen simulate --card` through a
//! hub, in real time, and the EtherCAT section reported as not run; the PROFINET card's section
//! (DCP and cyclic frames, in process) in both.

mod process_support;

use std::process::Command;

use edsgen_host::hub::{Hub, HubOptions};
use process_support::edsgen_simulate;

#[test]
fn every_step_of_the_demo_behaves_as_the_manuals_say() {
    let report = edsgen_demo::run();
    let failed: Vec<_> = report.steps.iter().filter(|s| s.outcome.is_err()).collect();
    assert_eq!(failed, Vec::<&edsgen_demo::Step>::new());
    assert_eq!(report.steps.len(), 59);
    // The Goodrive350 manual's PDO2 Tx (§3.5.4), 283: 01 01 88 13 7C 01 00 00, decoded.
    let pdo2 = "7.100000  283  TPDO2      node 3 Status word = 257 (0x0101), Monitoring data: \
                Returned value 1 = 5000 (0x1388), Monitoring data: Returned value 2 = 380 \
                (0x017C), Monitoring data: Returned value 3 = 0";
    assert!(report.lines.iter().any(|l| l.trim() == pdo2), "{pdo2}");
    // The CP301's speed read back while ramping (§5.3).
    let ramping = "0.500000  582  SDO        node 2 read 6044:00 vl velocity actual value = 750";
    assert!(
        report.lines.iter().any(|l| l.trim() == ramping),
        "{ramping}"
    );
}

#[test]
fn the_demo_validates_six_description_files() {
    let report = edsgen_demo::run();
    let validated: Vec<(&str, &Result<String, String>)> = report
        .steps
        .iter()
        .filter(|s| s.name.ends_with(" is valid"))
        .map(|s| (s.name.as_str(), &s.outcome))
        .collect();
    let clean = Ok("0 error(s), 0 warning(s)".to_string());
    let two = Ok("0 error(s), 2 warning(s)".to_string());
    assert_eq!(
        validated,
        [
            ("eds/cp301.eds is valid", &clean),
            ("eds/ms300.eds is valid", &clean),
            ("eds/goodrive350.eds is valid", &two),
            ("eds/rd11.eds is valid", &clean),
            ("eds/hd1e.eds is valid", &two),
            ("eds/ec-tx508.xml is valid", &clean),
        ]
    );
}

#[test]
fn the_ec_tx508_runs_in_csv_through_its_images_cycle_by_cycle() {
    let report = edsgen_demo::run();
    let start = report
        .lines
        .iter()
        .position(|l| l.starts_with("== EC-TX508"))
        .expect("the EtherCAT section");
    // The EC-TX508's steps, before the other cards' sections.
    let steps: Vec<(&str, &Result<String, String>)> = report.steps[27..35]
        .iter()
        .map(|s| (s.name.as_str(), &s.outcome))
        .collect();
    let ok = |seen: &str| Ok(seen.to_string());
    assert_eq!(
        steps,
        [
            ("6060h = 9: mode 9 (csv) confirmed by 6061h", &ok("9")),
            ("operation enabled by 06h, 07h, 0Fh", &ok("06h, 07h, 0Fh")),
            (
                "60FFh = 300: 606Ch 50 ms later, on the ramp of 3 rpm per ms",
                &ok("150")
            ),
            (
                "606Ch follows the target on its ramp to 300 rpm, 6041h bit 10 target reached",
                &ok("(300, true)")
            ),
            (
                "a drive fault: the quick-stop ramp to 0 rpm in 10 ms, then fault (6041h bit 3)",
                &ok("(10, 0, true)")
            ),
            (
                "a fault reset by a rising edge of bit 7, every other cycle until the cause is gone",
                &ok("80h, 00h, 80h, 00h, 80h, 00h, 80h, 00h, 80h, 00h, 80h")
            ),
            ("operation enabled again by 06h, 07h, 0Fh", &ok("06h, 07h, 0Fh")),
            (
                "shut down by 00h (disable voltage): switch on disabled, 606Ch 0",
                &ok("00h, 606Ch 0")
            ),
        ]
    );
    // The images of the cycle at 53 ms, on the ramp, decoded by the ESI file's names: the
    // 21-byte outputs (1600h) and the 23-byte inputs (1A00h).
    let section: Vec<&str> = report.lines[start..].iter().map(|l| l.trim()).collect();
    let outputs = "0.053000  SM2  OUTPUTS    Control word = 15, Target position = 0, \
                   Target speed = 300, Target torque = 0, Max. torque = 0, Operation mode = 9, \
                   Speed in industrial regulations = 0, Probe control = 0";
    let inputs = "0.053000  SM3  INPUTS     Status word = 567 (0x0237), \
                  Position actual value = 0, Actual speed = 150, Actual torque = 0, \
                  Position deviation = 0, Operation mode display = 9, Probe status = 0, \
                  Probe position rising edge = 0";
    let at = section.iter().position(|l| *l == outputs).expect(outputs);
    assert_eq!(section[at + 1], inputs);
    // A few cycles are shown, the others counted: 9 pairs of images in 201 cycles.
    assert_eq!(section.iter().filter(|l| l.contains("  SM2  ")).count(), 9);
    assert_eq!(section[at - 1], "… 50 cycle(s) not shown");
}

#[test]
fn the_goodrive350_profinet_card_is_found_named_and_driven_in_process() {
    let report = edsgen_demo::run();
    let steps: Vec<(&str, &Result<String, String>)> = report.steps[43..52]
        .iter()
        .map(|s| (s.name.as_str(), &s.outcome))
        .collect();
    let ok = |seen: &str| Ok(seen.to_string());
    assert_eq!(
        steps,
        [
            (
                "DCP Identify all: the card answers with its GSDML's name and IDs",
                &ok("(\"goodrive350-pn\", (848, 848))")
            ),
            (
                "DCP Set name of station `gd350-line-1`, then Identify by that name",
                &ok("(Some(0), true)")
            ),
            // Input CR 0xC001 (the controller's), output CR 0xC102 (the device's choice).
            (
                "RPC Connect (IOCRs, AlarmCR, expected submodules), PrmEnd, ApplicationReady",
                &ok("((49153, 49410), [\"Connected\", \"PrmEnd\", \"DataStart\"])")
            ),
            // P00.11's default acceleration time is 10.0 s: 2500 cycles of 4 ms to 50.00 Hz.
            (
                "CW 1 (run forward) and PZD2 5000: the drive ramps to 50.00 Hz",
                &ok("(1, 5000) after 2501 cycles (10004 ms)")
            ),
            (
                "PKW read of P00.11 (acceleration time)",
                &ok("Word { address: 11, value: 100 }")
            ),
            (
                "PKW write without CW bit 8 (enable writing): refused",
                &ok("Refused { address: 11, error: InvalidCommand }")
            ),
            (
                "CW 5 (stop): the drive decelerates and stops",
                &ok("0 after 2501 cycles")
            ),
            (
                "RPC Release: the AR ends and the card stops sending",
                &ok("(true, [\"Released\"], true)")
            ),
            (
                "the controller stops sending: watchdog, E-PN (fault 57), the AR aborted",
                &ok("(Some(57), true, true)")
            ),
        ]
    );
}

#[test]
fn the_demo_command_exits_0_with_its_summary() {
    let output = Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .arg("demo")
        .output()
        .expect("edsgen runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.ends_with("\n59 step(s): 59 as the manuals say, 0 not\n"),
        "{stdout}"
    );
}

#[test]
fn the_demo_drives_simulated_cards_on_a_bus() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).expect("a hub on loopback");
    let addr = hub.local_addr().to_string();
    let _simulate = edsgen_simulate(
        &["--card", "cp301", "--card", "goodrive350", "--bus", &addr],
        2,
    );
    let output = Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .args(["demo", "--bus", &addr])
        .output()
        .expect("edsgen demo runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    // The fault cannot be injected into a drive in another process: that step says so.
    assert!(
        stdout.contains(
            "ok    fault OUT1 injected, and its reset: not run: the drive is not in this process"
        ),
        "{stdout}"
    );
    // No EtherCAT network on a CANopen bus: the EC-TX508 is not run, and says so.
    assert!(
        stdout.contains(
            "ok    EC-TX508 over EtherCAT: not run: --bus is a CANopen bus, with no EtherCAT \
             network"
        ),
        "{stdout}"
    );
    // No EtherNet/IP network either: the card's workflow is not run, and says so.
    assert!(
        stdout.contains(
            "ok    EtherNet/IP card workflow: not run: a socketcand bus has no EtherNet/IP \
             network (run edsgen demo without --bus)"
        ),
        "{stdout}"
    );
    assert!(
        stdout.ends_with("\n44 step(s): 44 as the manuals say, 0 not\n"),
        "{stdout}"
    );
}

#[test]
fn the_goodrive350_enip_card_runs_through_pkw_and_pzd() {
    let report = edsgen_demo::run();
    let steps: Vec<(&str, &Result<String, String>)> = report.steps[35..43]
        .iter()
        .map(|s| (s.name.as_str(), &s.outcome))
        .collect();
    let ok = |seen: &str| Ok(seen.to_string());
    assert_eq!(
        steps,
        [
            (
                "RegisterSession, Identity product code (@1/1/3)",
                &ok("session 1, product code 350")
            ),
            (
                "Forward_Open 150 -> 100 at 50 ms (EXCLUSIVE_OWNER)",
                &ok("reply [D4, 00, 00, 00, 01, 00, 00, 10]")
            ),
            (
                "PKW write P16.32 = 1 (received PZD2: set frequency)",
                &ok("Word { address: 4128, value: 1 }")
            ),
            (
                "PKW write P16.43 = 1 (transmitted PZD2: running frequency)",
                &ok("Word { address: 4139, value: 1 }")
            ),
            (
                "PKW read P00.10 (keypad frequency)",
                &ok("Word { address: 10, value: 5000 }: 50.00 Hz")
            ),
            (
                "PKW write P07.27 refused (read only, error 7)",
                &ok("Refused { address: 1819, error: ReadOnly }")
            ),
            (
                "run forward at 25.00 Hz (CW 0x0001, PZD2 2500)",
                &ok("SW 0x4101, transmitted PZD2 0 -> 1000 (0.01 Hz)")
            ),
            (
                "scanner stops producing: timeout after 4 x RPI, fault E-EIP",
                &ok(
                    "connection 0x10000001 opened, connection 0x10000001 timed out, drive fault \
                     E-EIP; SW state Some(Fault)"
                )
            ),
        ]
    );
}

/// The PROFIBUS-DP section: profirust's master brings the Goodrive350 DP card to data exchange
/// and every step of chapter 2's workflow behaves.
#[test]
fn the_demo_runs_the_dp_card_with_profirust() {
    let report = edsgen_demo::run();
    let dp: Vec<&str> = report
        .steps
        .iter()
        .skip_while(|s| s.name != "the card's GSD reads and validates")
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(
        dp,
        [
            "the card's GSD reads and validates",
            "Set_Prm, Chk_Cfg, data exchange",
            "§2.6 example 1: read P00.10 (task 1, address 10)",
            "§2.6 example 2: write 50.00 Hz to P00.10 (task 4, CW bit 8)",
            "CW 1 (run forward) at 10.00 Hz on PZD2",
            "CW 6 (coast to stop)",
            "the master stops: the DP watchdog (200 ms) trips E-DP",
        ]
    );
    assert!(report.passed());
}

#[test]
fn the_demo_on_a_bus_nobody_listens_on_exits_2_saying_so() {
    let output = Command::new(env!("CARGO_BIN_EXE_edsgen"))
        .args(["demo", "--bus", "127.0.0.1:1"])
        .output()
        .expect("edsgen demo runs");
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(output.stdout, b"");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.starts_with("error: cannot reach the bus at 127.0.0.1:1: ")
            && stderr.ends_with(
                " (start `edsgen bus`, then `edsgen simulate --card cp301 --card goodrive350`)\n"
            ),
        "{stderr}"
    );
}
