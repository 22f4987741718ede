//! `edsgen simulate --ethercat` against a real MainDevice (ethercrab) over a veth pair in a
//! private network namespace (root only: a visible skip otherwise, a failure under `CI=true`).
//!
//! Run as a test (no libtest harness): this binary creates the namespace and its veth pair
//! (removed by a guard, also on failure), starts the simulator on one end, and runs itself in
//! the namespace as the MainDevice on the other end, once per part:
//! - `drive`: the EC-TX508 found by its identity and SII name (the order string, `EC-TX508`); the typed SDO read of 1C12h:01
//!   and write of 6060h; a skipped transition (Pre-Op to Op) refused with AL status code 0x0011,
//!   then acknowledged; Pre-Op → Safe-Op → Op with the typed 21/23-byte images; CSV velocity
//!   ramping in the inputs as the outputs ask; then the simulator stopped by SIGTERM (exit 0) and
//!   the MainDevice's next cycle failing: the SubDevice is gone.
//! - `reassign`: 1C12h set to {1601h} by SDO in Pre-Op; the images in Op are then 6/23 bytes.
//! - `edsgen ecat scan --esi ...` lists the SubDevice with the ESI device it matches; `edsgen ecat
//!   sdo read|write` reads 1018h:01, writes and reads back 6060h, and shows 0602 0000 for 1234h;
//!   without `--esi` reads 1008h's 13 bytes as hex and text, writes and reads with `--type`, and
//!   tells a write without a type what to pass;
//!   by name through `--esi`, typed values, an ambiguous name's suggestions and a refused write;
//!   `edsgen ecat pdo` prints the inputs by name, and sets outputs by name (`operation mode=9`,
//!   which the inputs' operation mode display then shows).
//! - `edsgen ecat check`: clean against eds/ec-tx508.xml; against tests/esi/ec-tx508-altered.xml,
//!   one finding per check (SII identity, SyncManager, PDO assignment and mapping, a missing
//!   object, a length, a default), exit 1.
//! - `eeprom`: ethercrab's own EEPROM reader reads back the SII the simulator serves, byte for
//!   byte what `edsgen sii` writes (EC-TX508 and tests/esi/io-no-mailbox.xml), and takes the
//!   identity, names and mailbox SyncManagers from it; the I/O device without CoE reaches Op
//!   with the image sizes of the SII's PDO categories.
//! - SOEM (python `pysoem`): discovery, identity and name, the 21/23-byte mapping, Op with the
//!   expected working counter (scripts/soem_master.py).
//! - `hostile`: 3,000 frames mutated (seeded) from a recorded good start-up, sent at the
//!   simulator from a raw socket; the simulator still runs and SOEM then reaches Op as above.
//! - `corpus`: each ESI of the ESI corpus (`EDSGEN_ESI_CORPUS`, else `../shared/esi-corpus`;
//!   a visible skip when absent) whose dictionary and PDOs are complete enough reaches Op, and
//!   `edsgen ecat check` finds it clean against its own ESI.

#[path = "ethercat_support/mod.rs"]
mod ethercat_support;
#[path = "../sim/tests/hostile_support/mod.rs"]
mod hostile_support;
#[path = "process_support/mod.rs"]
mod process_support;

use std::process::Command;
use std::time::Duration;

use std::path::Path;

use edsgen_sim::ethercat::EsiDevice;
use ethercat_support::{collect, complete_enough, Namespace, IFACE, ROLE};
use process_support::{esi_corpus_dir, python, root, skip, Process, EDSGEN};

fn main() {
    if let Ok(role) = std::env::var(ROLE) {
        let iface = std::env::var(IFACE).expect("the interface");
        if role == "hostile" {
            send_hostile_frames(&iface);
        } else {
            master::run(&role, &iface);
        }
        return;
    }
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.trim_ascii() == b"0");
    if !root {
        let _: Option<()> = skip("ethercat_wire: needs root for a network namespace and veth pair");
        return;
    }
    let ns = Namespace::new();
    drive(&ns);
    reassign(&ns);
    scan(&ns);
    check(&ns);
    sii_read_back(&ns);
    let soem = soem(&ns);
    let hostile = hostile(&ns);
    let corpus = corpus(&ns);
    println!("ethercat_wire: ok (drive, reassign, scan, check, SII, {soem}, {hostile}, {corpus})");
}

