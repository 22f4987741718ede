//! The drive against the manual: §2.6's PKW examples byte-exact, each CW command and SW state,
//! the refusals of Table 2-11, both parameter numberings, the timeout faults.

use super::*;
use edsgen_runtime::pkw_pzd::control::cw_bit;

const BE: ByteOrder = ByteOrder::BigEndian;

fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

/// A master's image as 32 big-endian bytes: PKW1–PKW4, the CW, then PZD2.
fn output(pkw: [u16; 4], cw: u16, pzd2: u16) -> [u8; IMAGE_BYTES] {
    let mut words = [0u16; 16];
    words[..4].copy_from_slice(&pkw);
    words[4] = cw;
    words[5] = pzd2;
    BE.image_bytes(&words)
}

fn cw(command: Command) -> u16 {
    ControlWord::new(command, WordLayout::ByByte).0
}

/// §2.6 example 1: the manual prints request "00 01 | 00 10 | 00 00 | 00 00" and response
/// "00 01 | 00 10 | 00 00 | 50 00" in decimal: task 1 at address 10 (P00.10, keypad frequency)
/// answered with response 1 and 5000 (50.00 Hz). On the wire, big-endian:
/// request 00 01 00 0A 00 00 00 00, response 00 01 00 0A 00 00 13 88.
#[test]
fn example_1_reads_the_keypad_frequency() {
    let mut drive = PkwPzdDrive::new(Bus::ProfibusDp, ms(0));
    let request = output([1, 10, 0, 0], 0, 0);
    assert_eq!(
        request[..8],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00]
    );
    let response = drive.exchange_bytes(ms(10), &request, BE);
    assert_eq!(
        response[..8],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88]
    );
    // SW: stopped (3), ready (bit 8), keypad control: 0103h.
    assert_eq!(response[8..10], [0x01, 0x03]);
}

/// §2.6 example 2: request "00 04 | 00 10 | 00 00 | 50 00" (task 4, write RAM and EEPROM,
/// address 10, 5000 = 50.00 Hz), response "00 01 | 00 10 | 00 00 | 50 00". On the wire:
/// 00 04 00 0A 00 00 13 88 and 00 01 00 0A 00 00 13 88. CW bit 8 enables the write.
#[test]
fn example_2_writes_the_keypad_frequency() {
    let mut drive = PkwPzdDrive::new(Bus::ProfibusDp, ms(0));
    assert_eq!(
        drive.set_parameter(parameter::KEYPAD_FREQUENCY, 1234),
        Ok(())
    );
    let request = output([4, 10, 0, 5000], cw_bit::ENABLE_WRITE, 0);
    assert_eq!(
        request[..8],
        [0x00, 0x04, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88]
    );
    let response = drive.exchange_bytes(ms(10), &request, BE);
    assert_eq!(
        response[..8],
        [0x00, 0x01, 0x00, 0x0A, 0x00, 0x00, 0x13, 0x88]
    );
    assert_eq!(drive.parameter(parameter::KEYPAD_FREQUENCY), Some(5000));
}

