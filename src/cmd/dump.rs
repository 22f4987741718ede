//! `edsgen dump`: the resolved model of one file as JSON; refuses a file nothing could be read
//! from (empty, binary, malformed XML) instead of printing an empty model.

use std::path::Path;
use std::process::ExitCode;

use edsgen_model::{dump, render};

use super::{fail, print_stdout};

/// Runs `edsgen dump FILE [--device NAME|#xCODE]`.
pub fn run(path: &Path, device: Option<&str>) -> ExitCode {
    let read = match super::load(path, device) {
        Ok(read) => read,
        Err(err) => return fail(err),
    };
    if read.nothing_read {
        let name = path.display().to_string();
        eprint!(
            "{}",
            render::human(&name, &read.text, &read.diagnostics, false)
        );
        return ExitCode::from(1);
    }
    let json = dump::to_json(&read.device);
    match serde_json::to_string_pretty(&json) {
        Ok(text) => {
            print_stdout(&format!("{text}\n"));
            ExitCode::SUCCESS
        }
        Err(err) => fail(err),
    }
}
