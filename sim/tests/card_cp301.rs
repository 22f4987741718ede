//! The CP301 card's EDS (`eds/cp301.eds`) checked against the CP301 user manual
//! (`shared/seeds/000_fb775a76a7956860.txt`): a table of entries, each citing the manual section
//! it comes from; the objects the manual does not have; the default PDOs; a snapshot of the
//! resolved model; and a validation that finds nothing but the one documented deviation.

mod card_support;

use card_support::{
    all_diagnostics, baud_rates, check_rows, default_value, dump, line_of, mapped, read, row, subs,
    warnings_and_errors, DefaultValue, Finding, Row,
};
use edsgen_model::diag::Severity;
use edsgen_model::model::{AccessType, BasicType, Value};

use AccessType::{Ro, Rw};
use BasicType::{Integer16 as I16, Integer8 as I8, Unsigned16 as U16};
use BasicType::{Unsigned32 as U32, Unsigned8 as U8};
use DefaultValue::{Absent, Int, NodeId};

/// The EDS under test, relative to the package root.
const EDS: &str = "eds/cp301.eds";

#[rustfmt::skip]
const ROWS: &[Row] = &[
    row(0x1000, 0, U32, Ro, Int(0), false, "§6.1 basic index: initial value 0, R, U32")
        .named("Device type"),
    row(0x1005, 0, U32, Ro, Int(0x80), false, "§6.1: COB-ID SYNC message, 80h, R, U32")
        .named("COB-ID SYNC message"),
    row(0x1008, 0, U32, Ro, Int(0), false, "§6.1: 0, R, U32 (the manual's type, not CiA 301's)")
        .named("Manufacturer device name"),
    row(0x1010, 1, U32, Rw, Int(0), false, "§6.1: sub1 Save all parameters, 0, RW, U32")
        .named("Save all parameters"),
    row(0x1011, 0, U8, Ro, Int(3), false, "§6.1: sub0 Restore Parameter = 3, R, U8")
        .named("Highest sub-index supported"),
    row(0x1014, 0, U32, Ro, NodeId(0x80), false, "§6.1: COB-ID emergency 0000080h+Node-ID, R, U32")
        .named("COB-ID EMCY"),
    row(0x1016, 1, U32, Rw, Int(0), false, "§6.1: sub1 Consumer 1, 0, RW, U32, unit 1 ms")
        .named("Consumer heartbeat time 1"),
    row(0x1017, 0, U16, Rw, Int(0), false, "§6.1: Producer heartbeat time, 0, RW, U16, unit 1 ms")
        .named("Producer heartbeat time"),
    row(0x1018, 0, U8, Ro, Int(3), false, "§6.1: sub0 Number = 3, R, U8 (no serial number)")
        .named("Number of entries"),
    row(0x1018, 1, U32, Ro, Int(0), false, "§6.1: sub1 Vender ID, 0, R, U32")
        .named("Vendor-ID"),
    row(0x1200, 2, U32, Ro, NodeId(0x580), false, "§6.1: COB-ID Client <- Server, 0000580h+Node-ID")
        .named("COB-ID server to client (tx)"),
    row(0x1400, 2, U8, Rw, Int(5), false, "§6.1 PDO table: sub2 Transmission Type 5, RW, U8")
        .named("Transmission type"),
    row(0x1402, 1, U32, Rw, NodeId(0x8000_0400), false, "§6.1: 80000400h+NodeID (not valid), RW")
        .named("COB-ID used by RPDO"),
    row(0x1600, 0, U8, Rw, Int(2), false, "§6.1: sub0 Number 2, RW, U8")
        .named("Number of mapped objects"),
    row(0x1600, 2, U32, Rw, Int(0x6042_0010), false, "§6.1: 2.Mapped Object 60420010h, RW, U32")
        .named("Mapped object 2"),
    row(0x1800, 3, U16, Rw, Int(0), false, "§6.1: sub3 Inhibit time 0, RW, U16, unit 100 us")
        .named("Inhibit time"),
    row(0x1801, 4, U8, Rw, Int(0), false, "§6.1: CMS-Priority Group 0, RW, U8 (CiA 301 reserved)")
        .named("CMS-Priority Group"),
    row(0x1803, 5, U16, Rw, Int(0), false, "§6.1: sub5 Event timer 0, RW, U16, unit 1 ms")
        .named("Event timer"),
    row(0x1A00, 1, U32, Rw, Int(0x6041_0010), false, "§6.1: 1.Mapped Object 60410010h, RW, U32")
        .named("Mapped object 1"),
    row(0x200A, 0x29, U16, Rw, Absent, false, "§6.2 example: 10-40 (type, access: this file's)")
        .named("VF separated voltage source (10-40)"),
    row(0x2103, 9, U16, Rw, Absent, false, "§6.2 example: P.308 is 2103h sub 9")
        .named("Motor power on current (P.308)"),
    row(0x2007, 0x10, U16, Rw, Absent, false, "§5.1 and §6.2: 07-15 (P.800) is 2007h sub 10h")
        .named("CANopen slave address (07-15, P.800)"),
    row(0x2108, 1, U16, Rw, Absent, false, "§5.1 and §6.2: P.800 (07-15) is 2108h sub 1")
        .named("CANopen slave address (P.800, 07-15)"),
    row(0x2D02, 6, U16, Ro, Absent, true, "§6.3 example: Modbus 1005h, sub 6, RO, U16, mappable")
        .named("Output voltage (INV monitor Modbus 1005h)"),
    row(0x6007, 0, I16, Rw, Int(2), true, "§6.4 and §8.2.1: 2, RW, S16, mappable")
        .named("Abort connection option code"),
    row(0x603F, 0, U16, Ro, Int(0), true, "§6.4 and §8.2.2: Error code, 0, RO, U16, mappable")
        .named("Error code"),
    row(0x6040, 0, U16, Rw, Int(0), true, "§6.4 and §8.2.3: Control word, 0, RW, U16, mappable")
        .named("Controlword"),
    row(0x6042, 0, I16, Rw, Int(0), true, "§6.4 and §8.2.5: 0, RW, S16 rpm, mappable")
        .named("vl target velocity"),
    row(0x6044, 0, I16, Ro, Int(0), true, "§8.2.7: RO, S16 rpm (table 6.4: vl control effort, 0)")
        .named("vl velocity actual value"),
    row(0x604F, 0, U32, Rw, Int(10000), true, "§8.2.8: default 10000 ms, RW, U32, mappable")
        .named("vl ramp function time"),
    row(0x6051, 0, U32, Rw, Int(1000), true, "§8.2.10: 1000 ms, RW, U32, mappable")
        .named("vl quick stop time"),
    row(0x605A, 0, I16, Rw, Int(2), false, "§5.2 table and §8.2.11: 2, RW, S16, not mappable")
        .named("Quick stop option code"),
    row(0x605B, 0, I16, Rw, Int(0), false, "§6.4 and §8.2.12: 0 (§5.2 says 1; see [Comments])")
        .named("Shutdown option code"),
    row(0x6061, 0, I8, Ro, Int(2), true, "§8.2.14: 2, RO, S8, mappable")
        .named("Modes of operation display"),
];

