//! `edsgen sdo read|write|dcf`: SDO transfers with a node, the value typed and named by an EDS
//! (or `--type`), an abort reported with its code and meaning (exit 1). `--file`/`--out` stream
//! a value of any length between a file and the entry ([`transfer`]).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Subcommand;
use edsgen_host::master::blocking::MasterError;
use edsgen_model::model::{AccessType, BasicType, Device};
use edsgen_runtime::master::Mode;
use edsgen_runtime::wire::sdo::Multiplexer;

use super::entry;
use crate::cmd::value::{hex, value_bytes, Kind};
use crate::cmd::{fail, parse_node_id, BusArgs};
use transfer::Stream;

mod progress;
mod transfer;

/// `edsgen sdo` subcommands.
#[derive(Subcommand, Debug)]
pub enum SdoCommand {
    /// Read an entry (SDO upload) and print its value, or stream it into a file (--out).
    Read {
        #[command(flatten)]
        target: Target,
        /// Stream the value into this file instead of printing it (`-`: standard output, raw
        /// bytes), for a domain of any length such as a log. Block transfer unless
        /// --segmented; a node that refuses block transfers is read segmented (unless --block).
        /// A summary goes to standard error.
        #[arg(long, value_name = "PATH", conflicts_with = "kind")]
        out: Option<PathBuf>,
        /// With --out: read by segmented transfer, not block.
        #[arg(long, requires = "out", conflicts_with = "block")]
        segmented: bool,
    },
    /// Write a value to an entry (SDO download), or stream a file into it (--file).
    Write {
        #[command(flatten)]
        target: Target,
        /// The value: a number (decimal or 0x hex, negative without `--`), true/false, text for
        /// a string, hex bytes for an octet string or domain.
        #[arg(required_unless_present = "file", allow_negative_numbers = true)]
        value: Option<String>,
        /// Stream this file into the entry (`-`: standard input), its size not announced: a
        /// program image to 1F50h, any DOMAIN, string or octet string. Block transfer unless
        /// --segmented; a node that refuses block transfers is written segmented (unless
        /// --block). A summary goes to standard error.
        #[arg(long, value_name = "PATH", conflicts_with_all = ["value", "kind"])]
        file: Option<PathBuf>,
        /// With --file: write by segmented transfer, not block.
        #[arg(long, requires = "file", conflicts_with = "block")]
        segmented: bool,
    },
    /// Download a DCF's ParameterValues to a node, PDOs disabled while they are configured.
    Dcf {
        #[command(flatten)]
        bus: BusArgs,
        /// The node-ID (1..=127).
        node: String,
        /// The DCF.
        file: PathBuf,
    },
}

/// What every SDO command addresses.
#[derive(clap::Args, Debug)]
pub struct Target {
    #[command(flatten)]
    bus: BusArgs,
    /// The node's description: types and names the value.
    #[arg(long, value_name = "FILE")]
    eds: Option<PathBuf>,
    /// The value's type where no EDS gives it: u8..u64, i8..i64, r32, r64, b, vs (text), os
    /// (bytes).
    #[arg(long = "type", value_name = "TYPE")]
    kind: Option<String>,
    /// Use SDO block transfer. With --file or --out: only block, no fallback to segmented; a
    /// node that refuses it, or answers a read with a segmented or expedited upload, fails
    /// the command (exit 1).
    #[arg(long)]
    block: bool,
    /// The node-ID (1..=127).
    node: String,
    /// The entry: INDEX[:SUB] in hex (6041, 6041:0, 0x6041sub0; sub-index 0 when none is
    /// given), or its name in the --eds file (Statusword; a unique prefix will do, case and
    /// spaces do not matter; "Identity object / Vendor-ID" for a sub-index).
    entry: String,
}

/// The entry as the command understood it: where, what kind of value, its name.
struct Resolved {
    node_id: u8,
    mux: Multiplexer,
    kind: Option<Kind>,
    name: Option<String>,
    /// The entry's data type, if an EDS gives it.
    data_type: Option<BasicType>,
    mode: Mode,
}

impl Target {
    fn resolve(&self) -> Result<Resolved, String> {
        let node_id = parse_node_id(&self.node)?;
        let device = match &self.eds {
            Some(path) => Some(load(path)?),
            None => None,
        };
        let mux = entry::resolve(&self.entry, device.as_ref())?;
        let mut kind = match &self.kind {
            Some(name) => Some(Kind::parse(name).ok_or_else(|| format!("unknown type `{name}`"))?),
            None => None,
        };
        let mut name = None;
        let mut data_type = None;
        if let (Some(path), Some(device)) = (&self.eds, &device) {
            let (entry_name, basic) = describe(device, mux)
                .ok_or_else(|| format!("{} has no entry {}", path.display(), show_mux(mux)))?;
            name = Some(entry_name);
            data_type = basic;
            kind = kind.or(basic.map(Kind::of));
        }
        let mode = if self.block {
            Mode::Block
        } else {
            Mode::Normal
        };
        Ok(Resolved {
            node_id,
            mux,
            kind,
            name,
            data_type,
            mode,
        })
    }
}

impl Resolved {
    /// `6041h:00h`, with the entry's name where the EDS gives it.
    fn label(&self) -> String {
        match &self.name {
            Some(name) => format!("{} {name}", show_mux(self.mux)),
            None => show_mux(self.mux),
        }
    }
}

