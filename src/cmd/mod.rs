//! The `edsgen` subcommands that talk to a CAN bus, one module each: [`bus`] runs a socketcand
//! hub, [`simulate`] serves devices built from description files, [`decode`] explains a candump
//! log. Each takes its clap arguments and returns the process exit code (0 done, 2 usage or I/O
//! problems).

pub mod bus;
pub mod decode;
pub mod simulate;

use std::path::Path;
use std::process::ExitCode;

use edsgen_codegen::model::Device;

/// Exit code for usage and I/O problems.
const EXIT_USAGE: u8 = 2;

/// Prints `error: message` and gives exit code 2.
fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(EXIT_USAGE)
}

/// A node-ID from the command line: 1 to 127, decimal or `0x` hexadecimal.
fn parse_node_id(text: &str) -> Result<u8, String> {
    let value = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => text.parse::<u32>(),
    };
    match value {
        Ok(id @ 1..=127) => Ok(id as u8),
        Ok(id) => Err(format!("node-ID {id} is not in 1..=127")),
        Err(_) => Err(format!("`{text}` is not a node-ID (1 to 127)")),
    }
}

/// Reads a description file into its model; the error is the message to print.
fn read_device(path: &Path) -> Result<Device, String> {
    if !path.is_file() {
        return Err(format!("cannot read `{}`: not a file", path.display()));
    }
    edsgen_codegen::read::read_file(path)
        .map(|read| read.device)
        .map_err(|e| e.to_string())
}
