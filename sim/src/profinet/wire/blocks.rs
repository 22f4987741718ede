//! The PNIO blocks of the Connect are the runtime's ([`edsgen_runtime::profinet::wire::connect`]),
//! the record access and control blocks too ([`edsgen_runtime::profinet::wire::records`]).

pub use edsgen_runtime::profinet::wire::connect::*;
pub use edsgen_runtime::profinet::wire::records::*;
