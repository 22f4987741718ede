//! `eds/rd11.eds` (RD11 option CANopen card) checked against its manual (seed 003): the
//! communication objects of section 3.1.2, the parameter index rules of sections 3.1.3-3.1.4
//! (F groups, power-down-save groups, C00 monitoring, the 0x3000 address group), the default PDO
//! mapping of Table 3.9, the model dump (snapshot), and the validator's verdict.

mod card_support;

use card_support::{
    above_info, baud_rates, check_absent, check_rows, dump, integer_default, read, row,
    warnings_and_errors, DefaultValue, Finding, Row,
};
use edsgen_model::model::{AccessType, BasicType, ObjectType};

use AccessType::{Ro, Rw, Wo};
use BasicType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use DefaultValue::{Absent, Int, NodeId};

/// The EDS under test, relative to the package root.
const EDS: &str = "eds/rd11.eds";

#[rustfmt::skip]
const ROWS: &[Row] = &[
    row(0x1000, 0, U32, Ro, Int(0), false, "no device profile is documented"),
    row(0x1001, 0, U8, Ro, Int(0), false, "3.1.7: error register 1001H"),
    row(0x1005, 0, U32, Rw, Int(0x80), false, "3.1.2 2): SYNC 0x080"),
    row(0x1014, 0, U32, Ro, NodeId(0x80), false, "3.1.2 5): EMCY 0x80+NodeID"),
    row(0x1017, 0, U16, Rw, Int(0), false, "3.1.1, 3.3.6: heartbeat"),
    row(0x1018, 1, U32, Ro, Int(0), false, "vendor-ID not given: placeholder"),
    row(0x1200, 1, U32, Ro, NodeId(0x600), false, "3.1.2 3): SDO 0x600+NodeID"),
    row(0x1200, 2, U32, Ro, NodeId(0x580), false, "3.1.2 3): SDO 0x580+NodeID"),
    row(0x1400, 1, U32, Rw, NodeId(0x200), false, "3.1.2 4): RPDO1 0x200+NodeID"),
    row(0x1400, 2, U8, Rw, Int(255), false, "Table 3.9: RPDO1 asynchronous"),
    row(0x1403, 1, U32, Rw, NodeId(0x500), false, "3.1.2 4): RPDO4 0x500+NodeID"),
    row(0x1800, 1, U32, Rw, NodeId(0x180), false, "3.1.2 4): TPDO1 0x180+NodeID"),
    row(0x1800, 2, U8, Rw, Int(255), false, "Tables 3.8/3.9: asynchronous timing"),
    row(0x1800, 3, U16, Rw, Int(0), false, "Table 3.8: suppression time"),
    row(0x1800, 5, U16, Rw, Int(100), false, "Table 3.9: TPDO1 period 100 ms"),
    row(0x1801, 1, U32, Rw, NodeId(0x280), false, "3.1.2 4): TPDO2 0x280+NodeID"),
    row(0x1801, 5, U16, Rw, Int(100), false, "Table 3.9: TPDO2 period 100 ms"),
    row(0x1802, 5, U16, Rw, Int(100), false, "Table 3.9: TPDO3 period 100 ms"),
    row(0x1803, 1, U32, Rw, NodeId(0x480), false, "3.1.2 4): TPDO4 0x480+NodeID"),
    row(0x1803, 5, U16, Rw, Int(0), false, "Table 3.9: TPDO4 not listed"),
    row(0x2000, 0, U8, Ro, Int(100), false, "3.1.3: F00 group, 100 entries"),
    row(0x2001, 6, U16, Rw, Absent, false, "3.1.3 3): F01.05 = 2001_06h"),
    row(0x2002, 3, U16, Rw, Absent, false, "3.1.4 2)/3): F02.02 = 2002_03H"),
    row(0x2001, 2, U16, Rw, Absent, false, "3.2.1 Table 3.14: F01.01 run command"),
    row(0x2001, 3, U16, Rw, Absent, false, "3.2.1 Table 3.14: F01.02 frequency source"),
    row(0x2001, 0xB, U16, Rw, Absent, false, "3.2.1 Table 3.14: F01.10 max frequency"),
    row(0x2003, 0x2A, U16, Rw, Absent, false, "3.2.1 Table 3.14: F03.41 torque command"),
    row(0x2003, 0x3A, U16, Rw, Absent, false, "3.2.1 Table 3.14: F03.57"),
    row(0x200C, 0x2B, U16, Rw, Absent, false, "3.2.1 Table 3.14: F12.42 baud rate"),
    row(0x200D, 3, U16, Rw, Absent, false, "3.1.3 Table 3.1: F13.02"),
    row(0x2010, 1, U16, Rw, Absent, false, "3.1.3: F16 = 0x2010"),
    row(0x201F, 100, U16, Rw, Absent, false, "3.1.3: F31 = 0x201F, F31.99"),
    row(0x20F0, 1, U16, Wo, Absent, false, "3.1.3: F00 power-down save 0x20F0"),
    row(0x20FF, 100, U16, Wo, Absent, false, "3.1.3: F15 power-down save 0x20FF"),
    row(0x20A0, 1, U16, Wo, Absent, false, "3.1.3: F16 power-down save 0x20A0"),
    row(0x20AF, 100, U16, Wo, Absent, false, "3.1.3: F31 power-down save 0x20AF"),
    row(0x2021, 0, U8, Ro, Int(27), false, "3.1.4 4): C00.00-C00.26"),
    row(0x2021, 2, U16, Ro, Absent, true, "Table 3.9: C00.01 output frequency"),
    row(0x2021, 0x1B, U16, Ro, Absent, true, "3.1.4 4): C00.26 = 2021h:1B"),
    row(0x2030, 0, U8, Ro, Int(7), false, "3.1.4 5): 0x3000 group, up to 0x3006"),
    row(0x2030, 1, U16, Rw, Absent, true, "Table 3.9: 0x3000 frequency command"),
    row(0x2030, 2, U16, Rw, Absent, true, "Table 3.9: 0x3001 control command"),
    row(0x2030, 3, U16, Ro, Absent, true, "Tables 3.9/3.10: 0x3002 status"),
    row(0x2030, 4, U16, Ro, Absent, true, "Table 3.9; 3.1.7 2): 0x3003 fault"),
    row(0x2030, 6, U16, Rw, Absent, true, "Table 3.9: 0x3005 torque feeding"),
    row(0x2030, 7, U16, Rw, Absent, true, "3.1.4 5): 0x3006 = 2030h:07"),
];

