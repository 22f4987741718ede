//! The node built without the optional services (`cargo test -p edsgen-runtime
//! --no-default-features`): a block request is an unknown command (abort
//! 0504 0001), and node guarding's RTR gets no answer while 100Ch/100Dh stay ordinary entries.
//! With the default features these tests are not built; the other node tests cover both services.
#![cfg(not(all(feature = "sdo-block", feature = "node-guarding")))]

mod node_support;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::{Event, Node};
use edsgen_runtime::CanFrame;
use node_support::node_od::TestOd;
use node_support::{at_ms, frame, ms, sdo_ok, sdo_read, sdo_write, sent};

fn booted() -> (Node<TestOd>, VirtualBus) {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(0, "703: 00")]));
    while node.poll_event().is_some() {}
    (node, bus)
}

#[cfg(not(feature = "sdo-block"))]
#[test]
fn block_requests_are_aborted_as_unknown_commands() {
    let (mut node, mut bus) = booted();
    // Block download initiate of 1008h:00 (ccs 6, CRC, size 4), then block upload initiate
    // (ccs 5, CRC, 127 segments per block, no protocol switch).
    bus.inject(
        frame(0x603, &[0xC6, 0x08, 0x10, 0x00, 0x04, 0, 0, 0]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x603, &[0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0]),
        &mut [&mut node],
    );
    // No transfer is in progress, so the abort names no entry (as for any unknown command).
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "583: 80 00 00 00 01 00 04 05"),
            (0, "583: 80 00 00 00 01 00 04 05"),
        ])
    );
    assert_eq!(node.poll_timeout(), None, "no transfer left running");
    assert_eq!(node.poll_event(), None);
    // Expedited transfers still work.
    bus.inject(sdo_write(0x1017, 0, 0, 2), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(0, &sdo_ok(0x1017, 0))]));
}

#[cfg(not(feature = "node-guarding"))]
#[test]
fn guarding_rtr_gets_no_answer_and_guard_entries_are_plain_values() {
    let (mut node, mut bus) = booted();
    // Guard time 100 ms, life time factor 3: accepted as values, without effect.
    bus.inject(sdo_write(0x100C, 0, 100, 2), &mut [&mut node]);
    bus.inject(sdo_write(0x100D, 0, 3, 1), &mut [&mut node]);
    bus.inject(sdo_read(0x100C, 0), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, &sdo_ok(0x100C, 0)),
            (0, &sdo_ok(0x100D, 0)),
            (0, "583: 4B 0C 10 00 64 00 00 00"),
        ])
    );
    assert_eq!(
        node.poll_event(),
        Some(Event::Written {
            index: 0x100C,
            sub: 0
        })
    );
    assert_eq!(
        node.poll_event(),
        Some(Event::Written {
            index: 0x100D,
            sub: 0
        })
    );
    bus.inject(CanFrame::remote(0x703, 1), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    bus.inject(CanFrame::remote(0x703, 1), &mut [&mut node]);
    // Nothing answers the RTRs, and no life time runs out: only the TPDO sent on entering
    // operational, and no timer.
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(0, "183: 00 00")]));
    assert_eq!(node.poll_timeout(), None);
    assert_eq!(
        node.poll_event(),
        Some(Event::NmtStateChanged(
            edsgen_runtime::NmtState::Operational
        ))
    );
    assert_eq!(node.poll_event(), None);
}
