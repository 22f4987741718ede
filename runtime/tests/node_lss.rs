//! The node as an LSS slave (CiA 305, feature `lss`): a node started with node-ID 255 serves
//! LSS only, takes the ID an LSS master gives it at reset communication (or when it leaves the
//! configuration state), stores it through its hooks, and reports an activated bit timing.
#![cfg(feature = "lss")]

mod node_support;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::{BitTiming, Event, NmtState, Node, NodeHooks, ResetKind};
use edsgen_runtime::wire::lss::LssError;
use node_support::node_od::TestOd;
use node_support::{frame, ms, sent, show};

/// Hooks that keep what the LSS master stored.
#[derive(Default)]
struct LssHooks {
    stored: Option<(u8, Option<BitTiming>)>,
    refuse: bool,
}

impl NodeHooks<TestOd> for LssHooks {
    fn reset(&mut self, kind: ResetKind, od: &mut TestOd) {
        match kind {
            ResetKind::Node => od.reset_range(0x0000..=0xFFFF),
            ResetKind::Communication => od.reset_range(0x1000..=0x1FFF),
        }
    }

    fn store_lss(&mut self, node_id: u8, bit_timing: Option<BitTiming>) -> Result<(), LssError> {
        if self.refuse {
            return Err(LssError::StorageAccess);
        }
        self.stored = Some((node_id, bit_timing));
        Ok(())
    }
}

fn unconfigured() -> Node<TestOd, LssHooks> {
    Node::with_hooks(TestOd::new(5), LssHooks::default(), 0xFF, ms(0)).unwrap()
}

fn lss(data: [u8; 8]) -> edsgen_runtime::CanFrame {
    frame(0x7E5, &data)
}