fn drive(ns: &Namespace) {
    let sim = ns.simulator(&["--card", "ec-tx508"]);
    let mut master = ns.master("drive");
    master.stdout_line(|l| l == "unplug", Duration::from_secs(60));
    let status = Command::new("kill")
        .args(["-TERM", &sim.id().to_string()])
        .status()
        .expect("kill");
    assert!(status.success());
    let exited = sim.finish(Duration::from_secs(10));
    assert_eq!(exited.code, Some(0), "{exited:?}");
    assert!(exited.stderr.starts_with("stopped: "), "{exited:?}");
    master.send_line("unplugged");
    let done = master.finish(Duration::from_secs(30));
    assert_eq!(done.code, Some(0), "{done:?}");
    assert!(done.stdout.contains("gone: "), "{done:?}");
}

fn reassign(ns: &Namespace) {
    let _sim = ns.simulator(&["--card", "ec-tx508"]);
    let master = ns.master("reassign");
    let done = master.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{done:?}");
    assert!(done.stdout.contains("images 6/23"), "{done:?}");
}

/// `edsgen ecat scan` finds the simulated EC-TX508 and names the ESI device it matches;
/// `edsgen ecat sdo` reads, writes and is refused.
fn scan(ns: &Namespace) {
    let _sim = ns.simulator(&["--card", "ec-tx508"]);
    let mut command = ns.exec(
        EDSGEN,
        &[
            "ecat",
            "scan",
            "--iface",
            "ecm",
            "--esi",
            "eds/ec-tx508.xml",
            "--esi",
            "codegen/tests/esi/drive.xml",
        ],
    );
    command.current_dir(root());
    let done = Process::start(&mut command).finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{done:?}");
    assert_eq!(
        done.stdout,
        "0: 0x1000 vendor 0x000004d8 product 0x00009252 revision 0x00000001 \"EC-TX508\" \
         = EC-TX508 (eds/ec-tx508.xml)\n"
    );
    let ecat = |args: &[&str]| {
        let mut command = ns.exec(EDSGEN, &[&["ecat", "sdo"][..], args].concat());
        Process::start(&mut command).finish(Duration::from_secs(60))
    };
    let read = ecat(&["read", "--iface", "ecm", "1018:1"]);
    assert_eq!(
        (read.code, read.stdout.as_str()),
        (Some(0), "1018h:01 = 0x000004d8 (1240)\n")
    );
    let write = ecat(&["write", "--iface", "ecm", "6060:0", "9", "--size", "1"]);
    assert_eq!(
        (write.code, write.stdout.as_str()),
        (Some(0), "6060h:00 := 0x09\n")
    );
    let back = ecat(&["read", "--iface", "ecm", "6060:0", "--size", "1"]);
    assert_eq!(
        (back.code, back.stdout.as_str()),
        (Some(0), "6060h:00 = 0x09 (9)\n")
    );
    // Without --esi: a read sized by what arrives (1008h's 13 bytes as hex and text), a typed
    // write and read, and a write without a type told what to pass.
    let name = ecat(&["read", "--iface", "ecm", "1008:0"]);
    assert_eq!(
        (name.code, name.stdout.as_str()),
        (
            Some(0),
            "1008h:00 = 49 4E 56 54 2D 45 74 68 65 72 43 41 54 (\"INVT-EtherCAT\")\n"
        ),
        "{name:?}"
    );
    let typed = ecat(&["write", "--iface", "ecm", "6060:0", "-3", "--type", "i8"]);
    assert_eq!(
        (typed.code, typed.stdout.as_str()),
        (Some(0), "6060h:00 := FD\n"),
        "{typed:?}"
    );
    let typed = ecat(&["read", "--iface", "ecm", "6060:0", "--type", "i8"]);
    assert_eq!(
        (typed.code, typed.stdout.as_str()),
        (Some(0), "6060h:00 = -3 (0xFD)\n"),
        "{typed:?}"
    );
    let untyped = ecat(&["write", "--iface", "ecm", "6060:0", "9"]);
    assert_eq!(
        (untyped.code, untyped.stderr.as_str()),
        (
            Some(2),
            "error: ecat sdo write without --esi needs the value's type: --type TYPE (u8, u16, \
             u32, u64, i8, i16, i32, i64, r32, r64, b, vs or os), such as `edsgen ecat sdo write \
             --iface ecm 6060:0 9 --type u8`\n"
        ),
        "{untyped:?}"
    );
    let missing = ecat(&["read", "--iface", "ecm", "1234:0"]);
    assert_eq!(missing.code, Some(1));
    assert!(missing.stderr.contains("0x06020000"), "{missing:?}");
    // By name through the ESI, typed by its data types (a segmented read for 1008h's 13 bytes).
    let esi = root().join("eds/ec-tx508.xml");
    let esi = esi.to_str().expect("a path");
    let named = |args: &[&str]| ecat(&[&["--iface", "ecm", "--esi", esi][..], args].concat());
    for (args, line) in [
        (
            &["read", "ID object / Supplier"][..],
            "1018h:01h ID object / Supplier ID = 1240 (0x000004D8)\n",
        ),
        (
            &["read", "factory device"],
            "1008h:00h Factory device name = INVT-EtherCAT\n",
        ),
        (
            &["write", "operationmode", "-3"],
            "6060h:00h Operation mode written\n",
        ),
        (
            &["read", "Operation mode"],
            "6060h:00h Operation mode = -3 (0xFD)\n",
        ),
    ] {
        let done = named(args);
        assert_eq!(
            (done.code, done.stdout.as_str()),
            (Some(0), line),
            "{done:?}"
        );
    }
    let ambiguous = named(&["read", "operation"]);
    assert_eq!(
        (ambiguous.code, ambiguous.stderr.as_str()),
        (
            Some(2),
            "error: `operation` names 2 entries; did you mean:\n  6060:0  Operation mode\n  \
             6061:0  Operation mode display\n"
        )
    );
    let too_big = named(&["write", "Operation mode", "300"]);
    assert_eq!(
        (too_big.code, too_big.stderr.as_str()),
        (Some(2), "error: 300 does not fit i8\n")
    );
    let refused = named(&["write", "ID object / Supplier", "5"]);
    assert_eq!(
        (refused.code, refused.stderr.as_str()),
        (
            Some(1),
            "error: ecm: 1018h:01h: 0x06010002: Attempt to write to a read only object\n"
        )
    );
    let ecat_pdo = |args: &[&str]| {
        let base = ["ecat", "pdo", "--iface", "ecm", "--esi", "eds/ec-tx508.xml"];
        let mut command = ns.exec(EDSGEN, &[&base[..], args].concat());
        command.current_dir(root());
        Process::start(&mut command).finish(Duration::from_secs(60))
    };
    let pdo = ecat_pdo(&["--cycles", "2"]);
    assert_eq!(pdo.code, Some(0), "{pdo:?}");
    // Outputs by name: the drive takes the operation mode, and its display shows it.
    let set = ecat_pdo(&["--cycles", "20", "operation mode=9"]);
    assert_eq!(set.code, Some(0), "{set:?}");
    let last = set.stdout.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("19: ") && last.contains(", Operation mode display=9, "),
        "{set:?}"
    );
    let lines: Vec<&str> = pdo.stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{pdo:?}");
    for (n, line) in lines.iter().enumerate() {
        assert!(
            line.starts_with(&format!(
                "{n}: Status word=1616, Position actual value=0, Actual speed=0, "
            )),
            "{line}"
        );
        assert!(
            line.ends_with(", Probe status=0, Probe position rising edge=0"),
            "{line}"
        );
    }
}

