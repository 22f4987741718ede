//! Interoperability with python `canopen` 2.4.1 over python-can 4.6.1's socketcand interface: the
//! hub runs in-process on a free port of 127.0.0.1 (once as the `edsgen bus` command), nodes
//! built from the generated cards (`edsgen::cards`) run on the runtime's driver with the
//! socketcand client, and `scripts/interop_master.py` (in the venv of `scripts/python-venv.sh`)
//! is the master.
//!
//! Every value python reports is asserted exactly. Without python the tests are skipped with a
//! message, except under `CI=true`, where that is a failure. Every wait is bounded and the python
//! processes are killed if a test ends early.

mod process_support;

use std::io::{Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use edsgen::cards::{cp301, goodrive350};
use edsgen_runtime::node::Node;
use edsgen_runtime::od::ObjectDictionary;
use edsgen_runtime::transport::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_runtime::transport::hub::{Hub, HubOptions};
use edsgen_runtime::transport::socketcand::SocketcandClient;
use process_support::{edsgen_bus, python, root, Process};
use serde_json::{json, Value};

/// How long one python script may take.
const SCRIPT_TIMEOUT: Duration = Duration::from_secs(60);
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

/// `scripts/interop_master.py ARGS`.
fn interop_master(python: &Path, args: &[&str]) -> Process {
    Process::python(python, "scripts/interop_master.py", args)
}

/// Runs a script to its `RESULT`, calling `on_wait` for each `WAIT <what>` and answering `GO`
/// after it.
fn result(script: &mut Process, mut on_wait: impl FnMut(&str)) -> Value {
    loop {
        let line = script.stdout_line(
            |l| l.starts_with("WAIT ") || l.starts_with("RESULT "),
            SCRIPT_TIMEOUT,
        );
        if let Some(what) = line.strip_prefix("WAIT ") {
            on_wait(what);
            script.send_line("GO");
        } else if let Some(json) = line.strip_prefix("RESULT ") {
            return serde_json::from_str(json).unwrap();
        }
    }
}

type NodeDriver<O> = DriverHandle<SocketcandClient, Node<O>>;

/// A node serving `od` as `node_id` on the hub, run by the driver on its own thread.
fn run_node<O>(hub: &Hub, od: O, node_id: u8) -> NodeDriver<O>
where
    O: ObjectDictionary + Send + 'static,
{
    let transport = SocketcandClient::connect(hub.local_addr(), "can0", CONNECT_TIMEOUT).unwrap();
    let clock = MonotonicClock::new();
    let node = Node::new(od, node_id, clock.now()).unwrap();
    Driver::with_clock(transport, node, clock).spawn().unwrap()
}

fn eds(name: &str) -> String {
    root().join("eds").join(name).to_str().unwrap().to_owned()
}

#[test]
fn python_canopen_masters_the_generated_cp301_node_through_the_hub() {
    let Some(python) = python() else { return };
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let port = hub.local_addr().port().to_string();
    let mut script = interop_master(&python, &["full", &port, &eds("cp301.eds"), "5"]);
    let mut node: Option<NodeDriver<cp301::Od>> = None;
    let mut result = result(&mut script, |what| match what {
        "bootup" => node = Some(run_node(&hub, cp301::Od::new(5), 5)),
        "emcy" => {
            let raised = node.as_ref().unwrap().with_device(|node, _| {
                node.raise_error(0x5000, 0x81, [0x01, 0x02, 0x03, 0x04, 0x05])
            });
            assert!(raised);
        }
        other => panic!("unexpected WAIT {other}"),
    });
    let period = result
        .as_object_mut()
        .unwrap()
        .remove("heartbeat period ms")
        .unwrap();
    let period = period.as_u64().unwrap();
    assert!(
        (40..=70).contains(&period),
        "heartbeat period {period} ms, 1017h = 50 ms"
    );
    // 1001h as the node computes it: the communication bit (10h), with the generic bit (01h)
    // where the node sets it for any error. The EMCY must carry the same register.
    let register = result["1001 after the short rpdo"]
        .as_str()
        .unwrap()
        .to_owned();
    assert_eq!(
        u8::from_str_radix(&register, 16).unwrap() & 0x10,
        0x10,
        "{register}"
    );
    let expected = json!({
        "boot-up": "00",
        "expedited upload 1000": "00000000",
        "expedited 6042 written and read": -1500,
        "segmented download 6040, read back": "3412",
        "block download 6042, read back": 777,
        "block upload 6040": "3412",
        "abort: upload 5FFF:00": "06020000",
        "abort: upload 1018:09": "06090011",
        "abort: download 1000:00 (ro)": "06010002",
        "abort: download 3 bytes to 6040:00": "06070012",
        "abort: download 1 byte to 6040:00": "06070013",
        "heartbeats in pre-operational": ["7f"],
        "nmt OPERATIONAL: python's state": "OPERATIONAL",
        "nmt STOPPED: python's state": "STOPPED",
        "nmt PRE-OPERATIONAL: python's state": "PRE-OPERATIONAL",
        "tpdo1 as the device has it": ["00000185", 1, 2, "60400010", "60420010"],
        "rpdo1 as the device has it": ["00000205", 255, 2, "60400010", "60420010"],
        "tpdo1 on three syncs": [
            {"6040": 15, "6042": -300},
            {"6040": 15, "6042": -300},
            {"6040": 15, "6042": -300},
        ],
        "tpdo1 frame": "0f00d4fe",
        "emcy: short rpdo": ["8210", register, "0100000000"],
        "1001 after the short rpdo": register,
        "emcy: error reset": ["0000", "00", "0000000000"],
        "emcy: raised by the device": ["5000", "81", "0102030405"],
        "boot-up after reset communication": "00",
    });
    assert_eq!(result, expected, "{result:#}");
    let (ended, _, _) = node.unwrap().stop();
    ended.unwrap();
}

/// Connects, completes the handshake, sends half a message and closes, until `stop`: the client
/// that drops mid-message. Returns how many times it did.
fn drop_mid_message_until(addr: std::net::SocketAddr, stop: &AtomicBool) -> u32 {
    let mut drops = 0;
    while !stop.load(Ordering::Relaxed) {
        let mut stream = std::net::TcpStream::connect(addr).unwrap();
        stream.set_read_timeout(Some(CONNECT_TIMEOUT)).unwrap();
        let mut reply = [0u8; 64];
        for command in ["< open can0 >", "< rawmode >", "< send 605 8 40 0 10"] {
            let n = stream.read(&mut reply).unwrap();
            assert!(n > 0, "the hub closed a well-behaved handshake");
            stream.write_all(command.as_bytes()).unwrap();
        }
        drop(stream);
        drops += 1;
        std::thread::sleep(Duration::from_millis(20));
    }
    drops
}

#[test]
fn two_python_masters_two_nodes_and_a_dropping_client_share_one_hub() {
    let Some(python) = python() else { return };
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let port = hub.local_addr().port().to_string();
    let cp301_node = run_node(&hub, cp301::Od::new(5), 5);
    let goodrive_node = run_node(&hub, goodrive350::Od::new(7), 7);
    let stop = Arc::new(AtomicBool::new(false));
    let dropper = {
        let stop = Arc::clone(&stop);
        let addr = hub.local_addr();
        std::thread::spawn(move || drop_mid_message_until(addr, &stop))
    };
    let mut loop_master = interop_master(&python, &["loop", &port, &eds("cp301.eds"), "5", "300"]);
    let mut string_master =
        interop_master(&python, &["strings", &port, &eds("goodrive350.eds"), "7"]);
    let no_wait = |what: &str| panic!("unexpected WAIT {what}");
    let strings = result(&mut string_master, no_wait);
    let round_trips = result(&mut loop_master, no_wait);
    stop.store(true, Ordering::Relaxed);
    let drops = dropper.join().unwrap();
    assert!(drops >= 1, "the dropping client never ran");
    assert_eq!(round_trips, json!({"round trips": 300, "mismatches": 0}));
    assert_eq!(
        strings,
        json!({
            "segmented upload 1008": "INVT CANopen",
            "block upload 1008": "INVT CANopen",
            "segmented upload 1009": "V1.00",
            "block upload 1009": "V1.00",
            "segmented upload 100A": "V1.00",
            "block upload 100A": "V1.00",
        })
    );
    for driver in [cp301_node.stop().0, goodrive_node.stop().0] {
        driver.unwrap();
    }
}

#[test]
fn ten_thousand_sdo_transactions_from_python_through_the_hub_without_a_failure() {
    let Some(python) = python() else { return };
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let port = hub.local_addr().port().to_string();
    let node = run_node(&hub, cp301::Od::new(5), 5);
    let bench = Process::python(
        &python,
        "scripts/bench_socketcand.py",
        &["master", &port, &eds("cp301.eds"), "5", "10000"],
    );
    let line = bench.stdout_line(|l| l.starts_with("RESULT "), SCRIPT_TIMEOUT);
    let result: Value = serde_json::from_str(line.strip_prefix("RESULT ").unwrap()).unwrap();
    assert_eq!(result["transactions"], 10_000);
    assert_eq!(result["failures"], 0, "{result}");
    assert!(hub.frames_relayed() >= 20_000, "{}", hub.frames_relayed());
    node.stop().0.unwrap();
}

#[test]
fn python_canopen_reaches_a_node_through_the_edsgen_bus_command() {
    let Some(python) = python() else { return };
    let (_bus, addr) = edsgen_bus(&[]);
    let transport = SocketcandClient::connect(addr, "can0", CONNECT_TIMEOUT).unwrap();
    let clock = MonotonicClock::new();
    let node = Node::new(cp301::Od::new(5), 5, clock.now()).unwrap();
    let node = Driver::with_clock(transport, node, clock).spawn().unwrap();
    let port = addr.port().to_string();
    let mut master = interop_master(&python, &["loop", &port, &eds("cp301.eds"), "5", "100"]);
    let result = result(&mut master, |what| panic!("unexpected WAIT {what}"));
    assert_eq!(result, json!({"round trips": 100, "mismatches": 0}));
    node.stop().0.unwrap();
}
