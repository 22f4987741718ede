//! Simulated drives behind the bundled cards: each card's behaviour as its manual describes it,
//! on the card's generated bindings and the device runtime, so that a master can be written and
//! tested before a drive is wired.
//!
//! Each card is a [`BusDevice`](edsgen_runtime::vbus::BusDevice): it runs on the in-memory bus in
//! tests, and on any transport through the runtime's driver.

pub mod cp301;
pub mod goodrive350;
pub mod hd1e;
pub mod ms300;
pub mod pdo1;
pub mod rd11;
pub mod vfd;

use edsgen_runtime::{Instant, ObjectDictionary};

pub use self::cp301::Cp301;
pub use self::goodrive350::Goodrive350;
pub use self::hd1e::Hd1e;
pub use self::ms300::Ms300;
pub use self::rd11::Rd11;

/// The earlier of two optional deadlines.
fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// An UNSIGNED16 of a card's dictionary, 0 if absent: the generated dictionaries have every
/// object the cards name, which the card tests check.
fn read_u16<O: ObjectDictionary>(od: &O, index: u16, sub: u8) -> u16 {
    let mut bytes = [0u8; 2];
    match od.read(index, sub, 0, &mut bytes) {
        Ok(2) => u16::from_le_bytes(bytes),
        _ => 0,
    }
}

/// Writes an UNSIGNED16 of a card's dictionary that takes any value (a monitored value, a
/// status word): a refusal is a bug in the simulation, caught by the tests' debug builds.
fn write_u16<O: ObjectDictionary>(od: &mut O, index: u16, sub: u8, value: u16) {
    let written = od.write(index, sub, &value.to_le_bytes());
    debug_assert_eq!(
        written,
        Ok(()),
        "{index:04X}h:{sub:02X}h takes any UNSIGNED16"
    );
}

/// [`write_u16`], and whether the value changed.
fn replace_u16<O: ObjectDictionary>(od: &mut O, index: u16, sub: u8, value: u16) -> bool {
    let changed = read_u16(od, index, sub) != value;
    if changed {
        write_u16(od, index, sub, value);
    }
    changed
}
