//! SYNC producer and consumer, EMCY producer with 1001h/1003h, store/restore through the hooks,
//! the second SDO server channel, and the application events.

mod node_support;

use edsgen_host::vbus::{ScriptedPeer, VirtualBus};
use edsgen_runtime::node::{error_register, Event, NmtState, Node, ResetKind};
use node_support::node_od::{RecordingHooks, TestOd};
use node_support::{at_ms, frame, ms, sdo_abort, sdo_ok, sdo_read, sdo_write, sent};

fn booted() -> (Node<TestOd, RecordingHooks>, VirtualBus) {
    let mut node = Node::with_hooks(TestOd::new(3), RecordingHooks::default(), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    sent(&mut bus);
    while node.poll_event().is_some() {}
    (node, bus)
}

fn events<H: edsgen_runtime::NodeHooks<TestOd>>(node: &mut Node<TestOd, H>) -> Vec<Event> {
    std::iter::from_fn(|| node.poll_event()).collect()
}

#[test]
fn sync_producer_with_counter_and_its_own_synchronous_tpdo() {
    let (mut node, mut bus) = booted();
    for (index, value, len) in [
        (0x1019u16, 3u32, 1usize),
        (0x1006, 10_000, 4),
        (0x1005, 0x4000_0080, 4),
    ] {
        bus.inject(sdo_write(index, 0, value, len), &mut [&mut node]);
    }
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    let mut consumer = ScriptedPeer::new();
    bus.run_until(ms(45), &mut [&mut node, &mut consumer]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, &sdo_ok(0x1019, 0)),
            (0, &sdo_ok(0x1006, 0)),
            (0, &sdo_ok(0x1005, 0)),
            (0, "183: 00 00"),
            (10, "080: 01"),
            (10, "283: 00 00 00 00"),
            (20, "080: 02"),
            (20, "283: 00 00 00 00"),
            (30, "080: 03"),
            (30, "283: 00 00 00 00"),
            (40, "080: 01"),
            (40, "283: 00 00 00 00"),
        ])
    );
    assert_eq!(
        consumer.received.len(),
        8,
        "the consumer joined after the configuration"
    );
    let syncs: Vec<_> = events(&mut node)
        .into_iter()
        .filter(|e| matches!(e, Event::Sync { .. }))
        .collect();
    assert_eq!(
        syncs,
        [1, 2, 3, 1].map(|c| Event::Sync { counter: Some(c) }),
        "the producer consumes its own SYNC"
    );
}

#[test]
fn sync_producer_refuses_counter_change_while_running_and_id_change_while_producing() {
    let (mut node, mut bus) = booted();
    bus.inject(sdo_write(0x1006, 0, 10_000, 4), &mut [&mut node]);
    bus.inject(sdo_write(0x1019, 0, 3, 1), &mut [&mut node]);
    bus.inject(sdo_write(0x1006, 0, 0, 4), &mut [&mut node]);
    bus.inject(sdo_write(0x1019, 0, 241, 1), &mut [&mut node]);
    bus.inject(sdo_write(0x1005, 0, 0x4000_0080, 4), &mut [&mut node]);
    bus.inject(sdo_write(0x1005, 0, 0x4000_0081, 4), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        vec![
            (0, sdo_ok(0x1006, 0)),
            (0, sdo_abort(0x1019, 0, 0x0800_0022)),
            (0, sdo_ok(0x1006, 0)),
            (0, sdo_abort(0x1019, 0, 0x0609_0030)),
            (0, sdo_ok(0x1005, 0)),
            (0, sdo_abort(0x1005, 0, 0x0609_0030)),
        ]
    );
}

#[test]
fn sync_consumer_raises_8100_when_sync_stops_for_one_and_a_half_periods() {
    let (mut node, mut bus) = booted();
    bus.inject(sdo_write(0x1006, 0, 10_000, 4), &mut [&mut node]);
    sent(&mut bus);
    let mut master = ScriptedPeer::new();
    for t in [0, 10, 50] {
        master.send_at(ms(t), frame(0x080, &[]));
    }
    bus.run_until(ms(60), &mut [&mut node, &mut master]);
    let node_frames = node_support::sent_by(&mut bus, 0);
    assert_eq!(
        node_frames,
        at_ms(&[
            (25, "083: 00 81 11 00 00 00 00 00"),
            (50, "083: 00 00 00 00 00 00 00 00")
        ])
    );
}

