//! `edsgen lss scan|inquire|set-id|set-bitrate|switch`: LSS (CiA 305) on a live bus, to give
//! a node without a node-ID one, by its identity or by fastscan. Identities are printed and
//! read as `VENDOR:PRODUCT:REVISION:SERIAL` in hex (`0x000004D8:0x00009252:0x00000001:0x00000007`).
//! Exit 0 done, 1 no answer or refused, 2 usage or bus errors.

use std::process::ExitCode;
use std::time::Duration;

use clap::{Subcommand, ValueEnum};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::Transport;
use edsgen_runtime::master::lss::{LssOutcome, LssService};
use edsgen_runtime::wire::lss::{LssAddress, LssMode};

use crate::cmd::{fail, parse_node_id, BusArgs};

/// The LSS commands.
#[derive(Debug, Subcommand)]
pub enum LssCommand {
    /// Fastscan: every node without a node-ID, its identity one a line. Each one found stays
    /// in configuration (out of the next scans) until the end, when all are switched back to
    /// waiting, still without a node-ID.
    Scan {
        #[command(flatten)]
        bus: BusArgs,
    },
    /// The identity and node-ID of the node in LSS configuration state.
    Inquire {
        #[command(flatten)]
        bus: BusArgs,
    },
    /// Switch the node with this identity to configuration, give it NODE-ID (255: none), store
    /// it with --store, and switch it back to waiting (an unconfigured node then starts with
    /// the new ID).
    SetId {
        #[command(flatten)]
        bus: BusArgs,
        /// VENDOR:PRODUCT:REVISION:SERIAL, each in hex (0x optional).
        identity: String,
        /// The new node-ID, 1..=127 or 255.
        node_id: String,
        /// Store the configuration in the node (store configuration).
        #[arg(long)]
        store: bool,
    },
    /// Set the bit rate of the node(s) in configuration state (CiA 301 table 0: 1000, 800,
    /// 500, 250, 125, 50, 20, 10 kbit/s).
    SetBitrate {
        #[command(flatten)]
        bus: BusArgs,
        /// The bit rate in kbit/s.
        kbit: u16,
        /// Store the configuration in the node.
        #[arg(long)]
        store: bool,
        /// Activate it on every node in configuration with this switch delay (ms).
        #[arg(long, value_name = "MS")]
        activate: Option<u16>,
    },
    /// Switch every node to LSS waiting or configuration state.
    Switch {
        #[command(flatten)]
        bus: BusArgs,
        /// Always `global`.
        #[arg(value_enum)]
        scope: Scope,
        /// The state.
        #[arg(value_enum)]
        mode: Mode,
    },
}

/// Which nodes a switch addresses.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Scope {
    /// Every node (switch state global).
    Global,
}

/// An LSS state.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Mode {
    /// LSS waiting state.
    Waiting,
    /// LSS configuration state.
    Configuration,
}

/// Runs `edsgen lss ...`.
pub fn run(command: &LssCommand) -> ExitCode {
    let bus = match command {
        LssCommand::Scan { bus }
        | LssCommand::Inquire { bus }
        | LssCommand::SetId { bus, .. }
        | LssCommand::SetBitrate { bus, .. }
        | LssCommand::Switch { bus, .. } => bus,
    };
    // Usage first, before the bus is opened.
    let request = match Request::of(command) {
        Ok(request) => request,
        Err(message) => return fail(message),
    };
    let mut master = match bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    match request.run(&mut master, bus) {
        Ok(code) => code,
        Err(MasterError::Lss(e)) => {
            println!("{e}");
            ExitCode::from(1)
        }
        Err(e) => fail(e),
    }
}

/// A command with its arguments checked.
enum Request {
    Scan,
    Inquire,
    SetId(LssAddress, u8, bool),
    SetBitrate(u8, bool, Option<u16>),
    Switch(LssMode),
}

impl Request {
    fn of(command: &LssCommand) -> Result<Self, String> {
        Ok(match command {
            LssCommand::Scan { .. } => Request::Scan,
            LssCommand::Inquire { .. } => Request::Inquire,
            LssCommand::SetId {
                identity,
                node_id,
                store,
                ..
            } => {
                let id = match node_id.as_str() {
                    "255" | "0xFF" | "0xff" => 0xFF,
                    other => parse_node_id(other).map_err(|e| format!("{e} (or 255)"))?,
                };
                Request::SetId(parse_identity(identity)?, id, *store)
            }
            LssCommand::SetBitrate {
                kbit,
                store,
                activate,
                ..
            } => {
                let index = table0_index(*kbit).ok_or_else(|| {
                    format!("{kbit} kbit/s is not in the CiA 301 table (1000, 800, 500, 250, 125, 50, 20, 10)")
                })?;
                Request::SetBitrate(index, *store, *activate)
            }
            LssCommand::Switch { mode, .. } => Request::Switch(match mode {
                Mode::Waiting => LssMode::Waiting,
                Mode::Configuration => LssMode::Configuration,
            }),
        })
    }