fn strings(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

fn texts(bus: &mut VirtualBus) -> Vec<String> {
    sent(bus).into_iter().map(|(_, f)| f).collect()
}

#[test]
fn an_unconfigured_node_is_silent_but_for_lss() {
    let mut node = unconfigured();
    assert!(node.is_unconfigured());
    assert_eq!(node.nmt_state(), NmtState::Initialising);
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(3000), &mut [&mut node]);
    assert_eq!(
        texts(&mut bus),
        Vec::<String>::new(),
        "no boot-up, no heartbeat"
    );
    // No SDO at any ID, no NMT start.
    bus.inject(
        frame(0x6FF, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    bus.inject(frame(0x000, &[0x01, 0x00]), &mut [&mut node]);
    bus.run_until(ms(3100), &mut [&mut node]);
    assert_eq!(texts(&mut bus), Vec::<String>::new());
    assert_eq!(node.nmt_state(), NmtState::Initialising);
    bus.inject(lss([0x4C, 0, 0, 0, 0, 0, 0, 0]), &mut [&mut node]);
    bus.run_until(ms(3200), &mut [&mut node]);
    assert_eq!(texts(&mut bus), strings(&["7E4: 50 00 00 00 00 00 00 00"]));
}

#[test]
fn given_an_id_it_boots_up_and_serves_sdo_there() {
    let mut node = unconfigured();
    let mut bus = VirtualBus::new(ms(0));
    for data in [
        [0x04, 0x01, 0, 0, 0, 0, 0, 0],
        [0x5A, 0, 0, 0, 0, 0, 0, 0],
        [0x11, 0x05, 0, 0, 0, 0, 0, 0],
        [0x5E, 0, 0, 0, 0, 0, 0, 0],
        [0x17, 0, 0, 0, 0, 0, 0, 0],
    ] {
        bus.inject(lss(data), &mut [&mut node]);
        bus.run_until(
            bus.now() + edsgen_runtime::Duration::from_millis(1),
            &mut [&mut node],
        );
    }
    assert_eq!(
        texts(&mut bus),
        strings(&[
            "7E4: 5A D8 04 00 00 00 00 00",
            "7E4: 11 00 00 00 00 00 00 00",
            "7E4: 5E FF 00 00 00 00 00 00",
            "7E4: 17 00 00 00 00 00 00 00",
        ])
    );
    assert_eq!(node.hooks().stored, Some((5, None)));
    assert!(
        node.is_unconfigured(),
        "the ID is pending until reset communication"
    );
    bus.inject(frame(0x000, &[0x82, 0x00]), &mut [&mut node]);
    bus.run_until(
        bus.now() + edsgen_runtime::Duration::from_millis(1),
        &mut [&mut node],
    );
    assert_eq!(node.node_id(), 5);
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
    assert_eq!(texts(&mut bus), strings(&["705: 00"]));
    bus.inject(
        frame(0x605, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    bus.run_until(
        bus.now() + edsgen_runtime::Duration::from_millis(1),
        &mut [&mut node],
    );
    assert_eq!(texts(&mut bus), strings(&["585: 43 18 10 01 D8 04 00 00"]));
    // The stored ID survives a reset node.
    bus.inject(frame(0x000, &[0x81, 0x05]), &mut [&mut node]);
    assert_eq!(node.node_id(), 5);
}

#[test]
fn leaving_configuration_with_a_new_id_resets_communication_and_an_unstored_id_is_lost() {
    let mut node = unconfigured();
    node.handle_frame(ms(1), &lss([0x04, 0x01, 0, 0, 0, 0, 0, 0]));
    node.handle_frame(ms(1), &lss([0x11, 0x09, 0, 0, 0, 0, 0, 0]));
    assert_eq!(
        show(&node.poll_transmit(ms(1)).unwrap()),
        "7E4: 11 00 00 00 00 00 00 00"
    );
    node.handle_frame(ms(2), &lss([0x04, 0x00, 0, 0, 0, 0, 0, 0]));
    assert_eq!(node.node_id(), 9);
    assert_eq!(show(&node.poll_transmit(ms(2)).unwrap()), "709: 00");
    // Not stored: a reset node starts unconfigured again.
    node.handle_frame(ms(3), &frame(0x000, &[0x81, 0x09]));
    assert!(node.is_unconfigured());
    assert_eq!(node.poll_transmit(ms(3)), None);
}

#[test]
fn a_refused_store_answers_its_error() {
    let mut node = unconfigured();
    node.hooks_mut().refuse = true;
    node.handle_frame(ms(1), &lss([0x04, 0x01, 0, 0, 0, 0, 0, 0]));
    node.handle_frame(ms(1), &lss([0x17, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(
        show(&node.poll_transmit(ms(1)).unwrap()),
        "7E4: 17 02 00 00 00 00 00 00"
    );
    let mut plain = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    plain.poll_transmit(ms(0));
    plain.handle_frame(ms(1), &lss([0x04, 0x01, 0, 0, 0, 0, 0, 0]));
    plain.handle_frame(ms(1), &lss([0x17, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(
        show(&plain.poll_transmit(ms(1)).unwrap()),
        "7E4: 17 01 00 00 00 00 00 00",
        "without a store hook: not supported"
    );
}

#[test]
fn activating_a_bit_timing_reports_it_and_keeps_the_node_silent_twice_the_delay() {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    node.poll_transmit(ms(0));
    while node.poll_event().is_some() {}
    node.handle_frame(ms(10), &lss([0x04, 0x01, 0, 0, 0, 0, 0, 0]));
    node.handle_frame(ms(10), &lss([0x13, 0x00, 0x04, 0, 0, 0, 0, 0]));
    assert_eq!(
        show(&node.poll_transmit(ms(10)).unwrap()),
        "7E4: 13 00 00 00 00 00 00 00"
    );
    node.handle_frame(ms(20), &lss([0x15, 100, 0, 0, 0, 0, 0, 0]));
    assert_eq!(
        node.poll_event(),
        Some(Event::BitTimingActivated {
            timing: BitTiming { table: 0, index: 4 },
            switch_delay_ms: 100,
        })
    );
    assert_eq!(BitTiming { table: 0, index: 4 }.table0_kbit(), Some(125));
    node.handle_frame(ms(30), &lss([0x5E, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(node.poll_transmit(ms(219)), None);
    assert_eq!(
        show(&node.poll_transmit(ms(220)).unwrap()),
        "7E4: 5E 03 00 00 00 00 00 00"
    );
}