#[test]
fn sync_window_drops_late_synchronous_tpdos() {
    let (mut node, mut bus) = booted();
    // 1007h = 500 µs; TPDO2 (type 1) inhibited by nothing, but we hold the bus: the node is
    // polled only 1 ms after the SYNC.
    bus.inject(sdo_write(0x1007, 0, 500, 4), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    sent(&mut bus);
    node.handle_frame(ms(1), &frame(0x080, &[]));
    assert_eq!(node.poll_transmit(ms(2)), None, "outside the window");
    node.handle_frame(ms(3), &frame(0x080, &[]));
    let tpdo = node.poll_transmit(ms(3)).unwrap();
    assert_eq!(node_support::show(&tpdo), "283: 00 00 00 00");
}

#[test]
fn emcy_raise_and_clear_with_error_register_and_history() {
    let (mut node, mut bus) = booted();
    // The Goodrive350 example (§3.4.8): fault OUT1, code 3000h, voltage bit, VFD code 1.
    assert!(node.raise_error(0x3000, error_register::VOLTAGE, [0x01, 0, 0, 0, 0]));
    assert!(
        !node.raise_error(0x3000, error_register::VOLTAGE, [0x01, 0, 0, 0, 0]),
        "already active"
    );
    bus.run_until(ms(1), &mut [&mut node]);
    assert_eq!(node.od().get(0x1001, 0), 0x05);
    assert_eq!(node.od().get(0x1003, 0), 1);
    assert_eq!(node.od().get(0x1003, 1), 0x3000);
    assert!(node.clear_error(0x3000));
    assert!(!node.clear_error(0x3000));
    bus.run_until(ms(2), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "083: 00 30 05 01 00 00 00 00"),
            (1, "083: 00 00 00 00 00 00 00 00")
        ])
    );
    assert_eq!(node.od().get(0x1001, 0), 0);
    assert_eq!(node.od().get(0x1003, 0), 1, "history keeps the entry");
}

#[test]
fn emcy_inhibit_time_spaces_emergencies() {
    let (mut node, mut bus) = booted();
    bus.inject(sdo_write(0x1015, 0, 50, 2), &mut [&mut node]); // 5 ms
    sent(&mut bus);
    node.raise_error(0x4210, error_register::TEMPERATURE, [0; 5]);
    node.raise_error(0x3210, error_register::VOLTAGE, [0; 5]);
    node.raise_error(0x2310, error_register::CURRENT, [0; 5]);
    bus.run_until(ms(20), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "083: 10 42 09 00 00 00 00 00"),
            (5, "083: 10 32 0D 00 00 00 00 00"),
            (10, "083: 10 23 0F 00 00 00 00 00"),
        ])
    );
    // 1003h: newest first, capped at its 4 sub-indices.
    node.raise_error(0x5000, 0x01, [0; 5]);
    node.raise_error(0x6000, 0x01, [0; 5]);
    let history: Vec<u64> = (0..=4).map(|s| node.od().get(0x1003, s)).collect();
    assert_eq!(history, [4, 0x6000, 0x5000, 0x2310, 0x3210]);
    // Writing 0 to 1003h:00 clears the history; other values are refused.
    bus.inject(sdo_write(0x1003, 0, 2, 1), &mut [&mut node]);
    bus.inject(sdo_write(0x1003, 0, 0, 1), &mut [&mut node]);
    assert_eq!(node.od().get(0x1003, 0), 0);
    let log = sent(&mut bus);
    assert_eq!(
        log[log.len() - 2..],
        [
            (20_000, sdo_abort(0x1003, 0, 0x0609_0030)),
            (20_000, sdo_ok(0x1003, 0))
        ]
    );
}

#[test]
fn reset_node_after_errors_announces_no_error() {
    let (mut node, mut bus) = booted();
    node.raise_error(0x3000, error_register::VOLTAGE, [1, 0, 0, 0, 0]);
    bus.run_until(ms(1), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x81, 0x03]), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "083: 00 30 05 01 00 00 00 00"),
            (1, "703: 00"),
            (1, "083: 00 00 00 00 00 00 00 00"),
        ])
    );
    assert_eq!(node.error_register(), 0);
}

