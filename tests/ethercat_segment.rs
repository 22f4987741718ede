//! `edsgen simulate --ethercat` serving a segment of three SubDevices (an EC-TX508, an ESI
//! device of the corpus, another EC-TX508) to third-party MainDevices over a veth pair in a
//! private network namespace (root only, and the ESI corpus: visible skips otherwise, failures
//! under `CI=true`). Run as a test without the libtest harness, as `ethercat_wire` is:
//! - the simulator prints each SubDevice with its position and identity;
//! - ethercrab (this binary, role `segment`) finds three SubDevices with their identities and
//!   names, brings them to Op with their own image sizes, and drives the two EC-TX508s' velocity
//!   each on its own (300 and 150 rpm, each seen in its own inputs); `fault 2` on the
//!   simulator's standard input then faults the drive at position 2 alone;
//! - SOEM (python `pysoem`, scripts/soem_segment.py) finds the three, maps them, reaches Op with
//!   the working counter it expects and drives the two velocities in the same way;
//! - then both again with a *modular* corpus device in the middle (ETG.2001's two-axis
//!   Modules/Slots example), axis 2 plugged by `--module 2=#x110` and axis 1 by its slot's
//!   default: each sees its identity and the modules' images, 28 bytes out and 20 in.

#[path = "ethercat_support/mod.rs"]
mod ethercat_support;
#[path = "process_support/mod.rs"]
mod process_support;

use std::path::PathBuf;
use std::time::Duration;

use ethercat_support::{collect, complete_enough, Namespace, IFACE, ROLE};
use process_support::{esi_corpus_dir, python, root, skip, Process, EDSGEN, START_TIMEOUT};

/// The variable carrying the corpus device's identity and image sizes to the MainDevice.
const EXPECTED: &str = "EDSGEN_ECAT_MIDDLE";

fn main() {
    if let Ok(role) = std::env::var(ROLE) {
        let iface = std::env::var(IFACE).expect("the interface");
        let middle = std::env::var(EXPECTED).expect("the corpus device");
        master::run(&role, &iface, &middle);
        return;
    }
    let root_user = std::process::Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.trim_ascii() == b"0");
    if !root_user {
        let _: Option<()> =
            skip("ethercat_segment: needs root for a network namespace and veth pair");
        return;
    }
    let Some(corpus) = esi_corpus_dir() else {
        return;
    };
    let (file, middle) = corpus_device(&corpus);
    let ns = Namespace::new();
    ethercrab(&ns, &file, &middle, &[]);
    let soem_plain = soem(&ns, &file, &middle, &[]);
    let modular = corpus.join(MODULAR);
    if !modular.is_file() {
        let _: Option<()> = skip(format!(
            "ethercat_segment: the modular device: no {}",
            modular.display()
        ));
        return;
    }
    ethercrab(&ns, &modular, MODULAR_SEEN, MODULAR_ARGS);
    let soem_modular = soem(&ns, &modular, MODULAR_SEEN, MODULAR_ARGS);
    println!(
        "ethercat_segment: ok (ethercrab, {soem_plain}; the corpus device {}; the modular device with \
         ethercrab, {soem_modular})",
        file.display()
    );
}

/// The modular device of the corpus: ETG.2001's DS402 Modules/Slots example, two axis slots
/// (`SlotPdoIncrement` 16, `SlotIndexIncrement` 800h), no PDO of its own.
const MODULAR: &str =
    "synapticon__siitool/examples__ModulesSlots_DS402_Simple__ETG2001_ModulesSlots_CiA402.xml";
/// Axis 2 plugged with module 110h (position, homing, touch probe: RxPDOs 1610h-1612h of 6, 4
/// and 12 bytes, TxPDOs 1A10h-1A12h of 6, 4 and 4), axis 1 with its default 100h (RxPDO 1600h
/// and TxPDO 1A00h, 6 bytes each); the file's F010h describes a reserved sub-index FFh (an
/// EDS307 error), allowed.
const MODULAR_ARGS: &[&str] = &["--module", "2=#x110", "--allow", "EDS307"];
/// What the MainDevices see of it: its identity, 6 + 22 bytes of outputs, 6 + 14 of inputs.
const MODULAR_SEEN: &str = "0xe0000001 0x00010000 0x00000000 28 20";

/// The first ESI of the corpus the simulator serves to Op, and what the MainDevices are to see
/// of it: `vendor product revision outputs inputs`, hexadecimal identity.
fn corpus_device(corpus: &std::path::Path) -> (PathBuf, String) {
    let mut files = Vec::new();
    collect(corpus, &mut files);
    files.sort();
    for file in files {
        let loaded = edsgen_model::load::load(&file, None).expect("readable");
        let clean = !loaded
            .diagnostics
            .iter()
            .any(|d| d.severity == edsgen_model::diag::Severity::Error);
        let Some((outputs, inputs)) = complete_enough(&loaded.device).filter(|_| clean) else {
            continue;
        };
        let info = &loaded.device.device_info;
        let number =
            |n: &Option<edsgen_model::model::Spanned<u32>>| n.as_ref().map_or(0, |n| n.value);
        let expected = format!(
            "{:#010x} {:#010x} {:#010x} {outputs} {inputs}",
            number(&info.vendor_number),
            number(&info.product_number),
            number(&info.revision_number),
        );
        return (file, expected);
    }
    panic!("no ESI of the corpus can be served to Op");
}

