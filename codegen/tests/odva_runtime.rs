//! The module generated from `tests/odva/io.eds` (checked in as `tests/generated/odva_io.rs`,
//! kept current by `emit_odva.rs`) at work: identity constants, images decoded from and encoded
//! to the exact bytes CIP carries (little-endian, members packed from bit 0), defaults from the
//! parameters, and the connection's words, sizes, RPI and path.

include!("generated/odva_io.rs");

use odva_io::*;

#[test]
fn identity() {
    assert_eq!(
        (
            VENDOR_ID,
            DEVICE_TYPE,
            PRODUCT_CODE,
            MAJOR_REVISION,
            MINOR_REVISION,
            PRODUCT_NAME
        ),
        (0x1234, 12, 7, 1, 2, "IO test")
    );
}

#[test]
fn images_decode_and_encode_little_endian() {
    let inputs = Inputs::from_slice(&[0x88, 0x13, 0x02]).expect("3 bytes");
    assert_eq!(
        inputs,
        Inputs {
            speed: 5000,
            mode: 2
        }
    );
    assert_eq!(inputs.to_bytes(), [0x88, 0x13, 0x02]);
    assert_eq!(Inputs::from_bytes(&[0x88, 0x13, 0x02]), inputs);
    let wrong = |actual| {
        Err(edsgen_runtime::PdoError::WrongLength {
            expected: 3,
            actual,
        })
    };
    assert_eq!(Inputs::from_slice(&[0x88, 0x13]), wrong(2));
    assert_eq!(Inputs::from_slice(&[0x88, 0x13, 0x02, 0x00]), wrong(4));
    assert_eq!((Inputs::INSTANCE, Inputs::SIZE), (100, 3));
    assert_eq!(Outputs { speed: 0x0102 }.to_bytes(), [0x02, 0x01]);
}

#[test]
fn a_scaled_parameter_has_its_engineering_value() {
    // Param1 `Speed`: scaling 1, 10, 1, 0 (multiplier, divisor, base, offset).
    let inputs = Inputs {
        speed: 5000,
        mode: 0,
    };
    assert_eq!(inputs.speed_scaled(), 500.0);
    assert_eq!(Outputs { speed: 15 }.speed_scaled(), 1.5);
}

#[test]
fn defaults_are_the_parameters() {
    assert_eq!(
        Inputs::default(),
        Inputs {
            speed: 1500,
            mode: 0
        }
    );
    assert_eq!(Outputs::default().to_bytes(), [0xDC, 0x05]);
}

#[test]
fn the_connection() {
    assert_eq!(
        EXCLUSIVE_OWNER,
        Connection {
            name: "Exclusive Owner",
            trigger_transport: 0x8401_0002,
            connection_params: 0x4464_0405,
            o_t_assembly: Some(150),
            t_o_assembly: Some(100),
            config_assembly: None,
            o_t_size: 2,
            t_o_size: 3,
            rpi_us: 50_000,
            path: &[0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64],
        }
    );
}

#[test]
fn the_mode_enumeration() {
    assert_eq!(Mode::try_from(2u8), Ok(Mode::Fast));
    assert_eq!(Mode::try_from(3u8), Err(3));
    assert_eq!(u8::from(Mode::Slow), 1);
    let inputs = Inputs::from_slice(&[0, 0, 1]).expect("3 bytes");
    assert_eq!(Mode::try_from(inputs.mode), Ok(Mode::Slow));
}