#[test]
fn refused_requests_carry_table_2_11_error_numbers() {
    let mut drive = PkwPzdDrive::bus_controlled(Bus::ProfibusDp, ms(0));
    let enable = cw_bit::ENABLE_WRITE;
    let cases: [([u16; 4], u16, [u8; 8]); 7] = [
        // Write P07.27 (present fault, read-only): response 3, error 7.
        ([4, 0x071B, 0, 1], enable, [0, 3, 0x07, 0x1B, 0, 7, 0, 0]),
        // Write without CW bit 8: error 1.
        ([4, 10, 0, 4000], 0, [0, 3, 0, 0x0A, 0, 1, 0, 0]),
        // Task 2 (RAM only, "not supported currently"): error 1.
        ([2, 10, 0, 4000], enable, [0, 3, 0, 0x0A, 0, 1, 0, 0]),
        // Undefined task 6: error 1.
        ([6, 10, 0, 4000], enable, [0, 3, 0, 0x0A, 0, 1, 0, 0]),
        // Beyond P15.13's range 0–31: error 3.
        ([4, 0x0F0D, 0, 32], enable, [0, 3, 0x0F, 0x0D, 0, 3, 0, 0]),
        // A value beyond one word: error 3.
        ([4, 10, 1, 0], enable, [0, 3, 0, 0x0A, 0, 3, 0, 0]),
        // No parameter at 0x7777: error 2.
        ([1, 0x7777, 0, 0], 0, [0, 3, 0x77, 0x77, 0, 2, 0, 0]),
    ];
    for (n, (pkw, control, expected)) in cases.iter().enumerate() {
        let response = drive.exchange_bytes(ms(10 * n as u64), &output(*pkw, *control, 0), BE);
        assert_eq!(response[..8], *expected, "case {n}");
    }
    // While running, P00.01 (stopped only) refuses with 8.
    drive.exchange_bytes(ms(100), &output([0; 4], cw(Command::RunForward), 1000), BE);
    let response = drive.exchange_bytes(
        ms(110),
        &output([4, 1, 0, 0], cw(Command::RunForward) | enable, 1000),
        BE,
    );
    assert_eq!(response[..8], [0, 3, 0, 1, 0, 8, 0, 0]);
    // Task 0 answers "no response".
    let response =
        drive.exchange_bytes(ms(120), &output([0; 4], cw(Command::RunForward), 1000), BE);
    assert_eq!(response[..8], [0; 8]);
}

#[test]
fn a_write_runs_once_per_new_request() {
    let mut drive = PkwPzdDrive::new(Bus::ProfibusDp, ms(0));
    let request = output([4, 10, 0, 3000], cw_bit::ENABLE_WRITE, 0);
    drive.exchange_bytes(ms(0), &request, BE);
    // The keypad changes it; the same request held again does not write again.
    assert_eq!(
        drive.set_parameter(parameter::KEYPAD_FREQUENCY, 100),
        Ok(())
    );
    let response = drive.exchange_bytes(ms(10), &request, BE);
    assert_eq!(response[..8], [0, 1, 0, 0x0A, 0, 0, 0x0B, 0xB8]);
    assert_eq!(drive.parameter(parameter::KEYPAD_FREQUENCY), Some(100));
}

