//! Interoperability with python `canopen` 2.4.1 over python-can 4.6.1's socketcand interface: the
//! hub runs in-process on a free port of 127.0.0.1 (or as the `edsgen bus` command), nodes
//! built from the generated cards (`edsgen_sim::cards`) or the simulator's run-time dictionary run on
//! the runtime's driver with the socketcand client, and `scripts/interop_master.py` (in the venv
//! of `scripts/python-venv.sh`) is the master: every service on a CP301, two masters and two
//! nodes on one hub, 10,000 SDO transactions, and large values (a 64 KiB domain by block
//! transfer both ways, a 100-byte string segmented both ways, and python's own failure when a
//! block download is written piece by piece).
//!
//! Every value python reports is asserted exactly. Without python the tests are skipped with a
//! message, except under `CI=true`, where that is a failure. Every wait is bounded and the python
//! processes are killed if a test ends early.

mod process_support;
#[path = "../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::io::{Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::socketcand::SocketcandClient;
use edsgen_runtime::node::Node;
use edsgen_runtime::od::ObjectDictionary;
use edsgen_runtime::sdo::crc::crc16;
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::cards::{cp301, goodrive350};
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

/// Large values: a 64 KiB DOMAIN (2001h) and a 100-byte VISIBLE_STRING (2000h, its capacity
/// set by an overlay) of the simulator's test device, served by the runtime's `Node` on the
/// driver (node 9), through `edsgen bus`, with its log of every frame.
struct LargeBench {
    dir: std::path::PathBuf,
    eds: String,
    log: std::path::PathBuf,
    node: NodeDriver<RuntimeDictionary>,
    port: String,
    _bus: Process,
}

impl LargeBench {
    fn start(name: &str) -> LargeBench {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        std::fs::create_dir_all(&dir).unwrap();
        let eds = dir.join("sim.eds");
        std::fs::write(&eds, sim_support::DEVICE_EDS).unwrap();
        let mut device = sim_support::test_device();
        let overlay = edsgen_model::overlay::apply("[capacity]\n2000 = 100\n", &mut device);
        assert!(overlay.is_empty(), "{overlay:?}");
        let od = RuntimeDictionary::new(&device, 9);
        let log = dir.join("bus.log");
        let (bus, addr) = edsgen_bus(&["--log", log.to_str().unwrap()]);
        let transport = SocketcandClient::connect(addr, "can0", CONNECT_TIMEOUT).unwrap();
        let clock = MonotonicClock::new();
        let node = Node::new(od, 9, clock.now()).unwrap();
        let node = Driver::with_clock(transport, node, clock).spawn().unwrap();
        LargeBench {
            eds: eds.to_str().unwrap().to_owned(),
            port: addr.port().to_string(),
            dir,
            log,
            node,
            _bus: bus,
        }
    }

    /// The value of `index`:00 in the node's dictionary.
    fn value(&self, index: u16) -> Vec<u8> {
        self.node.with_device(|node, _| {
            let od = node.od();
            let mut value = vec![0; od.value_len(index, 0).unwrap()];
            let n = od.read(index, 0, 0, &mut value).unwrap();
            value.truncate(n);
            value
        })
    }

    fn set(&self, index: u16, value: &[u8]) {
        self.node
            .with_device(|node, _| node.od_mut().write(index, 0, value))
            .unwrap();
    }

    fn file(&self, name: &str) -> Vec<u8> {
        std::fs::read(self.dir.join(name)).unwrap()
    }

    /// The SDO frames of node 9 in the log, as `ID#DATA`.
    fn sdo_frames(&self) -> Vec<String> {
        std::fs::read_to_string(&self.log)
            .unwrap()
            .lines()
            .filter_map(|line| line.split_whitespace().nth(2).map(str::to_owned))
            .filter(|frame| frame.starts_with("609#") || frame.starts_with("589#"))
            .collect()
    }
}

/// 64 KiB for 2001h: byte i is `i mod 251` (a period that does not divide the 7-byte segments).
fn domain_down() -> Vec<u8> {
    (0..65_536u32).map(|i| (i % 251) as u8).collect()
}

