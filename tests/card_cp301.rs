//! The CP301 card's EDS (`eds/cp301.eds`) checked against the CP301 user manual
//! (`shared/seeds/000_fb775a76a7956860.txt`): a table of entries, each citing the manual section
//! it comes from; the objects the manual does not have; the default PDOs; a snapshot of the
//! resolved model; and a validation that finds nothing but the one documented deviation.

use std::path::Path;

use edsgen_codegen::diag::Severity;
use edsgen_codegen::model::{AccessType, BasicType, Device, Value};
use edsgen_codegen::read::read_file;

/// The EDS under test, relative to the package root (the working directory of integration tests).
const EDS: &str = "eds/cp301.eds";

fn device() -> Device {
    let read = read_file(Path::new(EDS)).expect("eds/cp301.eds is readable");
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
    use BasicType::{Integer16, Integer8, Unsigned16, Unsigned32, Unsigned8};
    vec![
        // §6.1 basic index: 1000h Device type, initial value 0, R, U32.
        row(0x1000, 0, "Device type", Unsigned32, Ro, int(0), false),
        // §6.1: 1005h COB-ID SYNC message, 80h, R, U32.
        row(
            0x1005,
            0,
            "COB-ID SYNC message",
            Unsigned32,
            Ro,
            int(0x80),
            false,
        ),
        // §6.1: 1008h Manufacturer device name, 0, R, U32 (the manual's type, not CiA 301's).
        row(
            0x1008,
            0,
            "Manufacturer device name",
            Unsigned32,
            Ro,
            int(0),
            false,
        ),
        // §6.1: 1010h sub1 Save all parameters, 0, RW, U32.
        row(
            0x1010,
            1,
            "Save all parameters",
            Unsigned32,
            Rw,
            int(0),
            false,
        ),
        // §6.1: 1011h sub0 Restore Parameter = 3, R, U8.
        row(
            0x1011,
            0,
            "Highest sub-index supported",
            Unsigned8,
            Ro,
            int(3),
            false,
        ),
        // §6.1: 1014h COB-ID emergency 0000080h+Node-ID, R, U32.
        row(0x1014, 0, "COB-ID EMCY", Unsigned32, Ro, node(0x80), false),
        // §6.1: 1016h sub1 Consumer 1, 0, RW, U32, unit 1 ms.
        row(
            0x1016,
            1,
            "Consumer heartbeat time 1",
            Unsigned32,
            Rw,
            int(0),
            false,
        ),
        // §6.1: 1017h Producer heartbeat time, 0, RW, U16, unit 1 ms.
        row(
            0x1017,
            0,
            "Producer heartbeat time",
            Unsigned16,
            Rw,
            int(0),
            false,
        ),
        // §6.1: 1018h sub0 Number = 3, R, U8 (no serial number).
        row(0x1018, 0, "Number of entries", Unsigned8, Ro, int(3), false),
        // §6.1: 1018h sub1 Vender ID, 0, R, U32.
        row(0x1018, 1, "Vendor-ID", Unsigned32, Ro, int(0), false),
        // §6.1: 1200h sub2 COB-ID Client <- Server, 0000580h+Node-ID, R, U32.
        row(
            0x1200,
            2,
            "COB-ID server to client (tx)",
            Unsigned32,
            Ro,
            node(0x580),
            false,
        ),
        // §6.1 PDO table: 1400h sub2 Transmission Type 5, RW, U8.
        row(0x1400, 2, "Transmission type", Unsigned8, Rw, int(5), false),
        // §6.1: 1402h sub1 COB-ID used by PDO 80000400h+NodeID (not valid), RW, U32.
        row(
            0x1402,
            1,
            "COB-ID used by RPDO",
            Unsigned32,
            Rw,
            node(0x8000_0400),
            false,
        ),
        // §6.1: 1600h sub0 Number 2, RW, U8.
        row(
            0x1600,
            0,
            "Number of mapped objects",
            Unsigned8,
            Rw,
            int(2),
            false,
        ),
        // §6.1: 1600h sub2 2.Mapped Object 60420010h, RW, U32.
        row(
            0x1600,
            2,
            "Mapped object 2",
            Unsigned32,
            Rw,
            int(0x6042_0010),
            false,
        ),
        // §6.1: 1800h sub3 Inhibit time 0, RW, U16, unit 100 us.
        row(0x1800, 3, "Inhibit time", Unsigned16, Rw, int(0), false),
        // §6.1: 1801h sub4 CMS-Priority Group 0, RW, U8 (reserved by CiA 301, kept).
        row(
            0x1801,
            4,
            "CMS-Priority Group",
            Unsigned8,
            Rw,
            int(0),
            false,
        ),
        // §6.1: 1803h sub5 Event timer 0, RW, U16, unit 1 ms.
        row(0x1803, 5, "Event timer", Unsigned16, Rw, int(0), false),
        // §6.1: 1A00h sub1 1.Mapped Object 60410010h, RW, U32.
        row(
            0x1A00,
            1,
            "Mapped object 1",
            Unsigned32,
            Rw,
            int(0x6041_0010),
            false,
        ),
        // §6.2 example: parameter 10-40 is 200Ah sub 29h (type and access are this file's choice).
        row(
            0x200A,
            0x29,
            "VF separated voltage source (10-40)",
            Unsigned16,
            Rw,
            None,
            false,
        ),
        // §6.2 example: P.308 is 2103h sub 9.
        row(
            0x2103,
            9,
            "Motor power on current (P.308)",
            Unsigned16,
            Rw,
            None,
            false,
        ),
        // §5.1 and §6.2: 07-15 (P.800) is 2007h sub 10h and 2108h sub 1.
        row(
            0x2007,
            0x10,
            "CANopen slave address (07-15, P.800)",
            Unsigned16,
            Rw,
            None,
            false,
        ),
        row(
            0x2108,
            1,
            "CANopen slave address (P.800, 07-15)",
            Unsigned16,
            Rw,
            None,
            false,
        ),
        // §6.3 example: output voltage is Modbus 1005h, sub 6 of 2D02h, RO, U16, mappable.
        row(
            0x2D02,
            6,
            "Output voltage (INV monitor Modbus 1005h)",
            Unsigned16,
            Ro,
            None,
            true,
        ),
        // §6.4 and §8.2.1: 6007h Abort connection option code, 2, RW, S16, mappable.
        row(
            0x6007,
            0,
            "Abort connection option code",
            Integer16,
            Rw,
            int(2),
            true,
        ),
        // §6.4 and §8.2.2: 603Fh Error code, 0, RO, U16, mappable.
        row(0x603F, 0, "Error code", Unsigned16, Ro, int(0), true),
        // §6.4 and §8.2.3: 6040h Control word, 0, RW, U16, mappable.
        row(0x6040, 0, "Controlword", Unsigned16, Rw, int(0), true),
        // §6.4 and §8.2.5: 6042h vl target velocity, 0, RW, S16 rpm, mappable.
        row(0x6042, 0, "vl target velocity", Integer16, Rw, int(0), true),
        // §8.2.7: 6044h vl velocity actual value, RO, S16 rpm (table 6.4: vl control effort, 0).
        row(
            0x6044,
            0,
            "vl velocity actual value",
            Integer16,
            Ro,
            int(0),
            true,
        ),
        // §8.2.8: 604Fh vl ramp function time, default 10000 ms, RW, U32, mappable.
        row(
            0x604F,
            0,
            "vl ramp function time",
            Unsigned32,
            Rw,
            int(10000),
            true,
        ),
        // §8.2.10: 6051h vl quick stop time, 1000 ms, RW, U32, mappable.
        row(
            0x6051,
            0,
            "vl quick stop time",
            Unsigned32,
            Rw,
            int(1000),
            true,
        ),
        // §5.2 table and §8.2.11: 605Ah Quick stop option code, 2, RW, S16, not mappable.
        row(
            0x605A,
            0,
            "Quick stop option code",
            Integer16,
            Rw,
            int(2),
            false,
        ),
        // §6.4 and §8.2.12: 605Bh default 0 (the table of §5.2 says 1; see [Comments]).
        row(
            0x605B,
            0,
            "Shutdown option code",
            Integer16,
            Rw,
            int(0),
            false,
        ),
        // §8.2.14: 6061h Modes of operation display, 2, RO, S8, mappable.
        row(
            0x6061,
            0,
            "Modes of operation display",
            Integer8,
            Ro,
            int(2),
            true,
        ),
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
    // §6.1 has no pre-defined error field, node guarding, SYNC window, time stamp or EMCY
    // inhibit time; §6.4 has 6061h but no 6060h; 1018h stops at sub 3.
    for index in [
        0x1003, 0x1006, 0x1007, 0x100C, 0x100D, 0x1012, 0x1015, 0x6060,
    ] {
        assert!(
            !device.objects.contains_key(&index),
            "{index:04X}h is not in the manual"
        );
    }
    assert!(device.entry(0x1018, 4).is_none());
    let identity_subs: Vec<u8> = device.objects[&0x1018].subs.keys().copied().collect();
    assert_eq!(identity_subs, vec![0, 1, 2, 3]);
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
    // §6.1: RPDO1 = Controlword + vl target velocity; TPDO1 = Statusword + vl velocity demand;
    // PDO2-4 have no mapped object (the §4.2.2 figure shows the same RPDO1/TPDO1 start).
    assert_eq!(
        mapped(&device, 0x1600),
        vec![(0x6040, 0, 16), (0x6042, 0, 16)]
    );
    assert_eq!(
        mapped(&device, 0x1A00),
        vec![(0x6041, 0, 16), (0x6043, 0, 16)]
    );
    for index in [0x1601, 0x1602, 0x1603, 0x1A01, 0x1A02, 0x1A03] {
        assert_eq!(mapped(&device, index), vec![], "{index:04X}h");
    }
    // §6.1: every mapping object has four entries.
    for index in (0x1600..=0x1603).chain(0x1A00..=0x1A03) {
        let subs: Vec<u8> = device.objects[&index].subs.keys().copied().collect();
        assert_eq!(subs, vec![0, 1, 2, 3, 4], "{index:04X}h");
    }
    // §6.1: COB-IDs; PDO2-4 have bit 31 set (not valid).
    let cob_ids = [
        (0x1400, 0x200),
        (0x1401, 0x8000_0300),
        (0x1402, 0x8000_0400),
        (0x1403, 0x8000_0500),
        (0x1800, 0x180),
        (0x1801, 0x8000_0280),
        (0x1802, 0x8000_0380),
        (0x1803, 0x8000_0480),
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
}

#[test]
fn device_info_follows_the_manual() {
    let device = device();
    let info = &device.device_info;
    // §6.1: 1018h sub1..3 are 0; the EDS header repeats them.
    assert_eq!(info.vendor_number.as_ref().map(|v| v.value), Some(0));
    assert_eq!(info.product_number.as_ref().map(|v| v.value), Some(0));
    assert_eq!(info.revision_number.as_ref().map(|v| v.value), Some(0));
    // §1.2: PDO1-PDO4.
    assert_eq!(info.nr_of_rx_pdo.as_ref().map(|v| v.value), Some(4));
    assert_eq!(info.nr_of_tx_pdo.as_ref().map(|v| v.value), Some(4));
    assert!(!info.lss_supported);
    // §2.2: 1M, 500k, 250k, 125k, (100k: no CiA 306 key), 50k.
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
    insta::assert_json_snapshot!("cp301_model", edsgen_codegen::dump::to_json(&device));
}

#[test]
fn reads_and_validates_clean() {
    let read = read_file(Path::new(EDS)).expect("eds/cp301.eds is readable");
    let judged = edsgen_codegen::validate::validate(&read.device);
    let all: Vec<_> = read.diagnostics.iter().chain(judged.iter()).collect();
    let mut findings: Vec<(&str, &str, u32)> = all
        .iter()
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

    // The one deviation from CiA 301 that [Comments] explains: §6.1 documents sub 4
    // (CMS-Priority Group) of every TPDO communication record. It is reported once, as an info,
    // at the first such sub-object.
    let sub4_line = read
        .text
        .lines()
        .position(|line| line == "[1800sub4]")
        .map(|i| i as u32 + 1)
        .expect("[1800sub4] is in the file");
    let reserved: Vec<(&str, u32)> = all
        .iter()
        .filter(|d| d.rule.code == "EDS403")
        .map(|d| (d.severity.as_str(), d.span.map_or(0, |s| s.line)))
        .collect();
    assert_eq!(reserved, vec![("info", sub4_line)]);
}
