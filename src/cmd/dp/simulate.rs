//! `edsgen simulate --profibus TTY (--card goodrive350-dp[@ADDR] | FILE.gsd[@ADDR])`: one
//! PROFIBUS-DP slave on a serial line (`edsgen_sim::dp::serial`): the bundled Goodrive350 card
//! with its PKW/PZD drive, or a slave built from any GSD file whose inputs echo its outputs.
//! The address is `@ADDR`, else the card's default (2, P15.01's) or 2 for a file. State changes
//! go to stderr (`data exchange`, `wait for parameters`, the watchdog's E-DP), until the line
//! closes or SIGINT, SIGTERM or SIGHUP stops it (then `stopped:`).

use std::fs::OpenOptions;
use std::path::Path;
use std::process::ExitCode;

use edsgen_codegen::lint::Policy;
use edsgen_runtime::Instant;
use edsgen_sim::dp::card::{self, DEFAULT_ADDRESS};
use edsgen_sim::dp::serial::serve;
use edsgen_sim::dp::{DpState, Event};

use crate::cmd::fail;

/// The name `--card` takes for the DP card.
pub const CARD: &str = "goodrive350-dp";

/// Runs one DP slave on `tty`, from the `--card` or FILE arguments of `edsgen simulate`.
pub fn run(tty: &str, files: &[String], cards: &[String], allow: &Policy) -> ExitCode {
    let (what, address) = match (files, cards) {
        ([file], []) => (Some(file.as_str()), file.rsplit_once('@')),
        ([], [card]) => (None, card.rsplit_once('@')),
        _ => {
            return fail(format!(
                "--profibus serves one slave: --card {CARD}[@ADDR] or one FILE.gsd[@ADDR]"
            ))
        }
    };
    let (name, address) = match address {
        Some((name, address)) => match address.parse::<u8>() {
            Ok(a) if a <= 125 => (name.to_owned(), a),
            _ => return fail(format!("bad station address `{address}` (0 to 125)")),
        },
        None => (
            what.map_or_else(|| cards[0].clone(), str::to_owned),
            DEFAULT_ADDRESS,
        ),
    };
    // A FILE is judged before the line is opened: one with errors is not served.
    let gsd = match what {
        Some(_) => match crate::cmd::simulate::load_servable(Path::new(&name), None, allow) {
            Ok(loaded) => Some(loaded.device),
            Err(message) => return fail(message),
        },
        None => None,
    };
    let port = match OpenOptions::new().read(true).write(true).open(tty) {
        Ok(port) => port,
        Err(e) => return fail(format!("cannot open {tty}: {e}")),
    };
    let now = Instant::from_micros(0);
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    let stop = crate::cmd::signals::flag();
    let result = if let Some(gsd) = gsd {
        let Some(dp) = gsd.dp() else {
            return fail(format!("{name}: {}", card::CardError::NotGsd));
        };
        let mut slave = match card::loopback(dp, address, now) {
            Ok(slave) => slave,
            Err(e) => return fail(format!("{name}: {e}")),
        };
        eprintln!("simulating DP slave {address} ({name}) on {tty}");
        serve(port, &mut slave, stop, reporter())
    } else {
        if name != CARD {
            return fail(format!("--profibus: no DP card `{name}` (there is {CARD})"));
        }
        let mut slave = match card::goodrive350(address, now) {
            Ok(slave) => slave,
            Err(e) => return fail(e),
        };
        eprintln!("simulating DP slave {address} (card {CARD}) on {tty}");
        serve(port, &mut slave, stop, reporter())
    };
    match result {
        Ok(()) => {
            eprintln!("stopped: DP slave {address} on {tty}");
            ExitCode::SUCCESS
        }
        Err(e) => fail(format!("{tty}: {e}")),
    }
}

/// Prints the slave's state when it changes.
fn reporter() -> impl FnMut(Event) {
    |event| {
        let text = match event {
            Event::WatchdogExpired => "wait for parameters (the watchdog expired: E-DP)",
            Event::StateChanged {
                from: DpState::DataExchange,
                to: DpState::WaitPrm,
            } => "wait for parameters (the watchdog expired: E-DP)",
            Event::StateChanged { to, .. } => match to {
                DpState::WaitPrm => "wait for parameters",
                DpState::WaitCfg => "wait for configuration",
                DpState::DataExchange => "data exchange",
            },
        };
        eprintln!("{text}");
    }
}
