//! `eds/goodrive350.eds` (INVT EC-TX105 CANopen card on Goodrive350 VFDs) checked against its
//! manual (seed 002, chapter 3 and Appendix A): object by object, the default PDO mappings
//! against the manual's example frames, the model dump (snapshot), and the validator's verdict.

mod card_support;

use card_support::{
    above_info, baud_rates, check_absent, check_rows, cob_id, decode, dump, integer_default,
    key_line, node_relative, read, row, subs, warnings_and_errors, DefaultValue, Finding, Row,
};
use edsgen_model::diag::Severity;
use edsgen_model::model::{AccessType, BasicType};

use AccessType::{Const, Ro, Rw};
use BasicType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8, VisibleString as Str};
use DefaultValue::{Absent, Int, NodeId, Text};

/// The EDS under test, relative to the package root.
const EDS: &str = "eds/goodrive350.eds";

#[rustfmt::skip]
const ROWS: &[Row] = &[
    row(0x1000, 0, U32, Ro, Int(0), false, "App. A: device type 0x0000 0000"),
    row(0x1001, 0, U8, Ro, Int(0), false, "App. A: error register; Table 3-7"),
    row(0x1003, 0, U8, Rw, Int(0), false, "App. A: error code register, sub0 RW"),
    row(0x1003, 1, U32, Ro, Int(0), false, "App. A: error code register, sub1 RO"),
    row(0x1005, 0, U32, Rw, Int(0x80), false, "App. A; 3.4.7: COB-ID SYNC 0x80"),
    row(0x1008, 0, Str, Const, Text("INVT CANopen"), false, "App. A: device name"),
    row(0x1009, 0, Str, Const, Text("V1.00"), false, "App. A: hardware version"),
    row(0x100A, 0, Str, Const, Text("V1.00"), false, "App. A: software version"),
    row(0x100C, 0, U16, Rw, Int(0), false, "App. A; 3.4.4: guard time"),
    row(0x100D, 0, U8, Rw, Int(0), false, "App. A; 3.4.4: life time factor (CiA 301 type)"),
    row(0x1014, 0, U32, Ro, NodeId(0x80), false, "3.4.1, 3.4.8: EMCY on 0x80+node-ID"),
    row(0x1016, 1, U32, Rw, Int(0), false, "App. A: consumer heartbeat time"),
    row(0x1017, 0, U16, Rw, Int(0), false, "App. A; 3.4.5: heartbeat 0 by default"),
    row(0x1018, 0, U8, Ro, Int(4), false, "App. A: identity, 4 sub-indices"),
    row(0x1018, 1, U32, Ro, Int(0), false, "App. A: supplier ID 0x0000 0000"),
    row(0x1018, 2, U32, Ro, Int(0), false, "App. A: product code 0x0000 0000"),
    row(0x1018, 3, U32, Ro, Int(0), false, "App. A: revision 0x0000 0000"),
    row(0x1018, 4, U32, Ro, Int(0), false, "App. A: sequence no. 0x0000 0000"),
    row(0x1200, 1, U32, Ro, NodeId(0x600), false, "App. A: server SDO 600H+Node ID"),
    row(0x1200, 2, U32, Ro, NodeId(0x580), false, "App. A: server SDO 580H+Node ID"),
    row(0x1280, 3, U8, Ro, Int(0), false, "App. A: client SDO, node ID of server"),
    row(0x1400, 1, U32, Rw, NodeId(0x200), false, "App. A; 3.4.1: PDO1 Rx 0x201-0x27F"),
    row(0x1400, 2, U8, Rw, Int(255), false, "App. A: transmission type ('/': 255 chosen)"),
    row(0x1400, 5, U16, Rw, Int(0), false, "App. A: RPDO event timer"),
    row(0x1401, 1, U32, Rw, NodeId(0x300), false, "3.4.1; 3.5.3: PDO2 Rx 0x300+NODEID"),
    row(0x1402, 1, U32, Rw, NodeId(0x400), false, "3.4.1; 3.5.5: PDO3 Rx 0x400+NODEID"),
    row(0x1403, 1, U32, Rw, NodeId(0x500), false, "3.4.1; 3.5.5: PDO4 Rx 0x500+NODEID"),
    row(0x1800, 1, U32, Rw, NodeId(0x180), false, "3.4.1; 3.5.2.2: PDO1 Tx 0x180+NODEID"),
    row(0x1800, 2, U8, Rw, Int(255), false, "App. A; Table 3-12: PDO1 Tx type 255"),
    row(0x1800, 3, U16, Rw, Int(500), false, "App. A; Table 3-12: disabled time 500"),
    row(0x1800, 4, U8, Rw, Int(0), false, "App. A: sub4 reserved, RW Unsigned8"),
    row(0x1800, 5, U16, Rw, Int(0), false, "App. A; Table 3-12: event timer 0"),
    row(0x1801, 1, U32, Rw, NodeId(0x280), false, "3.4.1; 3.5.4: PDO2 Tx 0x280+NODEID"),
    row(0x1801, 2, U8, Rw, Int(254), false, "App. A; Table 3-12; 3.5.4: type 254"),
    row(0x1801, 3, U16, Rw, Int(500), false, "App. A; 3.4.9: 1801h:03 disabled time"),
    row(0x1802, 1, U32, Rw, NodeId(0x380), false, "3.4.1; 3.5.6: PDO3 Tx 0x380+NODEID"),
    row(0x1802, 2, U8, Rw, Int(254), false, "App. A; 3.5.6: type 254"),
    row(0x1802, 5, U16, Rw, Int(0), false, "Tables 3-11/3-12: event timer 0"),
    row(0x1803, 1, U32, Rw, NodeId(0x480), false, "3.4.1; 3.5.6: PDO4 Tx 0x480+NODEID"),
    row(0x1803, 5, U16, Rw, Int(0), false, "Tables 3-11/3-12: event timer 0"),
    row(0x2000, 0, U16, Ro, Absent, true, "Table 3-20; 3.5.2.2: response code"),
    row(0x2000, 1, U16, Ro, Absent, true, "Table 3-20; 3.5.2.2: error code"),
    row(0x2000, 2, U16, Ro, Absent, true, "Table 3-20; 3.5.2.2: response data"),
    row(0x2000, 3, U16, Ro, Absent, true, "Table 3-20; 3.5.4: returned value 1"),
    row(0x2000, 0xD, U16, Ro, Absent, true, "Table 3-20; 3.5.6: returned value 11"),
    row(0x2000, 0xF, U16, Ro, Absent, false, "Table 3-20: reserved"),
    row(0x2001, 0, U16, Ro, Absent, true, "Table 3-20; 3.5.4; 3.6 ex. 3: SW"),
    row(0x2100, 0, U16, Rw, Absent, true, "Table 3-19; 3.5.2.1: request code"),
    row(0x2100, 1, U16, Rw, Absent, true, "Table 3-19; 3.5.2.1: parameter address"),
    row(0x2100, 2, U16, Rw, Absent, true, "Table 3-19; 3.5.2.1: requested data"),
    row(0x2100, 3, U16, Rw, Absent, true, "Table 3-19; 3.6 ex. 2: setting 1"),
    row(0x2100, 0xD, U16, Rw, Absent, true, "Table 3-19; 3.5.5: setting 11"),
    row(0x2100, 0xE, U16, Rw, Absent, false, "Table 3-19: reserved"),
    row(0x2101, 0, U16, Rw, Absent, true, "Table 3-19; 3.5.3; 3.6 ex. 1: CW"),
];