/// `edsgen ecat check` judges the simulated EC-TX508 against its own ESI (clean, exit 0) and
/// against an ESI that differs from it once per check (exit 1, each difference shown).
fn check(ns: &Namespace) {
    let card = ns.simulator(&["--card", "ec-tx508"]);
    let check = |esi: &str| {
        let mut command = ns.exec(EDSGEN, &["ecat", "check", "--iface", "ecm", "--esi", esi]);
        command.current_dir(root());
        Process::start(&mut command).finish(Duration::from_secs(60))
    };
    let clean = check("eds/ec-tx508.xml");
    assert_eq!(
        (clean.code, clean.stdout.as_str()),
        (
            Some(0),
            "SubDevice 0 checked against eds/ec-tx508.xml: 0 error(s), 0 warning(s)\n"
        ),
        "{clean:?}"
    );
    let altered = check("tests/esi/ec-tx508-altered.xml");
    assert_eq!(altered.code, Some(1), "{altered:?}");
    assert_eq!(altered.stdout, ALTERED, "{altered:?}");
    drop(card);
    // A SubDevice without CoE is judged by its SII alone.
    let io = root().join("tests/esi/io-no-mailbox.xml");
    let _sim = ns.simulator(&[io.to_str().expect("a path")]);
    let clean = check("tests/esi/io-no-mailbox.xml");
    assert_eq!(
        (clean.code, clean.stdout.as_str()),
        (
            Some(0),
            "SubDevice 0 checked against tests/esi/io-no-mailbox.xml: 0 error(s), 0 warning(s)\n"
        ),
        "{clean:?}"
    );
}

