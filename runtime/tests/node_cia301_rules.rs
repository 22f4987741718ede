//! CiA 301 rules a black-box test found missing: restricted CAN-IDs, the generic bit of 1001h,
//! the SYNC length check, power-on values after NMT resets, deleting the error history, and
//! RPDOs applied all or nothing.

mod node_support;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::{error_register, Event, Node};
use node_support::node_od::TestOd;
use node_support::{at_ms, frame, ms, sdo_abort, sdo_ok, sdo_read, sdo_write, sent};

fn booted(od: TestOd) -> (Node<TestOd>, VirtualBus) {
    let mut node = Node::new(od, 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    sent(&mut bus);
    while node.poll_event().is_some() {}
    (node, bus)
}

fn events(node: &mut Node<TestOd>) -> Vec<Event> {
    std::iter::from_fn(|| node.poll_event()).collect()
}

const INVALID_VALUE: u32 = 0x0609_0030;

#[test]
fn restricted_can_ids_are_refused_for_sync_time_emcy_sdo_and_pdo_cob_ids() {
    let (mut node, mut bus) = booted(TestOd::with_second_sdo(3));
    for (index, sub, value) in [
        (0x1005u16, 0u8, 0x605u32), // SYNC on node 5's SDO request
        (0x1005, 0, 0x4000_0000),   // SYNC producer on the NMT ID
        (0x1012, 0, 0x701),         // TIME on node 1's heartbeat
        (0x1014, 0, 0x8000_0083),   // EMCY invalid first (a change while valid is refused anyway)
        (0x1014, 0, 0x000),         // EMCY on the NMT ID
        (0x1014, 0, 0x090),         // not restricted
        (0x1201, 1, 0x8000_0640),   // second SDO channel invalid first
        (0x1201, 1, 0x603),         // node 3's default SDO request
        (0x1401, 1, 0x8000_0303),   // RPDO2 invalid first
        (0x1401, 1, 0x6E0),         // LSS range
        (0x1401, 1, 0x303),         // its own default
        (0x1801, 1, 0x8000_0283),   // TPDO2 invalid first
        (0x1801, 1, 0x17F),         // node-0 EMCY range
        (0x1801, 1, 0x283),         // its own default
    ] {
        bus.inject(sdo_write(index, sub, value, 4), &mut [&mut node]);
    }
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, &sdo_abort(0x1005, 0, INVALID_VALUE)),
            (0, &sdo_abort(0x1005, 0, INVALID_VALUE)),
            (0, &sdo_abort(0x1012, 0, INVALID_VALUE)),
            (0, &sdo_ok(0x1014, 0)),
            (0, &sdo_abort(0x1014, 0, INVALID_VALUE)),
            (0, &sdo_ok(0x1014, 0)),
            (0, &sdo_ok(0x1201, 1)),
            (0, &sdo_abort(0x1201, 1, INVALID_VALUE)),
            (0, &sdo_ok(0x1401, 1)),
            (0, &sdo_abort(0x1401, 1, INVALID_VALUE)),
            (0, &sdo_ok(0x1401, 1)),
            (0, &sdo_ok(0x1801, 1)),
            (0, &sdo_abort(0x1801, 1, INVALID_VALUE)),
            (0, &sdo_ok(0x1801, 1)),
        ])
    );
    assert_eq!(node.od().get(0x1005, 0), 0x80);
    assert_eq!(node.od().get(0x1012, 0), 0x100);
    // SDO requests are still SDO requests, not SYNCs.
    bus.inject(sdo_read(0x1005, 0), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, "583: 43 05 10 00 80 00 00 00")])
    );
}

#[test]
fn error_register_generic_bit_is_set_whenever_an_error_is_active() {
    let (mut node, mut bus) = booted(TestOd::new(3));
    // An application error with the current bit only, then a communication error of the node.
    node.raise_error(0x2310, error_register::CURRENT, [0; 5]);
    bus.run_until(ms(1), &mut [&mut node]);
    assert_eq!(node.od().get(0x1001, 0), 0x03);
    node.clear_error(0x2310);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    bus.inject(frame(0x203, &[0x34]), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "083: 10 23 03 00 00 00 00 00"),
            (1, "083: 00 00 00 00 00 00 00 00"),
            (1, "183: 00 00"),
            (1, "083: 10 82 11 01 00 00 00 00"),
        ])
    );
    assert_eq!(node.error_register(), 0x11);
}

