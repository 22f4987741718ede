//! EtherNet/IP and CIP (behind the `enip` feature), `no_std` and allocation-free: the wire
//! formats as views over the caller's bytes ([`wire`]) and the originator's sans-IO core
//! ([`originator`]), shared by the simulated adapter, the bench scanner (`edsgen enip`) and the
//! demo. Parsing and emitting never panic.

pub mod originator;
pub mod wire;
