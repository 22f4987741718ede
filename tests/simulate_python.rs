//! `edsgen simulate` against python `canopen` 2.4.1 as master, through a socketcand hub on
//! 127.0.0.1 (the runtime's `transport::hub`, started in the test): for each bundled card and
//! five corpus files (a DCF whose node-ID comes from its `[DeviceComissioning]`, an XDD, one
//! with CompactSubObj, one with DOMAINs, a big Sevcon file), `scripts/canopen_master.py` runs
//! NMT, heartbeat, SDO expedited, segmented and block both ways, an abort, PDO configuration
//! through python's PDO API with TPDO exchange on SYNC and an RPDO, and an EMCY. The expected
//! lines are computed from the device's run-time dictionary. Three python masters run at once
//! against three devices of one `edsgen simulate` on one hub. And a session's hub trace,
//! decoded by `edsgen decode`, names the entries and shows the values sent.
//!
//! Every wait is bounded; the simulator is killed when its guard drops.

mod process_support;
#[path = "../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use edsgen_host::hub::{Hub, HubOptions};
use edsgen_model::model::Device;
use edsgen_runtime::{Access, DataType, ObjectDictionary};
use edsgen_sim::canopen::{commissioned_node_id, RuntimeDictionary};
use process_support::{corpus_file, edsgen_simulate, python, root, Process, EDSGEN};

/// `scripts/canopen_master.py ARGS` to its end (at most 60 s): its standard output's lines.
fn run_python(python: &Path, args: &[&str]) -> Vec<String> {
    run_script(python, "scripts/canopen_master.py", args)
}

