//! The commands. `main.rs` parses the command line and calls one of them; each returns the
//! process exit code (0 clean, 1 a problem found, 2 usage or I/O). One folder per bus, the
//! bus-neutral commands here:
//!
//! - Description files: [`validate`], [`dump`], [`generate`], [`devices`] (of an ESI file), and
//!   the rule catalogue ([`rules`]: rules, explain).
//! - [`simulate`] serves devices built from description files on the bus its flag names (each
//!   bus's simulator in its folder); [`decode`] explains a candump log; [`demo`]: the bundled cards
//!   at work.
//! - The buses: [`canopen`] (sdo, nmt, lss, scan, check, bus), [`ethercat`] (ecat, sii),
//!   [`enip`], [`dp`], [`profinet`] (pn).
//!
//! This module holds what they share: exit codes and messages, node-IDs and addresses from the
//! command line, and how the master's commands reach the bus.
//!
//! One convention for the subcommands' arguments (a new command follows it):
//!
//! - The thing worked on comes first, positional: a description `FILE` for the file commands
//!   (`validate`, `dump`, `generate`, `devices`, `sii`, `simulate FILE[@ID]`); for the bench
//!   commands, the device: `NODE` (CANopen node-ID, 1..=127 in decimal or `0x` hex, `all` where
//!   every node makes sense), `ADDR` (`IP` or `IP:PORT`), `IFACE` (a network interface), `TTY`
//!   (a serial line), `MAC`. Then what on the device, positional: the entry (`INDEX[:SUB]` in
//!   hex or its name) or the CIP path (`@CLASS/INST/ATTR` or a parameter's name); then the
//!   `VALUE`, last (a number in decimal or `0x` hex, negative without `--`; several as
//!   `NAME=VALUE...`).
//! - A description that only names and types things for a bench command is a flag named after
//!   its format: `--eds FILE` (CANopen, EtherNet/IP), `--esi FILE` (EtherCAT), `--gsd FILE`
//!   (PROFIBUS-DP), `--gsdml FILE` (PROFINET); one device of a file with several:
//!   `--device NAME|#xCODE`. A type where no description gives it: `--type TYPE`.
//! - How to reach the bus, when the device's address is not enough, is a flag: `--bus
//!   HOST:PORT`, `--socketcan IFACE`, `--channel` ([`BusArgs`]), `--from ADDR`, `--master N`
//!   (this master's station address). A node given as an option is `--node-id N`; a station
//!   address `--address N`; an EtherCAT SubDevice `--position N`. `simulate` picks the bus by
//!   its flag: `--bus`/`--socketcan`, `--ethercat IFACE`, `--enip ADDR`, `--profinet IFACE`,
//!   `--profibus TTY`.
//! - Times are milliseconds, `MS`: `--timeout MS` is the whole wait for an answer, other waits
//!   say what they wait for (`--rpi MS`, `--activate MS`); how long a command runs is
//!   `--seconds S` or `--cycles N` (until Ctrl-C when absent).
//! - Output: `--format human|json`, a file written `-o FILE`/`--output FILE` (`sdo read --out
//!   PATH` and `sdo write --file PATH` stream an entry's value, `-` for standard output/input).
//!
//! Known outliers, kept for compatibility: `ecat` takes `--iface IFACE` where `pn` takes a
//! positional `IFACE`; `ecat sdo` types a value by `--size 1|2|4|8` where `sdo` has `--type`.

pub mod canopen;
pub mod decode;
pub mod demo;
pub mod devices;
use edsgen_model::did_you_mean;
pub mod dp;
pub mod dump;
pub mod enip;
pub mod ethercat;
pub mod generate;
pub mod machine;
mod parallel;
pub mod profinet;
pub mod rules;
pub mod signals;
pub mod simulate;
pub mod validate;
pub mod value;

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use edsgen_host::master::blocking::Master;
use edsgen_host::socketcand::SocketcandClient;
use edsgen_host::Transport;
use edsgen_model::load::Loaded;
use edsgen_model::model::Device;

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
pub fn rule_named(flag: &str, code: &str) -> Result<&'static edsgen_model::rules::Rule, String> {
    let rule =
        edsgen_model::rules::by_code(code).ok_or_else(|| {
            match edsgen_model::rules::nearest(code) {
                Some(near) => format!(
                    "{flag} {code}: no such rule; did you mean {}? (`edsgen rules` lists them)",
                    near.code
                ),
                None => format!("{flag} {code}: no such rule (`edsgen rules` lists them)"),
            }
        })?;
    if flag.starts_with("--") && rule.code.starts_with("CHK") {
        return Err(format!(
            "{flag} {code}: `edsgen check` reports {}, not `edsgen validate`",
            rule.code
        ));
    }
    Ok(rule)
}

