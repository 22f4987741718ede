//! Shared by the bench commands' tests (`cli_master`, `cli_bench`): an in-process socketcand
//! hub on 127.0.0.1 with device nodes on it (the generated cp301 and goodrive350 cards, the
//! simulator test device, one refusing block transfers, one answering block uploads segmented),
//! run by the transport driver; `edsgen` run against it; scratch directories; the transfer
//! summary.
// Each test crate uses only some of these helpers.
#![allow(dead_code)]

use std::collections::VecDeque;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::vbus::BusDevice;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::node::Node;
use edsgen_runtime::time::Instant;
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::cards::{cp301, goodrive350};

use crate::sim_support;

pub const EDSGEN: &str = env!("CARGO_BIN_EXE_edsgen");

/// A hub with the two card nodes on it; everything stops when dropped.
pub struct Bench {
    pub hub: Option<Hub>,
    pub nodes: Vec<Box<dyn FnOnce()>>,
    pub addr: String,
}

impl Drop for Bench {
    fn drop(&mut self) {
        for stop in self.nodes.drain(..) {
            stop();
        }
        if let Some(hub) = self.hub.take() {
            hub.stop();
        }
    }
}

pub fn spawn_node<D: BusDevice + Send + 'static>(
    addr: &str,
    node: impl FnOnce(MonotonicClock) -> D,
) -> DriverHandle<SocketcandClient, D> {
    let client = SocketcandClient::connect(addr, "can0", Duration::from_secs(5)).unwrap();
    let clock = MonotonicClock::new();
    Driver::with_clock(client, node(clock), clock)
        .spawn()
        .unwrap()
}

pub fn bench() -> Bench {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let addr = hub.local_addr().to_string();
    let cp = spawn_node(&addr, |clock| {
        Node::new(cp301::Od::new(3), 3, clock.now()).unwrap()
    });
    let gd = spawn_node(&addr, |clock| {
        Node::new(goodrive350::Od::new(5), 5, clock.now()).unwrap()
    });
    Bench {
        hub: Some(hub),
        nodes: vec![
            Box::new(move || drop(cp.stop())),
            Box::new(move || drop(gd.stop())),
        ],
        addr,
    }
}

pub fn edsgen(bench: &Bench, args: &[&str]) -> Output {
    let mut command = Command::new(EDSGEN);
    command
        .args(args)
        .args(["--bus", &bench.addr, "--timeout", "500"]);
    command.output().unwrap()
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

pub fn eds(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("eds")
        .join(name)
        .display()
        .to_string()
}

/// A hub with the simulator test device (`sim_support`, its DOMAIN 2001h "Program" up to
/// 64 KiB) as node 4, and the same device refusing block transfers as node 6.
pub fn sim_bench() -> Bench {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let addr = hub.local_addr().to_string();
    let sim = |node_id: u8, clock: MonotonicClock| {
        let od = RuntimeDictionary::new(&sim_support::test_device(), node_id);
        Node::new(od, node_id, clock.now()).unwrap()
    };
    let node = spawn_node(&addr, |clock| sim(4, clock));
    let no_block = spawn_node(&addr, |clock| NoBlock(sim(6, clock), VecDeque::new()));
    Bench {
        hub: Some(hub),
        nodes: vec![
            Box::new(move || drop(node.stop())),
            Box::new(move || drop(no_block.stop())),
        ],
        addr,
    }
}

/// A device without SDO block transfer: its node's answers, except that the start of a block
/// download or upload is aborted with 0504 0001 (command specifier unknown), as by a server
/// that does not implement it.
pub struct NoBlock<D>(pub D, pub VecDeque<CanFrame>);

impl<D: BusDevice> BusDevice for NoBlock<D> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let data = frame.data();
        let to_node = frame.std_id() == Some(0x606) && data.len() == 8;
        let block_initiate = (data[0] & 0xE1) == 0xC0 || (data[0] & 0xE3) == 0xA0;
        if to_node && block_initiate {
            let mut abort = [0x80, data[1], data[2], data[3], 0, 0, 0, 0];
            abort[4..].copy_from_slice(&0x0504_0001u32.to_le_bytes());
            self.1.push_back(CanFrame::new(0x586, &abort).unwrap());
        } else {
            self.0.handle_frame(now, frame);
        }
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.1.pop_front().or_else(|| self.0.poll_transmit(now))
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.0.poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        self.0.handle_timeout(now)
    }
}

