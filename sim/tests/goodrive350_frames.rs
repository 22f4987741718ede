//! The Goodrive350 CANopen card manual's frames (chapter 3), reproduced byte for byte by a device
//! node serving the OD generated from `eds/goodrive350.eds`, node-ID 3, on the virtual bus.
//!
//! Two places where the manual and CiA 301 meet:
//! - Node guarding (§3.4.4): the manual's answers `85` then `05` are those of a node in
//!   operational whose toggle bit is already 1. CiA 301 starts the toggle at 0 after boot-up, so
//!   the master here guards once in pre-operational (`7F`) before starting the node.
//! - 1801h:03 (§3.4.9): CiA 301 forbids changing a PDO's inhibit time while the PDO is valid
//!   (0609 0030), and TPDO2 is valid by default, so the master disables TPDO2 first (1801h:01
//!   bit 31), as the CiA 301 procedure asks; the write and the read back are the manual's frames.
//!   The read back answers `4B` (2 bytes, UNSIGNED16), where the manual prints `43`.

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::{error_register, NmtState, Node};
use edsgen_runtime::{CanFrame, Instant};
use edsgen_sim::cards::goodrive350::{od, Od};

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

/// A frame as the manual prints it: `703: 85`.
fn show(frame: &CanFrame) -> String {
    let id = frame.std_id().unwrap();
    let bytes: Vec<String> = frame.data().iter().map(|b| format!("{b:02X}")).collect();
    format!("{id:03X}: {}", bytes.join(" "))
}

/// What the node sent since the last call, as (ms, text).
fn sent(bus: &mut VirtualBus) -> Vec<(u64, String)> {
    bus.take_log()
        .into_iter()
        .filter(|(_, sender, _)| *sender == 0)
        .map(|(at, _, f)| (at.as_micros() / 1000, show(&f)))
        .collect()
}

fn expect(list: &[(u64, &str)]) -> Vec<(u64, String)> {
    list.iter().map(|(t, s)| (*t, s.to_string())).collect()
}

fn booted() -> (Node<Od>, VirtualBus) {
    let mut node = Node::new(Od::new(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    (node, bus)
}

#[test]
fn boot_up_and_nmt_commands() {
    let (mut node, mut bus) = booted();
    // §3.4.6: after initialisation, node 3 sends its start packet.
    assert_eq!(sent(&mut bus), expect(&[(0, "703: 00")]));
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
    // §3.4.3: start all nodes, then node 3 to pre-operational.
    bus.inject(frame(0x000, &[0x01, 0x00]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::Operational);
    bus.inject(frame(0x000, &[0x80, 0x03]), &mut [&mut node]);
    assert_eq!(node.nmt_state(), NmtState::PreOperational);
}

#[test]
fn node_guarding_answers_85_then_05() {
    let (mut node, mut bus) = booted();
    let guard = CanFrame::remote(0x703, 1);
    bus.inject(guard, &mut [&mut node]);
    bus.inject(frame(0x000, &[0x01, 0x00]), &mut [&mut node]);
    let start = sent(&mut bus);
    assert_eq!(start[..2], expect(&[(0, "703: 00"), (0, "703: 7F")]));
    bus.run_until(ms(10), &mut [&mut node]);
    bus.inject(guard, &mut [&mut node]);
    bus.run_until(ms(20), &mut [&mut node]);
    bus.inject(guard, &mut [&mut node]);
    assert_eq!(sent(&mut bus), expect(&[(10, "703: 85"), (20, "703: 05")]));
}

#[test]
fn heartbeat_every_100_ms_and_disabled_by_sdo() {
    let (mut node, mut bus) = booted();
    assert_eq!(
        node.od().get(od::PRODUCER_HEARTBEAT_TIME),
        0,
        "off by default (§3.4.5)"
    );
    bus.inject(
        frame(0x603, &[0x2B, 0x17, 0x10, 0x00, 0x64, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    bus.inject(frame(0x000, &[0x01, 0x00]), &mut [&mut node]);
    let setup = sent(&mut bus);
    assert_eq!(
        setup[..2],
        expect(&[(0, "703: 00"), (0, "583: 60 17 10 00 00 00 00 00")])
    );
    bus.run_until(ms(300), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        expect(&[(100, "703: 05"), (200, "703: 05"), (300, "703: 05")])
    );
    bus.inject(
        frame(0x603, &[0x2B, 0x17, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    bus.run_until(ms(1000), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        expect(&[(300, "583: 60 17 10 00 00 00 00 00")])
    );
}

#[test]
fn sdo_write_and_read_of_1801h_03() {
    let (mut node, mut bus) = booted();
    sent(&mut bus);
    bus.inject(
        frame(0x603, &[0x23, 0x01, 0x18, 0x01, 0x83, 0x02, 0x00, 0x80]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x603, &[0x2B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x603, &[0x40, 0x01, 0x18, 0x03, 0x00, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        expect(&[
            (0, "583: 60 01 18 01 00 00 00 00"),
            (0, "583: 60 01 18 03 00 00 00 00"),
            (0, "583: 4B 01 18 03 E8 03 00 00"),
        ])
    );
    // While TPDO2 is valid, CiA 301 refuses the change.
    bus.inject(
        frame(0x603, &[0x23, 0x01, 0x18, 0x01, 0x83, 0x02, 0x00, 0x00]),
        &mut [&mut node],
    );
    bus.inject(
        frame(0x603, &[0x2B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        expect(&[
            (0, "583: 60 01 18 01 00 00 00 00"),
            (0, "583: 80 01 18 03 30 00 09 06"),
        ])
    );
}

#[test]
fn sdo_read_of_a_missing_object_aborts_0602_0000() {
    let (mut node, mut bus) = booted();
    sent(&mut bus);
    bus.inject(
        frame(0x603, &[0x40, 0x00, 0x60, 0x00, 0x00, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    assert_eq!(
        sent(&mut bus),
        expect(&[(0, "583: 80 00 60 00 00 00 02 06")])
    );
}

#[test]
fn emergency_for_fault_out1_and_after_its_reset() {
    let (mut node, mut bus) = booted();
    sent(&mut bus);
    // §3.4.8: fault OUT1, emergency code 3000h, error register 04h, VFD error code 1. CiA 301
    // sets the generic bit (bit 0) of the error register whenever any error is active, so the
    // node sends 05h where the manual prints 04h.
    node.raise_error(0x3000, error_register::VOLTAGE, [0x01, 0, 0, 0, 0]);
    bus.run_until(ms(1), &mut [&mut node]);
    node.clear_error(0x3000);
    bus.run_until(ms(2), &mut [&mut node]);
    assert_eq!(
        sent(&mut bus),
        expect(&[
            (0, "083: 00 30 05 01 00 00 00 00"),
            (1, "083: 00 00 00 00 00 00 00 00")
        ])
    );
}