/// Entries the file leaves out on purpose.
const ABSENT: &[(u16, u8, &str)] = &[
    (0x2030, 5, "0x3004 is not documented"),
    (0x2000, 101, "parameter numbers stop at 99"),
    (0x2021, 0x1C, "C00.27 is not documented"),
    (0x2022, 0, "only C00 is documented"),
    (0x100C, 0, "node guarding is not mentioned"),
    (0x1400, 5, "RPDO event timer is not mentioned"),
    (0x1800, 4, "TPDO sub4 is reserved by CiA 301"),
];

#[test]
fn objects_match_the_manual() {
    let device = read(EDS).device;
    check_rows(&device, ROWS);
    check_absent(&device, ABSENT);
}

#[test]
fn every_function_code_group_has_a_parameter_and_a_save_index() {
    // 3.1.3: F00-F15 -> 2000h-200Fh and 20F0h-20FFh; F16-F31 -> 2010h-201Fh and 20A0h-20AFh.
    // Each is an ARRAY of 100 UNSIGNED16 entries (sub-index = parameter number + 1).
    let device = read(EDS).device;
    for group in 0u16..32 {
        let save = if group < 16 {
            0x20F0 + group
        } else {
            0x20A0 + group - 16
        };
        for (index, access) in [(0x2000 + group, AccessType::Rw), (save, AccessType::Wo)] {
            let object = &device.objects[&index];
            assert_eq!(object.object_type, ObjectType::Array, "{index:04X}h");
            assert_eq!(object.subs.len(), 101, "{index:04X}h: sub0 + 100 entries");
            assert!(
                object.name.starts_with(&format!("F{group:02}")),
                "{index:04X}h is named {}",
                object.name
            );
            for sub in 1..=100u8 {
                let entry = &object.subs[&sub];
                assert_eq!(entry.data_type, Some(BasicType::Unsigned16.index()));
                assert_eq!(entry.access, Some(access), "{index:04X}h:{sub}");
                assert!(!entry.pdo_mapping);
            }
        }
    }
}

