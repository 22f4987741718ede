//! The blocking master over the in-memory bus against a device node run by the transport
//! driver on its own thread, in real time: typed reads and writes, an abort as an error with its
//! meaning, the timeout, NMT and waiting for boot-up, heartbeat events, and 10,000 transfers.

#[path = "../../runtime/tests/node_support/mod.rs"]
mod node_support;

use std::time::{Duration as StdDuration, Instant as StdInstant};

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::master::blocking::{Master, MasterError, MasterEvent};
use edsgen_host::memory::{MemoryBus, MemoryEndpoint};
use edsgen_runtime::master::{
    ExpectedIdentity, IdentityMismatch, Mode, MonitorEvent, SdoError, Watch,
};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::heartbeat::NmtState;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_runtime::{Duration, Entry};
use node_support::node_od::TestOd;

type NodeHandle = DriverHandle<MemoryEndpoint, Node<TestOd>>;

/// A bus with node `node_id` served by a driver thread, and a master on it.
fn bus_with_node(node_id: u8) -> (Master<MemoryEndpoint>, NodeHandle) {
    let bus = MemoryBus::new();
    let master = Master::new(bus.endpoint());
    let clock = MonotonicClock::new();
    let node = Node::new(TestOd::new(node_id), node_id, clock.now()).unwrap();
    let handle = Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap();
    (master, handle)
}

const WORD: Entry<u16> = Entry::new(0x2000, 0);
const DEVICE_TYPE: Entry<u32> = Entry::new(0x1000, 0);
const READ_ONLY: Entry<u32> = Entry::new(0x2003, 0);

#[test]
fn typed_reads_and_writes_reach_the_node() {
    let (mut master, node) = bus_with_node(5);
    assert_eq!(master.read(5, DEVICE_TYPE).unwrap(), 0x0000_0191);
    master.write(5, WORD, 0xBEEF).unwrap();
    assert_eq!(master.read(5, WORD).unwrap(), 0xBEEF);
    assert_eq!(node.with_device(|n, _| n.od().get(0x2000, 0)), 0xBEEF);
    let bytes = master
        .upload(5, Multiplexer::new(0x1018, 1), Mode::Normal)
        .unwrap();
    assert_eq!(bytes, [0xD8, 0x04, 0, 0]);
    let _ = node.stop();
}

#[test]
fn an_abort_is_an_error_with_its_code_and_meaning() {
    let (mut master, node) = bus_with_node(5);
    let error = master.write(5, READ_ONLY, 1).unwrap_err();
    assert!(matches!(
        error,
        MasterError::Sdo {
            node_id: 5,
            error: SdoError::Server(0x0601_0002),
            ..
        }
    ));
    assert_eq!(
        error.to_string(),
        "SDO 2003h:00h on node 5: node aborted with 0601 0002h (attempt to write a read-only object)"
    );
    // A u32 read of a u16 entry: the length does not match.
    let wrong: Entry<u32> = Entry::new(0x2000, 0);
    assert!(matches!(
        master.read(5, wrong),
        Err(MasterError::Length { got: 2, .. })
    ));
    let _ = node.stop();
}

#[test]
fn an_absent_node_times_out_after_its_own_timeout() {
    let (mut master, node) = bus_with_node(5);
    master
        .set_timeout(9, StdDuration::from_millis(100))
        .unwrap();
    let start = StdInstant::now();
    let error = master.read(9, WORD).unwrap_err();
    let took = start.elapsed();
    assert!(matches!(
        error,
        MasterError::Sdo {
            node_id: 9,
            error: SdoError::Timeout,
            ..
        }
    ));
    assert!(
        (StdDuration::from_millis(190)..StdDuration::from_millis(900)).contains(&took),
        "{took:?}"
    );
    assert!(error
        .to_string()
        .contains("0504 0000h (SDO protocol timed out)"));
    // A write is not repeated.
    let start = StdInstant::now();
    assert!(master.write(9, WORD, 1).is_err());
    assert!(start.elapsed() < StdDuration::from_millis(190));
    // Node 5 still answers on its own channel.
    assert_eq!(master.read(5, WORD).unwrap(), 0);
    let _ = node.stop();
}

#[test]
fn a_default_timeout_leaves_a_nodes_own_timeout_alone() {
    let (mut master, node) = bus_with_node(5);
    master
        .set_timeout(9, StdDuration::from_millis(150))
        .unwrap();
    master.set_default_timeout(StdDuration::from_millis(20));
    let start = StdInstant::now();
    assert!(master.read(9, WORD).is_err());
    // Two tries (one retry) of 150 ms each, not of 20 ms.
    let took = start.elapsed();
    assert!(took >= StdDuration::from_millis(300), "{took:?}");
    let _ = node.stop();
}

#[test]
fn nmt_reset_and_wait_for_boot() {
    let (mut master, node) = bus_with_node(5);
    master.wait_for_boot(5, StdDuration::from_secs(5)).unwrap();
    master.write(5, WORD, 7).unwrap();
    master.nmt(NmtCommand::Start, 5).unwrap();
    master.listen(StdDuration::from_millis(50)).unwrap();
    assert_eq!(
        node.with_device(|n, _| n.nmt_state()),
        NmtState::Operational
    );
    master.nmt(NmtCommand::ResetNode, 0).unwrap();
    master.wait_for_boot(5, StdDuration::from_secs(5)).unwrap();
    assert_eq!(master.last_state(5), Some(NmtState::PreOperational));
    assert_eq!(
        node.with_device(|n, _| n.nmt_state()),
        NmtState::PreOperational
    );
    assert!(matches!(
        master.wait_for_boot(9, StdDuration::from_millis(50)),
        Err(MasterError::Timeout)
    ));
    let _ = node.stop();
}