#[test]
fn sync_of_the_wrong_length_raises_8240_and_is_not_processed() {
    let (mut node, mut bus) = booted(TestOd::new(3));
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    sent(&mut bus);
    events(&mut node);
    // 1019h = 0: a SYNC carries no counter. One with a counter is refused...
    bus.inject(frame(0x080, &[0x05]), &mut [&mut node]);
    // ... and the next correct one clears the error and is processed (TPDO2, type 1).
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "083: 40 82 11 01 00 00 00 00"),
            (0, "083: 00 00 00 00 00 00 00 00"),
            (0, "283: 00 00 00 00"),
        ])
    );
    assert_eq!(events(&mut node), [Event::Sync { counter: None }]);
    // With a counter configured (1019h = 4), a SYNC without one is refused.
    bus.inject(frame(0x000, &[0x80, 0x03]), &mut [&mut node]);
    bus.inject(sdo_write(0x1019, 0, 4, 1), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, &sdo_ok(0x1019, 0)), (0, "083: 40 82 11 00 00 00 00 00"),])
    );
    assert!(node.error_active(0x8240));
}

#[test]
fn resets_restore_power_on_values_without_an_application_hook() {
    let (mut node, mut bus) = booted(TestOd::new(3));
    bus.inject(sdo_write(0x1017, 0, 1000, 2), &mut [&mut node]);
    bus.inject(sdo_write(0x6040, 0, 0x000F, 2), &mut [&mut node]);
    // Reset communication: 1017h back to 0 (no heartbeat), 6040h kept.
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    assert_eq!(node.od().get(0x1017, 0), 0);
    assert_eq!(node.od().get(0x6040, 0), 0x000F);
    bus.inject(sdo_write(0x1017, 0, 1000, 2), &mut [&mut node]);
    // Reset node: both back.
    bus.inject(frame(0x000, &[0x81, 0x03]), &mut [&mut node]);
    assert_eq!(node.od().get(0x1017, 0), 0);
    assert_eq!(node.od().get(0x6040, 0), 0);
    bus.run_until(ms(3000), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, &sdo_ok(0x1017, 0)),
            (0, &sdo_ok(0x6040, 0)),
            (0, "703: 00"),
            (0, &sdo_ok(0x1017, 0)),
            (0, "703: 00"),
        ]),
        "no heartbeat after either reset"
    );
}

#[test]
fn writing_0_to_1003_sub_0_deletes_the_history_and_its_codes() {
    let (mut node, mut bus) = booted(TestOd::new(3));
    node.raise_error(0x3000, error_register::VOLTAGE, [0; 5]);
    node.raise_error(0x4200, error_register::TEMPERATURE, [0; 5]);
    bus.run_until(ms(1), &mut [&mut node]);
    sent(&mut bus);
    bus.inject(sdo_write(0x1003, 0, 0, 1), &mut [&mut node]);
    bus.inject(sdo_read(0x1003, 0), &mut [&mut node]);
    bus.inject(sdo_read(0x1003, 1), &mut [&mut node]);
    bus.inject(sdo_read(0x1003, 2), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (1, &sdo_ok(0x1003, 0)),
            (1, "583: 4F 03 10 00 00 00 00 00"),
            (1, "583: 43 03 10 01 00 00 00 00"),
            (1, "583: 43 03 10 02 00 00 00 00"),
        ])
    );
    // A new error starts the history afresh.
    node.raise_error(0x5000, error_register::DEVICE_PROFILE, [0; 5]);
    assert_eq!(
        (node.od().get(0x1003, 0), node.od().get(0x1003, 1)),
        (1, 0x5000)
    );
    assert_eq!(node.od().get(0x1003, 2), 0);
}

#[test]
fn an_rpdo_with_a_refused_value_is_applied_all_or_nothing() {
    let (mut node, mut bus) = booted(TestOd::new(3).with_high_limit(0x6042, 0, 1000));
    // RPDO2 (303h) maps 6040h then 6042h; event-driven so that it applies at once.
    bus.inject(sdo_write(0x1401, 2, 255, 1), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [&mut node]);
    sent(&mut bus);
    events(&mut node);
    // 6042h = 2000 is above its limit: 6040h is not written either.
    bus.inject(frame(0x303, &[0x0F, 0x00, 0xD0, 0x07]), &mut [&mut node]);
    assert_eq!(node.od().get(0x6040, 0), 0);
    assert_eq!(node.od().get(0x6042, 0), 0);
    assert_eq!(events(&mut node), []);
    // 6042h = 100: both written, and the error reset.
    bus.inject(frame(0x303, &[0x0F, 0x00, 0x64, 0x00]), &mut [&mut node]);
    assert_eq!(node.od().get(0x6040, 0), 0x000F);
    assert_eq!(node.od().get(0x6042, 0), 100);
    assert_eq!(events(&mut node), [Event::RpdoReceived { pdo: 1 }]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            // 8200h, communication and generic bits, PDO 1, abort 0609 0031.
            (0, "083: 00 82 11 01 31 00 09 06"),
            (0, "083: 00 00 00 00 00 00 00 00"),
        ])
    );
}
