//! `Builder`: the build.rs entry point. Placeholder until code generation lands.

use std::path::PathBuf;

/// Generates typed bindings for one or more devices from build.rs.
#[derive(Debug, Default, Clone)]
pub struct Builder {
    devices: Vec<PathBuf>,
}

impl Builder {
    /// A builder with no devices.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a device description file.
    pub fn device(mut self, path: impl Into<PathBuf>) -> Self {
        self.devices.push(path.into());
        self
    }
}
