//! The driver running a node in real time over the in-memory bus and over a socketcand hub on
//! 127.0.0.1, with the test as the master: boot-up, SDO, heartbeat at its period, NMT, an EMCY
//! raised from another thread, stopping, and a bus that goes away.

#[path = "../../runtime/tests/node_support/mod.rs"]
mod node_support;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration as StdDuration, Instant as StdInstant};

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::hub::{Hub, HubOptions};
use edsgen_host::memory::MemoryBus;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_runtime::node::{NmtState, Node};
use edsgen_runtime::CanFrame;
use node_support::frame;
use node_support::node_od::TestOd;

const WAIT: StdDuration = StdDuration::from_secs(5);

/// The next frame on `bus`, failing the test after [`WAIT`].
fn next(bus: &mut impl Transport) -> CanFrame {
    bus.recv_timeout(WAIT)
        .unwrap()
        .expect("no frame within 5 s")
}

/// The next frame on `bus` with identifier `id`, skipping the others (TPDOs, heartbeats).
fn next_with_id(bus: &mut impl Transport, id: u16) -> CanFrame {
    loop {
        let got = next(bus);
        if got.std_id() == Some(id) {
            return got;
        }
    }
}

#[test]
fn driver_serves_a_node_over_the_memory_bus_in_real_time() {
    let bus = MemoryBus::new();
    let mut master = bus.endpoint();
    let clock = MonotonicClock::new();
    let node = Node::new(TestOd::new(5), 5, clock.now()).unwrap();
    let driver = Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap();
    assert_eq!(next(&mut master), frame(0x705, &[0x00]), "boot-up");
    master
        .send(&frame(0x605, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]))
        .unwrap();
    assert_eq!(
        next(&mut master),
        frame(0x585, &[0x43, 0x00, 0x10, 0, 0x91, 0x01, 0, 0])
    );
    // Heartbeat every 20 ms.
    master
        .send(&frame(0x605, &[0x2B, 0x17, 0x10, 0, 20, 0, 0, 0]))
        .unwrap();
    assert_eq!(
        next(&mut master),
        frame(0x585, &[0x60, 0x17, 0x10, 0, 0, 0, 0, 0])
    );
    let first = next(&mut master);
    let start = StdInstant::now();
    for _ in 0..10 {
        assert_eq!(next(&mut master), frame(0x705, &[0x7F]));
    }
    let period = start.elapsed() / 10;
    assert_eq!(first, frame(0x705, &[0x7F]));
    assert!(
        (StdDuration::from_millis(15)..StdDuration::from_millis(60)).contains(&period),
        "heartbeat period {period:?}"
    );
    master.send(&frame(0x000, &[0x01, 0x05])).unwrap();
    assert_eq!(
        next_with_id(&mut master, 0x705),
        frame(0x705, &[0x05]),
        "operational"
    );
    let raised = driver.with_device(|node, _now| node.raise_error(0x2310, 0x03, [1, 2, 3, 4, 5]));
    assert!(raised);
    assert_eq!(
        next_with_id(&mut master, 0x085),
        frame(0x085, &[0x10, 0x23, 0x03, 1, 2, 3, 4, 5])
    );
    let (result, _endpoint, node) = driver.stop();
    result.unwrap();
    assert_eq!(node.nmt_state(), NmtState::Operational);
}

#[test]
fn driver_runs_on_the_current_thread_until_its_stop_flag() {
    let bus = MemoryBus::new();
    let mut master = bus.endpoint();
    let node = Node::new(TestOd::new(9), 9, MonotonicClock::new().now()).unwrap();
    let mut driver = Driver::new(bus.endpoint(), node);
    let stop = Arc::new(AtomicBool::new(false));
    let master_thread = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            assert_eq!(next(&mut master), frame(0x709, &[0x00]));
            master.send(&frame(0x000, &[0x80, 0x00])).unwrap();
            master
                .send(&frame(0x609, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]))
                .unwrap();
            let answer = next(&mut master);
            stop.store(true, Ordering::Relaxed);
            answer
        })
    };
    driver.run(&stop).unwrap();
    assert_eq!(
        master_thread.join().unwrap(),
        frame(0x589, &[0x43, 0x00, 0x10, 0, 0x91, 0x01, 0, 0])
    );
    assert_eq!(driver.device().nmt_state(), NmtState::PreOperational);
}

#[test]
fn driver_over_a_hub_answers_and_stops_with_an_error_when_the_hub_goes_away() {
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let mut master = SocketcandClient::connect(hub.local_addr(), "can0", WAIT).unwrap();
    let transport = SocketcandClient::connect(hub.local_addr(), "can0", WAIT).unwrap();
    let node = Node::new(TestOd::new(3), 3, MonotonicClock::new().now()).unwrap();
    let driver = Driver::new(transport, node).spawn().unwrap();
    assert_eq!(next(&mut master), frame(0x703, &[0x00]));
    master
        .send(&frame(0x603, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]))
        .unwrap();
    assert_eq!(
        next(&mut master),
        frame(0x583, &[0x43, 0x00, 0x10, 0, 0x91, 0x01, 0, 0])
    );
    hub.stop();
    let deadline = StdInstant::now() + WAIT;
    while !driver.is_finished() {
        assert!(StdInstant::now() < deadline, "the driver did not notice");
        std::thread::sleep(StdDuration::from_millis(1));
    }
    let (result, _, _) = driver.stop();
    assert_eq!(
        result.unwrap_err().kind(),
        std::io::ErrorKind::UnexpectedEof
    );
}
