//! The Parameter object (class 0x0F) against exact bytes: the class attributes, a parameter's
//! full attributes, its value kept on its own or in its assembly's bytes, and the refusals of
//! Set_Attribute_Single (read-only, size, limits, an owned assembly).

use edsgen_runtime::Instant;

use super::tests_support::events;
use super::{device, Event};

const T0: Instant = Instant::from_micros(0);

fn io() -> super::Adapter {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/enip/io.eds");
    let read = edsgen_model::read::read_file(&path).expect("tests/enip/io.eds reads");
    device::from_cip(read.device.cip().expect("an ODVA EDS"), [127, 0, 0, 1])
}

/// Get_Attribute_Single `@0x0F/instance/attribute`: the response's bytes.
fn get<A: super::EnipApplication>(
    a: &mut super::Adapter<A>,
    instance: u8,
    attribute: u8,
) -> Vec<u8> {
    a.route(
        1,
        &[0x0E, 3, 0x20, 0x0F, 0x24, instance, 0x30, attribute],
        T0,
    )
}

/// Set_Attribute_Single of a parameter's value: the response's bytes.
fn set<A: super::EnipApplication>(
    a: &mut super::Adapter<A>,
    instance: u8,
    value: &[u8],
) -> Vec<u8> {
    let mut request = vec![0x10, 3, 0x20, 0x0F, 0x24, instance, 0x30, 1];
    request.extend_from_slice(value);
    a.route(1, &request, T0)
}

fn ok(data: &[u8]) -> Vec<u8> {
    [&[0x8E, 0, 0, 0][..], data].concat()
}

const SET_OK: [u8; 4] = [0x90, 0, 0, 0];

#[test]
fn class_and_instance_attributes() {
    let mut a = io();
    // Class: revision 1, max instance 8 (Param8), descriptor: instances and full attributes.
    assert_eq!(get(&mut a, 0, 1), ok(&[1, 0]));
    assert_eq!(get(&mut a, 0, 2), ok(&[8, 0]));
    assert_eq!(get(&mut a, 0, 8), ok(&[3, 0]));
    assert_eq!(get(&mut a, 0, 9), ok(&[0, 0]));
    assert_eq!(get(&mut a, 0, 3), [0x8E, 0, 0x14, 0]);
    assert_eq!(get(&mut a, 9, 1), [0x8E, 0, 0x16, 0], "no Param9");
    // Param8 `RPI`: UDINT, 10000..1000000 us, default 40000.
    let attributes: Vec<Vec<u8>> = (1..=21).map(|n| get(&mut a, 8, n)).collect();
    let expected: Vec<Vec<u8>> = [
        &[0x40, 0x9C, 0, 0][..],
        &[0],
        &[],
        &[0, 0],
        &[0xC8],
        &[4],
        &[3, b'R', b'P', b'I'],
        &[2, b'u', b's'],
        &[0],
        &[0x10, 0x27, 0, 0],
        &[0x40, 0x42, 0x0F, 0],
        &[0x40, 0x9C, 0, 0],
        &[1, 0],
        &[1, 0],
        &[1, 0],
        &[0, 0],
        &[0, 0],
        &[0, 0],
        &[0, 0],
        &[0, 0],
        &[0],
    ]
    .iter()
    .map(|d| ok(d))
    .collect();
    assert_eq!(attributes, expected);
    assert_eq!(get(&mut a, 8, 22), [0x8E, 0, 0x14, 0]);
    // Param2 `Setpoint`: INT scaled 1/10 with one decimal, -1000..1000, default -25.
    assert_eq!(get(&mut a, 2, 10), ok(&[0x18, 0xFC]));
    assert_eq!(get(&mut a, 2, 14), ok(&[10, 0]));
    assert_eq!(get(&mut a, 2, 21), ok(&[1]));
    // Only the value is settable; other services are not supported.
    assert_eq!(
        a.route(1, &[0x10, 3, 0x20, 0x0F, 0x24, 8, 0x30, 4, 0, 0], T0),
        [0x90, 0, 0x0E, 0]
    );
    assert_eq!(
        a.route(1, &[0x01, 2, 0x20, 0x0F, 0x24, 8], T0),
        [0x81, 0, 0x08, 0]
    );
}