#[test]
fn sdo_examples_address_existing_entries() {
    // 3.1.4: the index/sub-index bytes of every SDO example frame name an entry of the file, of
    // the 2-byte type their 4B answers carry.
    let device = read(EDS).device;
    for frame in [
        [0x40u8, 0x02, 0x20, 0x03, 0x00, 0x00, 0x00, 0x00], // read F02.02
        [0x2B, 0x02, 0x20, 0x03, 0x03, 0x00, 0x00, 0x00],   // write 3 to F02.02
        [0x40, 0x21, 0x20, 0x1B, 0x00, 0x00, 0x00, 0x00],   // read C00.26
        [0x40, 0x30, 0x20, 0x07, 0x00, 0x00, 0x00, 0x00],   // read 0x3006
        [0x2B, 0x30, 0x20, 0x07, 0x64, 0x00, 0x00, 0x00],   // write 100 to 0x3006
    ] {
        let index = u16::from_le_bytes([frame[1], frame[2]]);
        let entry = device
            .entry(index, frame[3])
            .unwrap_or_else(|| panic!("{index:04X}h:{:02X}", frame[3]));
        assert_eq!(entry.data_type, Some(BasicType::Unsigned16.index()));
        let access = entry.access.expect("access");
        if frame[0] == 0x40 {
            assert!(access.readable(), "{index:04X}h:{:02X}", frame[3]);
        } else {
            assert!(access.writable(), "{index:04X}h:{:02X}", frame[3]);
        }
    }
}

/// Table 3.9, in its column order.
const MAPPINGS: &[(u16, &[u32], &str)] = &[
    (
        0x1600,
        &[0x2030_0210, 0x2030_0110, 0x2030_0610],
        "RPDO1: control 0x3001, frequency 0x3000, torque 0x3005",
    ),
    (0x1601, &[], "RPDO2: no default mapping"),
    (0x1602, &[], "RPDO3: no default mapping"),
    (0x1603, &[], "RPDO4: no default mapping"),
    (
        0x1A00,
        &[0x2030_0310, 0x2021_0310, 0x2021_0210, 0x2021_0610],
        "TPDO1: status 0x3002, C00.02, C00.01, C00.05",
    ),
    (
        0x1A01,
        &[0x2021_0B10, 0x2021_0410, 0x2030_0410],
        "TPDO2: C00.10, C00.03, fault code 0x3003",
    ),
    (
        0x1A02,
        &[0x2021_0810, 0x2021_0C10, 0x2021_0510, 0x2021_0D10],
        "TPDO3: C00.07, C00.11, C00.04, C00.12",
    ),
    (0x1A03, &[], "TPDO4: no default mapping"),
];

#[test]
fn default_pdo_mappings_follow_table_3_9() {
    let device = read(EDS).device;
    for (index, entries, source) in MAPPINGS {
        let at = format!("{index:04X}h ({source})");
        assert_eq!(
            integer_default(&device, *index, 0),
            Some(entries.len() as i128),
            "{at}: sub0"
        );
        // Four 16-bit entries fill the 64 bits a PDO carries (3.1.6); unused ones are 0.
        for sub in 1..=4u8 {
            let expected = entries.get(usize::from(sub) - 1).copied().unwrap_or(0);
            assert_eq!(
                integer_default(&device, *index, sub),
                Some(i128::from(expected)),
                "{at}: sub{sub}"
            );
        }
        assert_eq!(device.objects[index].subs.len(), 5, "{at}");
        // Every mapped entry exists, is mappable and is 16 bits wide.
        for word in entries.iter() {
            let (target, sub, bits) = ((word >> 16) as u16, (word >> 8) as u8, *word as u8);
            let entry = device.entry(target, sub).expect("mapped entry exists");
            assert!(entry.pdo_mapping, "{target:04X}h:{sub:02X}");
            assert_eq!(entry.data_type, Some(BasicType::Unsigned16.index()));
            assert_eq!(bits, 16);
            let writable = entry.access.is_some_and(AccessType::writable);
            assert_eq!(
                writable,
                *index < 0x1800,
                "{target:04X}h:{sub:02X} direction"
            );
        }
    }
}

