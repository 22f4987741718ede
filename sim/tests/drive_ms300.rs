//! The simulated MS300 against chapter 15 of its manual on the in-memory bus, node-ID 3: the
//! three control modes of §15-3-1 (DS402, Delta's old and new definitions) by SDO, and a fault of
//! §15-5 with its emergency and reset.

mod drive_support;

use drive_support::{ms, Bench};
use edsgen_sim::drives::ms300::ControlMode;
use edsgen_sim::drives::Ms300;

/// Powered up, with Pr. 00-21 = 3 and Pr. 00-20 = 6 (CANopen commands and frequency).
fn booted() -> Bench<Ms300> {
    let mut bench = Bench::booted(Ms300::new(3, ms(0)).expect("node-ID 3"));
    bench.write(0, 0x2000, 22, 3);
    bench.write(0, 0x2000, 21, 6);
    bench
}

impl Bench<Ms300> {
    /// Frames the drive sent for an SDO request at `at`.
    fn request(&mut self, at: u64, data: [u8; 8]) -> Vec<String> {
        self.send(at, 0x603, &data)
    }

    /// An expedited 2-byte write, which must succeed.
    fn write(&mut self, at: u64, index: u16, sub: u8, value: u16) {
        let [i0, i1] = index.to_le_bytes();
        let [v0, v1] = value.to_le_bytes();
        let answer = self.sdo(at, 3, [0x2B, i0, i1, sub, v0, v1, 0, 0]);
        assert_eq!(
            answer,
            [0x60, i0, i1, sub, 0, 0, 0, 0],
            "{index:04X}h:{sub}"
        );
    }

    /// An upload of a 2-byte value.
    fn read(&mut self, at: u64, index: u16, sub: u8) -> u16 {
        let [i0, i1] = index.to_le_bytes();
        let answer = self.sdo(at, 3, [0x40, i0, i1, sub, 0, 0, 0, 0]);
        assert_eq!(answer[..4], [0x4B, i0, i1, sub], "a 2-byte upload");
        u16::from_le_bytes([answer[4], answer[5]])
    }
}

#[test]
fn ds402_is_the_factory_mode_and_runs_the_speed_mode_of_15_3_2_3() {
    let mut bench = booted();
    assert_eq!(bench.drive.control_mode(), ControlMode::Ds402);
    // 6060h = 2 (speed mode), 6042h = 900 rpm, 6040h = 0Eh then 0Fh, then the speed-mode bits
    // 4–6 (7Fh): the ramp (604Fh: 10 s to 1800 rpm) reaches 900 rpm after 5 s.
    bench.request(0, [0x2F, 0x60, 0x60, 0, 2, 0, 0, 0]);
    bench.write(0, 0x6042, 0, 900);
    bench.write(0, 0x6040, 0, 0x0E);
    bench.write(0, 0x6040, 0, 0x0F);
    bench.write(0, 0x6040, 0, 0x7F);
    assert_eq!(bench.read(2_500, 0x6044, 0), 450);
    assert_eq!(bench.read(5_000, 0x6044, 0), 900);
    // 6041h: operation enabled (0237h) with bit 10, target reached.
    assert_eq!(bench.read(5_000, 0x6041, 0), 0x0637);
}

#[test]
fn delta_old_definition_runs_by_2020h_and_reports_in_2021h() {
    let mut bench = booted();
    bench.write(0, 0x2009, 41, 0); // Pr. 09-40 = 0: Delta standard
    bench.write(0, 0x2009, 31, 0); // Pr. 09-30 = 0: old definition
    assert_eq!(bench.drive.control_mode(), ControlMode::DeltaOld);
    // §15-3-3-2: 2020h:02 = 600 (60.0 Hz), 2020h:01 = 0002h runs.
    bench.write(0, 0x2020, 2, 600);
    bench.write(0, 0x2020, 1, 0x0002);
    // 10 s from 0 to 60 Hz: 30.00 Hz at 5 s (2021h:04 in 0.01 Hz).
    assert_eq!(bench.read(5_000, 0x2021, 4), 3000);
    assert_eq!(bench.read(10_000, 0x2021, 4), 6000);
    // Status: in operation (11b), forward, frequency and commands by communication (bits 8, 10).
    assert_eq!(bench.read(10_000, 0x2021, 2), 0x0503);
    // 0001h stops on the ramp: decelerating to stop (01b), then stopped.
    bench.write(10_000, 0x2020, 1, 0x0001);
    assert_eq!(bench.read(15_000, 0x2021, 2), 0x0501);
    assert_eq!(bench.read(20_000, 0x2021, 2), 0x0500);
}

#[test]
fn delta_new_definition_runs_by_2060h_and_a_fault_of_15_5_resets() {
    let mut bench = booted();
    bench.write(0, 0x2009, 41, 0);
    bench.write(0, 0x2009, 31, 1); // Pr. 09-30 = 1: new definition
    assert_eq!(bench.drive.control_mode(), ControlMode::DeltaNew);
    // §15-3-4-2: 2060h:03 = 500 (50.0 Hz); 2060h:01 = 0081h (power on, ack) runs.
    bench.write(0, 0x2060, 3, 500);
    bench.write(0, 0x2060, 1, 0x0081);
    // 50 Hz of 60 Hz in 10 s: reached after 8.33 s. 2061h:01 arrive + power on; 2061h:03 in
    // 0.1 Hz.
    assert_eq!(bench.read(9_000, 0x2061, 1), 0x0081);
    assert_eq!(bench.read(9_000, 0x2061, 3), 500);
    // ocA, over-current during acceleration: emergency 2213h, register bit 1 (current) and the
    // generic bit, fault code 1.
    bench
        .drive
        .raise_fault(ms(9_100), "ocA")
        .expect("ocA is in 15-5");
    let sent = bench.frames_until(9_100);
    assert!(
        sent.contains(&"083: 13 22 03 01 00 00 00 00".to_string()),
        "{sent:?}"
    );
    assert_eq!(bench.read(9_100, 0x603F, 0), 0x2213);
    assert_eq!(bench.read(9_100, 0x2021, 1), 1);
    assert_eq!(bench.read(9_100, 0x2061, 1) & 0x0008, 0x0008);
    // The cause gone, RST (bit 15) clears the fault: the error-reset emergency.
    bench.drive.remove_fault_cause();
    let sent = bench.request(9_200, [0x2B, 0x60, 0x20, 1, 0x81, 0x80, 0, 0]);
    assert_eq!(
        sent,
        [
            "083: 00 00 00 00 00 00 00 00",
            "583: 60 60 20 01 00 00 00 00"
        ]
    );
    assert_eq!(bench.read(9_200, 0x603F, 0), 0);
}
