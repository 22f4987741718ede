//! The generated code at work: `tests/generated/gd350.rs` (kept current by `emit_model.rs`)
//! compiled against the runtime, its OD read/write semantics, typed addresses, and typed PDOs,
//! including the Goodrive350 manual's PDO2 frames.
#![deny(warnings, missing_docs)]

/// The generated module (a test binary uses only part of it, hence `dead_code`).
#[allow(dead_code)]
mod generated {
    include!("generated/gd350.rs");
}

use edsgen_runtime::{ObjectDictionary, PdoError, SdoAbort};
use generated::gd350::{self, od, pdo, Od};
use proptest::prelude::*;

fn read_all(od: &Od, index: u16, sub: u8) -> Vec<u8> {
    let mut buf = [0u8; 64];
    let n = od.read(index, sub, 0, &mut buf).unwrap();
    buf[..n].to_vec()
}

#[test]
fn goodrive_pdo2_rx_encodes_the_manual_frame() {
    let rpdo = pdo::Rpdo2 {
        control_word: 0x0001,
        setting_2: 5000,
        ..Default::default()
    };
    assert_eq!(
        rpdo.to_bytes(),
        [0x01, 0x00, 0x00, 0x00, 0x88, 0x13, 0x00, 0x00]
    );
    assert_eq!(pdo::Rpdo2::cob_id(3), 0x303);
    assert_eq!(pdo::Rpdo2::SIZE, 8);
}

#[test]
fn goodrive_pdo2_tx_decodes_the_manual_frame() {
    let tpdo = pdo::Tpdo2::from_slice(&[0x01, 0x01, 0x88, 0x13, 0x7C, 0x01, 0x00, 0x00]).unwrap();
    assert_eq!(
        tpdo,
        pdo::Tpdo2 {
            status_word: 0x0101,
            returned_value_1: 5000,
            returned_value_2: 380,
            returned_value_3: 0,
        }
    );
    assert_eq!(pdo::Tpdo2::cob_id(3), 0x283);
}

#[test]
fn pdo_of_wrong_length_is_an_error() {
    assert_eq!(
        pdo::Tpdo2::from_slice(&[1, 2, 3]),
        Err(PdoError::WrongLength {
            expected: 8,
            actual: 3
        })
    );
    assert_eq!(
        pdo::Tpdo3::from_slice(&[0; 7]),
        Err(PdoError::WrongLength {
            expected: 6,
            actual: 7
        })
    );
}

#[test]
fn non_aligned_pdo_is_bit_exact() {
    // nibble 4 bits, dummy 4 bits, INTEGER24 at bit 8, INTEGER8 at bit 32, BOOLEAN at bit 40.
    let t = pdo::Tpdo3 {
        nibble: 0xA,
        signed_24: -2,
        type_: -128,
        flag: true,
    };
    assert_eq!(t.to_bytes(), Ok([0x0A, 0xFE, 0xFF, 0xFF, 0x80, 0x01]));
    assert_eq!(
        pdo::Tpdo3::from_slice(&[0xFA, 0xFE, 0xFF, 0xFF, 0x80, 0x01]),
        Ok(t)
    );
    let too_wide = pdo::Tpdo3 { nibble: 0x10, ..t };
    assert_eq!(
        too_wide.to_bytes(),
        Err(PdoError::OutOfRange { field: "nibble" })
    );
    let too_big = pdo::Tpdo3 {
        signed_24: 1 << 23,
        ..t
    };
    assert_eq!(
        too_big.to_bytes(),
        Err(PdoError::OutOfRange { field: "signed_24" })
    );
}

#[test]
fn byte_string_field_at_an_odd_bit_offset() {
    // BOOLEAN at bit 0, a 4-byte OCTET_STRING at bit 1, INTEGER8 at bit 33.
    let t = pdo::Tpdo4 {
        flag: true,
        tag: [0x80, 0x01, 0xFF, 0x00],
        type_: -1,
    };
    assert_eq!(t.to_bytes(), [0x01, 0x03, 0xFE, 0x01, 0xFE, 0x01]);
    assert_eq!(
        pdo::Tpdo4::from_slice(&[0x01, 0x03, 0xFE, 0x01, 0xFE, 0x01]),
        Ok(t)
    );
}

