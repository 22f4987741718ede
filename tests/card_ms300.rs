//! The Delta MS300 EDS (`eds/ms300.eds`) checked against chapter 15 of the MS300 manual
//! (`shared/seeds/001_f0d0d2d9cd9c9520.txt`): a table of entries, each citing the manual section
//! it comes from; the objects the manual does not have; the PDO defaults (CiA 301, the manual has
//! none); a snapshot of the resolved model; and a clean validation.

use std::path::Path;

use edsgen_codegen::diag::Severity;
use edsgen_codegen::model::{AccessType, BasicType, Device, Value};
use edsgen_codegen::read::read_file;

/// The EDS under test, relative to the package root (the working directory of integration tests).
const EDS: &str = "eds/ms300.eds";

fn device() -> Device {
    let read = read_file(Path::new(EDS)).expect("eds/ms300.eds is readable");
    read.device
}

/// One entry as the manual describes it.
struct Row {
    index: u16,
    sub: u8,
    name: &'static str,
    data_type: BasicType,
    access: AccessType,
    default: Option<Value>,
    pdo: bool,
}

fn row(
    index: u16,
    sub: u8,
    name: &'static str,
    data_type: BasicType,
    access: AccessType,
    default: Option<Value>,
    pdo: bool,
) -> Row {
    Row {
        index,
        sub,
        name,
        data_type,
        access,
        default,
        pdo,
    }
}

fn int(v: i128) -> Option<Value> {
    Some(Value::Integer(v))
}

fn node(offset: i64) -> Option<Value> {
    Some(Value::NodeRelative(offset))
}

fn manual_rows() -> Vec<Row> {
    use AccessType::{Ro, Rw};
    use BasicType::{Integer16, Integer32, Integer8, Unsigned16, Unsigned32, Unsigned8};
    vec![
        // 15-5: each fault sets a bit (0-7) of the CANopen fault register, 1001h.
        row(0x1001, 0, "Error register", Unsigned8, Ro, int(0), false),
        // 15-1 (CiA 301 data, the manual gives no 1000h value): DSP-402 frequency converter.
        row(
            0x1000,
            0,
            "Device type",
            Unsigned32,
            Ro,
            int(0x0001_0192),
            false,
        ),
        // 15-1 node guarding (Node Guard in the NMT diagram, fault 101 CGdE): 100Ch guard time.
        row(0x100C, 0, "Guard time", Unsigned16, Rw, int(0), false),
        // 15-1 and 15-5 fault 102 CHbE: one heartbeat consumer entry.
        row(
            0x1016,
            0,
            "Highest sub-index supported",
            Unsigned8,
            Ro,
            int(1),
            false,
        ),
        // 15-1 EMCY service with the predefined connection set COB-ID.
        row(0x1014, 0, "COB-ID EMCY", Unsigned32, Rw, node(0x80), false),
        // 15-1: the identity is not given: placeholders, sub1..4.
        row(0x1018, 4, "Serial number", Unsigned32, Ro, int(0), false),
        // 15-1: SDO with the predefined connection set.
        row(
            0x1200,
            1,
            "COB-ID client to server (rx)",
            Unsigned32,
            Ro,
            node(0x600),
            false,
        ),
        // 15-1 PDO: type 254 is not supported; 255 is the asynchronous default here.
        row(
            0x1403,
            2,
            "Transmission type",
            Unsigned8,
            Rw,
            int(255),
            false,
        ),
        row(
            0x1802,
            2,
            "Transmission type",
            Unsigned8,
            Rw,
            int(255),
            false,
        ),
        // 15-4 parameter rule: Pr. 10-15 is 200Ah sub 10h.
        row(
            0x200A,
            0x10,
            "Encoder slip error treatment (Pr. 10-15)",
            Unsigned16,
            Rw,
            None,
            false,
        ),
        // 15-3-1: Pr. 09-40 = 1 (factory setting) selects DS402; 2009h sub 29h.
        row(
            0x2009,
            0x29,
            "CANopen control mode selection (Pr. 09-40)",
            Unsigned16,
            Rw,
            int(1),
            false,
        ),
        // 15-4 Delta standard (old): 2020h sub0 Number 3, R, U8.
        row(0x2020, 0, "Number", Unsigned8, Ro, int(3), false),
        // 15-4 and 15-3-3-2: 2020h sub2 frequency command (XXXX.X Hz), 0, RW, U16.
        row(0x2020, 2, "Frequency command", Unsigned16, Rw, int(0), true),
        // 15-4: 2021h sub1 error code, 0, R, U16.
        row(0x2021, 1, "Error code", Unsigned16, Ro, int(0), true),
        // 15-4: 2021h sub 17h multi-function display (Pr. 00-04), 0, R, U16.
        row(
            0x2021,
            0x17,
            "Multi-function display",
            Unsigned16,
            Ro,
            int(0),
            true,
        ),
        // 15-4: 2022h sub 3 actual output frequency (XXX.XX Hz), 0, R, U16.
        row(
            0x2022,
            3,
            "Actual output frequency",
            Unsigned16,
            Ro,
            int(0),
            true,
        ),
        // 15-4: 2022h sub 0 is written Reserved U16; CiA 301 sub0 here (highest sub 2Ch).
        row(
            0x2022,
            0,
            "Highest sub-index supported",
            Unsigned8,
            Ro,
            int(0x2C),
            false,
        ),
        // 15-4 remote I/O and 15-3-5: 2026h sub 41h digital outputs, RW.
        row(0x2026, 0x41, "Digital outputs", Unsigned16, Rw, None, true),
        // 15-4 and 15-3-5: 2026h sub 61h AVI (%), R.
        row(0x2026, 0x61, "AVI", Unsigned16, Ro, None, true),
        // 15-4 Delta standard (new): 2060h sub1 control word, RW, U16.
        row(0x2060, 1, "Control word", Unsigned16, Rw, None, true),
        // 15-3-1 control mode table: 2060-04 torque limit (%); 15-4: RW, U16.
        row(0x2060, 4, "Torque limit", Unsigned16, Rw, None, true),
        // 15-4: 2060h sub 5, RW, S32, no definition.
        row(0x2060, 5, "Reserved command 5", Integer32, Rw, None, true),
        // 15-4: 2061h sub 3 actual output frequency, R, U16.
        row(
            0x2061,
            3,
            "Actual output frequency",
            Unsigned16,
            Ro,
            None,
            true,
        ),
        // 15-4 DS402 table: 6007h, 2, RW, S16, mappable.
        row(
            0x6007,
            0,
            "Abort connection option code",
            Integer16,
            Rw,
            int(2),
            true,
        ),
        // 15-4 DS402 table: 603Fh error code, 0, R0 (RO), U16, mappable.
        row(0x603F, 0, "Error code", Unsigned16, Ro, int(0), true),
        // 15-4 DS402 table: 6041h status word, 0, RO, U16, mappable.
        row(0x6041, 0, "Statusword", Unsigned16, Ro, int(0), true),
        // 15-4 DS402 table: 6043h vl velocity demand, 0, RO, S16 rpm, mappable.
        row(0x6043, 0, "vl velocity demand", Integer16, Ro, int(0), true),
        // 15-4 DS402 table: 6044h vl control effort, 0, RO, S16 rpm, mappable.
        row(0x6044, 0, "vl control effort", Integer16, Ro, int(0), true),
        // 15-4 DS402 table: 6050h vl slow down time, 10000, RW, U32 1 ms, mappable.
        row(
            0x6050,
            0,
            "vl slow down time",
            Unsigned32,
            Rw,
            int(10000),
            true,
        ),
        // 15-3-2-2 and 15-4: 605Ch disable operation option code, 1, RW, S16, not mappable.
        row(
            0x605C,
            0,
            "Disable operation option code",
            Integer16,
            Rw,
            int(1),
            false,
        ),
        // 15-4 DS402 table and 15-3-2-3: 6060h mode of operation, 2 (velocity), RW, S8.
        row(0x6060, 0, "Modes of operation", Integer8, Rw, int(2), true),
    ]
}