#[test]
fn entries_match_the_manual() {
    check_rows(&read(EDS).device, ROWS);
}

#[test]
fn objects_the_manual_does_not_list_are_absent() {
    let device = read(EDS).device;
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
    assert_eq!(subs(&device, 0x1018), vec![0, 1, 2, 3]);
}

#[test]
fn default_pdos_are_the_manuals() {
    let device = read(EDS).device;
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
        assert_eq!(subs(&device, index), vec![0, 1, 2, 3, 4], "{index:04X}h");
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
        assert_eq!(
            default_value(&device, index, 1),
            Some(Value::NodeRelative(offset)),
            "{index:04X}h sub 1"
        );
    }
}

#[test]
fn device_info_follows_the_manual() {
    let device = read(EDS).device;
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
    assert_eq!(baud_rates(&device), vec![50, 125, 250, 500, 1000]);
}

#[test]
fn model_snapshot() {
    let device = read(EDS).device;
    insta::assert_json_snapshot!("cp301_model", dump(&device, EDS));
}

#[test]
fn reads_and_validates_clean() {
    let read = read(EDS);
    assert_eq!(warnings_and_errors(&read), Vec::<Finding>::new());

    // The one deviation from CiA 301 that [Comments] explains: §6.1 documents sub 4
    // (CMS-Priority Group) of every TPDO communication record. It is reported once, as an info,
    // at the first such sub-object.
    let reserved: Vec<(Severity, Option<u32>)> = all_diagnostics(&read)
        .iter()
        .filter(|d| d.rule.code == "EDS403")
        .map(|d| (d.severity, d.span.map(|s| s.line)))
        .collect();
    let sub4_line = line_of(&read.text, "[1800sub4]");
    assert_eq!(reserved, vec![(Severity::Info, Some(sub4_line))]);
}
