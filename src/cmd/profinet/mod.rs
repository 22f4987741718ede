//! `edsgen pn`: PROFINET at the bench, as a controller (root, or `CAP_NET_RAW`). DCP
//! ([`dcp_verbs`]): `list` sends Identify all and prints one tab-separated line per device that
//! answers in its window, by MAC: MAC, name of station, VendorID:DeviceID, IP, type of
//! station, and with `--gsdml` the file whose VendorID and DeviceID it has (or `-`);
//! `set-name`, `set-ip` and `blink` set a device's name of station, IP parameter or signal and
//! print its answer. Records without a connection ([`record`]): `im` (I&M0 in words) and
//! `record` (a hex dump). A controller at the bench ([`io`]). Exit 0; 1 when no device answers
//! or the device refuses; 2 for usage and I/O problems.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Subcommand;
use edsgen_model::model::modules::{choose_pn, parse_choices};
use edsgen_model::model::Profinet;

use dcp_verbs::{check_name, request, show_mac};

mod dcp_verbs;
mod io;
mod io_data;
mod io_link;
mod record;
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
        /// The window the devices spread their answers over, in ms: sent as the Identify's
        /// ResponseDelayFactor (10 ms steps, up to 64 s); `list` listens that long and 0.5 s
        /// more, and says so on standard error.
        #[arg(long, value_name = "MS", default_value_t = 1000, alias = "timeout")]
        window: u64,
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
    /// Set a device's IP address, netmask and gateway (DCP Set, permanent unless --temporary).
    SetIp {
        /// The network interface.
        iface: String,
        /// The device: its name of station or MAC address.
        device: String,
        /// The address and prefix (`10.0.0.5/24`).
        #[arg(value_name = "ADDR/PREFIX")]
        address: String,
        /// The gateway (default: none, 0.0.0.0).
        gateway: Option<String>,
        /// Set it temporarily: the device forgets it at power-off.
        #[arg(long)]
        temporary: bool,
    },
    /// Have a device flash its LED (DCP Control Signal), to find it in the cabinet.
    Blink {
        /// The network interface.
        iface: String,
        /// The device: its name of station or MAC address.
        device: String,
    },
    /// Read a device's I&M0 (vendor, order ID, serial number, revisions) without a connection.
    Im {
        /// The network interface.
        iface: String,
        /// The device's name of station.
        name: String,
    },
    /// Read one record of a device without a connection (RPC ReadImplicit) as a hex dump.
    Record {
        /// The network interface.
        iface: String,
        /// The device's name of station.
        name: String,
        /// The slot (decimal or 0x hex).
        #[arg(long, value_parser = number)]
        slot: u16,
        /// The subslot (decimal or 0x hex, such as 0x8000).
        #[arg(long, value_parser = number)]
        subslot: u16,
        /// The record's index (decimal or 0x hex, such as 0xAFF0 for I&M0).
        #[arg(long, value_parser = number)]
        index: u16,
    },
    /// Connect to a device as its IO controller and exchange its IO data (RT_CLASS_1).
    ///
    /// Finds the device by its name of station, connects with the GSDML's configuration (the
    /// overlay's `[modules]`, else --access-point and --module, else its first access point
    /// with the modules it fixes or uses), writes their parameter records, and exchanges cyclic frames: the
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
        /// Plug this GSDML module (its ID or name) in SLOT, or in the first free slot it may
        /// take (`[SLOT=]NAME`, repeatable; docs/modules.md), for devices whose modules are
        /// only allowed in their slots, or to replace the ones they use by default.
        #[arg(long = "module", value_name = "[SLOT=]NAME")]
        modules: Vec<String>,
        /// The access point (a DeviceAccessPointItem's ID or name) to connect with; default:
        /// the GSDML's first.
        #[arg(long = "access-point", value_name = "NAME")]
        access_point: Option<String>,
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
            window,
        } => dcp_verbs::list(iface, gsdml, Duration::from_millis(*window)),
        PnCommand::SetName { iface, mac, name } => dcp_verbs::set_name(iface, mac, name),
        PnCommand::SetIp {
            iface,
            device,
            address,
            gateway,
            temporary,
        } => dcp_verbs::set_ip(iface, device, address, gateway.as_deref(), *temporary),
        PnCommand::Blink { iface, device } => dcp_verbs::blink(iface, device),
        PnCommand::Im { iface, name } => record::im(iface, name),
        PnCommand::Record {
            iface,
            name,
            slot,
            subslot,
            index,
        } => record::record(iface, name, (*slot, *subslot, *index)),
        PnCommand::Io {
            iface,
            name,
            gsdml,
            settings,
            modules,
            access_point,
            records,
            cycles,
            cycle_ms,
        } => io::run(&io::IoArgs {
            iface,
            name,
            gsdml,
            settings,
            modules,
            access_point: access_point.as_deref(),
            records,
            cycles: *cycles,
            cycle_ms: *cycle_ms,
        }),
    }
}

/// `pn` with the configuration its device runs with, set as [`Profinet::chosen`]: the
/// overlay's `[modules]` when `FILE.toml` has one, else `access_point` and `modules`
/// (`[SLOT=]NAME`) when given, else the default. Choices the GSDML does not allow are refused
/// with every problem, as the overlay's EDS708 states them; so are choices on the command line
/// for a file whose overlay already chooses.
pub(crate) fn configured(
    pn: &Profinet,
    path: &str,
    modules: &[String],
    access_point: Option<&str>,
) -> Result<Profinet, String> {
    let mut pn = pn.clone();
    if modules.is_empty() && access_point.is_none() {
        return Ok(pn);
    }
    if pn.chosen.is_some() {
        return Err(format!(
            "`{path}`: its overlay's [modules] already chooses the configuration; --module and --access-point would contradict it"
        ));
    }
    let choices = parse_choices(modules).map_err(|e| format!("--module {e}"))?;
    let chosen = choose_pn(&pn, access_point, &choices).map_err(|problems| {
        format!(
            "`{path}`: the modules chosen do not fit: {}",
            problems.join("; ")
        )
    })?;
    pn.chosen = Some(chosen);
    Ok(pn)
}

/// A 16-bit number, decimal or `0x` hex.
fn number(text: &str) -> Result<u16, String> {
    let parsed = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u16::from_str_radix(hex, 16),
        None => text.parse(),
    };
    parsed.map_err(|_| format!("`{text}` is not a number from 0 to 65535 (decimal or 0x hex)"))
}
