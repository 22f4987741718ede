//! Simulated drives behind the bundled cards: each card's behaviour as its manual describes it,
//! on the card's generated bindings and the device runtime, so that a master can be written and
//! tested before a drive is wired.
//!
//! Each card is a [`BusDevice`](edsgen_runtime::vbus::BusDevice): it runs on the in-memory bus in
//! tests, and on any transport through the runtime's driver.

pub mod cp301;
pub mod goodrive350;
pub mod vfd;

pub use self::cp301::Cp301;
pub use self::goodrive350::Goodrive350;
