//! A simulated PROFINET IO device built from a GSDML model, one module per protocol machine as
//! p-net names them: [`dcp`] (discovery and naming), [`cyclic`] (the cyclic consumer with its
//! watchdog and the provider, on a layout a Connect would give); [`drive`] puts the Goodrive350's
//! PKW/PZD drive behind the cyclic data; wire formats apart in [`wire`]; the raw-socket driver in
//! [`driver`]; [`station`] derives what the device says about itself from the GSDML.
//!
//! Not yet here: connection management (the DCE/RPC endpoint on UDP 34964: Connect, Write,
//! Read, PrmEnd, ApplicationReady, Release), which would fill the cyclic layout, and alarms.

pub mod ar;
pub mod controller;
pub mod cyclic;
pub mod dcp;
pub mod device;
pub mod drive;
pub mod driver;
pub mod station;
pub mod wire;