/// A node-ID from the command line: 1 to 127, decimal or `0x` hexadecimal.
pub fn parse_node_id(text: &str) -> Result<u8, String> {
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

/// Loads a description for a command ([`edsgen_model::load`]: read, its overlay applied,
/// validated; one device of an ESI file when `device` names it). The error is the message to
/// print: the file or its overlay cannot be read, or the overlay does not apply (unless nothing
/// of the file could be read: the caller reports that).
pub fn load(path: &Path, device: Option<&str>) -> Result<Loaded, String> {
    let loaded = edsgen_model::load::load(path, device).map_err(|e| e.to_string())?;
    match loaded.overlay.as_ref() {
        Some(overlay) if !overlay.diagnostics.is_empty() && !loaded.nothing_read => Err(format!(
            "the overlay `{}` cannot be applied:\n{}",
            overlay.path.display(),
            overlay.rendered().trim_end()
        )),
        _ => Ok(loaded),
    }
}

/// Loads a description file's model ([`load`]); the error is the message to print.
pub fn read_device(path: &Path) -> Result<Device, String> {
    if !path.is_file() {
        return Err(format!("cannot read `{}`: not a file", path.display()));
    }
    load(path, None).map(|loaded| loaded.device)
}

/// The address `edsgen bus` listens on by default, and every client command joins by default.
pub const DEFAULT_BUS: &str = "127.0.0.1:29536";

/// How to reach the bus.
#[derive(Args, Debug, Clone)]
pub struct BusArgs {
    /// A socketcand server (`edsgen bus`, socketcand on a Linux box) as HOST:PORT [default:
    /// 127.0.0.1:29536, where `edsgen bus` listens].
    #[arg(long, value_name = "HOST:PORT")]
    pub bus: Option<String>,
    /// A Linux SocketCAN interface (can0, vcan0).
    #[cfg(feature = "socketcan")]
    #[arg(long, value_name = "IFACE", conflicts_with = "bus")]
    pub socketcan: Option<String>,
    /// The CAN channel to open on the socketcand server.
    #[arg(long, default_value = "can0")]
    pub channel: String,
    /// The whole wait for a node's answer, in milliseconds (scan: for every node to answer).
    /// Retries happen inside it: a read not answered within half of it is asked once more (a
    /// lost frame), so an absent node costs exactly MS; a write is never repeated (the node
    /// may have applied it) and waits all of MS. In a segmented or block transfer, MS is the
    /// wait for each answer.
    #[arg(long, value_name = "MS", default_value_t = 1000,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout: u64,
}

impl BusArgs {
    /// A master on the bus, or the reason there is none.
    pub fn connect(&self) -> Result<Master<Box<dyn Transport + Send>>, String> {
        let mut master = Master::new(self.open()?);
        self.for_reads(&mut master);
        Ok(master)
    }

    /// A connection of its own to the bus, or the reason there is none.
    pub fn open(&self) -> Result<Box<dyn Transport + Send>, String> {
        Ok(match self.target()? {
            Target::Socketcand(addr) => Box::new(
                SocketcandClient::connect(addr, &self.channel, Duration::from_secs(5))
                    .map_err(|e| format!("cannot reach the bus at {addr}: {e}"))?,
            ),
            #[cfg(feature = "socketcan")]
            Target::SocketCan(iface) => Box::new(
                edsgen_host::socketcan::SocketCan::open(iface)
                    .map_err(|e| format!("cannot open {iface}: {e}"))?,
            ),
        })
    }

    /// Sets `master`'s timeout for reads: half of `--timeout`, one retry.
    pub fn for_reads<T: Transport>(&self, master: &mut Master<T>) {
        master.set_read_retries(1);
        master.set_default_timeout(Duration::from_millis(self.timeout.div_ceil(2)));
    }

    /// Sets `master`'s timeout for writes: all of `--timeout` (a write is never repeated).
    pub fn for_writes<T: Transport>(&self, master: &mut Master<T>) {
        master.set_default_timeout(Duration::from_millis(self.timeout));
    }
}

/// Where the bus is.
enum Target<'a> {
    Socketcand(&'a str),
    #[cfg(feature = "socketcan")]
    SocketCan(&'a str),
}

impl BusArgs {
    fn target(&self) -> Result<Target<'_>, String> {
        #[cfg(feature = "socketcan")]
        if let Some(iface) = &self.socketcan {
            return Ok(Target::SocketCan(iface));
        }
        Ok(Target::Socketcand(
            self.bus.as_deref().unwrap_or(DEFAULT_BUS),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_ids_parse_in_the_usual_spellings() {
        assert_eq!(parse_node_id("5"), Ok(5));
        assert_eq!(parse_node_id("0x7F"), Ok(127));
        assert_eq!(
            parse_node_id("0"),
            Err("node-ID 0 is not in 1..=127".into())
        );
        assert_eq!(
            parse_node_id("128"),
            Err("node-ID 128 is not in 1..=127".into())
        );
        assert_eq!(
            parse_node_id("x"),
            Err("`x` is not a node-ID (1 to 127)".into())
        );
    }

    #[test]
    fn edsgen_bus_listens_where_the_clients_go_by_default() {
        use clap::{Args, Command};
        let bus = canopen::bus::BusArgs::augment_args(Command::new("bus"));
        let listen = bus
            .get_arguments()
            .find(|arg| arg.get_id() == "listen")
            .map(|arg| arg.get_default_values().to_vec());
        assert_eq!(listen, Some(vec![DEFAULT_BUS.into()]));
    }
}