/// The segment's simulator (`extra` arguments right after the middle FILE, whose `--module`s
/// they are), its SubDevices' lines checked.
fn segment(ns: &Namespace, file: &std::path::Path, middle: &str, extra: &[&str]) -> Process {
    let file = file.to_str().expect("a path");
    let mut args = vec!["simulate", "--ethercat", "ecs", "--card", "ec-tx508", file];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--card", "ec-tx508", "--faults-on-stdin"]);
    let mut command = ns.exec(EDSGEN, &args);
    let sim = Process::start(&mut command);
    let tx508 = "EC-TX508 EtherCAT communication card (Goodrive350) (vendor 0x000004D8, product \
        0x00009252, revision 0x00000001)";
    let vendor = middle.split(' ').next().expect("a vendor");
    for (position, starts) in [
        (0, format!("SubDevice 0: {tx508}")),
        (1, "SubDevice 1: ".to_owned()),
        (2, format!("SubDevice 2: {tx508}")),
    ] {
        let line = sim.stderr_line(|l| l.starts_with("SubDevice "), START_TIMEOUT);
        assert!(line.starts_with(&starts), "{position}: {line}");
        if position == 1 {
            let vendor = format!(
                "(vendor {:#010X}",
                u32::from_str_radix(&vendor[2..], 16).expect("hex")
            );
            assert!(line.contains(&vendor), "{line}");
        }
    }
    let serving = sim.stderr_line(|l| l.starts_with("serving "), START_TIMEOUT);
    assert_eq!(
        serving,
        "serving a segment of 3 SubDevices on ecs; Ctrl-C stops"
    );
    sim
}

fn ethercrab(ns: &Namespace, file: &std::path::Path, middle: &str, extra: &[&str]) {
    let mut sim = segment(ns, file, middle, extra);
    let me = std::env::current_exe().expect("this test");
    let mut command = ns.exec(me.to_str().expect("a path"), &[]);
    command
        .env(ROLE, "segment")
        .env(IFACE, "ecm")
        .env(EXPECTED, middle);
    let master = Process::start(&mut command);
    master.stdout_line(|l| l == "at speed", Duration::from_secs(90));
    sim.send_line("fault 2");
    let said = sim.stderr_line(|l| l.starts_with("drive fault raised at "), START_TIMEOUT);
    assert!(said.ends_with(" ms (SubDevice 2)"), "{said}");
    let done = master.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{done:?}");
    assert!(done.stdout.contains("fault at 2 only\n"), "{done:?}");
}

/// SOEM (pysoem) brings the segment to Op and drives both EC-TX508s.
fn soem(ns: &Namespace, file: &std::path::Path, middle: &str, extra: &[&str]) -> String {
    let Some(python) = python() else {
        return "SOEM skipped".to_owned();
    };
    let _sim = segment(ns, file, middle, extra);
    let script = root().join("scripts/soem_segment.py");
    let master = Process::start(&mut ns.exec(
        python.to_str().expect("a path"),
        &[script.to_str().expect("a path"), "ecm"],
    ));
    let done = master.finish(Duration::from_secs(90));
    assert_eq!(done.code, Some(0), "{done:?}");
    let fields: Vec<&str> = middle.split(' ').collect();
    let expected = format!(
        "found 3\n\
         0 identity 0x000004d8 0x00009252 0x00000001 name EC-TX508 images 21/23\n\
         1 identity {} {} {} name {{}} images {}/{}\n\
         2 identity 0x000004d8 0x00009252 0x00000001 name EC-TX508 images 21/23\n\
         op True\n",
        fields[0], fields[1], fields[2], fields[3], fields[4]
    );
    // The middle one's name is the corpus's; the rest is exact.
    let lines: Vec<&str> = done.stdout.lines().collect();
    let expected: Vec<&str> = expected.lines().collect();
    assert_eq!(lines.len(), 8, "{done:?}");
    for (line, wanted) in lines.iter().zip(&expected) {
        match wanted.split_once("name {}") {
            Some((before, after)) => {
                assert!(
                    line.starts_with(before) && line.ends_with(after),
                    "{line} / {wanted}"
                )
            }
            None => assert_eq!(line, wanted),
        }
    }
    // Every SubDevice counted in every cycle: the working counter SOEM expects.
    let wkc = lines[5];
    let (got, expected) = wkc
        .strip_prefix("wkc ")
        .and_then(|w| w.split_once(" expected "))
        .expect("the wkc line");
    assert_eq!(got, expected, "{wkc}");
    assert_eq!(lines[6], "speeds 300 150", "{done:?}");
    assert_eq!(lines[7], "done", "{done:?}");
    "SOEM".to_owned()
}