/// Entries the manual says do not exist.
const ABSENT: &[(u16, u8, &str)] = &[
    (
        0x6000,
        0,
        "3.4.9: read of 6000h:00 is answered with abort 0602 0000",
    ),
    (0x1400, 3, "App. A: RPDO sub3 has no access ('/')"),
    (0x1400, 4, "App. A: RPDO sub4 has no access ('/')"),
    (
        0x1010,
        1,
        "3.2: saving OD parameters at power loss is not supported",
    ),
    (0x1012, 0, "3.2: the time stamp service is not supported"),
];

#[test]
fn objects_match_the_manual() {
    let device = read(EDS).device;
    check_rows(&device, ROWS);
    check_absent(&device, ABSENT);
}

#[test]
fn manufacturer_records_cover_sub_indices_0_to_f() {
    // Tables 3-19 and 3-20 list sub-indices 0..F of 2100h and 2000h.
    let device = read(EDS).device;
    for index in [0x2000u16, 0x2100] {
        assert_eq!(
            subs(&device, index),
            (0..=0xF).collect::<Vec<u8>>(),
            "{index:04X}h"
        );
    }
    // Setting k is 2100h sub k+2 (received PZD k+1), returned value k is 2000h sub k+2
    // (transmitted PZD k+1), k = 1..11 (Tables 3-19, 3-20, 3-22, 3-23).
    for k in 1..=11u8 {
        let setting = device.entry(0x2100, k + 2).map(|e| e.name.as_str());
        assert_eq!(setting, Some(format!("Setting {k}").as_str()));
        let returned = device.entry(0x2000, k + 2).map(|e| e.name.as_str());
        assert_eq!(returned, Some(format!("Returned value {k}").as_str()));
    }
}