/// Each command of Table 2-5 and the state of Table 2-7 it leads to.
#[test]
fn commands_and_states() {
    let mut drive = PkwPzdDrive::bus_controlled(Bus::ProfibusDp, ms(0));
    let sw = |image: [u8; IMAGE_BYTES]| u16::from_be_bytes([image[8], image[9]]);
    let pzd2 = |image: [u8; IMAGE_BYTES]| u16::from_be_bytes([image[10], image[11]]);
    // Stopped, ready, communication control: 4103h.
    let image = drive.exchange_bytes(ms(0), &output([0; 4], 0, 2500), BE);
    assert_eq!(sw(image), 0x4103);
    // Run forward (CW 1) towards 25.00 Hz on the 10 s ramp: 1.00 s later 5.00 Hz.
    drive.exchange_bytes(ms(0), &output([0; 4], cw(Command::RunForward), 2500), BE);
    let image = drive.exchange_bytes(ms(1000), &output([0; 4], cw(Command::RunForward), 2500), BE);
    assert_eq!((sw(image), pzd2(image)), (0x4101, 500));
    // Decelerate to stop (5): on the ramp, then stopped.
    drive.exchange_bytes(
        ms(1000),
        &output([0; 4], cw(Command::DecelerateToStop), 2500),
        BE,
    );
    let image = drive.exchange_bytes(
        ms(1500),
        &output([0; 4], cw(Command::DecelerateToStop), 2500),
        BE,
    );
    assert_eq!((sw(image), pzd2(image)), (0x4101, 250));
    let image = drive.exchange_bytes(
        ms(3000),
        &output([0; 4], cw(Command::DecelerateToStop), 2500),
        BE,
    );
    assert_eq!((sw(image), pzd2(image)), (0x4103, 0));
    // Run reverse (2): state 2.
    drive.exchange_bytes(ms(3000), &output([0; 4], cw(Command::RunReverse), 2500), BE);
    let image = drive.exchange_bytes(ms(4000), &output([0; 4], cw(Command::RunReverse), 2500), BE);
    assert_eq!((sw(image), pzd2(image)), (0x4102, 500));
    // Coast (6): output cut at once.
    let image = drive.exchange_bytes(
        ms(4000),
        &output([0; 4], cw(Command::CoastToStop), 2500),
        BE,
    );
    assert_eq!((sw(image), pzd2(image)), (0x4103, 0));
    // Jog forward (3) at 5.00 Hz whatever PZD2 says, stop jogging (8).
    drive.exchange_bytes(ms(4000), &output([0; 4], cw(Command::JogForward), 2500), BE);
    let image = drive.exchange_bytes(ms(6000), &output([0; 4], cw(Command::JogForward), 2500), BE);
    assert_eq!((sw(image), pzd2(image)), (0x4101, 500));
    drive.exchange_bytes(
        ms(6000),
        &output([0; 4], cw(Command::StopJogging), 2500),
        BE,
    );
    let image = drive.exchange_bytes(
        ms(8000),
        &output([0; 4], cw(Command::StopJogging), 2500),
        BE,
    );
    assert_eq!((sw(image), pzd2(image)), (0x4103, 0));
    // Jog reverse (4).
    drive.exchange_bytes(ms(8000), &output([0; 4], cw(Command::JogReverse), 0), BE);
    let image = drive.exchange_bytes(ms(10000), &output([0; 4], cw(Command::JogReverse), 0), BE);
    assert_eq!(sw(image), 0x4102);
    // A fault (state 4), a reset (7) refused while its cause lasts, accepted after.
    drive.inject_fault(ms(10000), 2);
    let image = drive.exchange_bytes(
        ms(10000),
        &output([1, 0x071B, 0, 0], cw(Command::FaultReset), 0),
        BE,
    );
    assert_eq!(sw(image), 0x4104);
    assert_eq!(image[..8], [0, 1, 0x07, 0x1B, 0, 0, 0, 2]);
    drive.remove_fault_cause();
    drive.exchange_bytes(ms(10010), &output([0; 4], 0, 0), BE);
    let image = drive.exchange_bytes(ms(10020), &output([0; 4], cw(Command::FaultReset), 0), BE);
    assert_eq!(sw(image), 0x4103);
    assert_eq!(drive.parameter(parameter::LAST_FAULT), Some(2));
    // Heartbeat: SW bit 15 echoes CW bit 15.
    let image = drive.exchange_bytes(ms(10030), &output([0; 4], 0x8000, 0), BE);
    assert_eq!(sw(image), 0xC103);
}

/// The bus's watchdog trips E-DP (29); the cause goes with the next exchange, a reset clears.
#[test]
fn the_dp_watchdog_trips_e_dp() {
    let mut drive = PkwPzdDrive::bus_controlled(Bus::ProfibusDp, ms(0));
    drive.exchange_bytes(ms(0), &output([0; 4], cw(Command::RunForward), 5000), BE);
    drive.communication_lost(ms(500));
    assert_eq!(drive.vfd().fault(), Some(29));
    assert_eq!(Bus::ProfibusDp.fault_name(), "E-DP");
    assert_eq!(drive.parameter(parameter::PRESENT_FAULT), Some(29));
    let image = drive.exchange_bytes(ms(600), &output([0; 4], 0, 0), BE);
    assert_eq!(image[8..10], [0x41, 0x04]);
    assert_eq!(image[10..12], [0, 0]);
    drive.exchange_bytes(ms(610), &output([0; 4], cw(Command::FaultReset), 0), BE);
    assert_eq!(drive.vfd().fault(), None);
}

/// P15.25 / P16.31 / P16.54 in 0.1 s: no exchange for that long trips the bus's fault.
#[test]
fn the_timeout_parameters_trip_each_bus_fault() {
    for (bus, fault) in [
        (Bus::ProfibusDp, 29),
        (Bus::Profinet, 57),
        (Bus::EthernetIp, 70),
    ] {
        let mut drive = PkwPzdDrive::bus_controlled(bus, ms(0));
        assert_eq!(drive.set_parameter(bus.timeout_parameter(), 10), Ok(()));
        assert_eq!(
            drive.poll_timeout(),
            None,
            "{bus:?}: no exchange yet, no watchdog"
        );
        drive.exchange_bytes(ms(100), &output([0; 4], 0, 0), BE);
        assert_eq!(drive.poll_timeout(), Some(ms(1100)));
        drive.handle_timeout(ms(1099));
        assert_eq!(drive.vfd().fault(), None);
        drive.handle_timeout(ms(1100));
        assert_eq!(drive.vfd().fault(), Some(fault), "{bus:?}");
    }
    assert_eq!(Bus::Profinet.fault_name(), "E-PN");
    assert_eq!(Bus::EthernetIp.fault_name(), "E-EIP");
}