/// The MainDevice side (ethercrab), run in the namespace.
mod master {
    use std::time::Duration;

    use edsgen_runtime::cia402::State;
    use edsgen_runtime::master::cia402::{Controller, Outcome};
    use edsgen_sim::cards::ec_tx508::ethercat;
    use ethercrab::std::{ethercat_now, tx_rx_task};
    use ethercrab::{EtherCrabWireRead, EtherCrabWireWrite};
    use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

    const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
    static PDU_STORAGE: PduStorage<16, MAX_PDU_DATA> = PduStorage::new();

    /// The two EC-TX508s' positions and the speeds each is asked for.
    const DRIVES: [(usize, i32); 2] = [(0, 300), (2, 150)];

    pub fn run(role: &str, iface: &str, middle: &str) {
        assert_eq!(role, "segment");
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime");
        runtime.block_on(async {
            let (tx, rx, pdu_loop) = PDU_STORAGE.try_split().expect("split once");
            let timeouts = Timeouts {
                pdu: Duration::from_millis(500),
                state_transition: Duration::from_secs(10),
                mailbox_response: Duration::from_secs(2),
                eeprom: Duration::from_secs(2),
                ..Timeouts::default()
            };
            let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
            tokio::spawn(tx_rx_task(iface, tx, rx).expect("the raw socket"));
            let group = maindevice
                .init_single_group::<8, 512>(ethercat_now)
                .await
                .expect("discovery");
            assert_eq!(group.len(), 3);
            let group = group.into_op(&maindevice).await.expect("Op");
            group.tx_rx(&maindevice).await.expect("a cycle");
            let fields: Vec<&str> = middle.split(' ').collect();
            for position in 0..3 {
                let device = group.subdevice(&maindevice, position).expect("a SubDevice");
                let id = device.identity();
                let seen = format!(
                    "{:#010x} {:#010x} {:#010x} {} {}",
                    id.vendor_id,
                    id.product_id,
                    id.revision,
                    device.outputs_raw().len(),
                    device.inputs_raw().len()
                );
                let wanted = if position == 1 {
                    fields.join(" ")
                } else {
                    assert_eq!(device.name(), "EC-TX508");
                    "0x000004d8 0x00009252 0x00000001 21 23".to_owned()
                };
                assert_eq!(seen, wanted, "SubDevice {position}");
                // Station addresses as ethercrab gives them: 0x1000 up.
                assert_eq!(device.configured_address(), 0x1000 + position as u16);
                println!("{position}: {seen}");
            }
            let mut controllers: Vec<Controller> = DRIVES
                .iter()
                .map(|_| {
                    Controller::new(State::OperationEnabled)
                        .with_mode(9)
                        .with_limit(2_000)
                })
                .collect();
            let mut speeds = [0i32; 2];
            for _ in 0u32..3_000 {
                group.tx_rx(&maindevice).await.expect("a cycle");
                for ((position, target), (drive, speed)) in
                    DRIVES.iter().zip(controllers.iter_mut().zip(&mut speeds))
                {
                    let card = group.subdevice(&maindevice, *position).expect("a drive");
                    let inputs =
                        ethercat::Inputs::unpack_from_slice(&card.inputs_raw()).expect("inputs");
                    let status = inputs.tx_pdo_1a00;
                    let step = drive.cycle(status.status_word, status.operation_mode_display);
                    assert!(
                        matches!(step.outcome, Outcome::Busy | Outcome::Reached),
                        "{position}: {:?}",
                        step.outcome
                    );
                    let mut outputs = ethercat::Outputs::default();
                    let rx = &mut outputs.rx_pdo_1600;
                    rx.control_word = step.controlword;
                    rx.operation_mode = step.mode.unwrap_or(9);
                    rx.target_speed = if step.outcome == Outcome::Reached {
                        *target
                    } else {
                        0
                    };
                    outputs
                        .pack_to_slice(&mut card.outputs_raw_mut())
                        .expect("outputs");
                    *speed = status.actual_speed;
                }
                if speeds == [300, 150] {
                    break;
                }
                tokio::time::sleep(Duration::from_millis(1)).await;
            }
            // Each drive reached the speed its own outputs asked for.
            assert_eq!(speeds, [300, 150]);
            println!("at speed");
            // `fault 2` on the simulator's standard input reaches the drive at position 2; the
            // other runs on.
            let fault = |position: usize| {
                let card = group.subdevice(&maindevice, position).expect("a drive");
                let inputs =
                    ethercat::Inputs::unpack_from_slice(&card.inputs_raw()).expect("inputs");
                inputs.tx_pdo_1a00.status_word & 0x0008 != 0
            };
            let mut seen = (false, false);
            for _ in 0..10_000 {
                group.tx_rx(&maindevice).await.expect("a cycle");
                seen = (fault(0), fault(2));
                if seen.1 {
                    break;
                }
                tokio::time::sleep(Duration::from_millis(1)).await;
            }
            assert_eq!(seen, (false, true));
            println!("fault at 2 only");
        });
    }
}
