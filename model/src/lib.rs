//! edsgen-model: read fieldbus device descriptions (CANopen EDS, DCF, XDD, XDC; EtherCAT ESI and
//! SII; ODVA EDS for EtherNet/IP; PROFINET GSDML; PROFIBUS-DP GSD) into one model, apply their
//! overlays and judge them.
//!
//! The stages only call forward, each talking to the next through its output type: [`read`]
//! turns bytes into a [`model::Device`] (plus the diagnostics the text itself calls for),
//! [`overlay`] adds what the description cannot say, [`validate`] turns a model into diagnostics.
//! [`load`] runs the three for one file, with one [`lint`] policy. [`values`] gives each stored
//! CANopen entry's type, initial value and limits as generated code and the simulators hold it. The code generator
//! (`edsgen-codegen`), the simulators and the CLI start from a loaded model.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod diag;
pub mod did_you_mean;
pub mod dump;
pub mod lint;
pub mod load;
pub mod model;
pub mod overlay;
pub mod read;
pub mod render;
pub mod rules;
pub mod sii;
pub mod validate;
pub mod values;