#[test]
fn store_and_restore_go_through_the_hooks_with_their_signatures() {
    let (mut node, mut bus) = booted();
    bus.inject(
        sdo_write(0x1010, 1, u32::from_le_bytes(*b"save"), 4),
        &mut [&mut node],
    );
    bus.inject(
        sdo_write(0x1010, 1, u32::from_le_bytes(*b"SAVE"), 4),
        &mut [&mut node],
    );
    bus.inject(sdo_write(0x1011, 1, 0x6461_6F6C, 4), &mut [&mut node]);
    bus.inject(sdo_write(0x1011, 1, 0x6576_6173, 4), &mut [&mut node]);
    bus.inject(sdo_read(0x1010, 1), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        vec![
            (0, sdo_ok(0x1010, 1)),
            (0, sdo_abort(0x1010, 1, 0x0800_0020)),
            (0, sdo_ok(0x1011, 1)),
            (0, sdo_abort(0x1011, 1, 0x0800_0020)),
            (0, "583: 43 10 10 01 01 00 00 00".to_string()),
        ],
        "1010h:01 still reads 1 (saves on command)"
    );
    assert_eq!(node.hooks().saved, [1]);
    assert_eq!(node.hooks().restored, [1]);
}

#[test]
fn a_node_without_hooks_refuses_to_store() {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(
        sdo_write(0x1010, 1, u32::from_le_bytes(*b"save"), 4),
        &mut [&mut node],
    );
    assert_eq!(sent(&mut bus), vec![(0, sdo_abort(0x1010, 1, 0x0800_0020))]);
}

#[test]
fn second_sdo_server_channel_from_1201h() {
    let mut node = Node::new(TestOd::with_second_sdo(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(
        frame(0x640, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    bus.inject(sdo_read(0x1018, 1), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "5C0: 43 18 10 01 D8 04 00 00"),
            (0, "583: 43 18 10 01 D8 04 00 00"),
        ])
    );
    // Disable the second channel through its own COB-ID; it falls silent.
    bus.inject(
        frame(0x640, &[0x23, 0x01, 0x12, 0x01, 0x40, 0x06, 0x00, 0x80]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x640, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, "5C0: 60 01 12 01 00 00 00 00")])
    );
}

#[test]
fn default_sdo_server_uses_600h_580h_whatever_1200h_stores() {
    // A description may hold 8000 0000h in 1200h (CANopenNode's XDDs, set at run time); CiA 301
    // fixes the default server's COB-IDs to 600h/580h + node-ID, and 1200h is read-only.
    let mut od = TestOd::new(3);
    od.set(0x1200, 1, 0x8000_0000);
    od.set(0x1200, 2, 0x8000_0000);
    let mut node = Node::new(od, 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(sdo_read(0x1018, 1), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, "583: 43 18 10 01 D8 04 00 00")])
    );
    // A reset communication reads the configuration again: still served.
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    bus.inject(sdo_read(0x1018, 1), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, "703: 00"), (0, "583: 43 18 10 01 D8 04 00 00")])
    );
}

#[test]
fn application_events_in_order() {
    let (mut node, mut bus) = booted();
    bus.inject(sdo_write(0x2002, 0, 9, 1), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    bus.inject(frame(0x203, &[1, 0]), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x82, 0x00]), &mut [&mut node]);
    assert_eq!(
        events(&mut node),
        [
            Event::Written {
                index: 0x2002,
                sub: 0
            },
            Event::NmtStateChanged(NmtState::Operational),
            Event::RpdoReceived { pdo: 0 },
            Event::Sync { counter: None },
            Event::Reset(ResetKind::Communication),
            Event::NmtStateChanged(NmtState::PreOperational),
        ]
    );
    assert_eq!(
        node.hooks().resets,
        [ResetKind::Node, ResetKind::Communication]
    );
}

#[test]
fn unpolled_events_are_counted_not_overwritten() {
    let (mut node, mut bus) = booted();
    for _ in 0..20 {
        bus.inject(frame(0x080, &[]), &mut [&mut node]);
    }
    assert_eq!(events(&mut node).len(), edsgen_runtime::node::EVENT_QUEUE);
    assert_eq!(node.events_lost(), 4);
}