/// What `edsgen ecat check` says of the EC-TX508 against tests/esi/ec-tx508-altered.xml.
const ALTERED: &str = "\
error[CHK006]: the revision in the SII of SubDevice 0 is 0x00000001, the ESI says 0x00000002
  --> tests/esi/ec-tx508-altered.xml:25:52
   |
25 |         <Type ProductCode=\"#x00009252\" RevisionNo=\"#x00000002\">EC-TX508</Type>
   |                                                    ^^^^^^^^^^
   |

warning[CHK005]: 1018h:03h Identity object / Revision number of SubDevice 0 holds 1 (0x00000001), the description's default is 2
   --> tests/esi/ec-tx508-altered.xml:133:37
    |
133 |                       <DefaultValue>2</DefaultValue>
    |                                     -
    |

error[CHK001]: object 2100h is missing on SubDevice 0
   --> tests/esi/ec-tx508-altered.xml:138:15
    |
138 |               <Object>
    |               ^^^^^^^
    |

error[CHK002]: 6060h:00h of SubDevice 0 is 1 byte(s) long, its data type INTEGER16 has 2
   --> tests/esi/ec-tx508-altered.xml:147:15
    |
147 |               <Object>
    |               ^^^^^^^
    |

error[CHK007]: SM2 in the SII of SubDevice 0 starts at 0x1800 (the ESI: 0x1100)
   --> tests/esi/ec-tx508-altered.xml:165:9
    |
165 |         <Sm DefaultSize=\"128\" StartAddress=\"#x1100\" ControlByte=\"#x64\" Enable=\"1\">Outputs</Sm>
    |         ^^^
    |

error[CHK008]: 1C13h of SubDevice 0 assigns 1A00h to SM3, the ESI assigns 1A01h by default
   --> tests/esi/ec-tx508-altered.xml:166:9
    |
166 |         <Sm DefaultSize=\"128\" StartAddress=\"#x1C00\" ControlByte=\"#x20\" Enable=\"1\">Inputs</Sm>
    |         ^^^
    |

error[CHK008]: 1600h of SubDevice 0 maps 6040h:00h/16, 607Ah:00h/32, 60FFh:00h/32, 6071h:00h/16, 6072h:00h/16, 6060h:00h/8, 6081h:00h/32, 60B8h:00h/16, the ESI's 1600h (RX PDO1 mapping parameter) maps 6040h:00h/16, 6060h:00h/16
   --> tests/esi/ec-tx508-altered.xml:167:9
    |
