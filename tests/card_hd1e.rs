//! `eds/hd1e.eds` (HD1-E CANopen card) checked against its manual fragment (seed 004, section
//! 8.2.2 and Tables 19-21): the PDO1 parameter-access objects and mappings, the frame layout of
//! PDO1 Rx/Tx, the model dump (snapshot), and the validator's verdict.

use std::path::Path;

use edsgen_codegen::diag::Severity;
use edsgen_codegen::model::{AccessType, BasicType, Device, Value};
use edsgen_codegen::read::{read_file, Read};

const EDS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/eds/hd1e.eds");

fn read() -> Read {
    read_file(Path::new(EDS)).expect("eds/hd1e.eds is readable")
}

/// What the file gives as the default value.
#[derive(Debug, Clone, Copy)]
enum DefaultValue {
    /// The manual gives none (runtime value): no DefaultValue in the file.
    Absent,
    Int(i128),
    NodeId(i64),
}

/// One object-dictionary entry as the manual describes it.
struct Row {
    index: u16,
    sub: u8,
    data_type: BasicType,
    access: AccessType,
    default: DefaultValue,
    pdo_mapping: bool,
    source: &'static str,
}

const fn row(
    index: u16,
    sub: u8,
    data_type: BasicType,
    access: AccessType,
    default: DefaultValue,
    pdo_mapping: bool,
    source: &'static str,
) -> Row {
    Row {
        index,
        sub,
        data_type,
        access,
        default,
        pdo_mapping,
        source,
    }
}

use AccessType::{Ro, Rw};
use BasicType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use DefaultValue::{Absent, Int, NodeId};

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

fn default_matches(device: &Device, index: u16, sub: u8, expected: DefaultValue) -> bool {
    let Some(entry) = device.entry(index, sub) else {
        return false;
    };
    let value = entry.default.as_ref().and_then(|d| d.value.clone());
    match expected {
        Absent => entry.default.is_none(),
        Int(v) => value == Some(Value::Integer(v)),
        NodeId(offset) => value == Some(Value::NodeRelative(offset)),
    }
}

#[test]
fn objects_match_the_fragment() {
    let device = read().device;
    for r in ROWS {
        let at = format!("{:04X}h:{:02X} ({})", r.index, r.sub, r.source);
        let entry = device
            .entry(r.index, r.sub)
            .unwrap_or_else(|| panic!("{at}: missing"));
        assert_eq!(
            entry.data_type,
            Some(r.data_type.index()),
            "{at}: data type"
        );
        assert_eq!(entry.access, Some(r.access), "{at}: access");
        assert_eq!(entry.pdo_mapping, r.pdo_mapping, "{at}: PDO mapping");
        assert!(
            default_matches(&device, r.index, r.sub, r.default),
            "{at}: default {:?}, expected {:?}",
            entry.default,
            r.default
        );
    }
}

