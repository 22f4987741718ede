//! TPDOs and RPDOs: every transmission type, inhibit time, event timer, change of state, SYNC
//! start value, RTR, the CiA 301 dynamic-mapping procedure with its aborts, the EMCYs of
//! wrong-length RPDOs, and RPDO deadline monitoring (event timer, EMCY 8250h).

mod node_support;

use edsgen_host::vbus::{ScriptedPeer, VirtualBus};
use edsgen_runtime::node::{Event, Node};
use edsgen_runtime::CanFrame;
use node_support::node_od::TestOd;
use node_support::{at_ms, frame, ms, sdo_abort, sdo_ok, sdo_write, sent};

/// A booted node in pre-operational, boot-up already on the bus and events drained.
fn booted() -> (Node<TestOd>, VirtualBus) {
    let mut node = Node::new(TestOd::new(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    sent(&mut bus);
    while node.poll_event().is_some() {}
    (node, bus)
}

fn start(node: &mut Node<TestOd>, bus: &mut VirtualBus) {
    bus.inject(frame(0x000, &[0x01, 0x03]), &mut [node]);
}

/// Writes (index, sub, value, len) by SDO and asserts each was accepted.
fn configure(node: &mut Node<TestOd>, bus: &mut VirtualBus, writes: &[(u16, u8, u32, usize)]) {
    for &(index, sub, value, len) in writes {
        bus.inject(sdo_write(index, sub, value, len), &mut [node]);
        let at = bus.now().as_micros();
        assert_eq!(
            sent(bus),
            vec![(at, sdo_ok(index, sub))],
            "{index:04X}:{sub}"
        );
    }
    while node.poll_event().is_some() {}
}

#[test]
fn event_driven_rpdo_writes_the_od_at_once() {
    let (mut node, mut bus) = booted();
    start(&mut node, &mut bus);
    sent(&mut bus);
    while node.poll_event().is_some() {}
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.od().get(0x2000, 0), 0x1234);
    assert_eq!(node.poll_event(), Some(Event::RpdoReceived { pdo: 0 }));
    assert_eq!(sent(&mut bus), vec![]);
}

#[test]
fn wrong_length_rpdos_raise_8210_and_8220() {
    let (mut node, mut bus) = booted();
    start(&mut node, &mut bus);
    sent(&mut bus);
    bus.inject(frame(0x203, &[0x34]), &mut [&mut node]);
    assert_eq!(node.od().get(0x2000, 0), 0, "too short: not processed");
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.inject(frame(0x203, &[0x78, 0x56, 0x00]), &mut [&mut node]);
    assert_eq!(node.od().get(0x2000, 0), 0x5678, "too long: processed");
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "083: 10 82 11 01 00 00 00 00"),
            (0, "083: 00 00 00 00 00 00 00 00"),
            (0, "083: 20 82 11 03 00 00 00 00"),
        ])
    );
    assert_eq!(node.od().get(0x1001, 0), 0x11);
    assert_eq!(node.od().get(0x1003, 0), 2);
    assert_eq!(node.od().get(0x1003, 1), 0x8220);
    assert_eq!(node.od().get(0x1003, 2), 0x8210);
}

#[test]
fn synchronous_rpdo_is_applied_at_the_next_sync() {
    let (mut node, mut bus) = booted();
    start(&mut node, &mut bus);
    while node.poll_event().is_some() {}
    bus.inject(frame(0x303, &[0x0F, 0x00, 0x18, 0xFC]), &mut [&mut node]);
    assert_eq!(node.od().get(0x6040, 0), 0);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    assert_eq!(node.od().get(0x6040, 0), 0x000F);
    assert_eq!(node.od().get(0x6042, 0), 0xFC18);
    assert_eq!(node.poll_event(), Some(Event::Sync { counter: None }));
    assert_eq!(node.poll_event(), Some(Event::RpdoReceived { pdo: 1 }));
}