/// A python script's standard output, line by line; it must exit 0 within a minute.
fn run_script(python: &Path, script: &str, args: &[&str]) -> Vec<String> {
    let master = Process::python(python, script, args);
    let exited = master.finish(Duration::from_secs(60));
    assert_eq!(
        exited.code,
        Some(0),
        "python master failed:\n{}\n{}",
        exited.stdout,
        exited.stderr
    );
    exited.stdout.lines().map(str::to_owned).collect()
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn read_value(od: &impl ObjectDictionary, index: u16, sub: u8) -> Vec<u8> {
    let mut buf = vec![0u8; od.value_len(index, sub).unwrap()];
    let n = od.read(index, sub, 0, &mut buf).unwrap();
    buf.truncate(n);
    buf
}

fn is_integer(data_type: DataType) -> bool {
    !matches!(
        data_type,
        DataType::Boolean
            | DataType::Real32
            | DataType::Real64
            | DataType::VisibleString
            | DataType::OctetString
            | DataType::UnicodeString
            | DataType::Domain
            | DataType::TimeOfDay
            | DataType::TimeDifference
    )
}

/// A new value for the entry at `position` the dictionary accepts (its value plus 1, else
/// minus 1), if there is one.
fn new_value(od: &RuntimeDictionary, position: usize) -> Option<Vec<u8>> {
    let e = od.entries()[position];
    let now = read_value(od, e.index(), e.sub());
    let plus = now
        .iter()
        .copied()
        .fold((Vec::new(), 1u16), |(mut v, carry), b| {
            let sum = u16::from(b) + carry;
            v.push(sum as u8);
            (v, sum >> 8)
        });
    let minus = now
        .iter()
        .copied()
        .fold((Vec::new(), 1i16), |(mut v, borrow), b| {
            let diff = i16::from(b) - borrow;
            v.push(diff as u8);
            (v, i16::from(diff < 0))
        });
    [plus.0, minus.0]
        .into_iter()
        .find(|candidate| od.clone().write(e.index(), e.sub(), candidate).is_ok())
}

/// What python should do with `device` as node `node_id`, and the lines it should print.
fn plan(device: &Device, node_id: u8) -> (serde_json::Value, Vec<String>) {
    let mut od = RuntimeDictionary::new(device, node_id);
    let entries = od.entries().to_vec();
    let name = |e: &edsgen_runtime::EntryDescriptor| format!("{:04X}:{:02X}", e.index(), e.sub());
    // Python's object dictionary: every object the dictionary holds.
    let mut objects: Vec<serde_json::Value> = Vec::new();
    for object in device.objects.values() {
        let subs: Vec<serde_json::Value> = entries
            .iter()
            .filter(|e| e.index() == object.index)
            .map(|e| {
                let sub = &object.subs[&e.sub()];
                let basic = device.basic_type(sub.data_type.unwrap()).unwrap();
                serde_json::json!([e.sub(), basic.index(), access(e.access()), sub.name])
            })
            .collect();
        if !subs.is_empty() {
            objects.push(serde_json::json!({
                "index": object.index,
                "name": object.name,
                "record": object.object_type.has_subs(),
                "subs": subs,
            }));
        }
    }
    let skip_comm = |index: u16| (0x1000..0x2000).contains(&index);
    let fixed_integer = |e: &edsgen_runtime::EntryDescriptor| {
        is_integer(e.data_type()) && e.data_type().fixed_size().is_some_and(|s| s <= 4)
    };
    let rw = (0..entries.len())
        .find(|&p| {
            let e = entries[p];
            !skip_comm(e.index()) && e.access().writable() && fixed_integer(&e)
        })
        .expect("a writable integer");
    let rw_value = new_value(&od, rw).expect("a new value");
    od.write(entries[rw].index(), entries[rw].sub(), &rw_value)
        .unwrap();
    let bytes = (0..entries.len()).find(|&p| {
        let e = entries[p];
        e.access().writable()
            && matches!(
                e.data_type(),
                DataType::VisibleString | DataType::OctetString | DataType::Domain
            )
            && od.capacity(p).is_some_and(|c| c >= 20)
    });
    // PDO1 is configured only where its mapping can change (sub-index 0 writable).
    let dynamic = |index: u16| od.find(index, 0).is_ok_and(|e| e.access().writable());
    let tpdo = (0..entries.len()).find(|&p| {
        let e = entries[p];
        dynamic(0x1A00)
            && e.pdo_mappable()
            && matches!(e.access(), Access::Ro | Access::Rw | Access::Rwr)
            && fixed_integer(&e)
            && p != rw
    });
    let rpdo = (0..entries.len()).find(|&p| {
        let e = entries[p];
        dynamic(0x1600)
            && e.pdo_mappable()
            && matches!(e.access(), Access::Rw | Access::Rww | Access::Wo)
            && fixed_integer(&e)
            && new_value(&od, p).is_some()
    });
    // The node sends emergencies on 80h + node-ID without 1014h, else where 1014h holds a
    // valid COB-ID (Sevcon's has no default: 0).
    let emcy = od.find(0x1014, 0).is_err() || {
        let cob = read_value(&od, 0x1014, 0);
        cob.len() == 4
            && cob[3] & 0x80 == 0
            && u32::from_le_bytes([cob[0], cob[1], cob[2], cob[3]]) != 0
    };
    let absent = (0x5FFFu16..).find(|&i| od.locate(i, 0).is_err()).unwrap();

    let mut expected = vec![
        "boot-up".to_owned(),
        "heartbeat pre-operational".to_owned(),
        format!("read 1000:00 {}", hex(&read_value(&od, 0x1000, 0))),
        format!("write {} {}", name(&entries[rw]), hex(&rw_value)),
    ];
    let mut plan = serde_json::json!({
        "node_id": node_id,
        "objects": objects,
        "rw": {"entry": name(&entries[rw]), "value": hex(&rw_value)},
        "absent": format!("{absent:04X}:00"),
        "emcy": emcy,
    });
    if let Some(p) = bytes {
        let value: Vec<u8> = b"edsgen simulate 2026".to_vec();
        let reversed: Vec<u8> = value.iter().rev().copied().collect();
        plan["bytes"] = serde_json::json!({"entry": name(&entries[p]), "value": hex(&value)});
        expected.push(format!("segmented {} {}", name(&entries[p]), hex(&value)));
        expected.push(format!("block {} {}", name(&entries[p]), hex(&reversed)));
    }
    expected.extend(["abort 06020000".to_owned(), "operational".to_owned()]);
    if let Some(p) = tpdo {
        let e = entries[p];
        plan["tpdo"] = serde_json::json!(name(&e));
        expected.push(format!(
            "tpdo {} {}",
            name(&e),
            hex(&read_value(&od, e.index(), e.sub()))
        ));
    }
    if let Some(p) = rpdo {
        let value = new_value(&od, p).unwrap();
        plan["rpdo"] = serde_json::json!({"entry": name(&entries[p]), "value": hex(&value)});
        expected.push(format!("rpdo {} {}", name(&entries[p]), hex(&value)));
        expected.push(format!("emcy {}", if emcy { "8210" } else { "none" }));
    }
    expected.push("stopped".to_owned());
    (plan, expected)
}

fn access(access: Access) -> &'static str {
    match access {
        Access::Ro => "ro",
        Access::Wo => "wo",
        Access::Rw => "rw",
        Access::Rwr => "rwr",
        Access::Rww => "rww",
        Access::Const => "const",
    }
}

/// python as master of `path` simulated as `node_id` (`None`: the DCF's own), through a hub
/// whose trace goes to `trace` if given.
fn python_masters(path: &Path, node_id: Option<u8>, trace: Option<&Path>) {
    python_masters_all(&[(path, node_id)], trace, &[]);
}

