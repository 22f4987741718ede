//! Frame layouts only: a typed view of each CANopen message's bytes, with parse and emit.
//!
//! State machines live elsewhere and never index bytes themselves. Every layout is tested byte for
//! byte against the manuals' examples.

pub mod emcy;
pub mod heartbeat;
pub mod lss;
pub mod nmt;
pub mod pdo;
pub mod sdo;
pub mod sync;