#[test]
fn only_the_pdo1_pair_is_described() {
    let device = read().device;
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

fn integer_default(device: &Device, index: u16, sub: u8) -> Option<i128> {
    match device.entry(index, sub)?.default.as_ref()?.value {
        Some(Value::Integer(v)) => Some(v),
        _ => None,
    }
}

#[test]
fn pdo1_mappings_carry_the_protocol_fields() {
    let device = read().device;
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

/// Splits a PDO payload by the default mapping of `mapping_index`, checking each mapped entry
/// exists, is mappable and has the mapped width.
fn decode(device: &Device, mapping_index: u16, payload: &[u8]) -> Vec<((u16, u8), u64)> {
    let count = integer_default(device, mapping_index, 0).expect("mapping sub0") as u8;
    let mut bit = 0usize;
    let mut out = Vec::new();
    for sub in 1..=count {
        let word = integer_default(device, mapping_index, sub).expect("mapping entry") as u32;
        let (index, target_sub, bits) = ((word >> 16) as u16, (word >> 8) as u8, word as u8);
        if (1..=7).contains(&index) && target_sub == 0 {
            assert_eq!(
                device.dummy_usage.get(&index),
                Some(&true),
                "Dummy{index:04X}"
            );
        } else {
            let entry = device.entry(index, target_sub).expect("mapped entry");
            assert!(entry.pdo_mapping, "{index:04X}h:{target_sub:02X}");
            assert_eq!(entry.data_type, Some(BasicType::Unsigned16.index()));
        }
        assert_eq!(bits, 16);
        let bytes = &payload[bit / 8..(bit + bits as usize) / 8];
        let value = bytes
            .iter()
            .rev()
            .fold(0u64, |acc, b| (acc << 8) | u64::from(*b));
        out.push(((index, target_sub), value));
        bit += bits as usize;
    }
    assert_eq!(bit, payload.len() * 8, "PDO length = frame length");
    out
}

#[test]
fn pdo1_rx_is_six_bytes_and_reads_p10_01() {
    // p. 15: PDO1 Rx data must be six bytes; address of P10.01 is 0x0A01 (high byte 10, low 01);
    // request data in Byte4 (low) and Byte5 (high). Request code 1 = read.
    let device = read().device;
    assert_eq!(
        decode(&device, 0x1600, &[0x01, 0x00, 0x01, 0x0A, 0x00, 0x00]),
        vec![((0x2100, 0), 1), ((0x2100, 1), 0x0A01), ((0x2100, 2), 0)]
    );
}

#[test]
fn pdo1_tx_is_eight_bytes_with_reserved_byte6_and_byte7() {
    // 8.2.2: response code Byte0-1, error code Byte2-3 (Table 21: 07H read-only parameter),
    // response data from Byte4 (low), Byte6-7 reserved 0x00.
    let device = read().device;
    assert_eq!(
        decode(
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

/// The 1-based number of the line that reads exactly `line` in the file text.
fn line_of(text: &str, line: &str) -> u32 {
    let position = text.lines().position(|l| l.trim_end() == line);
    position.map(|i| i as u32 + 1).expect(line)
}

/// Read and validate diagnostics above info, as (code, severity, line), sorted.
fn warnings_and_errors(read: &Read) -> Vec<(&'static str, Severity, Option<u32>)> {
    let validated = edsgen_codegen::validate::validate(&read.device);
    let mut found: Vec<_> = read
        .diagnostics
        .iter()
        .chain(validated.iter())
        .filter(|d| d.severity > Severity::Info)
        .map(|d| (d.rule.code, d.severity, d.span.map(|s| s.line)))
        .collect();
    found.sort_by_key(|(code, _, line)| (*line, *code));
    found
}

#[test]
fn validates_with_only_the_card_s_own_deviation_from_cia_301() {
    // 2000h:00 and 2100h:00 are 16-bit data on this card (section 8.2.2: 0x2000.00 is the response code), not the UNSIGNED8
    // number of entries; the file describes them as they are, and its [Comments] say so.
    let read = read();
    // Each at the DataType key of the sub-0 section.
    let data_type_of = |header: &str| {
        let start = line_of(&read.text, header);
        let below = read.text.lines().skip(start as usize);
        below
            .take_while(|l| !l.starts_with('['))
            .position(|l| l.starts_with("DataType="))
            .map(|i| start + i as u32 + 1)
    };
    let sub0_2000 = data_type_of("[2000sub0]");
    let sub0_2100 = data_type_of("[2100sub0]");
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
    let read = read();
    let loud: Vec<_> = read
        .diagnostics
        .iter()
        .filter(|d| d.severity > Severity::Info)
        .collect();
    assert!(loud.is_empty(), "{loud:#?}");
}

#[test]
fn dump_snapshot() {
    let device = read().device;
    let mut dump = edsgen_codegen::dump::to_json(&device);
    // The dump names the file as given (an absolute path here); keep the snapshot portable.
    dump["file"] = "eds/hd1e.eds".into();
    insta::assert_json_snapshot!("hd1e_dump", dump);
}
