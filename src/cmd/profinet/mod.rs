//! `edsgen pn list IFACE [--gsdml FILE]...`, `edsgen pn set-name IFACE MAC NAME` and `edsgen pn
//! io` (a controller at the bench, [`io`]): PROFINET
//! DCP at the bench, as a controller (root, or `CAP_NET_RAW`). `list` sends Identify all and
//! prints one tab-separated line per device that answers within the timeout: MAC, name of
//! station, VendorID:DeviceID, IP, type of station, and with `--gsdml` the file whose VendorID
//! and DeviceID it has (or `-`). `set-name` sets the name of station (permanently) and prints
//! the device's answer. Exit 0; 1 when no device answers or the device refuses; 2 for usage and
//! I/O problems.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Subcommand;

use dcp_verbs::{check_name, list, request, set_name, show_mac};

mod dcp_verbs;
mod io;
mod io_data;
mod io_link;
pub mod simulate;

/// `edsgen pn` verbs.
#[derive(Subcommand, Debug)]
pub enum PnCommand {
    /// Identify all devices on an interface (DCP).
    List {
        /// The network interface.
        iface: String,
        /// GSDML files to match the devices to, by VendorID and DeviceID.
        #[arg(long = "gsdml", value_name = "FILE")]
        gsdml: Vec<PathBuf>,
        /// How long to collect answers, in ms.
        #[arg(long, value_name = "MS", default_value_t = 1000)]
        timeout: u64,
    },
    /// Set a device's name of station (DCP Set, permanent).
    SetName {
        /// The network interface.
        iface: String,
        /// The device's MAC address (`aa:bb:cc:dd:ee:ff`).
        mac: String,
        /// The new name of station (DNS-compatible: lowercase letters, digits, `-`, `.`).
        name: String,
    },
    /// Connect to a device as its IO controller and exchange its IO data (RT_CLASS_1).
    ///
    /// Finds the device by its name of station, connects with the GSDML's default access
    /// point and modules, writes their parameter records, and exchanges cyclic frames: the
    /// outputs as set here (zero elsewhere), the inputs printed by name whenever they change,
    /// alarms printed and acknowledged. Releases the connection after --cycles, or on Ctrl-C.
    /// Exit 0; 1 when the device is not found, refuses or is lost; 2 for usage.
    Io {
        /// The network interface.
        iface: String,
        /// The device's name of station.
        name: String,
        /// The device's GSDML file.
        #[arg(long = "gsdml", value_name = "FILE")]
        gsdml: PathBuf,
        /// Outputs to set: `NAME=VALUE` (a data item's name, as printed for the inputs, or its
        /// whole GSDML text) or `SLOT.SUBSLOT=HEX` (a submodule's whole output data).
        #[arg(value_name = "SETTING")]
        settings: Vec<String>,
        /// Plug the GSDML module with this ID in SLOT (`SLOT=MODULE_ID`), for devices whose
        /// modules are only allowed, not used, in their slots.
        #[arg(long = "module", value_name = "SLOT=MODULE_ID")]
        modules: Vec<String>,
        /// Write this content to a parameter record instead of the GSDML's defaults
        /// (`SLOT.SUBSLOT.INDEX=HEX`).
        #[arg(long = "record", value_name = "SLOT.SUBSLOT.INDEX=HEX")]
        records: Vec<String>,
        /// Release the connection after this many cycles of data exchange (default: run until
        /// Ctrl-C or SIGTERM).
        #[arg(long, value_name = "N")]
        cycles: Option<u64>,
        /// The cycle time in ms: a power of two from 1 to 512.
        #[arg(long = "cycle-ms", value_name = "MS", default_value_t = 8)]
        cycle_ms: u16,
    },
}

/// Runs an `edsgen pn` verb.
pub fn run(command: &PnCommand) -> ExitCode {
    match command {
        PnCommand::List {
            iface,
            gsdml,
            timeout,
        } => list(iface, gsdml, Duration::from_millis(*timeout)),
        PnCommand::SetName { iface, mac, name } => set_name(iface, mac, name),
        PnCommand::Io {
            iface,
            name,
            gsdml,
            settings,
            modules,
            records,
            cycles,
            cycle_ms,
        } => io::run(&io::IoArgs {
            iface,
            name,
            gsdml,
            settings,
            modules,
            records,
            cycles: *cycles,
            cycle_ms: *cycle_ms,
        }),
    }
}

