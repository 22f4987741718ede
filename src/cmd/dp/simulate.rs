//! `edsgen simulate --profibus TTY (--card goodrive350-dp[@ADDR] | FILE.gsd[@ADDR])...`:
//! PROFIBUS-DP slaves on one serial line (`edsgen_sim::dp::serial`), each at its own address:
//! the bundled Goodrive350 card with its PKW/PZD drive, or a slave built from any GSD file
//! whose inputs echo its outputs. The address is `@ADDR`, else the card's default (2, P15.01's)
//! or 2 for a file. A file's slave accepts in Chk_Cfg any combination of its modules its GSD
//! allows, unless `--module [SLOT=]NAME` after it plugs it with those modules, which it then
//! accepts alone. State changes go to stderr (`data exchange`, `wait for parameters`, the
//! watchdog's E-DP; `station N: ` before each with several slaves), until the line closes or
//! SIGINT, SIGTERM or SIGHUP stops it (then `stopped:`).

use std::fs::OpenOptions;
use std::path::Path;
use std::process::ExitCode;

use edsgen_model::lint::Policy;
use edsgen_model::model::modules::{parse_choices, ModuleChoice};
use edsgen_runtime::dp::DpSlave;
use edsgen_runtime::Instant;
use edsgen_sim::dp::card::{self, Simulated, DEFAULT_ADDRESS};
use edsgen_sim::dp::serial::serve;
use edsgen_sim::dp::{DpState, Event};

use crate::cmd::fail;

/// The name `--card` takes for the DP card.
pub const CARD: &str = "goodrive350-dp";

/// `NAME[@ADDR]`: the name and the address (the card's default, 2, without one).
fn name_and_address(text: &str) -> Result<(String, u8), String> {
    match text.rsplit_once('@') {
        Some((name, address)) => match address.parse::<u8>() {
            Ok(a) if a <= 125 => Ok((name.to_owned(), a)),
            _ => Err(format!("bad station address `{address}` (0 to 125)")),
        },
        None => Ok((text.to_owned(), DEFAULT_ADDRESS)),
    }
}

/// The slave one `--card` or FILE argument names.
fn slave(
    text: &str,
    is_card: bool,
    modules: &[ModuleChoice],
    now: Instant,
    allow: &Policy,
) -> Result<(DpSlave<Simulated>, String), String> {
    let (name, address) = name_and_address(text)?;
    if is_card {
        if name != CARD {
            return Err(format!("--profibus: no DP card `{name}` (there is {CARD})"));
        }
        let card = card::goodrive350(address, now).map_err(|e| e.to_string())?;
        let config = card.config().clone();
        let app = Simulated::Card(card.app().clone());
        return Ok((DpSlave::new(config, app, now), format!("card {CARD}")));
    }
    // A FILE is judged before the line is opened: one with errors is not served.
    let loaded = crate::cmd::simulate::load_servable(Path::new(&name), None, allow)?;
    let dp = loaded
        .device
        .dp()
        .ok_or_else(|| format!("{name}: {}", card::CardError::NotGsd))?;
    let echo = card::loopback(dp, modules, address, now).map_err(|e| format!("{name}: {e}"))?;
    let config = echo.config().clone();
    let app = Simulated::Loopback(echo.app().clone());
    Ok((DpSlave::new(config, app, now), name))
}

/// Runs the DP slaves of the `--card` and FILE arguments of `edsgen simulate` on `tty`, each at
/// its own address; `modules` holds each FILE's `--module`s, in the order of `files` (none for
/// a FILE past its end).
pub fn run(
    tty: &str,
    files: &[String],
    cards: &[String],
    modules: &[Vec<String>],
    allow: &Policy,
) -> ExitCode {
    if files.is_empty() && cards.is_empty() {
        return fail(format!(
            "--profibus serves slaves: --card {CARD}[@ADDR] or FILE.gsd[@ADDR], one or more"
        ));
    }
    let mut chosen = Vec::new();
    for (n, file) in files.iter().enumerate() {
        match parse_choices(modules.get(n).map_or(&[][..], Vec::as_slice)) {
            Ok(choices) => chosen.push(choices),
            Err(message) => return fail(format!("{file}: --module {message}")),
        }
    }
    let now = Instant::from_micros(0);
    let named = cards.iter().map(|c| (c, true, &[][..])).chain(
        files
            .iter()
            .zip(&chosen)
            .map(|(f, m)| (f, false, m.as_slice())),
    );
    let mut slaves = Vec::new();
    let mut lines = Vec::new();
    for (text, is_card, modules) in named {
        let (slave, what) = match slave(text, is_card, modules, now, allow) {
            Ok(slave) => slave,
            Err(message) => return fail(message),
        };
        let address = slave.config().address;
        if slaves
            .iter()
            .any(|s: &DpSlave<Simulated>| s.config().address == address)
        {
            return fail(format!("two slaves at station address {address}"));
        }
        lines.push(format!("simulating DP slave {address} ({what}) on {tty}"));
        slaves.push(slave);
    }
    let port = match OpenOptions::new().read(true).write(true).open(tty) {
        Ok(port) => port,
        Err(e) => return fail(format!("cannot open {tty}: {e}")),
    };
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    for line in lines {
        eprintln!("{line}");
    }
    let several = slaves.len() > 1;
    let report = move |address: u8, event: Event| {
        let text = event_text(event);
        if several {
            eprintln!("station {address}: {text}");
        } else {
            eprintln!("{text}");
        }
    };
    let result = serve(port, &mut slaves, crate::cmd::signals::flag(), report);
    let addresses: Vec<String> = slaves
        .iter()
        .map(|s| s.config().address.to_string())
        .collect();
    match result {
        Ok(()) => {
            let s = if several { "s" } else { "" };
            eprintln!("stopped: DP slave{s} {} on {tty}", addresses.join(", "));
            ExitCode::SUCCESS
        }
        Err(e) => fail(format!("{tty}: {e}")),
    }
}

/// A slave's state change in words.
fn event_text(event: Event) -> &'static str {
    {
        match event {
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
        }
    }
}