proptest! {
    #[test]
    fn tpdo4_round_trips(flag in any::<bool>(), tag in any::<[u8; 4]>(), type_ in any::<i8>()) {
        let t = pdo::Tpdo4 { flag, tag, type_ };
        prop_assert_eq!(pdo::Tpdo4::from_slice(&t.to_bytes()), Ok(t));
    }

    #[test]
    fn tpdo3_round_trips(nibble in 0u8..16, signed_24 in -(1i32 << 23)..(1i32 << 23), type_ in any::<i8>(), flag in any::<bool>()) {
        let t = pdo::Tpdo3 { nibble, signed_24, type_, flag };
        let bytes = t.to_bytes().unwrap();
        prop_assert_eq!(pdo::Tpdo3::from_slice(&bytes), Ok(t));
    }

    #[test]
    fn rpdo2_round_trips(payload in any::<[u8; 8]>()) {
        let r = pdo::Rpdo2::from_slice(&payload).unwrap();
        prop_assert_eq!(r.to_bytes(), payload);
    }

    #[test]
    fn od_write_then_read_round_trips(value in any::<u16>()) {
        let mut od = Od::new(1);
        od.write(0x6040, 0, &value.to_le_bytes()).unwrap();
        prop_assert_eq!(od.get(od::CONTROLWORD), value);
        prop_assert_eq!(read_all(&od, 0x6040, 0), value.to_le_bytes().to_vec());
    }
}

#[test]
fn new_resolves_nodeid_defaults() {
    let od = Od::new(3);
    assert_eq!(od.get(od::COB_ID_EMCY), 0x83);
    assert_eq!(od.get(od::rpdo2_communication_parameter::COB_ID), 0x303);
    assert_eq!(Od::new(0x7F).get(od::COB_ID_EMCY), 0xFF);
    assert_eq!(od.get(od::identity_object::VENDOR_ID), 0x4D8);
    let name = od.get(od::MANUFACTURER_DEVICE_NAME);
    assert_eq!(name.as_str(), Some("GD350"));
    assert_eq!(od.get(od::sparse_record::SIGNED_24), -5);
    assert_eq!(od.get(od::sparse_record::BIG), 0xFFFF_FFFF_FFFF);
    assert!(od.get(od::FLAG));
    assert_eq!(od.get(od::GAIN), 1.5);
}

#[test]
fn identity_and_pdo_count_constants() {
    assert_eq!(gd350::VENDOR_ID, 0x4D8);
    assert_eq!(gd350::PRODUCT_CODE, 0x9252);
    assert_eq!(gd350::REVISION_NUMBER, 0x10001);
    assert_eq!((gd350::NR_OF_RXPDO, gd350::NR_OF_TXPDO), (1, 1));
}

#[test]
fn typed_addresses_name_index_and_sub() {
    let cw: edsgen_runtime::Entry<u16, Od> = od::CONTROLWORD;
    assert_eq!((cw.index, cw.sub), (0x6040, 0));
    // Unbranded, as a master's typed SDO access takes it.
    let s24: edsgen_runtime::Entry<i32> = od::sparse_record::SIGNED_24.unbranded();
    assert_eq!((s24.index, s24.sub), (0x2003, 1));
    assert_eq!(
        (od::STATUS_WORD_6041.index, od::STATUS_WORD_6041.sub),
        (0x6041, 0)
    );
    assert_eq!(
        (
            od::pre_defined_error_field::STANDARD_ERROR_FIELD_SUB2.index,
            od::pre_defined_error_field::STANDARD_ERROR_FIELD_SUB2.sub
        ),
        (0x1003, 2)
    );
}

