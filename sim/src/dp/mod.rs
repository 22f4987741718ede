//! A simulated PROFIBUS-DP slave: the runtime's sans-IO DP slave core
//! ([`edsgen_runtime::dp`]) with the bundled Goodrive350 DP card ([`card`]) or a loopback
//! application behind it, and its drivers (a serial line, profirust's simulated bus).

pub mod card;
pub mod serial;
pub mod simulator_phy;

pub use edsgen_runtime::dp::{fdl, slave, DpApplication, DpSlave, DpState, Event, SlaveConfig};
