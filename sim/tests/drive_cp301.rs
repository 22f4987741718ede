//! The simulated CP301 against its manual on the in-memory bus, node-ID 3: the velocity-mode
//! sequence of §5.3 with the ramps running on their own, the output voltage in 2D02h:06 (§6.3),
//! an alarm of §7 with its emergency and 603Fh, and 6007h on heartbeat loss.

mod drive_support;

use drive_support::{ms, Bench};
use edsgen_runtime::cia402::State;
use edsgen_sim::drives::Cp301;

const NODE: u8 = 3;

fn booted() -> Bench<Cp301> {
    Bench::booted(Cp301::new(NODE, ms(0)).expect("node-ID 3"))
}

const READ_STATUSWORD: [u8; 8] = [0x40, 0x41, 0x60, 0, 0, 0, 0, 0];
const READ_ACTUAL: [u8; 8] = [0x40, 0x44, 0x60, 0, 0, 0, 0, 0];
const READ_OUTPUT_VOLTAGE: [u8; 8] = [0x40, 0x02, 0x2D, 0x06, 0, 0, 0, 0];

/// §5.3: 6042h = 1500 rpm, 604Fh = 5000 ms, 6050h = 10000 ms, 6040h = 06h, 07h, 0Fh, 7Fh at 0.
fn start_velocity_mode(bench: &mut Bench<Cp301>) {
    for request in [
        [0x2B, 0x42, 0x60, 0, 0xDC, 0x05, 0, 0],
        [0x23, 0x4F, 0x60, 0, 0x88, 0x13, 0, 0],
        [0x23, 0x50, 0x60, 0, 0x10, 0x27, 0, 0],
        [0x2B, 0x40, 0x60, 0, 0x06, 0, 0, 0],
        [0x2B, 0x40, 0x60, 0, 0x07, 0, 0, 0],
        [0x2B, 0x40, 0x60, 0, 0x0F, 0, 0, 0],
        [0x2B, 0x40, 0x60, 0, 0x7F, 0, 0, 0],
    ] {
        let response = bench.sdo(0, NODE, request);
        assert_eq!(response[..4], [0x60, request[1], request[2], request[3]]);
    }
}