#[test]
fn event_driven_tpdo_with_inhibit_time_and_event_timer() {
    let (mut node, mut bus) = booted();
    configure(
        &mut node,
        &mut bus,
        &[
            (0x1800, 1, 0x8000_0183, 4),
            (0x1800, 3, 100, 2), // 10 ms inhibit
            (0x1800, 5, 50, 2),  // 50 ms event timer
            (0x1800, 1, 0x0000_0183, 4),
        ],
    );
    start(&mut node, &mut bus);
    bus.run_until(ms(20), &mut [&mut node]);
    node.od_mut().set(0x6041, 0, 0x0237);
    bus.run_until(ms(22), &mut [&mut node]);
    node.od_mut().set(0x6041, 0, 0x0637);
    bus.run_until(ms(25), &mut [&mut node]);
    node.od_mut().set(0x6041, 0, 0x0637); // no change: nothing sent
    bus.run_until(ms(135), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "183: 00 00"),
            (20, "183: 37 02"),
            (30, "183: 37 06"),
            (80, "183: 37 06"),
            (130, "183: 37 06"),
        ])
    );
}

#[test]
fn application_trigger_sends_an_event_driven_tpdo() {
    let (mut node, mut bus) = booted();
    start(&mut node, &mut bus);
    bus.run_until(ms(5), &mut [&mut node]);
    assert!(node.trigger_tpdo(0));
    assert!(!node.trigger_tpdo(1), "TPDO2 is synchronous cyclic");
    assert!(!node.trigger_tpdo(2), "TPDO3 is not valid");
    assert!(!node.trigger_tpdo(9));
    bus.run_until(ms(6), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(0, "183: 00 00"), (5, "183: 00 00")])
    );
}

#[test]
fn cyclic_synchronous_tpdo_every_nth_sync() {
    let (mut node, mut bus) = booted();
    configure(
        &mut node,
        &mut bus,
        &[(0x1801, 2, 3, 1), (0x1800, 1, 0x8000_0183, 4)],
    );
    node.od_mut().set(0x2001, 0, 0xA1B2_C3D4);
    start(&mut node, &mut bus);
    for t in 1..=7 {
        bus.run_until(ms(t), &mut [&mut node]);
        bus.inject(frame(0x080, &[]), &mut [&mut node]);
    }
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(3, "283: D4 C3 B2 A1"), (6, "283: D4 C3 B2 A1")])
    );
}

#[test]
fn sync_start_value_delays_the_first_cyclic_tpdo() {
    let (mut node, mut bus) = booted();
    configure(
        &mut node,
        &mut bus,
        &[
            (0x1019, 0, 5, 1),
            (0x1800, 1, 0x8000_0183, 4),
            (0x1801, 1, 0x8000_0283, 4),
            (0x1801, 2, 2, 1),
            (0x1801, 6, 3, 1),
            (0x1801, 1, 0x0000_0283, 4),
        ],
    );
    start(&mut node, &mut bus);
    for counter in 1..=5u8 {
        bus.run_until(ms(u64::from(counter)), &mut [&mut node]);
        bus.inject(frame(0x080, &[counter]), &mut [&mut node]);
    }
    for counter in 1..=3u8 {
        bus.run_until(ms(5 + u64::from(counter)), &mut [&mut node]);
        bus.inject(frame(0x080, &[counter]), &mut [&mut node]);
    }
    // First at counter 3, then every second SYNC: counters 5, 2.
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (3, "283: 00 00 00 00"),
            (5, "283: 00 00 00 00"),
            (7, "283: 00 00 00 00"),
        ])
    );
}

#[test]
fn acyclic_synchronous_tpdo_goes_at_the_sync_after_a_change() {
    let (mut node, mut bus) = booted();
    configure(&mut node, &mut bus, &[(0x1800, 2, 0, 1)]);
    start(&mut node, &mut bus);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    bus.run_until(ms(1), &mut [&mut node]);
    node.od_mut().set(0x6041, 0, 0x0027);
    bus.run_until(ms(2), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    bus.run_until(ms(3), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    bus.run_until(ms(4), &mut [&mut node]);
    assert!(node.trigger_tpdo(0));
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "283: 00 00 00 00"),
            (2, "183: 27 00"),
            (2, "283: 00 00 00 00"),
            (3, "283: 00 00 00 00"),
            (4, "183: 27 00"),
            (4, "283: 00 00 00 00"),
        ])
    );
}

