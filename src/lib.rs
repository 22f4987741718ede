//! edsgen: typed Rust from fieldbus device descriptions.
//!
//! This crate is the `edsgen` command-line tool (and the demo behind it); the generator is
//! `edsgen-codegen`, the runtime `edsgen-runtime` (with `edsgen-host` for operating systems), the
//! bus decoder `edsgen-decode`, and the simulated devices with the bundled cards' bindings and
//! drives `edsgen-sim`.
#![forbid(unsafe_code)]

pub mod demo;
#[cfg(feature = "ethercrab")]
pub mod ecat;
pub mod netns;