#[test]
fn mapped_entries_are_named_after_table_3_9() {
    let device = read(EDS).device;
    for (index, sub, name) in [
        (0x2030u16, 2u8, "Control command (0x3001)"),
        (0x2030, 1, "Frequency command (0x3000)"),
        (0x2030, 3, "Operation status (0x3002)"),
        (0x2030, 4, "Fault code (0x3003)"),
        (0x2021, 3, "Output current (C00.02)"),
        (0x2021, 0xD, "Module temperature (C00.12)"),
        (0x2021, 0x1B, "Inverter rated voltage (C00.26)"),
    ] {
        assert_eq!(
            device.entry(index, sub).map(|e| e.name.as_str()),
            Some(name)
        );
    }
}

#[test]
fn device_info_matches_the_manual() {
    let device = read(EDS).device;
    let info = &device.device_info;
    // Table 1.2, Tables 3.1/3.2: 20k, 50k, 100k, 125k, 250k, 500k, 1M; 100k has no CiA 306 key.
    assert_eq!(baud_rates(&device), [20, 50, 125, 250, 500, 1000]);
    // 3.1.1: 4 TPDO, 4 RPDO.
    assert_eq!(info.nr_of_rx_pdo.as_ref().map(|s| s.value), Some(4));
    assert_eq!(info.nr_of_tx_pdo.as_ref().map(|s| s.value), Some(4));
    assert!(device.dummy_usage.values().all(|on| !on));
}

#[test]
fn validates_without_warnings_or_errors() {
    assert_eq!(warnings_and_errors(&read(EDS)), Vec::<Finding>::new());
}

#[test]
fn reads_without_diagnostics_above_info() {
    let read = read(EDS);
    assert_eq!(above_info(&read.diagnostics), Vec::<Finding>::new());
}

/// Whether `index` is one of the 64 function-code group arrays (parameters or power-down save).
fn is_parameter_group(index: u16) -> bool {
    matches!(index, 0x2000..=0x201F | 0x20A0..=0x20AF | 0x20F0..=0x20FF)
}

#[test]
fn dump_snapshot() {
    let device = read(EDS).device;
    let mut dump = dump(&device, EDS);
    // The 64 parameter-group arrays hold 6400 implied entries that differ only in name and
    // sub-index (every_function_code_group_has_a_parameter_and_a_save_index checks them all);
    // the snapshot keeps sub 0, 1 and 100 of each so that it stays reviewable.
    let objects = dump["objects"].as_array_mut().expect("objects array");
    let mut trimmed = 0;
    for object in objects.iter_mut() {
        let index = object["index"].as_u64().expect("index") as u16;
        if !is_parameter_group(index) {
            continue;
        }
        let subs = object["subs"].as_array_mut().expect("subs array");
        assert_eq!(subs.len(), 101, "{index:04X}h");
        subs.retain(|sub| matches!(sub["sub"].as_u64(), Some(0 | 1 | 100)));
        trimmed += 1;
    }
    assert_eq!(trimmed, 64);
    insta::assert_json_snapshot!("rd11_dump", dump);
}

#[test]
fn generated_names_follow_the_manuals_parameter_numbers() {
    // The overlay eds/rd11.toml: sub-index = parameter number + 1 (3.1.3), so F28.85 is
    // 201Ch sub 86, and the manual's example F01.05 is 2001h:06.
    use edsgen_sim::cards::rd11::od;
    assert_eq!((od::f28::F28_85.index, od::f28::F28_85.sub), (0x201C, 86));
    assert_eq!((od::f01::F01_05.index, od::f01::F01_05.sub), (0x2001, 6));
    assert_eq!((od::f02::F02_02.index, od::f02::F02_02.sub), (0x2002, 3));
    assert_eq!(
        (
            od::f00_save::F00_SAVE_00.index,
            od::f00_save::F00_SAVE_00.sub
        ),
        (0x20F0, 1)
    );
    assert_eq!(
        (
            od::f31_save::F31_SAVE_99.index,
            od::f31_save::F31_SAVE_99.sub
        ),
        (0x20AF, 100)
    );
}
