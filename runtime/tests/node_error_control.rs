//! Error control: heartbeat producer (1017h), heartbeat consumer (1016h), node guarding with the
//! toggle bit and life guarding (100Ch/100Dh), stepped on the virtual bus with exact timing.

mod node_support;

use edsgen_host::vbus::{ScriptedPeer, VirtualBus};
use edsgen_runtime::node::{Event, Node};
use edsgen_runtime::CanFrame;
use node_support::node_od::TestOd;
use node_support::{at_ms, frame, ms, sent};

fn booted() -> (Node<TestOd>, VirtualBus) {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(0, "703: 00")]));
    while node.poll_event().is_some() {}
    (node, bus)
}

fn sdo_write_u16(index: u16, value: u16) -> CanFrame {
    let i = index.to_le_bytes();
    let v = value.to_le_bytes();
    frame(0x603, &[0x2B, i[0], i[1], 0x00, v[0], v[1], 0, 0])
}

#[test]
fn heartbeat_every_period_with_the_nmt_state() {
    let (mut node, mut bus) = booted();
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(sdo_write_u16(0x1017, 100), &mut [&mut node]);
    bus.run_until(ms(350), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "583: 60 17 10 00 00 00 00 00"),
            (100, "703: 05"),
            (200, "703: 05"),
            (300, "703: 05"),
        ])
    );
    // Goodrive350 §3.4.5: "2B 17 10 00 00 00 00 00" disables the heartbeat.
    bus.inject(
        frame(0x603, &[0x2B, 0x17, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(350, "583: 60 17 10 00 00 00 00 00")])
    );
}

#[test]
fn heartbeat_period_change_takes_effect_at_once() {
    let (mut node, mut bus) = booted();
    bus.inject(sdo_write_u16(0x1017, 1000), &mut [&mut node]);
    bus.run_until(ms(1500), &mut [&mut node]);
    bus.inject(sdo_write_u16(0x1017, 50), &mut [&mut node]);
    bus.run_until(ms(1620), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "583: 60 17 10 00 00 00 00 00"),
            (1000, "703: 7F"),
            (1500, "583: 60 17 10 00 00 00 00 00"),
            (1550, "703: 7F"),
            (1600, "703: 7F"),
        ])
    );
}

#[test]
fn heartbeat_continues_when_stopped() {
    let (mut node, mut bus) = booted();
    bus.inject(sdo_write_u16(0x1017, 10), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x02, 0x00]), &mut [&mut node]);
    bus.run_until(ms(25), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "583: 60 17 10 00 00 00 00 00"),
            (10, "703: 04"),
            (20, "703: 04")
        ])
    );
}

#[cfg(feature = "node-guarding")]
#[test]
fn node_guarding_toggles_from_zero_after_boot() {
    let (mut node, mut bus) = booted();
    let rtr = CanFrame::remote(0x703, 1);
    bus.inject(rtr, &mut [&mut node]);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    bus.run_until(ms(10), &mut [&mut node]);
    bus.inject(rtr, &mut [&mut node]);
    bus.run_until(ms(20), &mut [&mut node]);
    bus.inject(rtr, &mut [&mut node]);
    bus.inject(rtr, &mut [&mut node]);
    // The first answer after boot-up has toggle 0 (CiA 301); in operational the answers are the
    // Goodrive350 manual's 85 then 05 (§3.4.4).
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "703: 7F"),
            (0, "183: 00 00"),
            (10, "703: 85"),
            (20, "703: 05"),
            (20, "703: 85"),
        ])
    );
}

#[cfg(feature = "node-guarding")]
#[test]
fn reset_communication_restarts_the_toggle_bit() {
    let (mut node, mut bus) = booted();
    let rtr = CanFrame::remote(0x703, 1);
    bus.inject(rtr, &mut [&mut node]);
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    bus.inject(rtr, &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, "703: 7F"), (0, "703: 00"), (0, "703: 7F")])
    );
}

#[cfg(feature = "node-guarding")]
#[test]
fn life_guarding_event_and_emcy_when_guarding_stops() {
    let (mut node, mut bus) = booted();
    // Guard time 100 ms, life time factor 3: life time 300 ms.
    bus.inject(sdo_write_u16(0x100C, 100), &mut [&mut node]);
    bus.inject(
        frame(0x603, &[0x2F, 0x0D, 0x10, 0x00, 3, 0, 0, 0]),
        &mut [&mut node],
    );
    sent(&mut bus);
    let mut master = ScriptedPeer::new();
    for t in [0, 100, 200] {
        master.send_at(ms(t), CanFrame::remote(0x703, 1));
    }
    master.send_at(ms(900), CanFrame::remote(0x703, 1));
    while node.poll_event().is_some() {}
    bus.run_until(ms(1000), &mut [&mut node, &mut master]);
    let node_frames = node_support::sent_by(&mut bus, 0);
    assert_eq!(
        node_frames,
        at_ms(&[
            (0, "703: 7F"),
            (100, "703: FF"),
            (200, "703: 7F"),
            (500, "083: 30 81 11 00 00 00 00 00"),
            (900, "083: 00 00 00 00 00 00 00 00"),
            (900, "703: FF"),
        ])
    );
    assert_eq!(node.poll_event(), Some(Event::LifeGuardingLost));
    assert_eq!(node.poll_event(), None);
}