#[test]
fn a_watched_heartbeat_reports_the_state_change_and_the_loss() {
    let (mut master, node) = bus_with_node(5);
    master.write(5, Entry::<u16>::new(0x1017, 0), 20).unwrap();
    master
        .watch(5, Watch::Heartbeat(Duration::from_millis(100)))
        .unwrap();
    // Pre-operational heartbeats every 20 ms, then operational ones.
    master.listen(StdDuration::from_millis(70)).unwrap();
    master.nmt(NmtCommand::Start, 5).unwrap();
    master.listen(StdDuration::from_millis(100)).unwrap();
    master.write(5, Entry::<u16>::new(0x1017, 0), 0).unwrap();
    master.listen(StdDuration::from_millis(250)).unwrap();
    let events: Vec<MasterEvent> = std::iter::from_fn(|| master.poll_event()).collect();
    let monitor: Vec<MonitorEvent> = events
        .iter()
        .filter_map(|e| match e {
            MasterEvent::Monitor(m) => Some(*m),
            _ => None,
        })
        .collect();
    assert_eq!(
        monitor,
        [
            MonitorEvent::StateChanged {
                node_id: 5,
                from: None,
                to: NmtState::PreOperational
            },
            MonitorEvent::StateChanged {
                node_id: 5,
                from: Some(NmtState::PreOperational),
                to: NmtState::Operational
            },
            MonitorEvent::Lost { node_id: 5 },
        ]
    );
    let _ = node.stop();
}

#[test]
fn ten_thousand_transfers_without_a_failure() {
    let (mut master, node) = bus_with_node(5);
    let start = StdInstant::now();
    for i in 0..5_000u16 {
        master.write(5, WORD, i).unwrap();
        assert_eq!(master.read(5, WORD).unwrap(), i);
    }
    let took = start.elapsed();
    assert!(took < StdDuration::from_secs(60), "{took:?}");
    eprintln!("10,000 SDO transfers over the memory bus: {took:?}");
    let _ = node.stop();
}

#[test]
fn boot_node_checks_the_identity_then_configures_and_starts_or_stops_at_a_mismatch() {
    let (mut master, node) = bus_with_node(5);
    let heartbeat = [(Multiplexer::new(0x1017, 0), vec![50u8, 0])];
    let right = ExpectedIdentity {
        device_type: Some(0x0000_0191),
        vendor_id: Some(0x0000_04D8),
        ..ExpectedIdentity::default()
    };
    let mismatches = master
        .boot_node(5, &right, &heartbeat, StdDuration::from_secs(5))
        .unwrap();
    assert_eq!(mismatches, []);
    master.listen(StdDuration::from_millis(20)).unwrap();
    assert_eq!(
        node.with_device(|n, _| n.nmt_state()),
        NmtState::Operational
    );
    assert_eq!(node.with_device(|n, _| n.od().get(0x1017, 0)), 50);

    // The node resets; this time the master expects another product (1018h:2, which the test
    // dictionary does not even have).
    master.nmt(NmtCommand::ResetNode, 5).unwrap();
    let wrong = ExpectedIdentity {
        product_code: Some(0x1234),
        ..right
    };
    let mismatches = master
        .boot_node(5, &wrong, &heartbeat, StdDuration::from_secs(5))
        .unwrap();
    assert_eq!(
        mismatches,
        [IdentityMismatch {
            node_id: 5,
            entry: Entry::new(0x1018, 2),
            expected: 0x1234,
            actual: None,
            abort: Some(0x0609_0011),
        }]
    );
    let events: Vec<MasterEvent> = std::iter::from_fn(|| master.poll_event()).collect();
    assert!(events.contains(&MasterEvent::IdentityMismatch(mismatches[0])));
    assert_eq!(
        node.with_device(|n, _| n.nmt_state()),
        NmtState::PreOperational
    );
    let _ = node.stop();
}

#[test]
fn the_master_guards_a_node_and_reports_its_loss() {
    let (mut master, node) = bus_with_node(5);
    master.wait_for_boot(5, StdDuration::from_secs(5)).unwrap();
    let guarding = Watch::Guarding {
        guard_time: Duration::from_millis(30),
        life_factor: 2,
    };
    master.watch(5, guarding).unwrap();
    master.listen(StdDuration::from_millis(100)).unwrap();
    let _ = node.stop();
    master.listen(StdDuration::from_millis(200)).unwrap();
    let events: Vec<MasterEvent> = std::iter::from_fn(|| master.poll_event()).collect();
    assert_eq!(
        events,
        [
            MasterEvent::Monitor(MonitorEvent::StateChanged {
                node_id: 5,
                from: None,
                to: NmtState::PreOperational
            }),
            MasterEvent::Monitor(MonitorEvent::Lost { node_id: 5 }),
        ]
    );
}
