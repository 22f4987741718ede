//! The generated EtherCAT code at work: `tests/generated/ec_hand.rs` (kept current by
//! `emit_ethercat.rs`) compiled against the runtime. Every process image is compared with bytes
//! built bit by bit from the mapping, independently of the runtime's bit packing.
#![deny(warnings, missing_docs)]

/// The generated module (a test binary uses only part of it, hence `dead_code`).
#[allow(dead_code)]
mod generated {
    include!("generated/ec_hand.rs");
}

use edsgen_runtime::ethercat::{ProcessData, SmKind};
use edsgen_runtime::PdoError;
use generated::ec_hand::ethercat::{self, Inputs, Outputs, RxPdo1600, RxPdo1601, TxPdo1A00};

/// Bytes from (value, bit length) pairs, least significant bit first, one bit at a time.
fn pack(fields: &[(u128, u32)]) -> Vec<u8> {
    let total: u32 = fields.iter().map(|f| f.1).sum();
    let mut out = vec![0u8; total.div_ceil(8) as usize];
    let mut pos = 0usize;
    for &(value, bits) in fields {
        for i in 0..bits {
            if (value >> i) & 1 == 1 {
                out[pos / 8] |= 1 << (pos % 8);
            }
            pos += 1;
        }
    }
    out
}

/// The low `bits` bits of a signed value.
fn twos(value: i128, bits: u32) -> u128 {
    (value as u128) & ((1u128 << bits) - 1)
}

fn rx_a() -> RxPdo1600 {
    RxPdo1600 {
        control_word: 0x000F,
        enable: true,
        offset: -5,
        target_position: -100_000,
        mode_of_operation: 8,
        select: 2,
        counter: 0x0123_4567_89AB_CDEF,
    }
}

fn rx_a_bits() -> Vec<(u128, u32)> {
    vec![
        (0x000F, 16),
        (0, 3),
        (1, 1),
        (twos(-5, 12), 12),
        (twos(-100_000, 32), 32),
        (8, 8),
        (2, 2),
        (0x0123_4567_89AB_CDEF, 64),
    ]
}

#[test]
fn rx_pdo_fields_land_at_their_mapped_bits() {
    let bytes = rx_a().to_bytes().unwrap();
    assert_eq!(RxPdo1600::LEN, 18);
    assert_eq!(bytes.to_vec(), pack(&rx_a_bits()));
    assert_eq!(RxPdo1600::from_slice(&bytes), Ok(rx_a()));
}

#[test]
fn narrow_fields_are_range_checked_and_sign_extended() {
    let mut too_big = rx_a();
    too_big.offset = 2048;
    assert_eq!(
        too_big.to_bytes(),
        Err(PdoError::OutOfRange { field: "offset" })
    );
    too_big.offset = -2048;
    too_big.select = 4;
    assert_eq!(
        too_big.to_bytes(),
        Err(PdoError::OutOfRange { field: "select" })
    );
    let mut bytes = [0xFFu8; 18];
    bytes[2] = 0x07; // padding bits 16-18 set, `enable` (bit 19) and offset's low nibble clear
    let decoded = RxPdo1600::from_slice(&bytes).unwrap();
    assert_eq!(decoded.offset, -16); // 0xFF0 in 12 bits
    assert_eq!(decoded.mode_of_operation, -1);
    assert!(!decoded.enable);
}

#[test]
fn a_field_wider_than_64_bits_keeps_its_bytes() {
    let mut blob = [0u8; 13];
    for (i, b) in blob.iter_mut().enumerate() {
        *b = 0x11 * (i as u8 + 1);
    }
    blob[12] = 0x0C; // 100 bits: the last byte holds 4
    let pdo = RxPdo1601 { blob, small: -3 };
    let mut fields: Vec<(u128, u32)> = blob[..12].iter().map(|b| (u128::from(*b), 8)).collect();
    fields.push((0x0C, 4));
    fields.push((twos(-3, 5), 5));
    assert_eq!(pdo.to_bytes().unwrap().to_vec(), pack(&fields));
    assert_eq!(RxPdo1601::from_slice(&pack(&fields)), Ok(pdo));
}