    fn run<T: Transport>(
        self,
        master: &mut Master<T>,
        bus: &BusArgs,
    ) -> Result<ExitCode, MasterError> {
        match self {
            Request::Scan => {
                let found = master.lss_scan_all(Duration::from_millis(100), |_, address| {
                    println!("{}", show_identity(&address));
                    Ok(false)
                })?;
                println!(
                    "{} unconfigured node(s) found on {}",
                    found.len(),
                    bus.channel
                );
            }
            Request::Inquire => {
                let LssOutcome::Address(address) = master.lss(LssService::InquireAddress)? else {
                    unreachable!("an inquiry answers an address")
                };
                let LssOutcome::NodeId(id) = master.lss(LssService::InquireNodeId)? else {
                    unreachable!("an inquiry answers a node-ID")
                };
                let id = if id == 0xFF {
                    "255 (unconfigured)".to_owned()
                } else {
                    id.to_string()
                };
                println!("{} node-ID {id}", show_identity(&address));
            }
            Request::SetId(address, id, store) => {
                master.lss(LssService::SwitchSelective(address))?;
                let configured = master.lss(LssService::ConfigureNodeId(id)).and_then(|_| {
                    if store {
                        master.lss(LssService::Store)?;
                    }
                    Ok(())
                });
                master.lss(LssService::SwitchGlobal(LssMode::Waiting))?;
                configured?;
                let stored = if store { ", stored" } else { "" };
                println!("{}: node-ID {id}{stored}", show_identity(&address));
            }
            Request::SetBitrate(index, store, activate) => {
                master.lss(LssService::ConfigureBitTiming { table: 0, index })?;
                if store {
                    master.lss(LssService::Store)?;
                }
                if let Some(delay) = activate {
                    master.lss(LssService::ActivateBitTiming(delay))?;
                }
                println!("bit timing table 0 entry {index} configured");
            }
            Request::Switch(mode) => {
                master.lss(LssService::SwitchGlobal(mode))?;
            }
        }
        Ok(ExitCode::SUCCESS)
    }
}

/// The line `scan` and `check` print when an LSS inquiry (identify non-configured remote
/// slave) finds nodes without a node-ID: they answer no SDO, so a scan cannot see them.
pub fn unconfigured_note<T: Transport>(master: &mut Master<T>) -> Option<&'static str> {
    match master.lss(LssService::IdentifyNonConfigured) {
        Ok(LssOutcome::Identified(true)) => Some(
            "unconfigured node(s) on the bus (LSS, node-ID 255): they answer no SDO; \
             `edsgen lss scan` lists them, `edsgen lss set-id` gives each a node-ID",
        ),
        _ => None,
    }
}

/// The table 0 entry of a bit rate (CiA 301: entry 5 reserved, 9 automatic detection).
fn table0_index(kbit: u16) -> Option<u8> {
    const TABLE: [(u16, u8); 8] = [
        (1000, 0),
        (800, 1),
        (500, 2),
        (250, 3),
        (125, 4),
        (50, 6),
        (20, 7),
        (10, 8),
    ];
    TABLE.iter().find(|(k, _)| *k == kbit).map(|(_, i)| *i)
}

/// `0x000004D8:0x00009252:0x00000001:0x00000007`.
pub fn show_identity(address: &LssAddress) -> String {
    address
        .iter()
        .map(|v| format!("0x{v:08X}"))
        .collect::<Vec<_>>()
        .join(":")
}

/// Reads `VENDOR:PRODUCT:REVISION:SERIAL`, each hex with or without 0x.
pub fn parse_identity(text: &str) -> Result<LssAddress, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let usage = || {
        format!("`{text}` is not an identity VENDOR:PRODUCT:REVISION:SERIAL (hex, e.g. 0x000004D8:0x00009252:0x00000001:0x00000007)")
    };
    let [vendor, product, revision, serial] = parts[..] else {
        return Err(usage());
    };
    let mut address = [0u32; 4];
    for (value, part) in address.iter_mut().zip([vendor, product, revision, serial]) {
        let hex = part
            .strip_prefix("0x")
            .or_else(|| part.strip_prefix("0X"))
            .unwrap_or(part);
        *value = u32::from_str_radix(hex, 16).map_err(|_| usage())?;
    }
    Ok(address)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identities_in_hex_both_ways() {
        let address = parse_identity("0x000004D8:0x00009252:0x00000001:0x00000007").unwrap();
        assert_eq!(address, [0x4D8, 0x9252, 1, 7]);
        assert_eq!(
            show_identity(&address),
            "0x000004D8:0x00009252:0x00000001:0x00000007"
        );
        assert_eq!(parse_identity("4d8:9252:1:7"), Ok(address));
        assert!(parse_identity("4d8:9252:1").is_err());
        assert!(parse_identity("4d8:9252:1:x").is_err());
        assert_eq!(table0_index(125), Some(4));
        assert_eq!(table0_index(100), None);
    }
}