#[test]
fn entries_are_sorted_and_found() {
    let od = Od::new(1);
    let entries: Vec<_> = edsgen_runtime::od::descriptors(&od)
        .map(|(_, e)| e)
        .collect();
    assert_eq!(entries.len(), od.entry_count());
    assert!(entries
        .windows(2)
        .all(|w| (w[0].index(), w[0].sub()) < (w[1].index(), w[1].sub())));
    let d = od.find(0x2003, 5).unwrap();
    assert_eq!(d.data_type(), edsgen_runtime::DataType::Unsigned64);
    assert_eq!(od.capacity(od.locate(0x2003, 5).unwrap()), Some(8));
    assert_eq!(od.find(0x2003, 3), Err(SdoAbort::NoSubIndex));
    assert_eq!(od.find(0x6000, 0), Err(SdoAbort::NoObject));
    let s = od.find(0x1009, 0).unwrap();
    let capacity = od.capacity(od.locate(0x1009, 0).unwrap());
    assert_eq!(
        (capacity, s.access()),
        (Some(32), edsgen_runtime::Access::Rw)
    );
}

/// `read` and `write` dispatch on the position in `ENTRIES`: every described entry is served at
/// its own address, and no two addresses share a value.
#[test]
fn every_entry_reads_and_writes_its_own_value() {
    let mut od = Od::new(3);
    let addresses: Vec<(u16, u8, usize)> = edsgen_runtime::od::descriptors(&od)
        .map(|(position, e)| (e.index(), e.sub(), od.capacity(position).unwrap()))
        .collect();
    let mut written = Vec::new();
    for (i, &(index, sub, size)) in addresses.iter().enumerate() {
        // A pattern unique to this entry (its position in the first byte); limited entries may
        // refuse it, which leaves them out of the check.
        let len = od.value_len(index, sub).unwrap().max(1).min(size);
        let pattern: Vec<u8> = (0..len)
            .map(|k| (i as u8).wrapping_add(k as u8 * 7))
            .collect();
        if od.write(index, sub, &pattern).is_ok() {
            assert_eq!(read_all(&od, index, sub), pattern, "{index:04X}h sub {sub}");
            written.push((index, sub, pattern));
        }
    }
    assert!(
        written.len() > addresses.len() / 2,
        "most entries take a write"
    );
    for (index, sub, pattern) in written {
        assert_eq!(read_all(&od, index, sub), pattern, "{index:04X}h sub {sub}");
    }
}

#[test]
fn read_gives_little_endian_bytes_and_honours_offset() {
    let od = Od::new(3);
    assert_eq!(read_all(&od, 0x1018, 1), vec![0xD8, 0x04, 0, 0]);
    assert_eq!(read_all(&od, 0x2003, 1), vec![0xFB, 0xFF, 0xFF]); // INTEGER24 -5: three bytes
    assert_eq!(read_all(&od, 0x2004, 0), vec![1]);
    assert_eq!(read_all(&od, 0x1008, 0), b"GD350".to_vec());
    let mut two = [0u8; 2];
    assert_eq!(od.read(0x1008, 0, 3, &mut two), Ok(2));
    assert_eq!(&two, b"50");
    assert_eq!(od.read(0x1008, 0, 9, &mut two), Ok(0));
    assert_eq!(od.value_len(0x1008, 0), Ok(5));
    assert_eq!(od.value_len(0x2003, 1), Ok(3));
    assert_eq!(od.read(0x2003, 4, 0, &mut two), Err(SdoAbort::NoSubIndex));
    assert_eq!(od.read(0x5FFF, 0, 0, &mut two), Err(SdoAbort::NoObject));
    assert_eq!(od.value_len(0x5FFF, 0), Err(SdoAbort::NoObject));
}

#[test]
fn write_checks_length() {
    let mut od = Od::new(3);
    assert_eq!(
        od.write(0x6040, 0, &[1, 2, 3]),
        Err(SdoAbort::LengthTooHigh)
    );
    assert_eq!(od.write(0x6040, 0, &[1]), Err(SdoAbort::LengthTooLow));
    assert_eq!(
        od.write(0x2003, 1, &[0, 0, 0, 0]),
        Err(SdoAbort::LengthTooHigh)
    );
    assert_eq!(od.get(od::CONTROLWORD), 0);
    assert_eq!(od.write(0x2003, 1, &[0x00, 0x00, 0x80]), Ok(()));
    assert_eq!(od.get(od::sparse_record::SIGNED_24), -(1 << 23));
    assert_eq!(od.write(0x2003, 5, &[1, 2, 3, 4, 5, 6, 7, 8]), Ok(()));
    assert_eq!(od.get(od::sparse_record::BIG), 0x0807_0605_0403_0201);
}

