//! edsgen: typed Rust from fieldbus device descriptions.
//!
//! This crate is the `edsgen` command-line tool (and the decoding and demo code behind it); the
//! generator is `edsgen-codegen`, the runtime `edsgen-runtime`, and the simulated devices with the
//! bundled cards' bindings and drives `edsgen-sim`, re-exported here under their earlier paths.
#![forbid(unsafe_code)]

pub mod demo;
#[cfg(feature = "ethercrab")]
pub mod ecat;
pub mod netns;

pub use edsgen_sim::canopen as sim;
pub use edsgen_sim::{cards, drives};
