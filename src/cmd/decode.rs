//! `edsgen decode [--eds FILE --node-id N]... [LOG]`: every frame of a candump -L log (a file,
//! or standard input) as one decoded line (see [`edsgen::decode`] for the format). A malformed
//! line is a warning with its line number on standard error; decoding goes on.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use edsgen_runtime::transport::trace::{TraceReadError, TraceReader};

use super::{fail, parse_node_id, read_device};
use edsgen::decode::Decoder;

/// The arguments of `edsgen decode`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A description of a node on the bus (EDS, DCF, XDD, XDC); each `--eds` pairs with the
    /// `--node-id` in the same position.
    #[arg(long = "eds", value_name = "FILE")]
    eds: Vec<PathBuf>,
    /// The node-ID of the device described by the `--eds` in the same position.
    #[arg(long = "node-id", value_name = "N", value_parser = parse_node_id)]
    node_id: Vec<u8>,
    /// The candump -L log (standard input when absent).
    log: Option<PathBuf>,
}

/// Runs `edsgen decode`.
pub fn run(args: Args) -> ExitCode {
    if args.eds.len() != args.node_id.len() {
        return fail(format!(
            "{} --eds but {} --node-id: give each description its node-ID (`--eds FILE --node-id N`)",
            args.eds.len(),
            args.node_id.len()
        ));
    }
    let mut decoder = Decoder::new();
    for (path, &node_id) in args.eds.iter().zip(&args.node_id) {
        match read_device(path) {
            Ok(device) => decoder.describe(node_id, &device),
            Err(message) => return fail(message),
        }
    }
    let input: Box<dyn BufRead> = match &args.log {
        Some(path) => match std::fs::File::open(path) {
            Ok(file) => Box::new(BufReader::new(file)),
            Err(e) => return fail(format!("cannot read `{}`: {e}", path.display())),
        },
        None => Box::new(std::io::stdin().lock()),
    };
    let mut out = std::io::stdout().lock();
    let mut last = Duration::ZERO;
    for record in TraceReader::new(input) {
        let record = match record {
            Ok(record) => record,
            Err(TraceReadError::Parse(e)) => {
                eprintln!("warning: {e}");
                continue;
            }
            Err(e) => return fail(e),
        };
        last = Duration::from_micros(record.timestamp_us);
        for line in decoder.decode(last, &record.frame) {
            if writeln!(out, "{line}").is_err() {
                // A closed pipe (`edsgen decode log | head`): nobody reads any more.
                return ExitCode::SUCCESS;
            }
        }
    }
    for line in decoder.finish(last) {
        let _ = writeln!(out, "{line}");
    }
    ExitCode::SUCCESS
}