#[test]
fn write_checks_limits() {
    let mut od = Od::new(3);
    assert_eq!(
        od.write(0x2102, 0, &9u16.to_le_bytes()),
        Err(SdoAbort::ValueTooLow)
    );
    assert_eq!(
        od.write(0x2102, 0, &5001u16.to_le_bytes()),
        Err(SdoAbort::ValueTooHigh)
    );
    assert_eq!(od.get(od::SETTING_LIMITED), 100);
    assert_eq!(od.write(0x2102, 0, &5000u16.to_le_bytes()), Ok(()));
    assert_eq!(od.get(od::SETTING_LIMITED), 5000);
}

#[test]
fn write_strings_booleans_and_reals() {
    let mut od = Od::new(3);
    assert_eq!(od.write(0x1009, 0, b"2.0-rc1"), Ok(()));
    let version = od.get(od::MANUFACTURER_HARDWARE_VERSION);
    assert_eq!(version.as_str(), Some("2.0-rc1"));
    assert_eq!(od.value_len(0x1009, 0), Ok(7));
    assert_eq!(
        od.write(0x1009, 0, &[b'x'; 33]),
        Err(SdoAbort::LengthTooHigh)
    );
    assert_eq!(od.write(0x1008, 0, b"LONGER"), Err(SdoAbort::LengthTooHigh));
    assert_eq!(od.write(0x2004, 0, &[2]), Err(SdoAbort::InvalidValue));
    assert_eq!(od.write(0x2004, 0, &[0]), Ok(()));
    assert!(!od.get(od::FLAG));
    assert_eq!(od.write(0x2005, 0, &2.25f32.to_le_bytes()), Ok(()));
    assert_eq!(od.get(od::GAIN), 2.25);
    assert_eq!(od.write(0x2100, 3, &5000u16.to_le_bytes()), Ok(()));
    assert_eq!(od.get(od::settings::SETTING_3), 5000);
    assert_eq!(od.write(0x2100, 5, &[0, 0]), Err(SdoAbort::NoSubIndex));
}

#[test]
fn typed_address_of_a_narrow_entry_encodes_its_wire_width() {
    let mut dict = Od::new(3);
    let entry = od::sparse_record::SIGNED_24;
    assert_eq!(entry.wire_width(), Some(3));
    let mut buf = [0u8; 8];
    let n = entry.encode(&-300, &mut buf).unwrap();
    assert_eq!(dict.write(entry.index, entry.sub, &buf[..n]), Ok(()));
    assert_eq!(dict.get(entry), -300);
    assert_eq!(entry.encode(&(1 << 23), &mut buf), None);
    let back = read_all(&dict, entry.index, entry.sub);
    assert_eq!(entry.decode(&back), Some(-300));
}

#[test]
fn access_by_position_agrees_with_access_by_address_for_every_entry() {
    let mut by_position = Od::new(3);
    let mut by_address = Od::new(3);
    let entries: Vec<_> = edsgen_runtime::od::descriptors(&by_address)
        .map(|(_, e)| e)
        .collect();
    for (position, entry) in entries.iter().enumerate() {
        assert_eq!(by_address.locate(entry.index(), entry.sub()), Ok(position));
        let (mut a, mut b) = ([0u8; 64], [0u8; 64]);
        let read_a = by_position.read_at(position, 0, &mut a);
        let read_b = by_address.read(entry.index(), entry.sub(), 0, &mut b);
        assert_eq!(read_a, read_b, "{:04X}h sub {}", entry.index(), entry.sub());
        // Write the value's bytes back, each byte changed, through both paths.
        let len = read_b
            .unwrap_or(0)
            .max(by_address.capacity(position).unwrap().min(4));
        let data: Vec<u8> = b[..len].iter().map(|x| x.wrapping_add(1)).collect();
        assert_eq!(
            by_position.write_at(position, &data),
            by_address.write(entry.index(), entry.sub(), &data),
            "{:04X}h sub {}",
            entry.index(),
            entry.sub()
        );
        assert_eq!(
            by_position,
            by_address,
            "{:04X}h sub {}",
            entry.index(),
            entry.sub()
        );
    }
    let past = entries.len();
    assert_eq!(
        by_position.read_at(past, 0, &mut [0u8; 8]),
        Err(SdoAbort::NoObject)
    );
    assert_eq!(by_position.write_at(past, &[0]), Err(SdoAbort::NoObject));
    assert_eq!(by_address.locate(0x6000, 0), Err(SdoAbort::NoObject));
    assert_eq!(by_address.locate(0x1018, 9), Err(SdoAbort::NoSubIndex));
}