#[test]
fn the_outputs_image_concatenates_the_pdos_assigned_to_sm2() {
    let mut blob = [0xA5; 13];
    blob[12] = 0x05; // 100 bits: the last byte holds 4
    let image = Outputs {
        rx_pdo_1600: rx_a(),
        rx_pdo_1601: RxPdo1601 { blob, small: 15 },
    };
    let mut fields = rx_a_bits();
    fields.extend([(0xA5, 8); 12]);
    fields.push((0x5, 4));
    fields.push((15, 5));
    let expected = pack(&fields);
    assert_eq!(Outputs::LEN, 31);
    assert_eq!(<Outputs as ProcessData>::BITS, 243);
    assert_eq!(image.to_bytes().unwrap().to_vec(), expected);
    assert_eq!(Outputs::from_slice(&expected), Ok(image));
}

#[test]
fn process_data_goes_at_any_bit_offset_and_leaves_its_neighbours() {
    let pdo = TxPdo1A00 {
        status_word: 0x1237,
        gain: 1.5,
        tag: *b"ABCDEFGH",
    };
    let mut buf = [0xFFu8; 16];
    pdo.write_to(&mut buf, 3).unwrap();
    let mut fields = vec![(0b111, 3), (0x1237, 16), (u128::from(1.5f32.to_bits()), 32)];
    fields.extend(b"ABCDEFGH".iter().map(|c| (u128::from(*c), 8)));
    fields.push((0x1FFF, 13)); // the bits after the PDO stay set
    assert_eq!(buf.to_vec(), pack(&fields));
    assert_eq!(TxPdo1A00::read_from(&buf, 3), Ok(pdo));
    assert_eq!(
        TxPdo1A00::read_from(&buf[..14], 3),
        Err(PdoError::WrongLength {
            expected: 15,
            actual: 14
        })
    );
    assert_eq!(
        pdo.write_to(&mut [0u8; 13], 0),
        Err(PdoError::WrongLength {
            expected: 14,
            actual: 13
        })
    );
    let inputs = Inputs::from_slice(&pdo.to_bytes()).unwrap();
    assert_eq!(inputs.tx_pdo_1a00, pdo);
}

#[test]
fn an_empty_pdo_is_zero_bytes() {
    let empty = ethercat::TxPdo1A01 {};
    assert_eq!(empty.to_bytes(), [0u8; 0]);
    assert_eq!(ethercat::TxPdo1A01::from_slice(&[]), Ok(empty));
    assert_eq!(
        ethercat::TxPdo1A01::from_slice(&[0]),
        Err(PdoError::WrongLength {
            expected: 0,
            actual: 1
        })
    );
}

#[test]
fn identity_syncmanagers_and_dc_modes_are_the_descriptions() {
    assert!(ethercat::IDENTITY.matches_exactly(0x4D8, 0x9252, 1));
    assert_eq!(ethercat::TYPE_NAME, "HAND-1");
    assert_eq!(ethercat::PROFILES, [402]);
    let sm: Vec<_> = ethercat::SYNC_MANAGERS
        .iter()
        .map(|s| (s.kind, s.start_address, s.default_size, s.control_byte))
        .collect();
    assert_eq!(
        sm,
        [
            (SmKind::MailboxOut, 0x1000, 128, 0x26),
            (SmKind::MailboxIn, 0x1080, 128, 0x22),
            (SmKind::Outputs, 0x1100, 0, 0x64),
            (SmKind::Inputs, 0x1180, 0, 0x20),
        ]
    );
    assert_eq!(ethercat::OP_MODES[1].assign_activate, 0x300);
    assert_eq!(ethercat::OP_MODES[1].cycle_time_sync0, 1_000_000);
    assert_eq!(
        ethercat::COE,
        edsgen_runtime::ethercat::Coe {
            sdo_info: true,
            pdo_assign: true,
            pdo_config: false,
            complete_access: false,
            segmented_sdo: true,
        }
    );
}