#[test]
fn rtr_only_tpdos_252_and_253() {
    let (mut node, mut bus) = booted();
    configure(
        &mut node,
        &mut bus,
        &[(0x1800, 2, 253, 1), (0x1801, 2, 252, 1)],
    );
    start(&mut node, &mut bus);
    node.od_mut().set(0x6041, 0, 0x0001);
    node.od_mut().set(0x2001, 0, 0x11);
    bus.run_until(ms(1), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![], "nothing without a request");
    bus.inject(CanFrame::remote(0x283, 4), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![], "252: nothing sampled before a SYNC");
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    node.od_mut().set(0x2001, 0, 0x22);
    node.od_mut().set(0x6041, 0, 0x0002);
    bus.run_until(ms(2), &mut [&mut node]);
    bus.inject(CanFrame::remote(0x283, 4), &mut [&mut node]);
    bus.inject(CanFrame::remote(0x183, 2), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(2, "283: 11 00 00 00"), (2, "183: 02 00")]),
        "252 answers with the SYNC's sample, 253 samples now"
    );
}

#[test]
fn dynamic_mapping_follows_the_cia_301_procedure() {
    let (mut node, mut bus) = booted();
    let steps: &[(u16, u8, u32, usize, Option<u32>)] = &[
        (0x1A00, 1, 0x2000_0010, 4, Some(0x0800_0022)), // PDO valid
        (0x1800, 1, 0x8000_0183, 4, None),              // 1. disable
        (0x1A00, 1, 0x2000_0010, 4, Some(0x0800_0022)), // sub0 still 1
        (0x1A00, 0, 0, 1, None),                        // 2. sub0 = 0
        (0x1A00, 1, 0x2002_0008, 4, Some(0x0604_0041)), // not mappable
        (0x1A00, 1, 0x6000_0010, 4, Some(0x0604_0041)), // no such object
        (0x1A00, 1, 0x2000_0008, 4, Some(0x0604_0041)), // wrong length
        (0x1A00, 1, 0x0006_0020, 4, Some(0x0604_0041)), // dummy of the wrong length
        (0x1A00, 1, 0x2000_0010, 4, None),              // 3. entries
        (0x1A00, 2, 0x2001_0020, 4, None),
        (0x1A00, 3, 0x6041_0010, 4, None),
        (0x1A00, 4, 0x6041_0010, 4, None),
        (0x1A00, 0, 4, 1, Some(0x0604_0042)), // 10 bytes
        (0x1A00, 0, 9, 1, Some(0x0604_0042)), // more than 8 entries
        (0x1A00, 0, 3, 1, None),              // 4. sub0 = n
        (0x1800, 1, 0x0000_0183, 4, None),    // 5. enable
        (0x1800, 1, 0x0000_0185, 4, Some(0x0609_0030)), // COB-ID change while valid
        (0x1800, 3, 10, 2, Some(0x0609_0030)), // inhibit while valid
        (0x1800, 2, 241, 1, Some(0x0609_0030)), // reserved type
        (0x1800, 1, 0x8000_0005, 4, None),    // invalid: any ID
        (0x1800, 1, 0x0000_0005, 4, Some(0x0609_0030)), // restricted ID
        (0x1800, 1, 0x0000_0183, 4, None),
        (0x1600, 1, 0x6041_0010, 4, Some(0x0800_0022)), // RPDO valid
        (0x1400, 1, 0x8000_0203, 4, None),
        (0x1600, 0, 0, 1, None),
        (0x1600, 1, 0x6041_0010, 4, Some(0x0604_0041)), // read-only into an RPDO
        (0x1600, 1, 0x0006_0010, 4, None),              // dummy u16
        (0x1600, 2, 0x2000_0010, 4, None),
        (0x1600, 0, 2, 1, None),
        (0x1400, 2, 252, 1, Some(0x0609_0030)), // RTR types are TPDO-only
        (0x1400, 2, 300, 4, Some(0x0607_0012)), // wrong length: the length abort first
        (0x1400, 1, 0x0000_0203, 4, None),
    ];
    for &(index, sub, value, len, abort) in steps {
        bus.inject(sdo_write(index, sub, value, len), &mut [&mut node]);
        let expected = match abort {
            Some(code) => sdo_abort(index, sub, code),
            None => sdo_ok(index, sub),
        };
        assert_eq!(
            sent(&mut bus),
            vec![(0, expected)],
            "{index:04X}:{sub} = {value:X}"
        );
    }
    node.od_mut().set(0x2000, 0, 0x1122);
    node.od_mut().set(0x2001, 0, 0x3344_5566);
    node.od_mut().set(0x6041, 0, 0x7788);
    start(&mut node, &mut bus);
    bus.inject(frame(0x203, &[0xAA, 0xBB, 0xCC, 0xDD]), &mut [&mut node]);
    assert_eq!(
        node.od().get(0x2000, 0),
        0xDDCC,
        "dummy skipped the first two bytes"
    );
    // TPDO1 went out on entering operational, before the RPDO changed 2000h; the RPDO's change
    // of a mapped object sends it again.
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (0, "183: 22 11 66 55 44 33 88 77"),
            (0, "183: CC DD 66 55 44 33 88 77"),
        ])
    );
}