/// The application's typed access: `set` checks like an SDO write but allows read-only entries,
/// and `get` agrees with what the protocols read.
#[test]
fn typed_get_and_set_check_like_an_sdo_write() {
    let mut dict = Od::new(3);
    assert_eq!(dict.set(od::SETTING_LIMITED, 9), Err(SdoAbort::ValueTooLow));
    assert_eq!(
        dict.set(od::SETTING_LIMITED, 5001),
        Err(SdoAbort::ValueTooHigh)
    );
    assert_eq!(dict.get(od::SETTING_LIMITED), 100);
    assert_eq!(dict.set(od::SETTING_LIMITED, 4321), Ok(()));
    assert_eq!(read_all(&dict, 0x2102, 0), 4321u16.to_le_bytes().to_vec());
    // 1018h sub 1 is read-only for an SDO client, not for the application.
    assert_eq!(dict.set(od::identity_object::VENDOR_ID, 0x1234), Ok(()));
    assert_eq!(read_all(&dict, 0x1018, 1), vec![0x34, 0x12, 0, 0]);
    assert_eq!(
        dict.set(od::sparse_record::SIGNED_24, 1 << 23),
        Err(SdoAbort::InvalidValue)
    );
    assert_eq!(dict.set(od::sparse_record::SIGNED_24, -(1 << 23)), Ok(()));
    assert_eq!(read_all(&dict, 0x2003, 1), vec![0x00, 0x00, 0x80]);
    let version = edsgen_runtime::FixedBytes::from_slice(b"3.1");
    assert_eq!(dict.set(od::MANUFACTURER_HARDWARE_VERSION, version), Ok(()));
    assert_eq!(read_all(&dict, 0x1009, 0), b"3.1".to_vec());
    assert_eq!(dict.set(od::GAIN, -0.5), Ok(()));
    assert_eq!(read_all(&dict, 0x2005, 0), (-0.5f32).to_le_bytes().to_vec());
    // An address of another device: found by (index, sub) despite its recorded position.
    let foreign: edsgen_runtime::Entry<u16> = edsgen_runtime::Entry::new(0x6040, 0).at_position(0);
    assert_eq!(dict.set(foreign, 0x0F), Ok(()));
    assert_eq!(dict.get(od::CONTROLWORD), 0x0F);
}

/// The position each typed address records is its entry's position in `ENTRIES`.
#[test]
fn typed_addresses_record_their_positions() {
    let dict = Od::new(3);
    let positions = [
        (od::CONTROLWORD.position(), 0x6040, 0),
        (od::STATUS_WORD_6041.position(), 0x6041, 0),
        (od::identity_object::VENDOR_ID.position(), 0x1018, 1),
        (od::sparse_record::SIGNED_24.position(), 0x2003, 1),
        (od::settings::SETTING_3.position(), 0x2100, 3),
        (od::MANUFACTURER_DEVICE_NAME.position(), 0x1008, 0),
    ];
    for (recorded, index, sub) in positions {
        assert_eq!(
            recorded,
            dict.locate(index, sub).ok(),
            "{index:04X}h sub {sub}"
        );
    }
}