#[test]
fn heartbeat_consumer_reports_a_lost_node_after_its_first_heartbeat() {
    let (mut node, mut bus) = booted();
    // Watch node 5 with 150 ms.
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x01, 0x96, 0x00, 0x05, 0x00]),
        &mut [&mut node],
    );
    while node.poll_event().is_some() {}
    let mut peer = ScriptedPeer::new();
    peer.send_at(ms(400), frame(0x705, &[0x7F])); // no monitoring before the first heartbeat
    peer.send_at(ms(500), frame(0x705, &[0x7F]));
    peer.send_at(ms(600), frame(0x706, &[0x7F])); // another node: not watched
    bus.run_until(ms(640), &mut [&mut node, &mut peer]);
    assert_eq!(node.poll_event(), None);
    bus.run_until(ms(649), &mut [&mut node, &mut peer]);
    assert_eq!(node.poll_event(), None);
    bus.run_until(ms(650), &mut [&mut node, &mut peer]);
    assert_eq!(node.poll_event(), Some(Event::HeartbeatLost { node_id: 5 }));
    bus.run_until(ms(2000), &mut [&mut node, &mut peer]);
    assert_eq!(node.poll_event(), None, "reported once");
}

#[test]
fn heartbeat_consumer_timeout_raises_8130_until_every_watched_node_is_back() {
    let (mut node, mut bus) = booted();
    // Watch node 5 with 150 ms and node 6 with 200 ms.
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x01, 0x96, 0x00, 0x05, 0x00]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x02, 0xC8, 0x00, 0x06, 0x00]),
        &mut [&mut node],
    );
    sent(&mut bus);
    while node.poll_event().is_some() {}
    let mut peer = ScriptedPeer::new();
    peer.send_at(ms(100), frame(0x705, &[0x05]));
    peer.send_at(ms(100), frame(0x706, &[0x05]));
    peer.send_at(ms(400), frame(0x706, &[0x05])); // node 6 late: lost at 300 ms, back at 400
    peer.send_at(ms(500), frame(0x705, &[0x05])); // node 5 lost at 250 ms, back at 500
    bus.run_until(ms(520), &mut [&mut node, &mut peer]);
    let node_frames = node_support::sent_by(&mut bus, 0);
    // One emergency for both losses (manufacturer byte 0: the first lost node), cleared when
    // the last lost node is heard again.
    assert_eq!(
        node_frames,
        at_ms(&[
            (250, "083: 30 81 11 05 00 00 00 00"),
            (500, "083: 00 00 00 00 00 00 00 00"),
        ])
    );
    assert_eq!(
        std::iter::from_fn(|| node.poll_event()).collect::<Vec<_>>(),
        [
            Event::HeartbeatLost { node_id: 5 },
            Event::HeartbeatLost { node_id: 6 },
        ]
    );
    assert_eq!(node.od().get(0x1001, 0), 0);
    assert_eq!(node.od().get(0x1003, 0), 1);
    assert_eq!(node.od().get(0x1003, 1), 0x8130);
}

#[test]
fn heartbeat_consumer_loss_ends_when_the_lost_node_is_no_longer_watched() {
    let (mut node, mut bus) = booted();
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x01, 0x96, 0x00, 0x05, 0x00]),
        &mut [&mut node],
    );
    let mut peer = ScriptedPeer::new();
    peer.send_at(ms(100), frame(0x705, &[0x05]));
    bus.run_until(ms(300), &mut [&mut node, &mut peer]);
    assert_eq!(node.od().get(0x1001, 0), 0x11);
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x01, 0x00, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "583: 60 16 10 01 00 00 00 00"),
            (100, "705: 05"),
            (250, "083: 30 81 11 05 00 00 00 00"),
            (300, "083: 00 00 00 00 00 00 00 00"),
            (300, "583: 60 16 10 01 00 00 00 00"),
        ])
    );
    assert_eq!(node.od().get(0x1001, 0), 0);
}

#[test]
fn heartbeat_consumer_refuses_a_second_entry_for_the_same_node() {
    let (mut node, mut bus) = booted();
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x01, 0x96, 0x00, 0x05, 0x00]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x603, &[0x23, 0x16, 0x10, 0x02, 0x20, 0x00, 0x05, 0x00]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "583: 60 16 10 01 00 00 00 00"),
            (0, "583: 80 16 10 02 43 00 04 06"),
        ])
    );
}