#[test]
fn a_value_of_its_own_checked_against_its_limits() {
    let mut a = io();
    assert_eq!(
        set(&mut a, 8, &[0x0F, 0x27, 0, 0]),
        [0x90, 0, 0x09, 0],
        "9999 < 10000"
    );
    assert_eq!(
        set(&mut a, 8, &[0x41, 0x42, 0x0F, 0]),
        [0x90, 0, 0x09, 0],
        "> 1000000"
    );
    assert_eq!(set(&mut a, 8, &[0x20, 0x4E]), [0x90, 0, 0x13, 0]);
    assert_eq!(set(&mut a, 8, &[0x20, 0x4E, 0, 0, 0]), [0x90, 0, 0x15, 0]);
    assert_eq!(get(&mut a, 8, 1), ok(&[0x40, 0x9C, 0, 0]), "unchanged");
    assert_eq!(set(&mut a, 8, &[0x20, 0x4E, 0, 0]), SET_OK);
    assert_eq!(get(&mut a, 8, 1), ok(&[0x20, 0x4E, 0, 0]));
    assert!(events(&mut a).is_empty());
}

#[test]
fn members_live_in_their_assemblys_bytes() {
    let mut a = io();
    // Output assembly 150: Mode (8 bits), Setpoint (16), Enable (1), padding (7), Gain (REAL).
    assert_eq!(
        a.device.assemblies[&150].data,
        [0x00, 0xE7, 0xFF, 0x00, 0x00, 0x00, 0xC0, 0x3F]
    );
    assert_eq!(get(&mut a, 2, 1), ok(&[0xE7, 0xFF]));
    assert_eq!(get(&mut a, 3, 1), ok(&1.5f32.to_le_bytes()));
    // Signed limits: -1001 refused, 100 taken, into bits 8..24.
    assert_eq!(
        set(&mut a, 2, &(-1001i16).to_le_bytes()),
        [0x90, 0, 0x09, 0]
    );
    assert_eq!(set(&mut a, 2, &100i16.to_le_bytes()), SET_OK);
    // A BOOL of one bit: its byte's value, into bit 24 alone.
    assert_eq!(set(&mut a, 4, &[2]), [0x90, 0, 0x09, 0]);
    assert_eq!(set(&mut a, 4, &[1]), SET_OK);
    // A REAL against its real limits.
    assert_eq!(set(&mut a, 3, &11.0f32.to_le_bytes()), [0x90, 0, 0x09, 0]);
    assert_eq!(set(&mut a, 3, &2.5f32.to_le_bytes()), SET_OK);
    assert_eq!(
        a.device.assemblies[&150].data,
        [0x00, 0x64, 0x00, 0x01, 0x00, 0x00, 0x20, 0x40]
    );
    assert_eq!(
        events(&mut a),
        [
            Event::Consumed(150),
            Event::Consumed(150),
            Event::Consumed(150)
        ]
    );
    // What the assembly gets, the parameter shows: one storage.
    a.device.assemblies.get_mut(&150).expect("150").data[0] = 2;
    assert_eq!(get(&mut a, 1, 1), ok(&[2]));
    // Not while a class-1 connection writes the assembly (as Set_Attribute_Single on it).
    a.device.connections.push(super::IoConnection {
        o_t_id: 1,
        t_o_id: 2,
        triad: (1, 2, 3),
        o_t_point: 150,
        t_o_point: 100,
        o_t_rpi: edsgen_runtime::Duration::from_micros(10_000),
        t_o_rpi: edsgen_runtime::Duration::from_micros(10_000),
        timeout: edsgen_runtime::Duration::from_micros(40_000),
        last_heard: T0,
        next_produce: T0,
        t_o_sequence: 0,
        o_t_sequence: None,
        run: false,
        peer: 1,
        t_o_port: None,
    });
    assert_eq!(set(&mut a, 1, &[1]), [0x90, 0, 0x10, 0]);
    // Input assembly 100: Status, Temperature, Mode echo at their defaults.
    assert_eq!(get(&mut a, 6, 1), ok(&(-40i16).to_le_bytes()));
    assert_eq!(get(&mut a, 7, 1), ok(&[1]));
}

#[test]
fn the_cards_parameters() {
    let mut a = device::goodrive350([127, 0, 0, 1], T0);
    // Param1 RPI: no member, 50 ms; Param22 SW read-only in assembly 100; Param2 PKW1 task in
    // 150.
    assert_eq!(get(&mut a, 1, 1), ok(&50_000u32.to_le_bytes()));
    assert_eq!(get(&mut a, 0, 2), ok(&[a.device.parameters.len() as u8, 0]));
    assert_eq!(set(&mut a, 22, &[0, 0]), [0x90, 0, 0x0E, 0]);
    assert_eq!(set(&mut a, 2, &[6, 0]), [0x90, 0, 0x09, 0]);
    assert_eq!(set(&mut a, 2, &[1, 0]), SET_OK);
    assert_eq!(a.device.assemblies[&150].data[..2], [1, 0]);
}
