//! `eds/hd1e.eds` (HD1-E CANopen card) checked against its manual fragment (seed 004, section
//! 8.2.2 and Tables 19-21): the PDO1 parameter-access objects and mappings, the frame layout of
//! PDO1 Rx/Tx, the model dump (snapshot), and the validator's verdict.

mod card_support;

use card_support::{
    above_info, check_rows, decode, dump, integer_default, is_dummy, key_line, read, row,
    warnings_and_errors, DefaultValue, Finding, Row,
};
use edsgen_model::diag::Severity;
use edsgen_model::model::{AccessType, BasicType, Device};

use AccessType::{Ro, Rw};
use BasicType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use DefaultValue::{Absent, Int, NodeId};

/// The EDS under test, relative to the package root.
const EDS: &str = "eds/hd1e.eds";

#[rustfmt::skip]
const ROWS: &[Row] = &[
    row(0x2000, 0, U16, Ro, Absent, true, "8.2.2: response code 0x2000.00"),
    row(0x2000, 1, U16, Ro, Absent, true, "8.2.2: error code 0x2000.01"),
    row(0x2000, 2, U16, Ro, Absent, true, "8.2.2: response data 0x2000.02"),
    row(0x2100, 0, U16, Rw, Absent, true, "PDO1 Rx request code (seed 002 3.5.2.1)"),
    row(0x2100, 1, U16, Rw, Absent, true, "p. 15: parameter address, 2 bytes"),
    row(0x2100, 2, U16, Rw, Absent, true, "p. 15: request data, Byte4-Byte5"),
    row(0x1800, 1, U32, Rw, NodeId(0x180), false, "8.2.2: 0x180+NODEID"),
    row(0x1800, 2, U8, Rw, Int(255), false, "PDO1 Tx supports type 255 only"),
    row(0x1800, 3, U16, Rw, Int(500), false, "inhibit ('disabled') time 500"),
    row(0x1800, 5, U16, Rw, Int(0), false, "event timer 0"),
    row(0x1400, 1, U32, Rw, NodeId(0x200), false, "PDO1 Rx 0x200+NODEID"),
    row(0x1400, 2, U8, Rw, Int(255), false, "PDO1 Rx event-driven"),
    row(0x1014, 0, U32, Ro, NodeId(0x80), false, "p. 15: the card sends EMCY"),
    row(0x1017, 0, U16, Rw, Int(0), false, "full manual: heartbeat producer"),
    row(0x1018, 1, U32, Ro, Int(0), false, "no vendor-ID assigned: 0"),
    row(0x1200, 1, U32, Ro, NodeId(0x600), false, "SDO server"),
];

#[test]
fn objects_match_the_fragment() {
    check_rows(&read(EDS).device, ROWS);
}

#[test]
fn only_the_pdo1_pair_is_described() {
    let device = read(EDS).device;
    let indices: Vec<u16> = device.objects.keys().copied().collect();
    assert_eq!(
        indices,
        [
            0x1000, 0x1001, 0x1014, 0x1017, 0x1018, 0x1200, 0x1400, 0x1600, 0x1800, 0x1A00, 0x2000,
            0x2100
        ]
    );
    assert_eq!(
        device.device_info.nr_of_rx_pdo.as_ref().map(|s| s.value),
        Some(1)
    );
    assert_eq!(
        device.device_info.nr_of_tx_pdo.as_ref().map(|s| s.value),
        Some(1)
    );
}

#[test]
fn pdo1_mappings_carry_the_protocol_fields() {
    let device = read(EDS).device;
    for (index, entries) in [
        (0x1600u16, &[0x2100_0010u32, 0x2100_0110, 0x2100_0210][..]),
        (
            0x1A00,
            &[0x2000_0010, 0x2000_0110, 0x2000_0210, 0x0006_0010][..],
        ),
    ] {
        assert_eq!(
            integer_default(&device, index, 0),
            Some(entries.len() as i128)
        );
        for (i, word) in entries.iter().enumerate() {
            assert_eq!(
                integer_default(&device, index, i as u8 + 1),
                Some(i128::from(*word)),
                "{index:04X}h sub{}",
                i + 1
            );
        }
    }
    assert_eq!(device.dummy_usage.get(&0x0006), Some(&true));
}

/// Splits a PDO1 payload like [`decode`], checking also that every field is an UNSIGNED16 word
/// (8.2.2: two bytes each).
fn decode_words(device: &Device, mapping_index: u16, payload: &[u8]) -> Vec<((u16, u8), u64)> {
    let fields = decode(device, mapping_index, payload);
    for ((index, sub), _) in &fields {
        let data_type = if is_dummy(*index, *sub) {
            Some(*index)
        } else {
            device.entry(*index, *sub).and_then(|e| e.data_type)
        };
        let unsigned16 = Some(BasicType::Unsigned16.index());
        assert_eq!(data_type, unsigned16, "{index:04X}h:{sub:02X}");
    }
    fields
}

#[test]
fn pdo1_rx_is_six_bytes_and_reads_p10_01() {
    // p. 15: PDO1 Rx data must be six bytes; address of P10.01 is 0x0A01 (high byte 10, low 01);
    // request data in Byte4 (low) and Byte5 (high). Request code 1 = read.
    let device = read(EDS).device;
    assert_eq!(
        decode_words(&device, 0x1600, &[0x01, 0x00, 0x01, 0x0A, 0x00, 0x00]),
        vec![((0x2100, 0), 1), ((0x2100, 1), 0x0A01), ((0x2100, 2), 0)]
    );
}

#[test]
fn pdo1_tx_is_eight_bytes_with_reserved_byte6_and_byte7() {
    // 8.2.2: response code Byte0-1, error code Byte2-3 (Table 21: 07H read-only parameter),
    // response data from Byte4 (low), Byte6-7 reserved 0x00.
    let device = read(EDS).device;
    assert_eq!(
        decode_words(
            &device,
            0x1A00,
            &[0x03, 0x00, 0x07, 0x00, 0x34, 0x12, 0x00, 0x00]
        ),
        vec![
            ((0x2000, 0), 3),
            ((0x2000, 1), 7),
            ((0x2000, 2), 0x1234),
            ((0x0006, 0), 0)
        ]
    );
}

#[test]
fn validates_with_only_the_card_s_own_deviation_from_cia_301() {
    // 2000h:00 and 2100h:00 are 16-bit data on this card (section 8.2.2: 0x2000.00 is the
    // response code), not the UNSIGNED8 number of entries; the file describes them as they are,
    // and its [Comments] say so.
    let read = read(EDS);
    // Each at the DataType key of the sub-0 section.
    let sub0_2000 = key_line(&read.text, "[2000sub0]", "DataType");
    let sub0_2100 = key_line(&read.text, "[2100sub0]", "DataType");
    assert_eq!(
        warnings_and_errors(&read),
        [
            ("EDS308", Severity::Warning, sub0_2000),
            ("EDS308", Severity::Warning, sub0_2100),
        ]
    );
}

#[test]
fn reads_without_diagnostics_above_info() {
    let read = read(EDS);
    assert_eq!(above_info(&read.diagnostics), Vec::<Finding>::new());
}

#[test]
fn dump_snapshot() {
    let device = read(EDS).device;
    insta::assert_json_snapshot!("hd1e_dump", dump(&device, EDS));
}