#[test]
fn reset_communication_forgets_rpdo_length_errors() {
    let (mut node, mut bus) = booted();
    start(&mut node, &mut bus);
    bus.inject(frame(0x203, &[0x34]), &mut [&mut node]);
    assert!(node.error_active(0x8210));
    node.raise_error(0x5000, 0x01, [0; 5]);
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    assert!(!node.error_active(0x8210));
    assert!(node.error_active(0x5000), "application errors stay");
    assert_eq!(node.od().get(0x1001, 0), 0x01);
}

#[test]
fn a_tpdo_padded_with_a_dummy_sends_zeros_there() {
    let (mut node, mut bus) = booted();
    configure(
        &mut node,
        &mut bus,
        &[
            (0x1800, 1, 0x8000_0183, 4),
            (0x1A00, 0, 0, 1),
            (0x1A00, 1, 0x6041_0010, 4),
            (0x1A00, 2, 0x0006_0010, 4),
            (0x1A00, 3, 0x6041_0010, 4),
            (0x1A00, 0, 3, 1),
            (0x1800, 1, 0x0000_0183, 4),
        ],
    );
    node.od_mut().set(0x6041, 0, 0xBEEF);
    start(&mut node, &mut bus);
    assert_eq!(sent(&mut bus), at_ms(&[(0, "183: EF BE 00 00 EF BE")]));
}

#[test]
fn a_valid_pdo_with_a_refused_mapping_is_reported_not_served() {
    let mut od = TestOd::new(3);
    od.set(0x1A00, 1, 0x2002_0008); // 2002h is not mappable
    let mut node = Node::new(od, 3, ms(0)).unwrap();
    let events: Vec<Event> = std::iter::from_fn(|| node.poll_event()).collect();
    assert_eq!(
        events,
        [
            Event::PdoMappingRejected {
                transmit: true,
                pdo: 0,
                reason: edsgen_runtime::SdoAbort::NotMappable
            },
            Event::NmtStateChanged(edsgen_runtime::NmtState::PreOperational),
        ]
    );
    assert!(!node.trigger_tpdo(0));
}

/// The node's events, drained.
fn events(node: &mut Node<TestOd>) -> Vec<Event> {
    std::iter::from_fn(|| node.poll_event()).collect()
}

/// A started node whose RPDO1 (203h) has the event timer `ms` (1400h:05), events and frames
/// drained; the clock is at 0.
fn started_with_rpdo_deadline(ms: u32) -> (Node<TestOd>, VirtualBus) {
    let (mut node, mut bus) = booted();
    configure(&mut node, &mut bus, &[(0x1400, 5, ms, 2)]);
    start(&mut node, &mut bus);
    sent(&mut bus);
    while node.poll_event().is_some() {}
    (node, bus)
}

#[test]
fn rpdo_event_timer_raises_8250_once_when_the_rpdo_stops() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    assert_eq!(
        node.poll_timeout(),
        None,
        "no monitoring before the first reception"
    );
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), Some(ms(100)));
    assert_eq!(events(&mut node), [Event::RpdoReceived { pdo: 0 }]);
    bus.run_until(ms(99), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![]);
    assert_eq!(events(&mut node), []);
    bus.run_until(ms(100), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(100, "083: 50 82 11 00 00 00 00 00")])
    );
    assert_eq!(events(&mut node), [Event::RpdoTimeout { pdo: 0 }]);
    assert_eq!(node.od().get(0x1001, 0), 0x11);
    assert_eq!(node.od().get(0x1003, 1), 0x8250);
    assert!(node.error_active(0x8250));
    assert_eq!(node.poll_timeout(), None);
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![], "reported once");
    assert_eq!(events(&mut node), []);
}

