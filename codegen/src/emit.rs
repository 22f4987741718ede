//! The emitter: a model to formatted Rust source. Placeholder until code generation lands.

use crate::model::Device;

/// Generates the Rust module for one device.
pub fn generate(_device: &Device, _module: &str) -> Result<String, String> {
    Err("code generation is not implemented yet".into())
}