167 |         <RxPdo Fixed=\"0\" Mandatory=\"0\" Sm=\"2\">
    |         ^^^^^^
    |

SubDevice 0 checked against tests/esi/ec-tx508-altered.xml: 6 error(s), 1 warning(s)
";

/// ethercrab reads back the SII image the simulator serves: byte for byte what `edsgen sii`
/// writes (0xFF past its end marker, up to the size word 0x3E gives), and it takes from it the
/// identity, the order string (its name), the device name (its description) and the mailbox
/// SyncManagers. A device without CoE is configured from the SII's PDO categories alone.
fn sii_read_back(ns: &Namespace) {
    let io = root().join("tests/esi/io-no-mailbox.xml");
    let io = io.to_str().expect("a path");
    for (served, esi, expected) in [
        (
            &["--card", "ec-tx508"][..],
            "eds/ec-tx508.xml",
            "identity 0x000004d8 0x00009252 0x00000001\nname EC-TX508\n\
             description EC-TX508 EtherCAT communication card (Goodrive350)\n\
             sm0 0x1000 512 0x26\nsm1 0x1400 512 0x22\n",
        ),
        (
            &[io][..],
            "tests/esi/io-no-mailbox.xml",
            "identity 0x00001234 0x00000101 0x00000003\nname TIO-8\n\
             description Test I/O, 8 outputs, 8 inputs and a counter\n\
             sm0 0x0000 0 0x00\nsm1 0x0000 0 0x00\n",
        ),
    ] {
        let image = std::env::temp_dir().join(format!("edsgen-sii-{}.bin", std::process::id()));
        let written = Command::new(EDSGEN)
            .current_dir(root())
            .args(["sii", esi, "-o", image.to_str().expect("a path")])
            .output()
            .expect("edsgen sii");
        assert!(written.status.success(), "{written:?}");
        let image_bytes = std::fs::read(&image).expect("the image");
        let _ = std::fs::remove_file(&image);
        let _sim = ns.simulator(served);
        let done = ns.master("eeprom").finish(Duration::from_secs(60));
        assert_eq!(done.code, Some(0), "{esi}: {done:?}");
        let (parsed, sii) = done.stdout.split_once("sii ").expect("the SII line");
        assert_eq!(parsed, expected, "{esi}");
        let sii = sii.trim_end();
        let read: Vec<u8> = (0..sii.len() / 2)
            .map(|i| u8::from_str_radix(&sii[2 * i..2 * i + 2], 16).expect("hex"))
            .collect();
        assert!(
            read.len() >= image_bytes.len(),
            "{esi}: {} bytes read",
            read.len()
        );
        assert_eq!(read[..image_bytes.len()], image_bytes[..], "{esi}");
        assert!(
            read[image_bytes.len()..].iter().all(|&b| b == 0xFF),
            "{esi}"
        );
    }
    let _sim = ns.simulator(&[io]);
    let done = ns.master("corpus").finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{done:?}");
    assert!(done.stdout.contains("op 1/3"), "{done:?}");
}

/// SOEM (pysoem, pinned in scripts/python-venv.sh) finds the EC-TX508, maps its 21/23-byte
/// images from CoE and brings it to Op with the working counter it expects.
fn soem(ns: &Namespace) -> String {
    let Some(python) = python() else {
        return "SOEM skipped".to_owned();
    };
    let _sim = ns.simulator(&["--card", "ec-tx508"]);
    soem_reaches_op(ns, &python);
    "SOEM".to_owned()
}