#[test]
fn rpdo_deadline_found_late_is_reported_at_the_first_timeout_after_it() {
    let (mut node, _bus) = started_with_rpdo_deadline(100);
    node.handle_frame(ms(0), &frame(0x203, &[0x34, 0x12]));
    while node.poll_event().is_some() {}
    node.handle_timeout(ms(99));
    assert_eq!(node.poll_transmit(ms(99)), None);
    assert_eq!(node.poll_event(), None);
    node.handle_timeout(ms(250));
    let emcy = node.poll_transmit(ms(250)).unwrap();
    assert_eq!(node_support::show(&emcy), "083: 50 82 11 00 00 00 00 00");
    assert_eq!(node.poll_transmit(ms(250)), None);
    assert_eq!(events(&mut node), [Event::RpdoTimeout { pdo: 0 }]);
    node.handle_timeout(ms(400));
    assert_eq!(node.poll_transmit(ms(400)), None);
    assert_eq!(node.poll_event(), None);
}

#[test]
fn rpdo_reception_clears_the_timeout_and_rearms_the_deadline() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    let mut master = ScriptedPeer::new();
    // 60 ms apart: within the deadline; then silent until 300, then once more at 330.
    for t in [0, 60, 300, 330] {
        master.send_at(ms(t), frame(0x203, &[0x34, 0x12]));
    }
    bus.run_until(ms(600), &mut [&mut node, &mut master]);
    let node_frames = node_support::sent_by(&mut bus, 0);
    assert_eq!(
        node_frames,
        at_ms(&[
            (160, "083: 50 82 11 00 00 00 00 00"),
            (300, "083: 00 00 00 00 00 00 00 00"),
            (430, "083: 50 82 11 00 00 00 00 00"),
        ])
    );
    let timeouts: Vec<Event> = events(&mut node)
        .into_iter()
        .filter(|e| !matches!(e, Event::RpdoReceived { .. }))
        .collect();
    assert_eq!(
        timeouts,
        [Event::RpdoTimeout { pdo: 0 }, Event::RpdoTimeout { pdo: 0 }]
    );
    assert_eq!(node.od().get(0x1003, 0), 2, "two timeouts in the history");
}

#[test]
fn rpdo_event_timer_zero_never_times_out() {
    let (mut node, mut bus) = started_with_rpdo_deadline(0);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), None);
    bus.run_until(ms(10_000), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![]);
    assert_eq!(events(&mut node), [Event::RpdoReceived { pdo: 0 }]);
}

#[test]
fn rpdo_deadline_is_monitored_only_in_operational() {
    let (mut node, mut bus) = booted();
    configure(&mut node, &mut bus, &[(0x1400, 5, 100, 2)]);
    // Pre-operational: the RPDO is not processed, so nothing is armed.
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(500), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![]);
    // Operational, received at 500, back to pre-operational at 550: the deadline is dropped.
    start(&mut node, &mut bus);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(550), &mut [&mut node]);
    bus.inject(frame(0x000, &[0x80, 0x03]), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), None);
    bus.run_until(ms(1000), &mut [&mut node]);
    // Operational again: monitoring waits for the first reception.
    start(&mut node, &mut bus);
    bus.run_until(ms(2000), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(500, "183: 00 00"), (1000, "183: 00 00")])
    );
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(2100), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(2100, "083: 50 82 11 00 00 00 00 00")])
    );
    let timeouts = events(&mut node)
        .into_iter()
        .filter(|e| matches!(e, Event::RpdoTimeout { .. }))
        .count();
    assert_eq!(timeouts, 1);
}

