//! The EC-TX508's generated process images as ethercrab-wire types (feature `ethercrab`): they
//! pack and unpack exactly as structs derived with ethercrab-wire's own `EtherCrabWireRead` /
//! `EtherCrabWireWrite` for the same layout (the 1600h and 1A00h mappings of the manual's
//! Appendix B, written out by hand below), and as bytes built from those mappings.

use edsgen_runtime::ethercat::ethercrab::wire::WireError;
use edsgen_sim::cards::ec_tx508::ethercat::{self, Inputs, Outputs, RxPdo1600, TxPdo1A00};
use ethercrab_wire::{
    EtherCrabWireRead, EtherCrabWireReadWrite, EtherCrabWireSized, EtherCrabWireWrite,
    EtherCrabWireWriteSized,
};

/// 1600h as ethercrab-wire derives it: 6040h/16, 607Ah/32, 60FFh/32, 6071h/16, 6072h/16,
/// 6060h/8, 6081h/32, 60B8h/16 (Appendix B).
#[derive(Debug, Clone, Copy, PartialEq, EtherCrabWireReadWrite)]
#[wire(bytes = 21)]
struct WireRx {
    #[wire(bytes = 2)]
    control_word: u16,
    #[wire(bytes = 4)]
    target_position: i32,
    #[wire(bytes = 4)]
    target_speed: i32,
    #[wire(bytes = 2)]
    target_torque: i16,
    #[wire(bytes = 2)]
    max_torque: u16,
    #[wire(bytes = 1)]
    operation_mode: i8,
    #[wire(bytes = 4)]
    profile_velocity: u32,
    #[wire(bytes = 2)]
    probe_control: u16,
}

/// 1A00h as ethercrab-wire derives it: 6041h/16, 6064h/32, 606Ch/32, 6077h/16, 60F4h/32,
/// 6061h/8, 60B9h/16, 60BAh/32 (Appendix B).
#[derive(Debug, Clone, Copy, PartialEq, EtherCrabWireReadWrite)]
#[wire(bytes = 23)]
struct WireTx {
    #[wire(bytes = 2)]
    status_word: u16,
    #[wire(bytes = 4)]
    position_actual_value: i32,
    #[wire(bytes = 4)]
    actual_speed: i32,
    #[wire(bytes = 2)]
    actual_torque: i16,
    #[wire(bytes = 4)]
    position_deviation: i32,
    #[wire(bytes = 1)]
    operation_mode_display: i8,
    #[wire(bytes = 2)]
    probe_status: u16,
    #[wire(bytes = 4)]
    probe_position_rising_edge: i32,
}

fn outputs() -> Outputs {
    Outputs {
        rx_pdo_1600: RxPdo1600 {
            control_word: 0x000F,
            target_position: -123_456,
            target_speed: 1500,
            target_torque: -250,
            max_torque: 3000,
            operation_mode: 9,
            speed_in_industrial_regulations: 0xDEAD_BEEF,
            probe_control: 0x0011,
        },
    }
}

fn wire_rx() -> WireRx {
    WireRx {
        control_word: 0x000F,
        target_position: -123_456,
        target_speed: 1500,
        target_torque: -250,
        max_torque: 3000,
        operation_mode: 9,
        profile_velocity: 0xDEAD_BEEF,
        probe_control: 0x0011,
    }
}

/// The outputs image of the manual's default mapping, byte by byte (little-endian).
fn rx_bytes() -> Vec<u8> {
    let mut bytes = Vec::new();
    bytes.extend(0x000Fu16.to_le_bytes());
    bytes.extend((-123_456i32).to_le_bytes());
    bytes.extend(1500i32.to_le_bytes());
    bytes.extend((-250i16).to_le_bytes());
    bytes.extend(3000u16.to_le_bytes());
    bytes.push(9);
    bytes.extend(0xDEAD_BEEFu32.to_le_bytes());
    bytes.extend(0x0011u16.to_le_bytes());
    bytes
}

#[test]
fn outputs_pack_as_ethercrab_wire_packs_the_same_layout() {
    let mut ours = [0u8; 21];
    let mut theirs = [0u8; 21];
    assert_eq!(
        outputs().pack_to_slice(&mut ours).map(<[u8]>::to_vec),
        Ok(rx_bytes())
    );
    wire_rx().pack_to_slice(&mut theirs).unwrap();
    assert_eq!(ours, theirs);
    assert_eq!(outputs().pack(), theirs);
    assert_eq!(<Outputs as EtherCrabWireSized>::PACKED_LEN, 21);
    assert_eq!(outputs().packed_len(), 21);
}

#[test]
fn inputs_unpack_what_ethercrab_wire_packs() {
    let wire = WireTx {
        status_word: 0x0637,
        position_actual_value: -7,
        actual_speed: 1499,
        actual_torque: -12,
        position_deviation: 3,
        operation_mode_display: 9,
        probe_status: 0x0101,
        probe_position_rising_edge: 0x0102_0304,
    };
    let mut bytes = [0u8; 23];
    wire.pack_to_slice(&mut bytes).unwrap();
    let inputs = Inputs::unpack_from_slice(&bytes).unwrap();
    assert_eq!(
        inputs.tx_pdo_1a00,
        TxPdo1A00 {
            status_word: 0x0637,
            position_actual_value: -7,
            actual_speed: 1499,
            actual_torque: -12,
            position_deviation: 3,
            operation_mode_display: 9,
            probe_status: 0x0101,
            probe_position_rising_edge: 0x0102_0304,
        }
    );
    // And the other way: our bytes are what ethercrab-wire reads.
    assert_eq!(WireTx::unpack_from_slice(&inputs.to_bytes()), Ok(wire));
    // A SubDevice's inputs slice may be longer than the image; never shorter.
    let mut longer = bytes.to_vec();
    longer.push(0xAA);
    assert_eq!(Inputs::unpack_from_slice(&longer), Ok(inputs));
    assert_eq!(
        Inputs::unpack_from_slice(&bytes[..22]),
        Err(WireError::ReadBufferTooShort)
    );
}

#[test]
fn packing_into_a_short_slice_is_an_error() {
    assert_eq!(
        outputs().pack_to_slice(&mut [0u8; 20]),
        Err(WireError::WriteBufferTooShort)
    );
}

#[test]
fn a_single_pdo_is_a_wire_type_too() {
    let rx = outputs().rx_pdo_1600;
    assert_eq!(rx.pack().to_vec(), rx_bytes());
    assert_eq!(RxPdo1600::unpack_from_slice(&rx_bytes()), Ok(rx));
    assert_eq!(ethercat::IDENTITY.vendor_id, 0x0000_04D8);
}
