//! The simulated Goodrive350 (EC-TX105 card) against its manual, chapter 3, frame for frame on the
//! in-memory bus, node-ID 3: the PDO1 parameter protocol (§3.5.2), running at 50.00 Hz by PDO2
//! (§3.5.3/§3.5.4), the error codes of Table 3-16, and a fault with its emergency (§3.4.8).

mod drive_support;

use drive_support::{ms, timed, Bench};
use edsgen_sim::drives::goodrive350::{parameter, Goodrive350};

/// The drive powered up and started (NMT start all, §3.4.3).
fn started() -> Bench<Goodrive350> {
    let mut bench = Bench::booted(Goodrive350::new(3, ms(0)).expect("node-ID 3"));
    bench.send(0, 0x000, &[0x01, 0x00]);
    bench
}

/// PDO1 writes setting up communication control (§3.5.3's example: P00.01 = 2, P00.02 = 1,
/// P00.06 = 9, P15.03 = 1) and the returned values of §3.5.4's (P15.13 = 1, P15.14 = 4), one
/// every 100 ms (PDO1 Tx has an inhibit time).
fn configure(bench: &mut Bench<Goodrive350>) {
    for (i, (request, response)) in [
        ("203: 02 00 01 00 02 00", "183: 01 00 00 00 02 00 00 00"),
        ("203: 02 00 02 00 01 00", "183: 01 00 00 00 01 00 00 00"),
        ("203: 02 00 06 00 09 00", "183: 01 00 00 00 09 00 00 00"),
        ("203: 02 00 03 0F 01 00", "183: 01 00 00 00 01 00 00 00"),
        // §3.5.2.2's example: P15.13 = 1.
        ("203: 02 00 0D 0F 01 00", "183: 01 00 00 00 01 00 00 00"),
        ("203: 02 00 0E 0F 04 00", "183: 01 00 00 00 04 00 00 00"),
    ]
    .into_iter()
    .enumerate()
    {
        let at = 100 * (i as u64 + 1);
        assert_eq!(
            bench.exchange(at, request, at + 1),
            timed(&[(at, response)]),
            "{request}"
        );
    }
}

/// Runs the drive forward at 50.00 Hz by PDO2 at 1 s (§3.5.3's frame) and lets it ramp up.
fn run_at_50_hz(bench: &mut Bench<Goodrive350>) -> Vec<(u64, String)> {
    bench.exchange(1_000, "303: 01 00 00 00 88 13 00 00", 12_000)
}

#[test]
fn pdo1_writes_parameters_as_the_manual_shows() {
    let mut bench = started();
    configure(&mut bench);
    assert_eq!(bench.drive.parameter(parameter::TRANSMITTED_PZD2), Some(1));
    assert_eq!(
        bench.drive.parameter(parameter::FREQUENCY_A_SOURCE),
        Some(9)
    );
}

#[test]
fn pdo2_runs_the_drive_to_50_hz_and_reports_it_as_the_manual_shows() {
    let mut bench = started();
    configure(&mut bench);
    let sent = run_at_50_hz(&mut bench);
    // Status word 0101h (forward running, bus voltage established) at once; then the running
    // frequency and output voltage every 50 ms (TPDO2's inhibit time) while P00.11's 10.0 s
    // ramp runs; the last frame is §3.5.4's, and nothing follows once the drive is steady.
    assert_eq!(sent.len(), 201);
    assert_eq!(sent[0], (1_000, "283: 01 01 00 00 00 00 00 00".to_string()));
    assert_eq!(sent[1], (1_050, "283: 01 01 19 00 01 00 00 00".to_string()));
    // Halfway: 25.00 Hz, 190 V.
    assert_eq!(
        sent[100],
        (6_000, "283: 01 01 C4 09 BE 00 00 00".to_string())
    );
    assert_eq!(
        sent[200],
        (11_000, "283: 01 01 88 13 7C 01 00 00".to_string())
    );
    assert_eq!(bench.drive.vfd().output_frequency(), 5000);
}

#[test]
fn pdo1_refusals_carry_the_error_codes_of_table_3_16() {
    let mut bench = started();
    configure(&mut bench);
    for (at, request, response) in [
        // Read P00.11, acceleration time 1: 10.0 s.
        (
            800,
            "203: 01 00 0B 00 00 00",
            "183: 01 00 00 00 64 00 00 00",
        ),
        // No parameter P99.99: invalid data address.
        (
            900,
            "203: 01 00 63 63 00 00",
            "183: 03 00 02 00 00 00 00 00",
        ),
        // P07.27 (present fault) is read-only.
        (
            1_000,
            "203: 02 00 1B 07 05 00",
            "183: 03 00 07 00 00 00 00 00",
        ),
        // P15.13 takes 0–26: operation failure.
        (
            1_100,
            "203: 02 00 0D 0F 63 00",
            "183: 03 00 04 00 00 00 00 00",
        ),
        // Request code 4 (RAM and EEPROM) is reserved: invalid command.
        (
            1_200,
            "203: 04 00 0B 00 32 00",
            "183: 03 00 01 00 00 00 00 00",
        ),
    ] {
        assert_eq!(
            bench.exchange(at, request, at + 1),
            timed(&[(at, response)]),
            "{request}"
        );
    }
    run_at_50_hz(&mut bench);
    // P00.01 cannot change while the drive runs.
    assert_eq!(
        bench.exchange(12_000, "203: 02 00 01 00 00 00", 12_001),
        timed(&[(12_000, "183: 03 00 08 00 00 00 00 00")])
    );
}