#[test]
fn writing_the_rpdo_event_timer_by_sdo_restarts_monitoring_with_the_new_period() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(50), &mut [&mut node]);
    bus.inject(sdo_write(0x1400, 5, 200, 2), &mut [&mut node]);
    // CiA 301: monitoring starts again with the next reception, so nothing at 100 or 150.
    assert_eq!(node.poll_timeout(), None);
    bus.run_until(ms(500), &mut [&mut node]);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), Some(ms(700)));
    bus.run_until(ms(699), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(50, &sdo_ok(0x1400, 5))]));
    bus.run_until(ms(700), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[(700, "083: 50 82 11 00 00 00 00 00")])
    );
    // Switching monitoring off ends the timeout it reported.
    bus.inject(sdo_write(0x1400, 5, 0, 2), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (700, "083: 00 00 00 00 00 00 00 00"),
            (700, &sdo_ok(0x1400, 5)),
        ])
    );
    assert!(!node.error_active(0x8250));
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(5000), &mut [&mut node]);
    assert_eq!(sent(&mut bus), vec![]);
}

#[test]
fn changing_the_rpdo_transmission_type_keeps_its_deadline() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(40), &mut [&mut node]);
    bus.inject(sdo_write(0x1400, 2, 254, 1), &mut [&mut node]);
    bus.run_until(ms(100), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (40, &sdo_ok(0x1400, 2)),
            (100, "083: 50 82 11 00 00 00 00 00"),
        ])
    );
}

/// A reception arms no deadline without an event timer, so a reload that finds none (the
/// application cleared 1400h:05 directly, then a master wrote 1400h:02) clears the slot.
#[test]
fn a_reload_without_an_event_timer_stops_the_deadline() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), Some(ms(100)));
    node.od_mut().set(0x1400, 5, 0);
    bus.run_until(ms(40), &mut [&mut node]);
    bus.inject(sdo_write(0x1400, 2, 254, 1), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), None);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), None);
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(40, &sdo_ok(0x1400, 2))]));
}

#[test]
fn disabling_a_monitored_rpdo_stops_its_deadline() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.inject(sdo_write(0x1400, 1, 0x8000_0203, 4), &mut [&mut node]);
    assert_eq!(node.poll_timeout(), None);
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(sent(&mut bus), at_ms(&[(0, &sdo_ok(0x1400, 1))]));
}

#[test]
fn two_timed_out_rpdos_share_one_8250_until_both_are_back() {
    let (mut node, mut bus) = booted();
    configure(
        &mut node,
        &mut bus,
        &[(0x1400, 5, 100, 2), (0x1401, 5, 150, 2)],
    );
    start(&mut node, &mut bus);
    sent(&mut bus);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.inject(frame(0x303, &[0, 0, 0, 0]), &mut [&mut node]);
    while node.poll_event().is_some() {}
    bus.run_until(ms(200), &mut [&mut node]);
    assert_eq!(
        events(&mut node),
        [Event::RpdoTimeout { pdo: 0 }, Event::RpdoTimeout { pdo: 1 }]
    );
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    assert!(node.error_active(0x8250), "RPDO2 is still missing");
    bus.inject(frame(0x303, &[0, 0, 0, 0]), &mut [&mut node]);
    assert!(!node.error_active(0x8250));
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (100, "083: 50 82 11 00 00 00 00 00"),
            (200, "083: 00 00 00 00 00 00 00 00"),
        ])
    );
}

#[test]
fn reset_communication_forgets_an_rpdo_timeout() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(100), &mut [&mut node]);
    assert!(node.error_active(0x8250));
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    assert!(!node.error_active(0x8250));
    assert_eq!(node.od().get(0x1001, 0), 0);
    start(&mut node, &mut bus);
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (100, "083: 50 82 11 00 00 00 00 00"),
            (100, "703: 00"),
            (100, "183: 00 00"),
        ])
    );
}

#[test]
fn a_too_short_rpdo_does_not_restart_the_deadline() {
    let (mut node, mut bus) = started_with_rpdo_deadline(100);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.run_until(ms(50), &mut [&mut node]);
    bus.inject(frame(0x203, &[0x34]), &mut [&mut node]);
    bus.run_until(ms(200), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        at_ms(&[
            (50, "083: 10 82 11 01 00 00 00 00"),
            (100, "083: 50 82 11 00 00 00 00 00"),
        ])
    );
}
