//! edsgen-codegen: read CANopen device descriptions (EDS, DCF, XDD, XDC) into one model, judge
//! them, and generate typed Rust for the edsgen runtime.
//!
//! The stages talk only through their output types: [`read`] turns bytes into a
//! [`model::Device`] (plus the diagnostics the text itself calls for), [`validate`] turns a model
//! into diagnostics, [`emit`] turns a model into Rust source. [`Builder`] drives them from
//! `build.rs`.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod diag;
pub mod dump;
pub mod emit;
pub mod lint;
pub mod load;
pub mod model;
pub mod overlay;
pub mod read;
pub mod render;
pub mod rules;
pub mod sii;
pub mod validate;

pub mod builder;
pub use builder::Builder;