#[test]
fn python_canopen_moves_64_kib_by_block_transfer_and_100_bytes_segmented_through_edsgen_bus() {
    let Some(python) = python() else { return };
    let bench = LargeBench::start("python-large-transfers");
    let domain = domain_down();
    let text: Vec<u8> = (0..100u8).map(|i| b'!' + i % 94).collect();
    let domain_up: Vec<u8> = (0..65_536u32).map(|i| (i * 7 + i / 256) as u8).collect();
    let text_up: Vec<u8> = text.iter().rev().copied().collect();
    std::fs::write(bench.dir.join("domain-down.bin"), &domain).unwrap();
    std::fs::write(bench.dir.join("string-down.bin"), &text).unwrap();
    let dir = bench.dir.to_str().unwrap();
    let mut master = interop_master(&python, &["large", &bench.port, &bench.eds, "9", dir]);
    let done = result(&mut master, |what| {
        assert_eq!(what, "downloaded");
        // What python downloaded is what the node holds, byte for byte.
        assert!(bench.value(0x2001) == domain, "2001h differs");
        assert_eq!(bench.value(0x2000), text);
        bench.set(0x2001, &domain_up);
        bench.set(0x2000, &text_up);
    });
    assert_eq!(done, json!({"done": true}));
    assert!(bench.file("domain-read-back.bin") == domain);
    assert_eq!(bench.file("string-read-back.bin"), text);
    assert!(bench.file("domain-up.bin") == domain_up);
    assert_eq!(bench.file("string-up.bin"), text_up);

    // The protocols python chose, from the initiations on the bus: block download of 65,536
    // bytes with CRC (C6h) answered with blocks of 127 segments and CRC (A4h); block upload with
    // CRC and 127-segment blocks (A4h) answered with the size (C6h); segmented download and
    // upload of 100 bytes (21h/60h, 40h/41h).
    let frames = bench.sdo_frames();
    let initiations: Vec<&str> = frames
        .iter()
        .map(String::as_str)
        .filter(|f| matches!(&f[6..12], "012000" | "002000"))
        .collect();
    assert_eq!(
        initiations,
        [
            "609#C601200000000100",
            "589#A40120007F000000",
            "609#A40120007F000000",
            "589#C601200000000100",
            "609#2100200064000000",
            "589#6000200000000000",
            "609#4000200000000000",
            "589#4100200064000000",
            "609#A40120007F000000",
            "589#C601200000000100",
            "609#4000200000000000",
            "589#4100200064000000",
        ]
    );
    bench.node.stop().0.unwrap();
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02X}")).collect()
}

/// Python `canopen` 2.4.1's block download fails when the value is written to its stream piece
/// by piece, as in its issue #379 (127-byte pieces to a stream buffered by 127 bytes, here too;
/// #618 reports the same "Block transfer was not finished"); written at once, as in the test
/// above, it works, 64 KiB included, so python's block download is not broken as such. The
/// cause is python's, on the client side: `BlockDownloadStream.write` returns `None` for a
/// piece of fewer than 7 bytes that is not the last, which `io.BufferedWriter` takes for "the
/// raw stream would block". When the buffer cannot take the next piece after such a flush,
/// `write` raises `BlockingIOError`, and closing the stream sends the "end block download"
/// request in the middle of a sub-block. Its frames break CiA 301 three ways: the end request
/// comes before any segment with the c bit (no last segment was sent, and no sub-block
/// acknowledged), its n field says 7 bytes of the last segment carry no data (a segment carries
/// 1 to 7, so n is at most 6), and 252 bytes were sent of the 1,000 the initiation announced.
/// The server does what CiA 301 says with the end request, which on this channel reads as a
/// segment out of sequence (DDh: c set, sequence number 5Dh): it acknowledges the last segment
/// received in order (24h), keeps the value it had, and aborts with 0504 0000 (timeout) when
/// the client sends nothing more.
#[test]
fn python_canopen_block_download_written_piecewise_breaks_cia_301_on_its_side() {
    let Some(python) = python() else { return };
    let bench = LargeBench::start("python-piecewise-block-download");
    let data = domain_down()[..1000].to_vec();
    std::fs::write(bench.dir.join("domain-down.bin"), &data).unwrap();
    let dir = bench.dir.to_str().unwrap();
    let mut master = interop_master(&python, &["chunked", &bench.port, &bench.eds, "9", dir]);
    let reported = result(&mut master, |what| panic!("unexpected WAIT {what}"));
    assert_eq!(
        reported,
        json!({
            "write": "BlockingIOError after 127 bytes: write could not complete without blocking",
            "close": "SdoCommunicationError: Block download unsuccessful",
        })
    );

    // The server's abort comes after its SDO timeout (1 s).
    let abort = "589#8001200000000405".to_owned();
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while !bench.sdo_frames().contains(&abort) {
        assert!(
            std::time::Instant::now() < deadline,
            "no abort: {:#?}",
            bench.sdo_frames()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let sent = 36 * 7;
    let mut expected = vec![
        "609#C6012000E8030000".to_owned(),
        "589#A40120007F000000".to_owned(),
    ];
    for (seqno, segment) in (1..).zip(data[..sent].chunks(7)) {
        expected.push(format!("609#{seqno:02X}{}", hex(segment)));
    }
    let [crc_low, crc_high] = crc16(&data[..sent]).to_le_bytes();
    expected.push(format!("609#DD{crc_low:02X}{crc_high:02X}0000000000"));
    expected.push("589#A2247F0000000000".to_owned());
    expected.push(abort);
    assert_eq!(bench.sdo_frames(), expected);
    // What breaks CiA 301, on python's side: no segment with the c bit (80h) before the end
    // request (C1h with n in bits 2-4), whose n is 7.
    let end = u8::from_str_radix(&expected[38][4..6], 16).unwrap();
    assert_eq!((end & 0xE3, (end >> 2) & 7), (0xC1, 7));
    assert!(expected[2..38].iter().all(|f| f.as_bytes()[4] < b'8'));
    // The node kept the value it had: 2001h is still empty.
    assert_eq!(bench.value(0x2001), b"");
    bench.node.stop().0.unwrap();
}