/// Reads a description, failing on an unreadable file.
pub fn load(path: &Path) -> Result<Device, String> {
    crate::cmd::load(path, None).map(|loaded| loaded.device)
}

/// The name of (index, sub) in `device` ("Object / Sub" for records and arrays) and its basic
/// type, if the description has the entry.
pub fn describe(
    device: &Device,
    mux: Multiplexer,
) -> Option<(String, Option<edsgen_model::model::BasicType>)> {
    let object = device.objects.get(&mux.index)?;
    let sub = object.subs.get(&mux.sub)?;
    let name = if object.subs.len() == 1 && mux.sub == 0 {
        object.name.clone()
    } else {
        format!("{} / {}", object.name, sub.name)
    };
    Some((name, sub.data_type.and_then(|t| device.basic_type(t))))
}

/// `6041h:00h`.
pub fn show_mux(mux: Multiplexer) -> String {
    format!("{:04X}h:{:02X}h", mux.index, mux.sub)
}

/// Runs `edsgen sdo ...`.
pub fn run(command: &SdoCommand) -> ExitCode {
    let (target, value) = match command {
        SdoCommand::Read {
            target,
            out: Some(path),
            segmented,
        } => return transfer::run(target, Stream::Upload(path), *segmented),
        SdoCommand::Write {
            target,
            file: Some(path),
            segmented,
            ..
        } => return transfer::run(target, Stream::Download(path), *segmented),
        SdoCommand::Read { target, .. } => (target, None),
        SdoCommand::Write { target, value, .. } => (target, value.as_ref()),
        SdoCommand::Dcf { bus, node, file } => return run_dcf(bus, node, file),
    };
    let resolved = match target.resolve() {
        Ok(resolved) => resolved,
        Err(message) => return fail(message),
    };
    let data = match (value, resolved.kind) {
        (Some(text), Some(kind)) => match kind.encode(text) {
            Ok(data) => Some(data),
            Err(message) => return fail(message),
        },
        (Some(_), None) => {
            return fail("the value's type is unknown: give --eds FILE or --type TYPE")
        }
        (None, _) => None,
    };
    let mut master = match target.bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    if data.is_some() {
        target.bus.for_writes(&mut master);
    }
    let label = resolved.label();
    let Resolved {
        node_id,
        mux,
        kind,
        mode,
        ..
    } = resolved;
    let result = match &data {
        Some(data) => master.download(node_id, mux, data, mode).map(|()| None),
        None => master.upload(node_id, mux, mode).map(Some),
    };
    match result {
        Ok(None) => {
            println!("{label} written");
            ExitCode::SUCCESS
        }
        Ok(Some(bytes)) => {
            let shown = match kind {
                Some(kind) => kind.show(&bytes),
                None => Ok(hex(&bytes)),
            };
            match shown {
                Ok(text) => {
                    println!("{label} = {text}");
                    ExitCode::SUCCESS
                }
                Err(message) => {
                    eprintln!("error: {label}: {message} ({})", hex(&bytes));
                    ExitCode::from(1)
                }
            }
        }
        Err(error) => master_failed(error),
    }
}

/// The exit of a master call that failed: the bus gone is an I/O problem (exit 2), an abort an
/// error of the node's (exit 1).
fn master_failed(error: MasterError) -> ExitCode {
    match error {
        MasterError::Io(e) => fail(format!("bus: {e}")),
        error => {
            eprintln!("error: {error}");
            ExitCode::from(1)
        }
    }
}

/// The writable entries `device` gives a ParameterValue, as (entry, bytes) for `node_id`.
pub fn parameter_values(
    device: &Device,
    node_id: u8,
) -> Result<Vec<(Multiplexer, Vec<u8>)>, String> {
    let mut entries = Vec::new();
    for object in device.objects.values().filter(|o| o.index >= 0x1000) {
        for sub in object.subs.values() {
            let (Some(source), Some(access)) = (&sub.parameter_value, sub.access) else {
                continue;
            };
            if matches!(access, AccessType::Ro | AccessType::Const) {
                continue;
            }
            let mux = Multiplexer::new(object.index, sub.sub_index);
            let kind = sub
                .data_type
                .and_then(|t| device.basic_type(t))
                .map_or(Kind::Bytes, Kind::of);
            let bytes = source
                .value
                .as_ref()
                .and_then(|value| value_bytes(kind, value, node_id))
                .ok_or_else(|| {
                    format!(
                        "{}: ParameterValue={} is not a value of its type",
                        show_mux(mux),
                        source.raw
                    )
                })?;
            entries.push((mux, bytes));
        }
    }
    Ok(entries)
}

fn run_dcf(bus: &BusArgs, node: &str, file: &Path) -> ExitCode {
    let node_id = match parse_node_id(node) {
        Ok(id) => id,
        Err(message) => return fail(message),
    };
    let entries = match load(file).and_then(|device| parameter_values(&device, node_id)) {
        Ok(entries) => entries,
        Err(message) => return fail(message),
    };
    let mut master = match bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    bus.for_writes(&mut master);
    match master.download_configuration(node_id, &entries) {
        Ok(()) => {
            println!("{} value(s) written to node {node_id}", entries.len());
            ExitCode::SUCCESS
        }
        Err(error) => master_failed(error),
    }
}
