//! edsgen: typed Rust from CANopen device descriptions.
//!
//! This crate is the `edsgen` command-line tool; the generator is `edsgen-codegen` and the
//! runtime `edsgen-runtime`.
#![forbid(unsafe_code)]

pub mod cards;
pub mod cmd;
pub mod decode;
pub mod sim;