#[test]
fn entries_match_the_manual() {
    let device = device();
    let mut mismatches = Vec::new();
    for r in manual_rows() {
        let Some(entry) = device.entry(r.index, r.sub) else {
            mismatches.push(format!("{:04X}h sub {}: missing", r.index, r.sub));
            continue;
        };
        let default = entry.default.as_ref().and_then(|d| d.value.clone());
        let actual = (
            entry.name.as_str(),
            entry.data_type,
            entry.access,
            default,
            entry.pdo_mapping,
        );
        let expected = (
            r.name,
            Some(r.data_type.index()),
            Some(r.access),
            r.default,
            r.pdo,
        );
        if actual != expected {
            mismatches.push(format!(
                "{:04X}h sub {}: expected {expected:?}, found {actual:?}",
                r.index, r.sub
            ));
        }
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

#[test]
fn objects_the_manual_does_not_list_are_absent() {
    let device = device();
    // Chapter 15 mentions no pre-defined error field, device name, store/restore or time stamp
    // (not supported, 15-1); the DS402 table of 15-4 has no 605Bh.
    for index in [
        0x1003, 0x1008, 0x1009, 0x100A, 0x1010, 0x1011, 0x1012, 0x605B,
    ] {
        assert!(
            !device.objects.contains_key(&index),
            "{index:04X}h is not in the manual"
        );
    }
    // 15-4: rows without a size (2060h sub 6, 2061h sub 2, 4, 6) are left out.
    for (index, sub) in [(0x2060, 6), (0x2061, 2), (0x2061, 4), (0x2061, 6)] {
        assert!(device.entry(index, sub).is_none(), "{index:04X}h sub {sub}");
    }
    let remote_io: Vec<u8> = device.objects[&0x2026].subs.keys().copied().collect();
    assert_eq!(remote_io, vec![0, 0x01, 0x02, 0x41, 0x61, 0x62, 0xA1, 0xA2]);
}

/// The mapped (index, sub, bit length) triples of a mapping object, as far as sub0 says.
fn mapped(device: &Device, index: u16) -> Vec<(u16, u8, u8)> {
    let count = match device.entry(index, 0).and_then(|e| e.default.as_ref()) {
        Some(d) => match d.value {
            Some(Value::Integer(n)) => n as u8,
            _ => panic!("{index:04X}h sub0 has no integer default"),
        },
        None => panic!("{index:04X}h sub0 is missing"),
    };
    (1..=count)
        .map(
            |sub| match device.entry(index, sub).and_then(|e| e.default.as_ref()) {
                Some(d) => match d.value {
                    Some(Value::Integer(v)) => ((v >> 16) as u16, (v >> 8) as u8, v as u8),
                    _ => panic!("{index:04X}h sub {sub} has no integer default"),
                },
                None => panic!("{index:04X}h sub {sub} is missing"),
            },
        )
        .collect()
}

#[test]
fn default_pdos_are_the_manuals() {
    let device = device();
    // The manual gives no default mapping: every mapping object maps nothing and has four
    // entries (this file's choice, see [Comments]).
    for index in (0x1600..=0x1603).chain(0x1A00..=0x1A03) {
        assert_eq!(mapped(&device, index), vec![], "{index:04X}h");
        let subs: Vec<u8> = device.objects[&index].subs.keys().copied().collect();
        assert_eq!(subs, vec![0, 1, 2, 3, 4], "{index:04X}h");
    }
    // 15-1: default COB-IDs of the predefined connection set, all valid.
    let cob_ids = [
        (0x1400, 0x200),
        (0x1401, 0x300),
        (0x1402, 0x400),
        (0x1403, 0x500),
        (0x1800, 0x180),
        (0x1801, 0x280),
        (0x1802, 0x380),
        (0x1803, 0x480),
    ];
    for (index, offset) in cob_ids {
        let value = device
            .entry(index, 1)
            .and_then(|e| e.default.as_ref())
            .and_then(|d| d.value.clone());
        assert_eq!(
            value,
            Some(Value::NodeRelative(offset)),
            "{index:04X}h sub 1"
        );
    }
    // TPDO records: sub 0, 1, 2, 3, 5 (CiA 301 reserves sub 4; DS301 V4.02 has no sub 6).
    for index in 0x1800..=0x1803 {
        let subs: Vec<u8> = device.objects[&index].subs.keys().copied().collect();
        assert_eq!(subs, vec![0, 1, 2, 3, 5], "{index:04X}h");
    }
}

#[test]
fn device_info_follows_the_manual() {
    let device = device();
    let info = &device.device_info;
    // Not in the manual: placeholders 0, equal to 1018h sub1..3.
    assert_eq!(info.vendor_number.as_ref().map(|v| v.value), Some(0));
    assert_eq!(info.product_number.as_ref().map(|v| v.value), Some(0));
    assert_eq!(info.revision_number.as_ref().map(|v| v.value), Some(0));
    // 15-1: PDO1-PDO4.
    assert_eq!(info.nr_of_rx_pdo.as_ref().map(|v| v.value), Some(4));
    assert_eq!(info.nr_of_tx_pdo.as_ref().map(|v| v.value), Some(4));
    assert!(!info.lss_supported);
    // 15-3-3-1 (Pr. 09-37): 1M, 500k, 250k, 125k, (100k: no CiA 306 key), 50k.
    let mut enabled: Vec<u32> = info
        .baud_rates
        .iter()
        .filter(|(_, on)| *on)
        .map(|(rate, _)| *rate)
        .collect();
    enabled.sort_unstable();
    assert_eq!(enabled, vec![50, 125, 250, 500, 1000]);
}

#[test]
fn model_snapshot() {
    let device = device();
    insta::assert_json_snapshot!("ms300_model", edsgen_codegen::dump::to_json(&device));
}

#[test]
fn reads_and_validates_clean() {
    let read = read_file(Path::new(EDS)).expect("eds/ms300.eds is readable");
    let judged = edsgen_codegen::validate::validate(&read.device);
    let mut findings: Vec<(&str, &str, u32)> = read
        .diagnostics
        .iter()
        .chain(judged.iter())
        .filter(|d| d.severity > Severity::Info)
        .map(|d| {
            (
                d.severity.as_str(),
                d.rule.code,
                d.span.map_or(0, |s| s.line),
            )
        })
        .collect();
    findings.sort();
    assert_eq!(findings, Vec::<(&str, &str, u32)>::new());
}
