//! The Delta MS300 EDS (`eds/ms300.eds`) checked against chapter 15 of the MS300 manual
//! (`shared/seeds/001_f0d0d2d9cd9c9520.txt`): a table of entries, each citing the manual section
//! it comes from; the objects the manual does not have; the PDO defaults (CiA 301, the manual has
//! none); a snapshot of the resolved model; and a clean validation.

mod card_support;

use card_support::{
    baud_rates, check_rows, default_value, dump, mapped, read, row, subs, warnings_and_errors,
    DefaultValue, Finding, Row,
};
use edsgen_model::model::{AccessType, BasicType, Value};

use AccessType::{Ro, Rw};
use BasicType::{Integer16 as I16, Integer32 as I32, Integer8 as I8, Unsigned16 as U16};
use BasicType::{Unsigned32 as U32, Unsigned8 as U8};
use DefaultValue::{Absent, Int, NodeId};

/// The EDS under test, relative to the package root.
const EDS: &str = "eds/ms300.eds";

#[rustfmt::skip]
const ROWS: &[Row] = &[
    row(0x1001, 0, U8, Ro, Int(0), false, "15-5: each fault sets a bit (0-7) of the fault register")
        .named("Error register"),
    row(0x1000, 0, U32, Ro, Int(0x0001_0192), false, "none in 15-1; CiA 301: DSP-402 converter")
        .named("Device type"),
    row(0x100C, 0, U16, Rw, Int(0), false, "15-1 node guarding (NMT diagram, fault 101 CGdE)")
        .named("Guard time"),
    row(0x1016, 0, U8, Ro, Int(1), false, "15-1 and 15-5 fault 102 CHbE: one heartbeat consumer")
        .named("Highest sub-index supported"),
    row(0x1014, 0, U32, Rw, NodeId(0x80), false, "15-1 EMCY, predefined connection set COB-ID")
        .named("COB-ID EMCY"),
    row(0x1018, 4, U32, Ro, Int(0), false, "15-1: the identity is not given: placeholders")
        .named("Serial number"),
    row(0x1200, 1, U32, Ro, NodeId(0x600), false, "15-1: SDO with the predefined connection set")
        .named("COB-ID client to server (rx)"),
    row(0x1403, 2, U8, Rw, Int(255), false, "15-1 PDO: 254 not supported; 255 (asynchronous) here")
        .named("Transmission type"),
    row(0x1802, 2, U8, Rw, Int(255), false, "15-1 PDO: 254 not supported; 255 (asynchronous) here")
        .named("Transmission type"),
    row(0x200A, 0x10, U16, Rw, Absent, false, "15-4 parameter rule: Pr. 10-15 is 200Ah sub 10h")
        .named("Encoder slip error treatment (Pr. 10-15)"),
    row(0x2009, 0x29, U16, Rw, Int(1), false, "15-3-1: Pr. 09-40 = 1 (factory setting): DS402")
        .named("CANopen control mode selection (Pr. 09-40)"),
    row(0x2020, 0, U8, Ro, Int(3), false, "15-4 Delta standard (old): sub0 Number 3, R, U8")
        .named("Number"),
    row(0x2020, 2, U16, Rw, Int(0), true, "15-4 and 15-3-3-2: frequency command (XXXX.X Hz)")
        .named("Frequency command"),
    row(0x2021, 1, U16, Ro, Int(0), true, "15-4: 2021h sub1 error code, 0, R, U16")
        .named("Error code"),
    row(0x2021, 0x17, U16, Ro, Int(0), true, "15-4: multi-function display (Pr. 00-04), 0, R")
        .named("Multi-function display"),
    row(0x2022, 3, U16, Ro, Int(0), true, "15-4: actual output frequency (XXX.XX Hz), 0, R, U16")
        .named("Actual output frequency"),
    row(0x2022, 0, U8, Ro, Int(0x2C), false, "15-4 says Reserved U16; CiA 301 sub0 (highest 2Ch)")
        .named("Highest sub-index supported"),
    row(0x2026, 0x41, U16, Rw, Absent, true, "15-4 remote I/O and 15-3-5: digital outputs, RW")
        .named("Digital outputs"),
    row(0x2026, 0x61, U16, Ro, Absent, true, "15-4 and 15-3-5: AVI (%), R")
        .named("AVI"),
    row(0x2060, 1, U16, Rw, Absent, true, "15-4 Delta standard (new): control word, RW, U16")
        .named("Control word"),
    row(0x2060, 4, U16, Rw, Absent, true, "15-3-1: 2060-04 torque limit (%); 15-4: RW, U16")
        .named("Torque limit"),
    row(0x2060, 5, I32, Rw, Absent, true, "15-4: 2060h sub 5, RW, S32, no definition")
        .named("Reserved command 5"),
    row(0x2061, 3, U16, Ro, Absent, true, "15-4: 2061h sub 3 actual output frequency, R, U16")
        .named("Actual output frequency"),
    row(0x6007, 0, I16, Rw, Int(2), true, "15-4 DS402 table: 2, RW, S16, mappable")
        .named("Abort connection option code"),
    row(0x603F, 0, U16, Ro, Int(0), true, "15-4 DS402 table: error code, 0, R0 (RO), U16, mappable")
        .named("Error code"),
    row(0x6041, 0, U16, Ro, Int(0), true, "15-4 DS402 table: status word, 0, RO, U16, mappable")
        .named("Statusword"),
    row(0x6043, 0, I16, Ro, Int(0), true, "15-4 DS402 table: 0, RO, S16 rpm, mappable")
        .named("vl velocity demand"),
    row(0x6044, 0, I16, Ro, Int(0), true, "15-4 DS402 table: 0, RO, S16 rpm, mappable")
        .named("vl control effort"),
    row(0x6050, 0, U32, Rw, Int(10000), true, "15-4 DS402 table: 10000, RW, U32 1 ms, mappable")
        .named("vl slow down time"),
    row(0x605C, 0, I16, Rw, Int(1), false, "15-3-2-2 and 15-4: 1, RW, S16, not mappable")
        .named("Disable operation option code"),
    row(0x6060, 0, I8, Rw, Int(2), true, "15-4 DS402 table and 15-3-2-3: 2 (velocity), RW, S8")
        .named("Modes of operation"),
];

