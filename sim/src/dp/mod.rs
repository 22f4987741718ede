//! A simulated PROFIBUS-DP slave: the FDL telegrams ([`fdl`]), the DP state machine
//! ([`slave`]), both sans-IO, and the bundled Goodrive350 DP card ([`card`]) behind them.

pub mod card;
pub mod fdl;
pub mod serial;
pub mod simulator_phy;
pub mod slave;

pub use slave::{DpApplication, DpSlave, DpState, SlaveConfig};
