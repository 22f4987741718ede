//! How far one CANopen bus scales: N simulated CP301 nodes (the runtime's node serving the
//! dictionary read from `eds/cp301.eds`, all on one driver thread and one connection to a
//! socketcand hub, as `edsgen simulate` runs them), a master reading 1018h:01 of every node by
//! SDO, then every node sending TPDO1 every 10 ms (event timer) for a while. Prints the SDO
//! round trips, the TPDOs received against those sent, and the frames per second the hub
//! relayed and dropped. Not a test: run it in release mode.
//!
//! ```text
//! cargo run --release --example canopen_scale [NODES (127)] [SECONDS (5)]
//! ```

use std::time::{Duration, Instant};

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::segment::Segment;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::node::Node;
use edsgen_runtime::CanFrame;
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::drives::Card;

/// How long one answer may take.
const TIMEOUT: Duration = Duration::from_secs(5);

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let nodes: u8 = args
        .next()
        .map_or(Ok(127), |a| a.parse())
        .map_err(|e| format!("NODES: {e}"))?;
    let seconds: u64 = args
        .next()
        .map_or(Ok(5), |a| a.parse())
        .map_err(|e| format!("SECONDS: {e}"))?;
    if !(1..=127).contains(&nodes) {
        return Err("NODES is 1 to 127".into());
    }
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).map_err(|e| e.to_string())?;
    let bus = hub.local_addr().to_string();
    let connect = || SocketcandClient::connect(&bus, "can0", TIMEOUT).map_err(|e| e.to_string());
    let cp301 = Card::named("cp301").ok_or("no cp301 card")?.model();
    let rss_before = resident_kib();
    let clock = MonotonicClock::new();
    let mut members = Vec::new();
    for id in 1..=nodes {
        let node = Node::new(RuntimeDictionary::new(&cp301, id), id, clock.now())
            .map_err(|e| format!("node {id}: {e:?}"))?;
        members.push(node);
    }
    let driver = Driver::with_clock(connect()?, Segment::new(members), clock)
        .spawn()
        .map_err(|e| e.to_string())?;
    let mut master = connect()?;
    std::thread::sleep(Duration::from_millis(200)); // the hub's quiet period after rawmode
    let per_node = match (rss_before, resident_kib()) {
        (Some(before), Some(after)) => format!(
            ", {:.0} KiB resident per node (its dictionary and node)",
            after.saturating_sub(before) as f64 / f64::from(nodes)
        ),
        _ => String::new(),
    };
    println!("{nodes} simulated CP301 nodes on one hub ({bus}){per_node}");

    // SDO: 1018h:01 of each node, one after the other.
    let start = Instant::now();
    for id in 1..=u16::from(nodes) {
        let answer = request(&mut master, id, [0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0])?;
        if answer[0] != 0x43 {
            return Err(format!("node {id}: 1018h:01 answered {answer:02X?}"));
        }
    }
    let sdo = start.elapsed();
    println!(
        "SDO upload of 1018h:01 from every node: {:.1} ms in all, {:.0} us per round trip",
        sdo.as_secs_f64() * 1e3,
        sdo.as_secs_f64() * 1e6 / f64::from(nodes)
    );

    // TPDO1 every 10 ms on every node: transmission type 254, event timer 10 ms, then start.
    for id in 1..=u16::from(nodes) {
        request(&mut master, id, [0x2F, 0x00, 0x18, 0x02, 254, 0, 0, 0])?;
        request(&mut master, id, [0x2B, 0x00, 0x18, 0x05, 10, 0, 0, 0])?;
    }
    let relayed_before = hub.frames_relayed();
    let dropped_before = hub.frames_dropped();
    master
        .send(&CanFrame::new(0x000, &[0x01, 0x00]).ok_or("NMT frame")?)
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    let mut received = vec![0u64; usize::from(nodes) + 1];
    while start.elapsed() < Duration::from_secs(seconds) {
        if let Some(frame) = master
            .recv_timeout(Duration::from_millis(10))
            .map_err(|e| e.to_string())?
        {
            if let Some(id @ 0x181..=0x1FF) = frame.std_id() {
                if let Some(count) = received.get_mut(usize::from(id - 0x180)) {
                    *count += 1;
                }
            }
        }
    }
    let elapsed = start.elapsed().as_secs_f64();
    let relayed = hub.frames_relayed() - relayed_before;
    let dropped = hub.frames_dropped() - dropped_before;
    let total: u64 = received.iter().sum();
    let expected = elapsed * 100.0 * f64::from(nodes);
    let least = received[1..].iter().min().copied().unwrap_or(0);
    println!(
        "TPDOs at 10 ms for {elapsed:.1} s: {total} received by the master ({:.1} % of the {expected:.0} that exact 10 ms timers would send; the slowest node {least}), {:.0} frames/s on the bus",
        100.0 * total as f64 / expected,
        total as f64 / elapsed
    );
    println!(
        "the hub relayed {:.0} frames/s to its {} clients and dropped {dropped}",
        relayed as f64 / elapsed,
        hub.clients()
    );
    let _ = driver.stop();
    hub.stop();
    Ok(())
}

/// This process's resident memory (VmRSS), in KiB, where /proc says it.
fn resident_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Sends an SDO request to `node` and waits for its answer's data.
fn request(master: &mut SocketcandClient, node: u16, data: [u8; 8]) -> Result<[u8; 8], String> {
    let frame = CanFrame::new(0x600 + node, &data).ok_or("SDO frame")?;
    master.send(&frame).map_err(|e| e.to_string())?;
    let deadline = Instant::now() + TIMEOUT;
    while Instant::now() < deadline {
        if let Some(answer) = master
            .recv_timeout(Duration::from_millis(50))
            .map_err(|e| e.to_string())?
        {
            if answer.std_id() == Some(0x580 + node) {
                let mut out = [0; 8];
                out.copy_from_slice(answer.data());
                if out[0] == 0x80 {
                    return Err(format!("node {node}: SDO abort {:02X?}", &out[4..]));
                }
                return Ok(out);
            }
        }
    }
    Err(format!("node {node}: no SDO answer within {TIMEOUT:?}"))
}