#[test]
fn a_fault_sends_its_emergency_and_resets_once_its_cause_is_gone() {
    let mut bench = started();
    configure(&mut bench);
    run_at_50_hz(&mut bench);
    // §3.4.8: fault OUT1 (type 1): emergency code 3000h, VFD error code 1; the output is cut
    // and the status word says faulty (04h). The manual's error register is 04h (voltage); CiA
    // 301 also sets bit 0 (generic) whenever an error is active, so the card sends 05h.
    bench.drive.inject_fault(ms(12_000), 1);
    assert_eq!(
        bench.run(12_001),
        timed(&[
            (12_000, "083: 00 30 05 01 00 00 00 00"),
            (12_000, "283: 04 01 00 00 00 00 00 00"),
        ])
    );
    // While faulted, parameter writes are refused (01h) and a reset does nothing.
    assert_eq!(
        bench.exchange(12_100, "203: 02 00 0B 00 32 00", 12_101),
        timed(&[(12_100, "183: 03 00 01 00 00 00 00 00")])
    );
    assert_eq!(
        bench.exchange(12_200, "303: 07 00 00 00 88 13 00 00", 12_300),
        []
    );
    // The cause gone, command 7 resets: the error-reset emergency, then "stopped" (03h).
    bench.drive.remove_fault_cause();
    assert_eq!(
        bench.exchange(12_400, "303: 07 00 00 00 88 13 00 00", 12_500),
        timed(&[
            (12_400, "083: 00 00 00 00 00 00 00 00"),
            (12_400, "283: 03 01 00 00 00 00 00 00"),
        ])
    );
    // P07.28, type of last fault, remembers OUT1.
    assert_eq!(
        bench.exchange(12_600, "203: 01 00 1C 07 00 00", 12_601),
        timed(&[(12_600, "183: 01 00 00 00 01 00 00 00")])
    );
}

#[test]
fn sdo_control_and_monitoring_as_the_manual_shows() {
    let mut bench = started();
    // Communication control (P00.01 = 2, P00.02 = 1, P00.06 = 9), setting 1 as the frequency
    // (P15.02 = 1), returned value 1 the running frequency (P15.13 = 1), by PDO1.
    for (i, (request, response)) in [
        ("203: 02 00 01 00 02 00", "183: 01 00 00 00 02 00 00 00"),
        ("203: 02 00 02 00 01 00", "183: 01 00 00 00 01 00 00 00"),
        ("203: 02 00 06 00 09 00", "183: 01 00 00 00 09 00 00 00"),
        ("203: 02 00 02 0F 01 00", "183: 01 00 00 00 01 00 00 00"),
        ("203: 02 00 0D 0F 01 00", "183: 01 00 00 00 01 00 00 00"),
    ]
    .into_iter()
    .enumerate()
    {
        let at = 100 * (i as u64 + 1);
        assert_eq!(
            bench.exchange(at, request, at + 1),
            timed(&[(at, response)])
        );
    }
    // §3.6's SDO frames: 2100h:03 (setting 1) = 5000, then 2101h:00 (CW) = 1, run forward.
    let sdo = |sent: Vec<(u64, String)>| -> Vec<String> {
        sent.into_iter()
            .map(|(_, f)| f)
            .filter(|f| f.starts_with("583"))
            .collect()
    };
    assert_eq!(
        sdo(bench.exchange(1_000, "603: 2B 00 21 03 88 13 00 00", 1_000)),
        ["583: 60 00 21 03 00 00 00 00"]
    );
    assert_eq!(
        sdo(bench.exchange(1_000, "603: 2B 01 21 00 01 00 00 00", 1_000)),
        ["583: 60 01 21 00 00 00 00 00"]
    );
    // After P00.11's 10 s ramp: SW 2001h:00 reads 0101h (running forward, bus voltage
    // established) and returned value 1 (2000h:03) 5000, 50.00 Hz: the manual's answers.
    assert_eq!(
        sdo(bench.exchange(11_000, "603: 40 01 20 00 00 00 00 00", 11_000)),
        ["583: 4B 01 20 00 01 01 00 00"]
    );
    assert_eq!(
        sdo(bench.exchange(11_000, "603: 40 00 20 03 00 00 00 00", 11_000)),
        ["583: 4B 00 20 03 88 13 00 00"]
    );
}