#[test]
fn velocity_mode_ramps_by_itself_and_the_monitor_follows() {
    let mut bench = booted();
    start_velocity_mode(&mut bench);
    // 604Fh is the time to 1500 rpm: 300 rpm/s. At 2.5 s: 750 rpm, 190 V.
    assert_eq!(
        bench.sdo(2_500, NODE, READ_ACTUAL),
        [0x4B, 0x44, 0x60, 0, 0xEE, 0x02, 0, 0]
    );
    assert_eq!(
        bench.sdo(2_500, NODE, READ_OUTPUT_VOLTAGE),
        [0x4B, 0x02, 0x2D, 0x06, 0xBE, 0, 0, 0]
    );
    assert_eq!(
        bench.sdo(2_500, NODE, READ_STATUSWORD),
        [0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0]
    );
    // At 5 s: 1500 rpm, 380 V, target reached.
    assert_eq!(
        bench.sdo(5_000, NODE, READ_ACTUAL),
        [0x4B, 0x44, 0x60, 0, 0xDC, 0x05, 0, 0]
    );
    assert_eq!(
        bench.sdo(5_000, NODE, READ_OUTPUT_VOLTAGE),
        [0x4B, 0x02, 0x2D, 0x06, 0x7C, 0x01, 0, 0]
    );
    assert_eq!(
        bench.sdo(5_000, NODE, READ_STATUSWORD),
        [0x4B, 0x41, 0x60, 0, 0x37, 0x06, 0, 0]
    );
    // -1500 reverses: 10 s down on 6050h, then 5 s up.
    bench.sdo(5_000, NODE, [0x2B, 0x42, 0x60, 0, 0x24, 0xFA, 0, 0]);
    assert_eq!(
        bench.sdo(15_000, NODE, READ_ACTUAL),
        [0x4B, 0x44, 0x60, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        bench.sdo(20_000, NODE, READ_ACTUAL),
        [0x4B, 0x44, 0x60, 0, 0x24, 0xFA, 0, 0]
    );
}

#[test]
fn an_alarm_of_table_7_sends_its_emergency_and_resets() {
    let mut bench = booted();
    start_velocity_mode(&mut bench);
    bench.run(5_000);
    // OC2, overcurrent at constant speed: 2214h, error register bit 1 (current) and bit 0
    // (generic, set with any error).
    bench
        .drive
        .raise_alarm(ms(5_000), "OC2")
        .expect("OC2 is in table 7");
    assert_eq!(bench.frames_until(5_000), ["083: 14 22 03 00 00 00 00 00"]);
    assert_eq!(
        bench.sdo(5_000, NODE, [0x40, 0x3F, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x3F, 0x60, 0, 0x14, 0x22, 0, 0]
    );
    // The fault reaction (605Eh: quick-stop ramp, 1 s from 1500 rpm), then fault.
    assert_eq!(
        bench.sdo(5_000, NODE, READ_STATUSWORD),
        [0x4B, 0x41, 0x60, 0, 0x1F, 0x02, 0, 0]
    );
    assert_eq!(
        bench.sdo(6_000, NODE, READ_STATUSWORD),
        [0x4B, 0x41, 0x60, 0, 0x18, 0x06, 0, 0]
    );
    // A reset while the cause is present does nothing; once it is gone, 6040h bit 7 rising
    // clears the fault and the emergency.
    bench.sdo(6_100, NODE, [0x2B, 0x40, 0x60, 0, 0x80, 0, 0, 0]);
    assert_eq!(bench.drive.drive().state(), State::Fault);
    bench.drive.remove_alarm_cause();
    bench.sdo(6_200, NODE, [0x2B, 0x40, 0x60, 0, 0x00, 0, 0, 0]);
    let sent = bench.send(6_300, 0x603, &[0x2B, 0x40, 0x60, 0, 0x80, 0, 0, 0]);
    // The error-reset emergency wins arbitration over the SDO response (083h before 583h).
    assert_eq!(
        sent,
        [
            "083: 00 00 00 00 00 00 00 00",
            "583: 60 40 60 00 00 00 00 00"
        ]
    );
    assert_eq!(
        bench.sdo(6_300, NODE, READ_STATUSWORD),
        [0x4B, 0x41, 0x60, 0, 0x50, 0x06, 0, 0]
    );
    assert_eq!(
        bench.drive.raise_alarm(ms(7_000), "XYZ").map_err(|e| e.0),
        Err("XYZ".to_string())
    );
}

#[test]
fn heartbeat_loss_disables_voltage_as_6007h_says() {
    let mut bench = booted();
    // 1016h:01: consume node 1's heartbeat every 100 ms; node 1 beats once at 0.
    assert_eq!(
        bench.sdo(0, NODE, [0x23, 0x16, 0x10, 0x01, 0x64, 0x00, 0x01, 0x00]),
        [0x60, 0x16, 0x10, 0x01, 0, 0, 0, 0]
    );
    start_velocity_mode(&mut bench);
    bench.send(0, 0x701, &[0x05]);
    // At 100 ms the heartbeat is lost: EMCY 8130h (manufacturer byte 0: node 1), and 6007h = 2
    // (the CP301's default): disable voltage, switch on disabled, the output cut.
    assert_eq!(bench.frames_until(200), ["083: 30 81 11 01 00 00 00 00"]);
    assert_eq!(bench.drive.drive().state(), State::SwitchOnDisabled);
    assert_eq!(
        bench.sdo(200, NODE, READ_ACTUAL),
        [0x4B, 0x44, 0x60, 0, 0, 0, 0, 0]
    );
    // The heartbeat returns: the error-reset emergency.
    assert_eq!(
        bench.send(300, 0x701, &[0x05]),
        ["083: 00 00 00 00 00 00 00 00"]
    );
}
