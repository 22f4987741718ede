//! The master's NMT commands, heartbeat consumer, guarding master, EMCY consumer and SYNC
//! producer against device nodes on the virtual bus.

mod node_support;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::master::{
    nmt_frame, Emergency, MonitorEvent, NodeMonitor, SdoClient, SyncProducer, Watch,
};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::emcy::meaning as emcy_meaning;
use edsgen_runtime::wire::heartbeat::NmtState;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::{Duration, Entry};
use node_support::node_od::TestOd;
use node_support::{frame, ms, show};

const HEARTBEAT_TIME: Entry<u16> = Entry::new(0x1017, 0);

fn events<const N: usize>(monitor: &mut NodeMonitor<N>) -> Vec<MonitorEvent> {
    std::iter::from_fn(|| monitor.poll_event()).collect()
}

#[test]
fn nmt_commands_are_the_manuals_frames_and_move_the_node() {
    let shown: Vec<String> = [
        (NmtCommand::Start, 5),
        (NmtCommand::Stop, 5),
        (NmtCommand::EnterPreOperational, 5),
        (NmtCommand::ResetNode, 0),
        (NmtCommand::ResetCommunication, 127),
    ]
    .iter()
    .map(|&(command, node)| show(&nmt_frame(command, node)))
    .collect();
    assert_eq!(
        shown,
        [
            "000: 01 05",
            "000: 02 05",
            "000: 80 05",
            "000: 81 00",
            "000: 82 7F"
        ]
    );
    let mut node = Node::new(TestOd::new(5), 5, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.inject(nmt_frame(NmtCommand::Start, 0), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::Operational);
    bus.inject(nmt_frame(NmtCommand::Stop, 5), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::Stopped);
}

#[test]
fn the_heartbeat_consumer_reports_boot_up_state_change_loss_and_recovery() {
    let mut monitor = NodeMonitor::<4>::new();
    monitor
        .watch(ms(0), 5, Watch::Heartbeat(Duration::from_millis(150)))
        .unwrap();
    let mut node = Node::new(TestOd::new(5), 5, ms(0)).unwrap();
    let mut client: SdoClient<32> = SdoClient::new(5);
    let mut bus = VirtualBus::new(ms(0));
    client.write(ms(0), HEARTBEAT_TIME, &100).unwrap();
    bus.run_until(ms(10), &mut [&mut monitor, &mut node, &mut client]);
    bus.inject(
        nmt_frame(NmtCommand::Start, 5),
        &mut [&mut monitor, &mut node],
    );
    bus.run_until(ms(300), &mut [&mut monitor, &mut node, &mut client]);
    assert_eq!(
        events(&mut monitor),
        [
            MonitorEvent::BootUp { node_id: 5 },
            MonitorEvent::StateChanged {
                node_id: 5,
                from: Some(NmtState::PreOperational),
                to: NmtState::Operational
            },
        ]
    );
    // Heartbeats at 100, 200, 300 ms; then the node stops producing.
    client.write(ms(300), HEARTBEAT_TIME, &0).unwrap();
    bus.run_until(ms(449), &mut [&mut monitor, &mut node, &mut client]);
    assert_eq!(events(&mut monitor), []);
    bus.run_until(ms(451), &mut [&mut monitor, &mut node, &mut client]);
    assert_eq!(events(&mut monitor), [MonitorEvent::Lost { node_id: 5 }]);
    assert!(monitor.is_lost(5));
    client.write(ms(600), HEARTBEAT_TIME, &100).unwrap();
    bus.run_until(ms(800), &mut [&mut monitor, &mut node, &mut client]);
    assert_eq!(
        events(&mut monitor),
        [MonitorEvent::Recovered {
            node_id: 5,
            state: NmtState::Operational
        }]
    );
    assert_eq!(monitor.state(5), Some(NmtState::Operational));
}

#[cfg(feature = "node-guarding")]
#[test]
fn the_guarding_master_checks_toggles_and_reports_loss_after_the_life_time() {
    let mut monitor = NodeMonitor::<2>::new();
    let guarding = Watch::Guarding {
        guard_time: Duration::from_millis(100),
        life_factor: 3,
    };
    monitor.watch(ms(1), 7, guarding).unwrap();
    let mut node = Node::new(TestOd::new(7), 7, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(250), &mut [&mut monitor, &mut node]);
    let log: Vec<(u64, String)> = bus
        .take_log()
        .iter()
        .map(|(t, _, f)| (t.as_micros() / 1000, show(f)))
        .collect();
    assert_eq!(
        log,
        [
            (0, "707: 00".to_string()),
            (1, "707: RTR".to_string()),
            (1, "707: 7F".to_string()),
            (101, "707: RTR".to_string()),
            (101, "707: FF".to_string()),
            (201, "707: RTR".to_string()),
            (201, "707: 7F".to_string()),
        ]
    );
    assert_eq!(events(&mut monitor), [MonitorEvent::BootUp { node_id: 7 }]);
    // The node leaves the bus: RTRs at 301, 401, 501 go unanswered; lost at 601.
    bus.run_until(ms(600), &mut [&mut monitor]);
    assert_eq!(events(&mut monitor), []);
    bus.run_until(ms(601), &mut [&mut monitor]);
    assert_eq!(events(&mut monitor), [MonitorEvent::Lost { node_id: 7 }]);
    bus.run_until(ms(702), &mut [&mut monitor, &mut node]);
    assert_eq!(
        events(&mut monitor),
        [MonitorEvent::Recovered {
            node_id: 7,
            state: NmtState::PreOperational
        }]
    );
}

#[test]
fn a_repeated_guarding_toggle_is_not_an_answer() {
    let mut monitor = NodeMonitor::<1>::new();
    let guarding = Watch::Guarding {
        guard_time: Duration::from_millis(100),
        life_factor: 1,
    };
    monitor.watch(ms(0), 7, guarding).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut monitor]);
    bus.inject(frame(0x707, &[0x7F]), &mut [&mut monitor]);
    bus.run_until(ms(100), &mut [&mut monitor]);
    // Toggle 0 again: ignored, so the RTR of 100 ms stays unanswered.
    bus.inject(frame(0x707, &[0x7F]), &mut [&mut monitor]);
    bus.run_until(ms(200), &mut [&mut monitor]);
    assert_eq!(
        events(&mut monitor),
        [
            MonitorEvent::StateChanged {
                node_id: 7,
                from: None,
                to: NmtState::PreOperational
            },
            MonitorEvent::Lost { node_id: 7 },
        ]
    );
}

