//! `edsgen decode [--eds FILE --node-id N]... [--full] [LOG]`: every frame of a CAN log (a
//! file, or standard input) as one decoded line (see [`edsgen_decode`] for the lines and
//! [`edsgen_decode::log`] for the formats: candump `-L` and default, Vector ASC, PCAN TRC,
//! recognised by their content). A line that cannot be read is a warning with its number on
//! standard error and decoding goes on; what was skipped (CAN FD, error frames, bytes that are
//! not UTF-8) is counted at the end. Exit code 1 when the log holds no frame at all; a closed
//! standard output (`edsgen decode log | head`) ends it quietly.

use std::io::{self, BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use super::{fail, parse_node_id, read_device};
use edsgen_decode::log::{Entry, LogReader};
use edsgen_decode::Decoder;

/// How many warnings about unreadable lines are printed; the rest are only counted.
const WARNINGS_SHOWN: u64 = 20;

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
    /// Print the whole value of long SDO transfers (by default: the first bytes, the size and
    /// the CRC of a block transfer).
    #[arg(long)]
    full: bool,
    /// The log: candump (-L or default, with or without -t), Vector ASC or PCAN TRC (standard
    /// input when absent).
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
    if args.full {
        decoder.show_full_values();
    }
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
        None => Box::new(io::stdin().lock()),
    };
    let mut out = io::stdout().lock();
    let mut reader = LogReader::new(input);
    let mut last = Duration::ZERO;
    loop {
        let entry = match reader.next_entry() {
            Ok(Some(entry)) => entry,
            Ok(None) => break,
            Err(e) => return fail(format!("cannot read the log: {e}")),
        };
        let lines = match entry {
            Entry::Frame { time_us, frame } => {
                last = Duration::from_micros(time_us);
                decoder.decode(last, &frame)
            }
            Entry::Warning(line, message) => {
                if reader.tally().unreadable <= WARNINGS_SHOWN {
                    warn(&format!("line {line}: {message}"));
                }
                continue;
            }
        };
        if !print(&mut out, &lines) {
            // A closed pipe (`edsgen decode log | head`): nobody reads any more.
            return ExitCode::SUCCESS;
        }
    }
    if !print(&mut out, &decoder.finish(last)) {
        return ExitCode::SUCCESS;
    }
    let tally = reader.tally();
    if tally.unreadable > WARNINGS_SHOWN {
        warn(&format!(
            "{} line(s) could not be read in all (the first {WARNINGS_SHOWN} are shown)",
            tally.unreadable
        ));
    }
    if tally.fd > 0 {
        warn(&format!("skipped {} CAN FD frame(s)", tally.fd));
    }
    if tally.errors > 0 {
        warn(&format!(
            "skipped {} error frame(s) and bus status line(s)",
            tally.errors
        ));
    }
    if tally.not_utf8 > 0 {
        warn(&format!(
            "{} line(s) held bytes that are not UTF-8 (read as U+FFFD)",
            tally.not_utf8
        ));
    }
    if tally.frames == 0 {
        let _ = writeln!(
            io::stderr(),
            "error: no CAN frame in the log (candump -L or default, Vector ASC and PCAN TRC are read)"
        );
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

/// Writes `lines`; false when standard output is gone.
fn print(out: &mut impl Write, lines: &[String]) -> bool {
    lines.iter().all(|line| writeln!(out, "{line}").is_ok())
}

/// `warning: {text}` on standard error (a closed one is ignored).
fn warn(text: &str) {
    let _ = writeln!(io::stderr(), "warning: {text}");
}