/// SOEM (pysoem) finds the EC-TX508 and takes it to Op.
fn soem_reaches_op(ns: &Namespace, python: &Path) {
    let script = root().join("scripts/soem_master.py");
    let master = Process::start(&mut ns.exec(
        python.to_str().expect("a path"),
        &[script.to_str().expect("a path"), "ecm"],
    ));
    let done = master.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{done:?}");
    assert_eq!(
        done.stdout,
        "found 1\nidentity 0x000004d8 0x00009252 0x00000001\nname EC-TX508\niomap 44\nstate 4\n\
         images 21/23\nop True\nwkc 3 expected 3\n",
        "{done:?}"
    );
}

/// Hostile frames over the wire (issue 34): the simulator outlives 3,000 mutated frames and
/// SOEM takes the SubDevice to Op afterwards.
fn hostile(ns: &Namespace) -> String {
    let Some(python) = python() else {
        return "hostile frames skipped (no python)".to_owned();
    };
    let _sim = ns.simulator(&["--card", "ec-tx508"]);
    let sent = ns.master("hostile").finish(Duration::from_secs(120));
    assert_eq!(sent.code, Some(0), "{sent:?}");
    assert_eq!(sent.stdout, "sent 3000\n", "{sent:?}");
    // The simulator still answers: SOEM needs it.
    soem_reaches_op(ns, &python);
    "3000 hostile frames".to_owned()
}

/// The `hostile` role: 3,000 frames mutated from a recorded start-up (seed 0x5EED_EC47), each
/// sent and its answer, if any, read.
fn send_hostile_frames(iface: &str) {
    use edsgen_sim::packet_socket::PacketSocket;
    let model = edsgen_model::read::read_file(&root().join("eds/ec-tx508.xml"))
        .expect("readable")
        .device;
    let device = EsiDevice::subdevice(&model, None).expect("the EC-TX508");
    let good = hostile_support::recorded_start_up(device);
    let mut rng = hostile_support::Rng(0x5EED_EC47);
    let mut socket =
        PacketSocket::open(iface, 0x88A4, Duration::from_millis(2)).expect("the raw socket");
    let mut buf = vec![0u8; 2048];
    for _ in 0..3000 {
        let frame = hostile_support::mutate(&mut rng, &good);
        socket.send(&frame).expect("sent");
        while let Ok(Some(_)) = socket.recv(&mut buf) {}
    }
    println!("sent 3000");
}

/// Every ESI of the corpus (its first device) whose dictionary and PDOs are complete enough
/// ([`complete_enough`]) reaches Op with the image sizes its assignment gives.
fn corpus(ns: &Namespace) -> String {
    let Some(dir) = esi_corpus_dir() else {
        return "corpus skipped".to_owned();
    };
    let mut files = Vec::new();
    collect(&dir, &mut files);
    files.sort();
    let (mut served, mut passed_over) = (0, Vec::new());
    for file in &files {
        let loaded = edsgen_model::load::load(file, None).expect("readable");
        let model = loaded.device;
        // `edsgen simulate` refuses a description with errors (without `--allow`).
        let clean = !loaded
            .diagnostics
            .iter()
            .any(|d| d.severity == edsgen_model::diag::Severity::Error);
        let Some((outputs, inputs)) = complete_enough(&model).filter(|_| clean) else {
            passed_over.push(
                file.strip_prefix(&dir)
                    .unwrap_or(file)
                    .display()
                    .to_string(),
            );
            continue;
        };
        let _sim = ns.simulator(&[file.to_str().expect("a path")]);
        let master = ns.master("corpus");
        let done = master.finish(Duration::from_secs(60));
        assert_eq!(done.code, Some(0), "{}: {done:?}", file.display());
        assert!(
            done.stdout.contains(&format!("op {outputs}/{inputs}")),
            "{}: {done:?}",
            file.display()
        );
        // Served from its own ESI, the SubDevice is clean by `edsgen ecat check`.
        let path = file.to_str().expect("a path");
        let mut command = ns.exec(EDSGEN, &["ecat", "check", "--iface", "ecm", "--esi", path]);
        let checked = Process::start(&mut command).finish(Duration::from_secs(60));
        assert_eq!(checked.code, Some(0), "{}: {checked:?}", file.display());
        assert!(
            checked.stdout.ends_with(": 0 error(s), 0 warning(s)\n"),
            "{}: {checked:?}",
            file.display()
        );
        served += 1;
    }
    assert!(served > 0, "no ESI of the corpus reached Op");
    println!(
        "corpus: {served} ESI files reached Op; {} passed over (errors, modular, no CoE mailbox or a disabled one, no process data, or PDOs naming objects the dictionary lacks): {passed_over:?}",
        passed_over.len()
    );
    format!("{served} corpus files")
}

