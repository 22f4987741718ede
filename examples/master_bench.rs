//! Measures the master through a socketcand hub on 127.0.0.1 (`cargo run --release --example
//! master_bench`): the SDO round trip edsgen master ↔ edsgen device (the cp301 card on the
//! driver) over 10,000 expedited uploads, counting failures; the same for python `canopen`
//! master ↔ python LocalNode (`scripts/bench_master_python.py`, in the venv of
//! `scripts/python-venv.sh` where it can be made); and a 64 KiB block upload in frames per
//! second, against the about 9,000 frames a second of a 1 Mbit/s bus (8-byte frames of 111
//! bits before stuffing).

mod venv;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::master::blocking::Master;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::vbus::BusDevice;
use edsgen_runtime::master::Mode;
use edsgen_runtime::node::Node;
use edsgen_runtime::sdo::SdoServer;
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_runtime::{
    Access, CanFrame, DataType, Duration as OdDuration, EntryDescriptor, ObjectDictionary, SdoAbort,
};
use edsgen_sim::cards::cp301::{self, od};

const ROUND_TRIPS: usize = 10_000;
const DOMAIN_LEN: usize = 64 * 1024;

/// One DOMAIN at 2100h:00 served by a bare SDO server: the block-transfer source.
struct DomainDevice {
    value: Vec<u8>,
    server: SdoServer,
}

const DOMAIN: [EntryDescriptor; 1] = [EntryDescriptor::new(
    0x2100,
    0,
    DataType::Domain,
    Access::Ro,
    false,
)];

struct DomainOd<'a>(&'a [u8]);

impl ObjectDictionary for DomainOd<'_> {
    fn entry_count(&self) -> usize {
        DOMAIN.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        DOMAIN.get(position).copied()
    }
    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.find(index, sub).map(|_| self.0.len())
    }
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.find(index, sub)?;
        let rest = self.0.get(offset..).unwrap_or(&[]);
        let n = rest.len().min(buf.len());
        buf[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }
    fn write(&mut self, _: u16, _: u8, _: &[u8]) -> Result<(), SdoAbort> {
        Err(SdoAbort::ReadOnly)
    }
}

impl BusDevice for DomainDevice {
    fn handle_frame(&mut self, now: edsgen_runtime::Instant, frame: &CanFrame) {
        if frame.std_id() == Some(0x608) {
            self.server
                .handle(now, frame.data(), &mut DomainOd(&self.value));
        }
    }
    fn poll_transmit(&mut self, now: edsgen_runtime::Instant) -> Option<CanFrame> {
        let data = self.server.poll_transmit(now, &DomainOd(&self.value))?;
        CanFrame::new(0x588, &data)
    }
    fn poll_timeout(&self) -> Option<edsgen_runtime::Instant> {
        self.server.poll_timeout()
    }
    fn handle_timeout(&mut self, now: edsgen_runtime::Instant) {
        self.server.handle_timeout(now, &mut DomainOd(&self.value))
    }
}

fn connect(hub: &Hub) -> SocketcandClient {
    SocketcandClient::connect(hub.local_addr(), "can0", Duration::from_secs(5)).expect("the hub")
}

fn main() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).expect("a hub on 127.0.0.1");
    let clock = MonotonicClock::new();
    let node = Node::new(cp301::Od::new(3), 3, clock.now()).expect("node-ID 3");
    let cp = Driver::with_clock(connect(&hub), node, clock)
        .spawn()
        .expect("the node's thread");
    let domain = DomainDevice {
        value: (0..DOMAIN_LEN).map(|i| (i * 7) as u8).collect(),
        server: SdoServer::new(OdDuration::from_millis(1000)),
    };
    let expected = domain.value.clone();
    let dom = Driver::new(connect(&hub), domain)
        .spawn()
        .expect("the domain's thread");
    let mut master = Master::new(connect(&hub));

    let mut times = Vec::with_capacity(ROUND_TRIPS);
    let mut failures = 0;
    for _ in 0..ROUND_TRIPS {
        let start = Instant::now();
        match master.read(3, od::DEVICE_TYPE) {
            Ok(_) => times.push(start.elapsed()),
            Err(e) => {
                failures += 1;
                eprintln!("{e}");
            }
        }
    }
    times.sort();
    let mean = times.iter().sum::<Duration>() / times.len().max(1) as u32;
    println!(
        "edsgen master <-> edsgen device, hub: {ROUND_TRIPS} SDO uploads, {failures} failed, \
         round trip median {} us, mean {} us",
        times[times.len() / 2].as_micros(),
        mean.as_micros()
    );

    let start = Instant::now();
    let value = master
        .upload(8, Multiplexer::new(0x2100, 0), Mode::Block)
        .expect("the block upload");
    let took = start.elapsed();
    assert!(value == expected, "the domain arrived intact");
    // Segments plus initiate, start, one ack per 127 segments, end, end response.
    let segments = DOMAIN_LEN.div_ceil(7);
    let frames = segments + 2 + 2 * segments.div_ceil(127) + 2;
    println!(
        "block upload of 64 KiB through the hub: {frames} frames in {} ms, {:.0} frames/s \
         ({:.0} KiB/s; a 1 Mbit/s bus carries about 9,000 frames/s)",
        took.as_millis(),
        frames as f64 / took.as_secs_f64(),
        64.0 / took.as_secs_f64()
    );

    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    match venv::python() {
        Ok(python) => {
            let out = Command::new(python)
                .arg(root.join("scripts/bench_master_python.py"))
                .arg(hub.local_addr().port().to_string())
                .arg(root.join("eds/cp301.eds"))
                .arg("2000")
                .output()
                .expect("python");
            let text = String::from_utf8_lossy(&out.stdout);
            let mut parts = text.split_whitespace();
            match (parts.next(), parts.next()) {
                (Some(median), Some(mean)) => println!(
                    "python master <-> python LocalNode, hub: 2000 SDO uploads, \
                     round trip median {median} us, mean {mean} us"
                ),
                _ => eprintln!("python: {}", String::from_utf8_lossy(&out.stderr)),
            }
        }
        Err(why) => println!("python: {why}"),
    }
    let _ = cp.stop();
    let _ = dom.stop();
    hub.stop();
}