/// One `edsgen simulate` serving every device, and one python master per device, all at once,
/// on one hub.
fn python_masters_all(devices: &[(&Path, Option<u8>)], trace: Option<&Path>, allow: &[&str]) {
    let Some(python) = python() else { return };
    let dir = std::env::temp_dir().join(format!("edsgen-simulate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut args = Vec::new();
    let mut masters = Vec::new();
    for &(path, node_id) in devices {
        let device = edsgen_model::read::read_file(path).unwrap().device;
        let id = node_id.unwrap_or_else(|| commissioned_node_id(&device).unwrap() as u8);
        let (plan, expected) = plan(&device, id);
        let plan_path = dir.join(format!("plan-{id}.json"));
        std::fs::write(&plan_path, plan.to_string()).unwrap();
        let file = path.to_str().unwrap().to_owned();
        args.push(match node_id {
            Some(id) => format!("{file}@{id}"),
            None => file,
        });
        masters.push((path.to_owned(), plan_path, expected));
    }
    for code in allow {
        args.extend(["--allow".to_owned(), (*code).to_owned()]);
    }
    let log: Option<Box<dyn std::io::Write + Send>> =
        trace.map(|p| Box::new(std::fs::File::create(p).unwrap()) as _);
    let hub = Hub::start(
        "127.0.0.1:0",
        HubOptions {
            log,
            ..HubOptions::default()
        },
    )
    .expect("the hub starts");
    let addr = hub.local_addr().to_string();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let bus = ["--bus", &addr];
    let (sim, _) = edsgen_simulate(&[args.as_slice(), &bus].concat(), devices.len());
    let (host, port) = addr.rsplit_once(':').unwrap();
    let running: Vec<_> = masters
        .into_iter()
        .map(|(path, plan_path, expected)| {
            let (python, host, port) = (python.clone(), host.to_owned(), port.to_owned());
            std::thread::spawn(move || {
                let got = run_python(&python, &[&host, &port, plan_path.to_str().unwrap()]);
                assert_eq!(got, expected, "{}", path.display());
            })
        })
        .collect();
    for master in running {
        master.join().expect("a python master passed");
    }
    drop(sim);
    hub.stop();
}

#[test]
fn several_python_masters_and_simulated_nodes_on_one_hub() {
    python_masters_all(
        &[
            (&root().join("eds/cp301.eds"), Some(21)),
            (&root().join("eds/goodrive350.eds"), Some(22)),
            (&root().join("eds/ms300.eds"), Some(23)),
        ],
        None,
        &[],
    );
}

/// A mixed bus, bundled cards and description files in one `simulate`: python `canopen`'s
/// scanner finds every node, and reads each one's device type and identity as its file says.
#[test]
fn python_canopen_scans_a_bus_of_cards_and_files() {
    let Some(python) = python() else { return };
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).expect("the hub starts");
    let addr = hub.local_addr().to_string();
    let ms300 = root().join("eds/ms300.eds");
    let rd11 = root().join("eds/rd11.eds");
    let args = [
        "--card".to_owned(),
        "cp301@2".to_owned(),
        "--card".to_owned(),
        "goodrive350@3".to_owned(),
        format!("{}@4", ms300.display()),
        format!("{}@5", rd11.display()),
        "--bus".to_owned(),
        addr.clone(),
    ];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (sim, _) = edsgen_simulate(&args, 4);
    let (host, port) = addr.rsplit_once(':').unwrap();
    let got = run_script(&python, "scripts/canopen_scan.py", &[host, port]);
    let mut expected = vec!["found 2 3 4 5".to_owned()];
    for (node, file) in [
        (2, "eds/cp301.eds"),
        (3, "eds/goodrive350.eds"),
        (4, "eds/ms300.eds"),
        (5, "eds/rd11.eds"),
    ] {
        let device = edsgen_model::read::read_file(&root().join(file))
            .unwrap()
            .device;
        let od = RuntimeDictionary::new(&device, node);
        let word = |index, sub| {
            let bytes = read_value(&od, index, sub);
            let mut le = [0u8; 4];
            le[..bytes.len()].copy_from_slice(&bytes);
            u32::from_le_bytes(le)
        };
        expected.push(format!(
            "node {node} 1000h {:#010x} vendor {:#010x} product {:#010x}",
            word(0x1000, 0),
            word(0x1018, 1),
            word(0x1018, 2)
        ));
    }
    assert_eq!(got, expected);
    drop(sim);
    hub.stop();
}

#[test]
fn python_masters_the_simulated_cp301() {
    python_masters(&root().join("eds/cp301.eds"), Some(3), None);
}

#[test]
fn python_masters_the_simulated_ms300() {
    python_masters(&root().join("eds/ms300.eds"), Some(4), None);
}

#[test]
fn python_masters_the_simulated_goodrive350() {
    python_masters(&root().join("eds/goodrive350.eds"), Some(5), None);
}

#[test]
fn python_masters_the_simulated_rd11() {
    python_masters(&root().join("eds/rd11.eds"), Some(6), None);
}

#[test]
fn python_masters_the_simulated_hd1e() {
    python_masters(&root().join("eds/hd1e.eds"), Some(7), None);
}

#[test]
fn python_masters_a_dcf_at_its_commissioned_node_id() {
    // Its PDO mappings are static (CompactSubObj: sub-index 0 read-only): no PDO part.
    if let Some(path) = corpus_file("ros-industrial__ros_canopen/canopen_402__resources__pilz.dcf")
    {
        python_masters(&path, None, None);
    }
}

#[test]
fn python_masters_a_dcf_with_dynamic_pdo_mapping() {
    if let Some(path) = corpus_file("lely-industries__lely-core/test__gw_txt-slave.dcf") {
        python_masters(&path, Some(20), None);
    }
}

#[test]
fn python_masters_an_xdd() {
    if let Some(path) = corpus_file("CANopenNode__CANopenDemo/demo__demoDevice.xdd") {
        python_masters(&path, Some(10), None);
    }
}

#[test]
fn python_masters_a_file_with_compact_sub_obj() {
    // The file has two errors python `canopen` does not mind (CompactSubObj=255 for 1003h, a
    // mapping of an entry whose PDOMapping is 0): served only when they are allowed.
    if let Some(path) = corpus_file("christiansandberg__canopen/test__sensor.eds") {
        python_masters_all(&[(&path, Some(11))], None, &["EDS322", "EDS409"]);
    }
}

#[test]
fn python_masters_a_file_with_domains() {
    if let Some(path) = corpus_file("CANopenNode__CANopenNode/example__IO.eds") {
        python_masters(&path, Some(12), None);
    }
}

#[test]
fn python_masters_a_big_sevcon_file() {
    if let Some(path) = corpus_file("brtiberio__Sevcon_gen4/Gen4.eds") {
        python_masters(&path, Some(13), None);
    }
}

#[test]
fn a_session_trace_decoded_names_the_entries_and_shows_the_values_sent() {
    let dir = std::env::temp_dir().join(format!("edsgen-trace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let eds = dir.join("sim.eds");
    std::fs::write(&eds, sim_support::DEVICE_EDS).unwrap();
    let trace = dir.join("session.log");
    if python().is_none() {
        return;
    }
    python_masters(&eds, Some(9), Some(&trace));
    let out = Command::new(EDSGEN)
        .args(["decode", "--eds", eds.to_str().unwrap(), "--node-id", "9"])
        .arg(&trace)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    // Without the timestamps.
    let lines: Vec<String> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|line| line.split_once("  ").unwrap().1.to_owned())
        .collect();
    for expected in [
        "000  NMT        reset node 9",
        "709  HEARTBEAT  node 9 boot-up",
        "589  SDO        node 9 write 1017:00 Producer heartbeat time = 50",
        "709  HEARTBEAT  node 9 pre-operational",
        "589  SDO        node 9 read 1000:00 Device type = 131474 (0x00020192)",
        "589  SDO        node 9 write 2002:00 Target speed = 101",
        "589  SDO        node 9 read 2002:00 Target speed = 101",
        "589  SDO        node 9 write 2000:00 Device label = \"edsgen simulate 2026\" (segmented, 20 bytes)",
        "589  SDO        node 9 read 2000:00 Device label = \"edsgen simulate 2026\" (segmented, 20 bytes)",
        "589  SDO        node 9 write 2000:00 Device label = \"6202 etalumis negsde\" (block, 20 bytes, CRC 6CDEh)",
        "609  SDO        node 9 read 2000:00 Device label = \"6202 etalumis negsde\" (block, 20 bytes, CRC 6CDEh)",
        "589  SDO        node 9 read 5FFF:00 (not in the description): abort 0602 0000 object does not exist in the object dictionary",
        "589  SDO        node 9 write 1A00:01 TPDO1 mapping parameter: Mapped object 1 = 537067536 (0x20030010)",
        "000  NMT        start node 9",
        "080  SYNC",
        "189  TPDO1      node 9 Actual speed = -2",
        "209  RPDO1      node 9 Target speed = 102",
        "209  RPDO1      node 9 (empty) (the mapping needs 16 bits, the PDO has 0)",
        "089  EMCY       node 9 8210 PDO not processed due to length error; register 11h (generic, communication); manufacturer 00 00 00 00 00",
        "000  NMT        stop node 9",
    ] {
        assert!(lines.iter().any(|l| l == expected), "{expected}\nnot in\n{}", lines.join("\n"));
    }
    // Every frame attributed.
    assert!(
        !lines
            .iter()
            .any(|l| l.contains(" RAW ") || l.contains("fits no")),
        "{lines:#?}"
    );
}
