//! The CANopen commands: the master's [`sdo`], [`nmt`], [`lss`], [`scan`] and [`check`] reach
//! live devices through [`crate::cmd::BusArgs`]; [`bus`] runs a socketcand hub, [`simulate`]
//! serves devices on it. [`entry`] finds an object dictionary entry by index or name (EtherCAT's
//! CoE commands use it too).

pub mod bus;
pub mod check;
pub mod entry;
pub mod lss;
pub mod nmt;
pub mod scan;
pub mod sdo;
pub mod simulate;