#[test]
fn emergencies_decode_with_their_meaning() {
    let fault = Emergency::from_frame(&frame(0x85, &[0x10, 0x23, 0x03, 1, 2, 3, 4, 5])).unwrap();
    assert_eq!(
        fault,
        Emergency {
            node_id: 5,
            code: 0x2310,
            register: 0x03,
            manufacturer: [1, 2, 3, 4, 5]
        }
    );
    assert_eq!(
        fault.meaning(),
        "continuous over-current (device output side)"
    );
    assert_eq!(emcy_meaning(0x8130), "life guard error or heartbeat error");
    assert_eq!(emcy_meaning(0x3000), "voltage");
    assert_eq!(emcy_meaning(0x5530), "device hardware");
    assert_eq!(emcy_meaning(0xFF42), "device specific");
    assert_eq!(emcy_meaning(0x0000), "error reset or no error");
    // Not an EMCY: SYNC, a short frame, an RTR.
    assert_eq!(Emergency::from_frame(&frame(0x80, &[])), None);
    assert_eq!(Emergency::from_frame(&frame(0x85, &[0, 0x10])), None);
    assert_eq!(
        Emergency::from_frame(&edsgen_runtime::CanFrame::remote(0x85, 8)),
        None
    );
}

#[cfg(feature = "node-guarding")]
#[test]
fn a_node_whose_guarding_master_stops_emits_emcy_8130_the_consumer_decodes() {
    // Node 3 expects guarding every 100 ms, life time factor 3; the master guards it until
    // 200 ms and then stops.
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut client: SdoClient<32> = SdoClient::new(3);
    let mut monitor = NodeMonitor::<1>::new();
    let mut bus = VirtualBus::new(ms(0));
    client
        .write(ms(0), Entry::<u16>::new(0x100C, 0), &100)
        .unwrap();
    bus.run_until(ms(1), &mut [&mut node, &mut client]);
    client
        .write(ms(1), Entry::<u8>::new(0x100D, 0), &3)
        .unwrap();
    bus.run_until(ms(2), &mut [&mut node, &mut client]);
    let guarding = Watch::Guarding {
        guard_time: Duration::from_millis(100),
        life_factor: 3,
    };
    monitor.watch(ms(2), 3, guarding).unwrap();
    bus.run_until(ms(250), &mut [&mut node, &mut monitor]);
    monitor.unwatch(3);
    bus.take_log();
    bus.run_until(ms(600), &mut [&mut node, &mut monitor]);
    let emcy: Vec<(u64, Emergency)> = bus
        .log()
        .iter()
        .filter_map(|(t, _, f)| Some((t.as_micros() / 1000, Emergency::from_frame(f)?)))
        .collect();
    assert_eq!(
        emcy,
        [(
            502,
            Emergency {
                node_id: 3,
                code: 0x8130,
                // Communication, and generic: CiA 301 sets bit 0 with any error.
                register: 0x11,
                manufacturer: [0; 5]
            }
        )]
    );
    assert_eq!(emcy[0].1.meaning(), "life guard error or heartbeat error");
}

#[test]
fn the_sync_producer_counts_to_the_overflow_value() {
    let mut sync = SyncProducer::new(Duration::from_millis(50), 3);
    sync.start(ms(10));
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(200), &mut [&mut sync]);
    let log: Vec<(u64, String)> = bus
        .take_log()
        .iter()
        .map(|(t, _, f)| (t.as_micros() / 1000, show(f)))
        .collect();
    let expected: Vec<(u64, String)> = [
        (10, "080: 01"),
        (60, "080: 02"),
        (110, "080: 03"),
        (160, "080: 01"),
    ]
    .iter()
    .map(|(t, s)| (*t, s.to_string()))
    .collect();
    assert_eq!(log, expected);
    sync.stop();
    bus.run_until(ms(400), &mut [&mut sync]);
    assert!(bus.take_log().is_empty());
    let mut plain = SyncProducer::new(Duration::from_millis(50), 0);
    plain.start(ms(0));
    bus.run_until(ms(401), &mut [&mut plain]);
    assert_eq!(show(&bus.take_log()[0].2), "080:");
}