/// `edsgen ARGS --bus ...` with `input` on its standard input.
pub fn edsgen_with_input(bench: &Bench, args: &[&str], input: Vec<u8>) -> Output {
    let mut child = Command::new(EDSGEN)
        .args(args)
        .args(["--bus", &bench.addr, "--timeout", "500"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(&input));
    let output = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    output
}

/// `len` bytes that show misplaced ones: byte i is (i * 7 + i / 251) mod 256.
pub fn pattern(len: usize) -> Vec<u8> {
    (0..len).map(|i| (i * 7 + i / 251) as u8).collect()
}

/// A directory of this test's own, removed when dropped, with the simulator device's EDS in it.
pub struct Scratch(pub PathBuf);

impl Scratch {
    pub fn new(test: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("edsgen-{test}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("sim.eds"), sim_support::DEVICE_EDS).unwrap();
        Scratch(dir)
    }

    pub fn path(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The summary line without its time: `LABEL: N bytes DONE by TRANSFER`.
pub fn summary(output: &Output) -> String {
    let text = stderr(output);
    let (line, seconds) = text
        .trim_end()
        .rsplit_once(" in ")
        .unwrap_or_else(|| panic!("no summary: {text}"));
    let seconds = seconds
        .strip_suffix(" s")
        .unwrap_or_else(|| panic!("{text}"));
    assert!(seconds.parse::<f64>().is_ok(), "{text}");
    assert_eq!(text.lines().count(), 1, "{text}");
    line.to_string()
}

/// A device that answers a block upload request with a normal upload, as CiA 301 allows a
/// server to: its node sees an initiate upload instead.
pub struct SegmentedOnly<D>(pub D);

impl<D: BusDevice> BusDevice for SegmentedOnly<D> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let data = frame.data();
        let request = frame
            .std_id()
            .is_some_and(|id| (0x601..=0x67F).contains(&id));
        if request && data.len() == 8 && (data[0] & 0xE3) == 0xA0 {
            let initiate = [0x40, data[1], data[2], data[3], 0, 0, 0, 0];
            let id = frame.std_id().unwrap();
            self.0
                .handle_frame(now, &CanFrame::new(id, &initiate).unwrap());
        } else {
            self.0.handle_frame(now, frame);
        }
    }
    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        self.0.poll_transmit(now)
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.0.poll_timeout()
    }
    fn handle_timeout(&mut self, now: Instant) {
        self.0.handle_timeout(now)
    }
}

/// A hub with the simulator test device answering block uploads segmented, as node 7.
pub fn segmented_bench() -> Bench {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let addr = hub.local_addr().to_string();
    let node = spawn_node(&addr, |clock| {
        let od = RuntimeDictionary::new(&sim_support::test_device(), 7);
        SegmentedOnly(Node::new(od, 7, clock.now()).unwrap())
    });
    Bench {
        hub: Some(hub),
        nodes: vec![Box::new(move || drop(node.stop()))],
        addr,
    }
}

/// A hub with two cp301 nodes that share node-ID 3.
pub fn twin_bench() -> Bench {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let addr = hub.local_addr().to_string();
    let one = spawn_node(&addr, |clock| {
        Node::new(cp301::Od::new(3), 3, clock.now()).unwrap()
    });
    let two = spawn_node(&addr, |clock| {
        Node::new(cp301::Od::new(3), 3, clock.now()).unwrap()
    });
    Bench {
        hub: Some(hub),
        nodes: vec![
            Box::new(move || drop(one.stop())),
            Box::new(move || drop(two.stop())),
        ],
        addr,
    }
}

/// A hub logging every frame (`candump -L` lines) into the returned buffer, with nothing on it.
pub fn logged_hub() -> (Hub, std::sync::Arc<std::sync::Mutex<Vec<u8>>>) {
    #[derive(Clone)]
    struct Shared(std::sync::Arc<std::sync::Mutex<Vec<u8>>>);
    impl Write for Shared {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let log = Shared(Default::default());
    let options = HubOptions {
        log: Some(Box::new(log.clone())),
        ..HubOptions::default()
    };
    (Hub::start("127.0.0.1:0", options).unwrap(), log.0)
}
