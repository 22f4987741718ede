//! The commands, one module each: those that read description files (validate, dump, generate,
//! and the rule catalogue: rules, explain) those that run on a bus (bus), and the demo. `main.rs` parses the command line and calls one of these; each returns the
//! process exit code (0 clean, 1 a problem found, 2 usage or I/O).

use std::io::Write;
use std::process::ExitCode;

pub mod bus;
pub mod demo;
pub mod dump;
pub mod generate;
pub mod rules;
pub mod validate;

/// Exit code for usage and I/O problems.
pub const EXIT_USAGE: u8 = 2;

/// Writes to standard output, ignoring a closed pipe (`edsgen dump f.eds | head` must not panic).
pub fn print_stdout(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// Prints `error: {message}` and returns the usage/I-O exit code.
pub fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(EXIT_USAGE)
}

/// The rule a `--allow`/`--deny`/`explain` argument names, or the usage error to print.
pub fn rule_named(flag: &str, code: &str) -> Result<&'static edsgen_codegen::rules::Rule, String> {
    edsgen_codegen::rules::by_code(code)
        .ok_or_else(|| format!("{flag} {code}: no such rule (`edsgen rules` lists them)"))
}