/// Default mappings: Appendix A 1600h-1A03h, with the two completions the file's comments explain.
const MAPPINGS: &[(u16, &[u32], &str)] = &[
    (
        0x1600,
        &[0x2100_0010, 0x2100_0110, 0x2100_0210],
        "App. A; 3.5.2.1",
    ),
    (
        0x1601,
        &[0x2101_0010, 0x2100_0310, 0x2100_0410, 0x2100_0510],
        "App. A; 3.5.3",
    ),
    (
        0x1602,
        &[0x2100_0610, 0x2100_0710, 0x2100_0810, 0x2100_0910],
        "App. A; 3.5.5",
    ),
    (
        0x1603,
        &[0x2100_0A10, 0x2100_0B10, 0x2100_0C10, 0x2100_0D10],
        "App. A sub1-3; 3.5.5 gives sub4 (setting 11)",
    ),
    (
        0x1A00,
        &[0x2000_0010, 0x2000_0110, 0x2000_0210, 0x0006_0010],
        "App. A sub1-3; 3.5.2.2 Byte6-7 reserved: 16-bit dummy",
    ),
    (
        0x1A01,
        &[0x2001_0010, 0x2000_0310, 0x2000_0410, 0x2000_0510],
        "App. A; 3.5.4",
    ),
    (
        0x1A02,
        &[0x2000_0610, 0x2000_0710, 0x2000_0810, 0x2000_0910],
        "App. A; 3.5.6",
    ),
    (
        0x1A03,
        &[0x2000_0A10, 0x2000_0B10, 0x2000_0C10, 0x2000_0D10],
        "App. A; 3.5.6",
    ),
];

#[test]
fn default_pdo_mappings_match_the_manual() {
    let device = read(EDS).device;
    for (index, entries, source) in MAPPINGS {
        let at = format!("{index:04X}h ({source})");
        assert_eq!(
            integer_default(&device, *index, 0),
            Some(entries.len() as i128),
            "{at}: sub0"
        );
        for (i, expected) in entries.iter().enumerate() {
            let sub = i as u8 + 1;
            let entry = device.entry(*index, sub).expect("mapping entry");
            assert_eq!(
                entry.data_type,
                Some(BasicType::Unsigned32.index()),
                "{at}:{sub}"
            );
            assert_eq!(
                entry.access,
                Some(AccessType::Rw),
                "{at}:{sub}: App. A says RW"
            );
            assert_eq!(
                integer_default(&device, *index, sub),
                Some(*expected as i128),
                "{at}: sub{sub}"
            );
        }
        assert_eq!(
            device.objects[index].subs.len(),
            entries.len() + 1,
            "{at}: no spare entries"
        );
    }
}

#[test]
fn sdo_and_emcy_cob_ids_match_the_examples_for_node_3() {
    let device = read(EDS).device;
    // 3.4.9: requests on 0x603, answers on 0x583.
    assert_eq!(node_relative(&device, 0x1200, 1, 3), 0x603);
    assert_eq!(node_relative(&device, 0x1200, 2, 3), 0x583);
    // 3.4.8: EMCY of node 3 on 0x83.
    assert_eq!(node_relative(&device, 0x1014, 0, 3), 0x83);
}

#[test]
fn pdo1_rx_frame_sets_p15_13_to_1() {
    // 3.5.2.1 example: 203: 02 00 0D 0F 01 00 (request 2 = write, address 0x0F0D = P15.13, data 1).
    let device = read(EDS).device;
    assert_eq!(cob_id(&device, 0x1400, 3), 0x203);
    assert_eq!(
        decode(&device, 0x1600, &[0x02, 0x00, 0x0D, 0x0F, 0x01, 0x00]),
        vec![((0x2100, 0), 2), ((0x2100, 1), 0x0F0D), ((0x2100, 2), 1)]
    );
}

