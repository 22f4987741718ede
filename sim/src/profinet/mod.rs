//! A simulated PROFINET IO device built from a GSDML model, one module per protocol machine as
//! p-net names them: [`dcp`] (discovery and naming) so far; wire formats apart in [`wire`]; the
//! raw-socket driver in [`driver`]; [`station`] derives what the device says about itself from
//! the GSDML.
//!
//! Not yet here: connection management (the DCE/RPC endpoint on UDP 34964), the cyclic
//! producer/consumer on EtherType 0x8892 and alarms.

pub mod dcp;
pub mod driver;
pub mod station;
pub mod wire;
