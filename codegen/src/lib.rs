//! edsgen-codegen: typed Rust for the edsgen runtime from a device model (CANopen, EtherCAT,
//! EtherNet/IP, PROFINET, PROFIBUS-DP), and the [`Builder`] that drives it from `build.rs`.
//!
//! Reading, overlays and validation are `edsgen-model`'s: `edsgen_model::load` reads a
//! description, applies its overlay and validates it; [`emit`] turns the model into Rust source.
//! This crate alone depends on syn, quote, prettyplease and heck, as prost-build alone does
//! beside prost.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod emit;

pub mod builder;
pub use builder::Builder;
