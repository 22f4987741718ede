//! EtherNet/IP and CIP (behind the `enip` feature): the wire formats as views over the caller's
//! bytes ([`wire`]), `no_std` and allocation-free, shared by the simulated adapter, the bench
//! scanner (`edsgen enip`) and the demo. Parsing and emitting never panic.

pub mod wire;
