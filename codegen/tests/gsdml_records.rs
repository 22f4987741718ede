//! The module generated from `tests/gsdml/records.xml` (checked in as
//! `tests/generated/pn_records.rs`, kept current by `emit_gsdml.rs`) at work: a parameter record
//! as a struct of typed fields, read from and written to the exact bytes a controller writes
//! (big-endian, bits in their byte, `Const` bytes kept), its default the file's.

include!("generated/pn_records.rs");

use pn_records::modules::access_point::subslot_1::record_100::{self, ModeValues, Record};

#[test]
fn the_default_record_is_the_file_s() {
    let record = Record::default();
    assert_eq!(
        record,
        Record {
            mode: 2,
            offset: -2,
            enable: true,
            filter: 5,
            tag: [0; 4],
            limit: 0x1234,
        }
    );
    assert_eq!(
        record.to_bytes(),
        [0xA5, 0x00, 0x02, 0xFF, 0xFE, 0x58, 0, 0, 0, 0, 0x12, 0x34]
    );
    assert_eq!(record.to_bytes(), record_100::DEFAULT);
    assert_eq!(record.mode_value(), Ok(ModeValues::Fast));
    let unnamed = Record { mode: 3, ..record };
    assert_eq!(unnamed.mode_value(), Err(3));
}

#[test]
fn fields_are_written_where_the_file_puts_them_and_const_bytes_stay() {
    let record = Record {
        mode: ModeValues::Slow.raw(),
        offset: 300,
        enable: false,
        filter: 0xFF,
        tag: *b"AB12",
        limit: 7,
    };
    // The bit area keeps its 3 bits; the bits of byte 5 no field names stay zero.
    assert_eq!(
        record.to_bytes(),
        [0xA5, 0x00, 0x01, 0x01, 0x2C, 0x70, b'A', b'B', b'1', b'2', 0x00, 0x07]
    );
    let read = Record::from_bytes(&record.to_bytes());
    assert_eq!(
        read,
        Record {
            filter: 7,
            ..record
        }
    );
}

#[test]
fn a_record_is_read_from_bytes_of_its_length_only() {
    let bytes = [
        0x00, 0x00, 0x03, 0x80, 0x00, 0x08, b'x', b'y', b'z', b'w', 0xFF, 0xFF,
    ];
    assert_eq!(
        Record::from_slice(&bytes),
        Ok(Record {
            mode: 3,
            offset: i16::MIN,
            enable: true,
            filter: 0,
            tag: *b"xyzw",
            limit: 0xFFFF,
        })
    );
    assert_eq!(
        Record::from_slice(&bytes[..11]),
        Err(edsgen_runtime::PdoError::WrongLength {
            expected: 12,
            actual: 11
        })
    );
    assert_eq!(
        (Record::SIZE, record_100::LENGTH, record_100::INDEX),
        (12, 12, 100)
    );
}

/// A `DataItem`'s named bits: a mask, a getter and a setter each, on the byte the frame carries.
#[test]
fn named_bits_are_read_and_written_in_their_byte() {
    use pn_records::modules::access_point::subslot_1::Input;
    assert_eq!((Input::STATUS_READY, Input::STATUS_FAULT), (0x01, 0x80));
    let mut input = Input::from_bytes(&[0x80]);
    assert!(!input.status_ready() && input.status_fault());
    input.set_status_ready(true);
    input.set_status_fault(false);
    assert_eq!(input.to_bytes(), [0x01]);
    assert!(input.status_ready() && !input.status_fault());
    input.set_status_ready(false);
    assert_eq!(input.to_bytes(), [0x00]);
}