/// The MainDevice side, run in the namespace.
mod master {
    use std::io::BufRead;
    use std::time::Duration;

    use edsgen_runtime::cia402::State;
    use edsgen_runtime::ethercat::ethercrab::SdoExt;
    use edsgen_runtime::master::cia402::{Controller, Outcome};
    use edsgen_sim::cards::ec_tx508::{ethercat, od};
    use ethercrab::std::{ethercat_now, tx_rx_task};
    use ethercrab::{EtherCrabWireRead, EtherCrabWireWrite};
    use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

    const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
    static PDU_STORAGE: PduStorage<16, MAX_PDU_DATA> = PduStorage::new();

    pub fn run(role: &str, iface: &str) {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime");
        runtime.block_on(async {
            let (tx, rx, pdu_loop) = PDU_STORAGE.try_split().expect("split once");
            // Generous timeouts: the machine running the tests may be loaded.
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
                .init_single_group::<4, 256>(ethercat_now)
                .await
                .expect("discovery");
            if role == "eeprom" {
                let card = group.subdevice(&maindevice, 0).expect("one SubDevice");
                let size = card.eeprom_size(&maindevice).await.expect("the SII's size");
                let mut image = vec![0u8; size];
                card.eeprom_read_raw(&maindevice, 0, &mut image)
                    .await
                    .expect("the SII");
                let id = card.identity();
                println!(
                    "identity {:#010x} {:#010x} {:#010x}",
                    id.vendor_id, id.product_id, id.revision
                );
                println!("name {}", card.name());
                let description = card.description().await.expect("the SII's name");
                println!("description {}", description.unwrap_or_default());
                // The mailbox SyncManagers ethercrab set up in Pre-Op from the SII's SyncM
                // category: start, length, control.
                for n in 0..2u16 {
                    let sm: [u8; 8] = card
                        .register_read(0x0800 + 8 * n)
                        .await
                        .expect("a SyncManager");
                    let start = u16::from_le_bytes([sm[0], sm[1]]);
                    let len = u16::from_le_bytes([sm[2], sm[3]]);
                    println!("sm{n} {start:#06x} {len} {:#04x}", sm[4]);
                }
                let hex: Vec<String> = image.iter().map(|b| format!("{b:02x}")).collect();
                println!("sii {}", hex.concat());
                return;
            }
            if role == "corpus" {
                let group = group.into_op(&maindevice).await.expect("Op");
                for _ in 0..10 {
                    group.tx_rx(&maindevice).await.expect("a cycle");
                }
                let card = group.subdevice(&maindevice, 0).expect("one SubDevice");
                println!(
                    "op {}/{}",
                    card.outputs_raw().len(),
                    card.inputs_raw().len()
                );
                return;
            }
            let card = group.subdevice(&maindevice, 0).expect("one SubDevice");
            assert!(ethercat::IDENTITY.matches_subdevice(&card));
            // ethercrab names a SubDevice by the SII's order string: the ESI's Type.
            assert_eq!(card.name(), "EC-TX508");
            let identity = card.identity();
            assert_eq!(
                (identity.vendor_id, identity.product_id, identity.revision),
                (0x04D8, 0x9252, 1)
            );
            if role == "reassign" {
                card.sdo_write(0x1C12, 0, 0u8).await.expect("1C12h:00 := 0");
                card.sdo_write(0x1C12, 1, 0x1601u16)
                    .await
                    .expect("1C12h:01 := 1601h");
                card.sdo_write(0x1C12, 0, 1u8).await.expect("1C12h:00 := 1");
                let group = group.into_op(&maindevice).await.expect("Op");
                group.tx_rx(&maindevice).await.expect("a cycle");
                let card = group.subdevice(&maindevice, 0).expect("one SubDevice");
                println!(
                    "images {}/{}",
                    card.outputs_raw().len(),
                    card.inputs_raw().len()
                );
                return;
            }
            let assigned: u16 = card
                .read_entry(od::rx_pdo_assignment::RX_PDO_ASSIGNED_OBJECT_INDEX)
                .await
                .expect("typed SDO read");
            assert_eq!(assigned, 0x1600);
            card.write_entry(od::OPERATION_MODE, 9)
                .await
                .expect("typed SDO write");
            // Pre-Op to Op skips Safe-Op: refused with 0x0011, then acknowledged.
            card.register_write(0x0120u16, 8u16)
                .await
                .expect("AL control");
            tokio::time::sleep(Duration::from_millis(100)).await;
            let status: u16 = card.register_read(0x0130u16).await.expect("AL status");
            let code: u16 = card.register_read(0x0134u16).await.expect("AL status code");
            assert_eq!((status, code), (0x12, 0x0011));
            card.register_write(0x0120u16, 0x12u16)
                .await
                .expect("acknowledge");
            tokio::time::sleep(Duration::from_millis(100)).await;
            let status: u16 = card.register_read(0x0130u16).await.expect("AL status");
            assert_eq!(status, 0x02);

            let group = group.into_op(&maindevice).await.expect("Op");
            let card = group.subdevice(&maindevice, 0).expect("one SubDevice");
            assert_eq!(card.outputs_raw().len(), ethercat::Outputs::SIZE);
            assert_eq!(card.inputs_raw().len(), ethercat::Inputs::SIZE);
            assert_eq!((ethercat::Outputs::SIZE, ethercat::Inputs::SIZE), (21, 23));
            let mut outputs = ethercat::Outputs::default();
            let mut drive = Controller::new(State::OperationEnabled)
                .with_mode(9)
                .with_limit(2_000);
            let mut speeds = Vec::new();
            for _ in 0u32..2_500 {
                group.tx_rx(&maindevice).await.expect("a cycle");
                let inputs =
                    ethercat::Inputs::unpack_from_slice(&card.inputs_raw()).expect("inputs");
                let status = inputs.tx_pdo_1a00;
                let step = drive.cycle(status.status_word, status.operation_mode_display);
                assert!(
                    matches!(step.outcome, Outcome::Busy | Outcome::Reached),
                    "{:?}",
                    step.outcome
                );
                let enabled = step.outcome == Outcome::Reached;
                let rx = &mut outputs.rx_pdo_1600;
                rx.control_word = step.controlword;
                rx.operation_mode = step.mode.unwrap_or(9);
                rx.target_speed = if enabled { 300 } else { 0 };
                outputs
                    .pack_to_slice(&mut card.outputs_raw_mut())
                    .expect("outputs");
                speeds.push(status.actual_speed);
                tokio::time::sleep(Duration::from_millis(1)).await;
            }
            // The 3 rpm/ms ramp: rising, then held at 300.
            assert!(speeds.windows(2).all(|w| w[0] <= w[1]), "{speeds:?}");
            assert_eq!(speeds.last(), Some(&300), "{speeds:?}");
            assert!(speeds.iter().any(|&s| s > 0 && s < 300), "{speeds:?}");
            let first = speeds.iter().position(|&s| s > 0).unwrap_or(0);
            let full = speeds.iter().position(|&s| s == 300).unwrap_or(0);
            println!("ramp: first motion at cycle {first}, 300 rpm at cycle {full}");
            println!("unplug");
            let mut line = String::new();
            let _ = std::io::stdin().lock().read_line(&mut line);
            let err = group
                .tx_rx(&maindevice)
                .await
                .expect_err("the SubDevice is gone");
            println!("gone: {err:?}");
        });
    }
}