/// PROFINET and EtherNet/IP take their PZD meanings from P16.32–P16.53, DP from P15.02–P15.23.
#[test]
fn each_bus_has_its_own_pzd_parameters() {
    let mut pn = PkwPzdDrive::new(Bus::Profinet, ms(0));
    for (address, value) in [
        (0x0001, 2),
        (0x0002, 3),
        (0x0006, 13),
        (0x1021, 1),
        (0x102C, 2),
    ] {
        assert_eq!(pn.set_parameter(address, value), Ok(()));
    }
    // Received PZD3 (P16.33) is the set frequency; transmitted PZD3 (P16.44) shows it.
    let mut words = [0u16; 16];
    words[6] = 3000;
    let image = pn.exchange_bytes(ms(0), &BE.image_bytes(&words), BE);
    assert_eq!(image[12..14], [0x0B, 0xB8]);
    // DP ignores P16.xx: its P15.03 is still 0.
    let mut dp = PkwPzdDrive::new(Bus::ProfibusDp, ms(0));
    assert_eq!(dp.set_parameter(0x102C, 2), Ok(()));
    let image = dp.exchange_bytes(ms(0), &BE.image_bytes(&words), BE);
    assert_eq!(image[12..14], [0, 0]);
}

/// EtherNet/IP with P16.56 = 1: CW and SW by bit (Tables 5-6, 5-9), little-endian if asked.
#[test]
fn ethernet_ip_by_bit() {
    let mut drive = PkwPzdDrive::bus_controlled(Bus::EthernetIp, ms(0));
    assert_eq!(drive.layout(), WordLayout::ByByte);
    assert_eq!(drive.set_parameter(parameter::EIP_WORD_LAYOUT, 1), Ok(()));
    assert_eq!(drive.layout(), WordLayout::ByBit);
    let le = ByteOrder::LittleEndian;
    let mut words = [0u16; 16];
    words[4] = 0x03; // no action
    words[5] = 1000;
    let image = drive.exchange_bytes(ms(0), &le.image_bytes(&words), le);
    // Stopped is bit 2: 04h; ready and communication control: 4104h, low byte first.
    assert_eq!(image[8..10], [0x04, 0x41]);
    words[4] = 0x01; // run forward
    drive.exchange_bytes(ms(0), &le.image_bytes(&words), le);
    let image = drive.exchange_bytes(ms(500), &le.image_bytes(&words), le);
    assert_eq!(image[8..10], [0x01, 0x41]);
    assert_eq!(image[10..12], 250u16.to_le_bytes());
}

#[test]
fn the_parameter_table_is_sorted() {
    assert!(PARAMETERS.windows(2).all(|w| w[0].address < w[1].address));
}

#[test]
fn fault_changes_are_reported_once_and_the_bus_fault_never() {
    let mut drive = PkwPzdDrive::bus_controlled(Bus::Profinet, ms(0));
    assert_eq!(drive.poll_fault_change(), None);
    drive.inject_fault(ms(10), 4);
    assert_eq!(drive.poll_fault_change(), Some(FaultChange::Appears(4)));
    assert_eq!(drive.poll_fault_change(), None);
    // A new connection hears of the present fault again.
    drive.forget_reported_fault();
    assert_eq!(drive.poll_fault_change(), Some(FaultChange::Appears(4)));
    // E-PN is the bus's own: reported by the bus, not as a fault change.
    let mut lost = PkwPzdDrive::bus_controlled(Bus::Profinet, ms(0));
    lost.communication_lost(ms(10));
    assert_eq!(lost.vfd().fault(), Some(57));
    assert_eq!(lost.poll_fault_change(), None);
}