proptest! {
    /// Any write by position either takes effect exactly (the value reads back as written) or is
    /// refused and changes nothing in the dictionary.
    #[test]
    fn writes_by_position_apply_exactly_or_not_at_all(
        position in 0usize..80,
        // Mostly the lengths of numbers (0 to 8 bytes), sometimes string lengths.
        data in prop_oneof![
            3 => proptest::collection::vec(any::<u8>(), 0..9),
            1 => proptest::collection::vec(any::<u8>(), 0..40),
        ],
    ) {
        let mut dict = Od::new(3);
        let before = dict.clone();
        match dict.write_at(position, &data) {
            Ok(()) => {
                let mut buf = [0u8; 64];
                let n = dict.read_at(position, 0, &mut buf).unwrap();
                prop_assert_eq!(&buf[..n], &data[..]);
                // Every other entry is as it was.
                for other in (0..dict.entry_count()).filter(|&p| p != position) {
                    let (mut a, mut b) = ([0u8; 64], [0u8; 64]);
                    let na = dict.read_at(other, 0, &mut a).unwrap();
                    let nb = before.read_at(other, 0, &mut b).unwrap();
                    prop_assert_eq!(&a[..na], &b[..nb], "position {}", other);
                }
            }
            Err(_) => prop_assert_eq!(dict, before),
        }
    }
}

#[test]
fn a_branded_address_reads_without_option_and_a_foreign_one_is_checked() {
    let dict = Od::new(3);
    let controlword: u16 = dict.get(od::CONTROLWORD);
    assert_eq!(controlword, 0);
    // The same address built by hand, and one this dictionary does not hold.
    let by_hand: edsgen_runtime::Entry<u16> = edsgen_runtime::Entry::new(0x6040, 0);
    assert_eq!(dict.get_checked(by_hand), Some(0));
    let absent: edsgen_runtime::Entry<u16> = edsgen_runtime::Entry::new(0x5FFF, 0);
    assert_eq!(dict.get_checked(absent), None);
    // set takes either.
    let mut dict = dict;
    assert_eq!(dict.set(by_hand, 0x0F), Ok(()));
    assert_eq!(dict.get(od::CONTROLWORD), 0x0F);
}

#[test]
fn written_events_match_a_typed_address() {
    let event = edsgen_runtime::Event::Written {
        index: 0x6040,
        sub: 0,
    };
    let which = match event {
        e if od::CONTROLWORD.written_by(&e) => "controlword",
        edsgen_runtime::Event::Written { .. } => "another entry",
        _ => "not a write",
    };
    assert_eq!(which, "controlword");
}

#[test]
fn the_generated_od_stages_a_string_download_and_applies_it_only_on_commit() {
    let mut od = Od::new(3);
    // 1009h (32 bytes) is the largest writable string: the stage is sized to it.
    let position = od.locate(0x1009, 0).unwrap();
    assert_eq!(od.capacity(position), Some(32));
    assert_eq!(gd350::STAGE_SIZE, 32);
    let before = od.clone();
    od.begin_write(position).unwrap();
    od.write_part(position, 0, b"AB").unwrap();
    od.write_part(position, 2, b"C").unwrap();
    // Staged: the value is the old one until the commit.
    assert_eq!(read_all(&od, 0x1009, 0), read_all(&before, 0x1009, 0));
    od.commit_write(position, 3).unwrap();
    assert_eq!(read_all(&od, 0x1009, 0), b"ABC");
    // An aborted download leaves the value, and the stage takes the next one.
    let committed = od.clone();
    od.begin_write(position).unwrap();
    od.write_part(position, 0, b"XYZW").unwrap();
    od.abort_write(position);
    assert_eq!(od, committed);
    assert_eq!(read_all(&od, 0x1009, 0), b"ABC");
    // One download at a time: a second one (the other SDO channel's) is refused, and cannot
    // end the first.
    od.begin_write(position).unwrap();
    let tag = od.locate(0x2006, 0).unwrap();
    assert_eq!(od.begin_write(tag), Err(SdoAbort::NoResource));
    od.abort_write(tag);
    assert_eq!(
        od.write_part(position, 32, b"D"),
        Err(SdoAbort::OutOfMemory)
    );
    od.write_part(position, 0, b"xyz!").unwrap();
    // A commit that fails its checks ends the download and changes nothing.
    assert_eq!(od.commit_write(position, 33), Err(SdoAbort::OutOfMemory));
    assert_eq!(od, committed);
    od.begin_write(tag).unwrap();
    od.commit_write(tag, 0).unwrap();
    assert_eq!(read_all(&od, 0x2006, 0), b"");
}
