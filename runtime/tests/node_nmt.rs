//! NMT slave: boot-up, the state machine, broadcast and addressed commands, resets and which
//! services run in which state.

mod node_support;

use edsgen_host::vbus::{BusDevice, VirtualBus};
use edsgen_runtime::node::{Event, NmtState, Node, ResetKind};
use node_support::node_od::{RecordingHooks, TestOd};
use node_support::{at_ms, frame, ms, sent, show};

fn node() -> Node<TestOd, RecordingHooks> {
    Node::with_hooks(TestOd::new(3), RecordingHooks::default(), 3, ms(0)).unwrap()
}

fn events(node: &mut Node<TestOd, RecordingHooks>) -> Vec<Event> {
    std::iter::from_fn(|| node.poll_event()).collect()
}

#[test]
fn boot_up_message_then_pre_operational() {
    let mut node = node();
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
    assert_eq!(
        events(&mut node),
        [Event::NmtStateChanged(NmtState::PreOperational)]
    );
    assert_eq!(node.hooks().resets, [ResetKind::Node]);
    let boot = node.poll_transmit(ms(0)).unwrap();
    assert_eq!(show(&boot), "703: 00");
    assert_eq!(node.poll_transmit(ms(0)), None);
    assert_eq!(node.poll_timeout(), None);
}

#[test]
fn node_id_out_of_range_is_refused() {
    assert!(Node::new(TestOd::new(3), 0, ms(0)).is_err());
    assert!(Node::new(TestOd::new(3), 128, ms(0)).is_err());
    assert!(Node::new(TestOd::new(127), 127, ms(0)).is_ok());
}

#[test]
fn addressed_and_broadcast_commands_walk_the_state_machine() {
    let mut node = node();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(1), &mut [&mut node]);
    events(&mut node);
    // Goodrive350 §3.4.3: start all nodes, then pre-operational to node 3.
    bus.inject(frame(0x000, &[0x01, 0x00]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::Operational);
    bus.inject(frame(0x000, &[0x80, 0x04]), &mut [&mut node]);
    assert_eq!(
        node.nmt_state(),
        NmtState::Operational,
        "addressed to node 4"
    );
    bus.inject(frame(0x000, &[0x80, 0x03]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
    bus.inject(frame(0x000, &[0x02, 0x03]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::Stopped);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::Operational);
    // Same state again: no event.
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    assert_eq!(
        events(&mut node),
        [
            Event::NmtStateChanged(NmtState::Operational),
            Event::NmtStateChanged(NmtState::PreOperational),
            Event::NmtStateChanged(NmtState::Stopped),
            Event::NmtStateChanged(NmtState::Operational),
        ]
    );
}

#[test]
fn malformed_nmt_frames_are_ignored() {
    let mut node = node();
    node.poll_transmit(ms(0));
    for data in [&[0x01][..], &[0x01, 0x03, 0x00], &[0x07, 0x03], &[]] {
        node.handle_frame(ms(1), &frame(0x000, data));
    }
    node.handle_frame(ms(1), &edsgen_runtime::CanFrame::remote(0x000, 2));
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
}

#[test]
fn reset_communication_restores_communication_area_and_boots_again() {
    let mut node = node();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(1), &mut [&mut node]);
    sent(&mut bus);
    // Heartbeat on through SDO, an application value set.
    bus.inject(
        frame(0x603, &[0x2B, 0x17, 0x10, 0x00, 0x64, 0, 0, 0]),
        &mut [&mut node],
    );
    node.od_mut().set(0x2002, 0, 7);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    events(&mut node);
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
    assert_eq!(node.od().get(0x1017, 0), 0, "1017h back to its default");
    assert_eq!(node.od().get(0x2002, 0), 7, "application area kept");
    assert_eq!(
        events(&mut node),
        [
            Event::Reset(ResetKind::Communication),
            Event::NmtStateChanged(NmtState::PreOperational)
        ]
    );
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (1, "583: 60 17 10 00 00 00 00 00"),
            (1, "183: 00 00"),
            (1, "703: 00")
        ]),
        "TPDO1 (event-driven) on entering operational, boot-up after the reset, no heartbeat"
    );
}

#[test]
fn reset_node_restores_application_area_too() {
    let mut node = node();
    node.od_mut().set(0x2002, 0, 7);
    node.handle_frame(ms(5), &frame(0x000, &[0x81, 0x00]));
    assert_eq!(node.od().get(0x2002, 0), 0);
    assert_eq!(node.hooks().resets, [ResetKind::Node, ResetKind::Node]);
    assert_eq!(show(&node.poll_transmit(ms(5)).unwrap()), "703: 00");
}

#[cfg(feature = "node-guarding")]
#[test]
fn stopped_node_serves_only_nmt_and_error_control() {
    let mut node = node();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(1), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x02, 0x03]), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(
        frame(0x603, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    assert!(node.raise_error(0x5000, 0x01, [0; 5]));
    bus.inject(edsgen_runtime::CanFrame::remote(0x703, 1), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(1, "703: 04")]),
        "no SDO, no EMCY; guarding answers"
    );
    assert_eq!(node.od().get(0x2000, 0), 0, "no RPDO");
    // Back to pre-operational: the EMCY raised while stopped goes out now.
    bus.inject(frame(0x000, &[0x80, 0x03]), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(1, "083: 00 50 01 00 00 00 00 00")])
    );
}

#[test]
fn pre_operational_serves_sdo_but_not_pdo() {
    let mut node = node();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(1), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.inject(
        frame(0x603, &[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(1, "583: 4B 00 20 00 00 00 00 00")])
    );
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.od().get(0x2000, 0), 0x1234);
}

#[test]
fn node_is_a_bus_device() {
    let mut node = node();
    let device: &mut dyn BusDevice = &mut node;
    assert_eq!(show(&device.poll_transmit(ms(0)).unwrap()), "703: 00");
}