#[test]
fn pdo1_tx_frame_answers_the_write() {
    // 3.5.2.2 example: 183: 01 00 00 00 01 00 00 00 (response 1 = success, error 0, data 1).
    let device = read(EDS).device;
    assert_eq!(cob_id(&device, 0x1800, 3), 0x183);
    assert_eq!(
        decode(
            &device,
            0x1A00,
            &[0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00]
        ),
        vec![
            ((0x2000, 0), 1),
            ((0x2000, 1), 0),
            ((0x2000, 2), 1),
            ((0x0006, 0), 0)
        ]
    );
}

#[test]
fn pdo2_rx_frame_runs_forward_at_50_hz() {
    // 3.5.3 example: 303: 01 00 00 00 88 13 00 00 (CW 1 = forward, setting 2 = 5000 = 50.00 Hz).
    let device = read(EDS).device;
    assert_eq!(cob_id(&device, 0x1401, 3), 0x303);
    assert_eq!(
        decode(
            &device,
            0x1601,
            &[0x01, 0x00, 0x00, 0x00, 0x88, 0x13, 0x00, 0x00]
        ),
        vec![
            ((0x2101, 0), 1),
            ((0x2100, 3), 0),
            ((0x2100, 4), 5000),
            ((0x2100, 5), 0)
        ]
    );
}

#[test]
fn pdo2_tx_frame_reports_50_hz_and_380_v() {
    // 3.5.4 example: 283: 01 01 88 13 7C 01 00 00 (SW 0x0101, returned values 5000, 380, 0).
    let device = read(EDS).device;
    assert_eq!(cob_id(&device, 0x1801, 3), 0x283);
    assert_eq!(
        decode(
            &device,
            0x1A01,
            &[0x01, 0x01, 0x88, 0x13, 0x7C, 0x01, 0x00, 0x00]
        ),
        vec![
            ((0x2001, 0), 0x0101),
            ((0x2000, 3), 5000),
            ((0x2000, 4), 380),
            ((0x2000, 5), 0)
        ]
    );
}

#[test]
fn pdo3_and_pdo4_carry_settings_and_returned_values_4_to_11() {
    // 3.5.5 and 3.5.6: four 16-bit words each, in order.
    let device = read(EDS).device;
    let frame = [0x01, 0x00, 0x02, 0x00, 0x03, 0x00, 0x04, 0x00];
    for (comm, mapping, base, first_sub, cob) in [
        (0x1402u16, 0x1602u16, 0x2100u16, 6u8, 0x403u32),
        (0x1403, 0x1603, 0x2100, 0xA, 0x503),
        (0x1802, 0x1A02, 0x2000, 6, 0x383),
        (0x1803, 0x1A03, 0x2000, 0xA, 0x483),
    ] {
        assert_eq!(cob_id(&device, comm, 3), cob);
        let expected: Vec<_> = (0..4u8)
            .map(|i| ((base, first_sub + i), u64::from(i) + 1))
            .collect();
        assert_eq!(decode(&device, mapping, &frame), expected, "{mapping:04X}h");
    }
}

#[test]
fn device_info_matches_the_manual() {
    let device = read(EDS).device;
    let info = &device.device_info;
    // Table 3-1: 1000/800/500/250/125/100/50/20 kbit/s; 100 has no CiA 306 key.
    assert_eq!(baud_rates(&device), [20, 50, 125, 250, 500, 800, 1000]);
    // 3.2: four PDO pairs.
    assert_eq!(info.nr_of_rx_pdo.as_ref().map(|s| s.value), Some(4));
    assert_eq!(info.nr_of_tx_pdo.as_ref().map(|s| s.value), Some(4));
    // App. A: 1018h defaults are all 0.
    assert_eq!(info.vendor_number.as_ref().map(|s| s.value), Some(0));
    assert_eq!(info.product_number.as_ref().map(|s| s.value), Some(0));
    assert!(!info.lss_supported);
    // Only the UNSIGNED16 dummy of 1A00h sub4 is enabled.
    let dummies: Vec<u16> = device
        .dummy_usage
        .iter()
        .filter(|(_, on)| **on)
        .map(|(t, _)| *t)
        .collect();
    assert_eq!(dummies, [0x0006]);
}

#[test]
fn validates_with_only_the_card_s_own_deviation_from_cia_301() {
    // 2000h:00 and 2100h:00 are 16-bit data on this card (Tables 3-19/3-20, App. A 1600h/1A00h),
    // not the UNSIGNED8 number of entries; the file describes them as they are, and its
    // [Comments] say so.
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
    insta::assert_json_snapshot!("goodrive350_dump", dump(&device, EDS));
}