#[test]
fn entries_match_the_manual() {
    check_rows(&read(EDS).device, ROWS);
}

#[test]
fn objects_the_manual_does_not_list_are_absent() {
    let device = read(EDS).device;
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
    assert_eq!(
        subs(&device, 0x2026),
        vec![0, 0x01, 0x02, 0x41, 0x61, 0x62, 0xA1, 0xA2]
    );
}

#[test]
fn default_pdos_are_the_manuals() {
    let device = read(EDS).device;
    // The manual gives no default mapping: every mapping object maps nothing and has four
    // entries (this file's choice, see [Comments]).
    for index in (0x1600..=0x1603).chain(0x1A00..=0x1A03) {
        assert_eq!(mapped(&device, index), vec![], "{index:04X}h");
        assert_eq!(subs(&device, index), vec![0, 1, 2, 3, 4], "{index:04X}h");
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
        assert_eq!(
            default_value(&device, index, 1),
            Some(Value::NodeRelative(offset)),
            "{index:04X}h sub 1"
        );
    }
    // TPDO records: sub 0, 1, 2, 3, 5 (CiA 301 reserves sub 4; DS301 V4.02 has no sub 6).
    for index in 0x1800..=0x1803 {
        assert_eq!(subs(&device, index), vec![0, 1, 2, 3, 5], "{index:04X}h");
    }
}

#[test]
fn device_info_follows_the_manual() {
    let device = read(EDS).device;
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
    assert_eq!(baud_rates(&device), vec![50, 125, 250, 500, 1000]);
}

#[test]
fn model_snapshot() {
    let device = read(EDS).device;
    insta::assert_json_snapshot!("ms300_model", dump(&device, EDS));
}

#[test]
fn reads_and_validates_clean() {
    assert_eq!(warnings_and_errors(&read(EDS)), Vec::<Finding>::new());
}
