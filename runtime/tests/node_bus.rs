//! Two nodes and a scripted master on the virtual bus: heartbeat production and consumption
//! between nodes, SYNC from one node driving the other's synchronous TPDO, and CAN arbitration
//! order at one instant.

mod node_support;

use edsgen_host::vbus::{ScriptedPeer, VirtualBus};
use edsgen_runtime::node::{Event, Node};
use node_support::node_od::{RecordingHooks, TestOd};
use node_support::{frame, ms, show};

fn write_to(node_id: u8, index: u16, sub: u8, value: u32, len: usize) -> edsgen_runtime::CanFrame {
    let command = match len {
        1 => 0x2F,
        2 => 0x2B,
        _ => 0x23,
    };
    let i = index.to_le_bytes();
    let v = value.to_le_bytes();
    frame(
        0x600 + u16::from(node_id),
        &[command, i[0], i[1], sub, v[0], v[1], v[2], v[3]],
    )
}

#[test]
fn a_node_watches_another_nodes_heartbeat_and_syncs_it() {
    let mut watcher = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    // The drive's hooks restore the communication area on reset communication.
    let mut drive = Node::with_hooks(TestOd::new(5), RecordingHooks::default(), 5, ms(0)).unwrap();
    let mut master = ScriptedPeer::new();
    // Drive: heartbeat 100 ms. Watcher: consume node 5 with 150 ms, produce SYNC every 50 ms.
    master.send_at(ms(1), write_to(5, 0x1017, 0, 100, 2));
    master.send_at(ms(1), write_to(3, 0x1016, 1, 0x0005_0096, 4));
    master.send_at(ms(1), write_to(3, 0x1006, 0, 50_000, 4));
    master.send_at(ms(1), write_to(3, 0x1005, 0, 0x4000_0080, 4));
    master.send_at(ms(2), frame(0x000, &[0x01, 0x05]));
    // Reset communication of the drive at 260 ms: 1017h back to 0, its heartbeat stops.
    master.send_at(ms(260), frame(0x000, &[0x82, 0x05]));
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(300), &mut [&mut watcher, &mut drive, &mut master]);
    assert!(std::iter::from_fn(|| watcher.poll_event())
        .all(|e| !matches!(e, Event::HeartbeatLost { .. })));
    bus.run_until(ms(409), &mut [&mut watcher, &mut drive, &mut master]);
    assert!(std::iter::from_fn(|| watcher.poll_event())
        .all(|e| !matches!(e, Event::HeartbeatLost { .. })));
    bus.run_until(ms(500), &mut [&mut watcher, &mut drive, &mut master]);
    let log: Vec<(u64, usize, String)> = bus
        .take_log()
        .into_iter()
        .filter(|(t, sender, _)| *t <= ms(260) && *sender != 2)
        .map(|(t, sender, f)| (t.as_micros() / 1000, sender, show(&f)))
        .collect();
    let expected: Vec<(u64, usize, String)> = [
        (0, 0, "703: 00"),
        (0, 1, "705: 00"),
        // The master's requests go one at a time; each answer (58xh) outranks its next request.
        (1, 1, "585: 60 17 10 00 00 00 00 00"),
        (1, 0, "583: 60 16 10 01 00 00 00 00"),
        (1, 0, "583: 60 06 10 00 00 00 00 00"),
        (1, 0, "583: 60 05 10 00 00 00 00 00"),
        (2, 1, "185: 00 00"),
        (51, 0, "080:"),
        (51, 1, "285: 00 00 00 00"),
        (101, 0, "080:"),
        // The drive's heartbeat was already in its transmit slot when the SYNC arrived.
        (101, 1, "705: 05"),
        (101, 1, "285: 00 00 00 00"),
        (151, 0, "080:"),
        (151, 1, "285: 00 00 00 00"),
        (201, 0, "080:"),
        (201, 1, "705: 05"),
        (201, 1, "285: 00 00 00 00"),
        (251, 0, "080:"),
        (251, 1, "285: 00 00 00 00"),
        (260, 1, "705: 00"),
    ]
    .iter()
    .map(|(t, s, f)| (*t, *s, f.to_string()))
    .collect();
    assert_eq!(log, expected);
    let lost: Vec<Event> = std::iter::from_fn(|| watcher.poll_event())
        .filter(|e| matches!(e, Event::HeartbeatLost { .. }))
        .collect();
    // The boot-up at 260 ms restarted the timer: lost at 410 ms, once.
    assert_eq!(lost, [Event::HeartbeatLost { node_id: 5 }]);
}

#[test]
fn lowest_identifier_wins_arbitration_at_one_instant() {
    let mut a = Node::new(TestOd::new(9), 9, ms(0)).unwrap();
    let mut b = Node::new(TestOd::new(2), 2, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut a, &mut b]);
    let order: Vec<(usize, String)> = bus
        .take_log()
        .into_iter()
        .map(|(_, sender, f)| (sender, show(&f)))
        .collect();
    assert_eq!(
        order,
        [(1, "702: 00".to_string()), (0, "709: 00".to_string())]
    );
}
