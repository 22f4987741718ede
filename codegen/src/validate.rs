//! The validator: rules over the model. Placeholder until the rules land.

use crate::diag::Diagnostic;
use crate::model::Device;

/// Judges a device model; the diagnostics come sorted by position.
pub fn validate(_device: &Device) -> Vec<Diagnostic> {
    Vec::new()
}
