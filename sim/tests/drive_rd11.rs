//! The simulated RD11 against its card's manual on the in-memory bus, node-ID 2: the SDO examples
//! of §3.1.4 frame for frame, running by the default RPDO1 with TPDO1 reporting (Table 3.9), and
//! a fault of Table 3.12 with its emergency (§3.1.7).

mod drive_support;

use drive_support::{ms, Bench};
use edsgen_sim::drives::Rd11;

fn booted() -> Bench<Rd11> {
    Bench::booted(Rd11::new(2, ms(0)).expect("node-ID 2"))
}

#[test]
fn sdo_examples_of_section_3_1_4() {
    let mut bench = booted();
    for (request, response) in [
        // 2), 3): F02.02 is 2002h:03. The manual prints 4B for the write's answer; CiA 301
        // answers a download with 60, which this card follows (as the 0x3006 example does).
        (
            [0x40, 0x02, 0x20, 0x03, 0, 0, 0, 0],
            "582: 4B 02 20 03 00 00 00 00",
        ),
        (
            [0x2B, 0x02, 0x20, 0x03, 0x03, 0, 0, 0],
            "582: 60 02 20 03 00 00 00 00",
        ),
        (
            [0x40, 0x02, 0x20, 0x03, 0, 0, 0, 0],
            "582: 4B 02 20 03 03 00 00 00",
        ),
        // 4): C00.26, the inverter's rated voltage, 220 V.
        (
            [0x40, 0x21, 0x20, 0x1B, 0, 0, 0, 0],
            "582: 4B 21 20 1B DC 00 00 00",
        ),
        // 5): 0x3006 is 2030h:07; write 100.
        (
            [0x40, 0x30, 0x20, 0x07, 0, 0, 0, 0],
            "582: 4B 30 20 07 00 00 00 00",
        ),
        (
            [0x2B, 0x30, 0x20, 0x07, 0x64, 0, 0, 0],
            "582: 60 30 20 07 00 00 00 00",
        ),
    ] {
        assert_eq!(bench.send(0, 0x602, &request), [response], "{request:02X?}");
    }
}

/// F01.01 = 3 and F01.02 = 10 by SDO (Table 3.14), then NMT start.
fn take_control(bench: &mut Bench<Rd11>) {
    for request in [
        [0x2B, 0x01, 0x20, 0x02, 0x03, 0, 0, 0],
        [0x2B, 0x01, 0x20, 0x03, 0x0A, 0, 0, 0],
    ] {
        let answer = bench.send(0, 0x602, &request);
        assert_eq!(
            answer,
            [format!("582: 60 01 20 {:02X} 00 00 00 00", request[3])]
        );
    }
    bench.send(0, 0x000, &[0x01, 0x02]);
}

#[test]
fn rpdo1_runs_the_inverter_and_tpdo1_reports_every_100_ms() {
    let mut bench = booted();
    take_control(&mut bench);
    // RPDO1 (Table 3.9): control command 1 (forward), frequency 50.00 Hz, torque 0. The status
    // changes at once (running, accelerating, ready: 0083h), so TPDO1 goes out.
    assert_eq!(
        bench.send(0, 0x202, &[0x01, 0x00, 0x88, 0x13, 0x00, 0x00]),
        ["182: 83 00 00 00 00 00 00 00"]
    );
    let sent = bench.run(10_050);
    let tpdo1: Vec<_> = sent.iter().filter(|(_, f)| f.starts_with("182")).collect();
    assert_eq!(tpdo1.len(), 100);
    // The card samples every 100 ms; bit 14 alternates with each sample. At 5 s, halfway up the
    // 10 s ramp: running, accelerating, ready (0083h), 9.0 A, 25.00 Hz, 750 rpm.
    assert_eq!(tpdo1[0], &(100, "182: 83 40 3C 00 32 00 0F 00".to_string()));
    assert_eq!(
        tpdo1[49],
        &(5_000, "182: 83 00 5A 00 C4 09 EE 02".to_string())
    );
    // At 10 s: running and ready (0081h), 8.0 A, 50.00 Hz, 1500 rpm.
    assert_eq!(
        tpdo1[99],
        &(10_000, "182: 81 00 50 00 88 13 DC 05".to_string())
    );
    // TPDO3: torque 30.0 %, DC bus 308.6 V, motor voltage 220.0 V, module 29.0 °C.
    let tpdo3 = sent
        .iter()
        .rev()
        .find(|(_, f)| f.starts_with("382"))
        .expect("TPDO3");
    assert_eq!(tpdo3, &(10_000, "382: 2C 01 0E 0C 98 08 22 01".to_string()));
    // TPDO2: output power, input voltage 220.0 V, no fault.
    let tpdo2 = sent
        .iter()
        .rev()
        .find(|(_, f)| f.starts_with("282"))
        .expect("TPDO2");
    assert_eq!(tpdo2, &(10_000, "282: 2C 01 98 08 00 00".to_string()));
}

#[test]
fn a_fault_of_table_3_12_sends_its_code_and_resets() {
    let mut bench = booted();
    take_control(&mut bench);
    bench.send(0, 0x202, &[0x01, 0x00, 0x88, 0x13, 0x00, 0x00]);
    bench.run(1_000);
    // 0x0005, overcurrent in acceleration: the emergency code is the fault code, the error
    // register generic and manufacturer-specific (81h), the code again in bytes 3-4.
    bench.drive.inject_fault(ms(1_000), 0x0005);
    let sent: Vec<String> = bench.run(1_000).into_iter().map(|(_, f)| f).collect();
    // Then the TPDOs report it: status fault (0010h), fault code 0005h in TPDO2, the output off.
    assert_eq!(
        sent,
        [
            "082: 05 00 81 05 00 00 00 00",
            "182: 10 00 00 00 00 00 00 00",
            "282: 00 00 98 08 05 00",
            "382: 00 00 26 0C 00 00 FA 00",
        ]
    );
    assert_eq!(bench.drive.vfd().output_frequency(), 0);
    // The cause gone, control command 7 resets: the error-reset emergency, then the status
    // (ready, 0080h, with the heartbeat bit of the sample at 1.1 s) and no fault code.
    bench.drive.remove_fault_cause();
    let sent = bench.send(1_100, 0x202, &[0x07, 0x00, 0x88, 0x13, 0x00, 0x00]);
    assert_eq!(
        sent,
        [
            "082: 00 00 00 00 00 00 00 00",
            "182: 80 40 00 00 00 00 00 00",
            "282: 00 00 98 08 00 00",
        ]
    );
}
