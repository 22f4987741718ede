//! `edsgen ecat sdo read|write --iface IFACE [--position N] ENTRY [VALUE]`: one CoE SDO transfer
//! with a SubDevice in Pre-Op. With `--esi FILE [--device NAME|#xCODE]` the entry may be named
//! (as `edsgen sdo --eds` names CANopen entries: exact or unique prefix, suggestions on a miss)
//! and the value is typed by the ESI's data type; without it, the entry is `INDEX:SUB`, the
//! value typed by `--type` (`u8`, `i16`, `vs`, ...; `--size N` for an unsigned number of N
//! bytes), and a read without either is sized by what arrives: 1, 2, 4 or 8 bytes as a number,
//! anything else as hex bytes and their text. A write without a type says what to pass. An
//! abort is exit 1 with its code and meaning.

use std::path::PathBuf;
use std::process::ExitCode;

use edsgen_model::model::Device;
use edsgen_runtime::wire::sdo::Multiplexer;
use ethercrab::error::{Error, MailboxError};
use ethercrab::{EtherCrabWireRead, EtherCrabWireSized, SubDevice, SubDeviceRef};

use super::{discover, runtime};
use crate::cmd::canopen::entry;
use crate::cmd::canopen::sdo::{describe, show_mux};
use crate::cmd::value::{hex, Kind};
use crate::cmd::{fail, print_stdout};

/// `edsgen ecat sdo` options.
#[derive(clap::Args, Debug)]
pub struct SdoArgs {
    /// `read` or `write`.
    #[arg(value_enum)]
    verb: SdoVerb,
    /// The network interface of the EtherCAT segment.
    #[arg(long, value_name = "IFACE")]
    iface: String,
    /// The SubDevice's position on the segment (0 first).
    #[arg(long, value_name = "N", default_value_t = 0)]
    position: usize,
    /// The SubDevice's ESI file: names and types the entry.
    #[arg(long, value_name = "FILE")]
    esi: Option<PathBuf>,
    /// The device of an ESI file with several (type name or `#x` product code).
    #[arg(long, value_name = "NAME|#xCODE", requires = "esi")]
    device: Option<String>,
    /// The entry: `INDEX:SUB` in hex (such as 1018:1), or its name in the --esi file
    /// ("Operation mode"; a unique prefix will do, case and spaces do not matter;
    /// "Identity object / Vendor ID" for a sub-index).
    entry: String,
    /// The value to write: a number (decimal or 0x hex), true/false, text, or hex bytes, as the
    /// ESI's data type says; a number of --size bytes without --esi.
    #[arg(allow_negative_numbers = true)]
    value: Option<String>,
    /// Without --esi: the value's size in bytes, an unsigned number.
    #[arg(long, value_parser = ["1", "2", "4", "8"], conflicts_with = "esi")]
    size: Option<String>,
    /// Without --esi: the value's type: u8, u16, u32, u64, i8, i16, i32, i64, r32, r64, b
    /// (boolean), vs (visible string), os (octet string).
    #[arg(long = "type", value_name = "TYPE", conflicts_with_all = ["esi", "size"])]
    kind: Option<String>,
}

/// The types `--type` takes, as the messages list them.
const TYPES: &str = "u8, u16, u32, u64, i8, i16, i32, i64, r32, r64, b, vs or os";

/// What `ecat sdo` does.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum SdoVerb {
    Read,
    Write,
}

/// An SDO value of any length up to 4 KiB, as ethercrab reads it (its own types are sized).
pub struct Raw(pub Vec<u8>);

impl EtherCrabWireRead for Raw {
    fn unpack_from_slice(buf: &[u8]) -> Result<Self, ethercrab_wire::WireError> {
        Ok(Raw(buf.to_vec()))
    }
}

impl EtherCrabWireSized for Raw {
    const PACKED_LEN: usize = 4096;
    type Buffer = [u8; 4096];
    fn buffer() -> Self::Buffer {
        [0; 4096]
    }
}

/// One SDO read: the bytes, the SubDevice's abort code, or (the outer error) a failed bus.
pub async fn upload(
    sub_device: &SubDeviceRef<'_, &SubDevice>,
    mux: Multiplexer,
) -> Result<Result<Vec<u8>, u32>, String> {
    match sub_device.sdo_read::<Raw>(mux.index, mux.sub).await {
        Ok(Raw(bytes)) => Ok(Ok(bytes)),
        Err(Error::Mailbox(MailboxError::Aborted { code, .. })) => Ok(Err(u32::from(code))),
        Err(err) => Err(format!("{}: {err}", show_mux(mux))),
    }
}

/// The entry as the command understood it.
struct Resolved {
    mux: Multiplexer,
    /// `None`: no type given, a read is sized by what arrives.
    kind: Option<Kind>,
    /// `6060h:00h Operation mode` with an ESI; `None` keeps the numeric form.
    label: Option<String>,
}

/// Runs `edsgen ecat sdo`: 0 done, 1 refused by the SubDevice, 2 usage or bus.
pub fn run(args: &SdoArgs) -> ExitCode {
    let resolved = match resolve(args) {
        Ok(resolved) => resolved,
        Err(message) => return fail(message),
    };
    let data = match (args.verb, &args.value) {
        (SdoVerb::Read, None) => None,
        (SdoVerb::Write, Some(_)) if resolved.kind.is_none() => {
            return fail(format!(
                "ecat sdo write without --esi needs the value's type: --type TYPE ({TYPES}), \
                 such as `edsgen ecat sdo write --iface {} {} {} --type u8`",
                args.iface,
                args.entry,
                args.value.as_deref().unwrap_or_default()
            ))
        }
        (SdoVerb::Write, Some(text)) => match resolved.kind.unwrap_or(Kind::Bytes).encode(text) {
            Ok(bytes) if bytes.len() <= 4 => Some(bytes),
            Ok(bytes) => {
                return fail(format!(
                    "{} takes {} bytes: ethercrab writes at most 4 by SDO (expedited)",
                    show_mux(resolved.mux),
                    bytes.len()
                ))
            }
            Err(message) => return fail(message),
        },
        (SdoVerb::Read, Some(_)) => return fail("ecat sdo read takes no value"),
        (SdoVerb::Write, None) => return fail("ecat sdo write needs a value"),
    };
    let runtime = match runtime() {
        Ok(runtime) => runtime,
        Err(message) => return fail(message),
    };
    let (mux, position) = (resolved.mux, args.position);
    let result: Result<Result<Option<Vec<u8>>, String>, String> = runtime.block_on(async {
        let (maindevice, group) = discover(&args.iface).await?;
        let sub_device = group
            .subdevice(&maindevice, position)
            .map_err(|_| format!("no SubDevice at position {position}"))?;
        let refused = |code: ethercrab::error::CoeAbortCode| format!("{}: {code}", show_mux(mux));
        Ok(match &data {
            None => match upload(&sub_device, mux).await? {
                Ok(bytes) => Ok(Some(bytes)),
                Err(code) => Err(refused(code.into())),
            },
            Some(bytes) => match sub_device
                .sdo_write(mux.index, mux.sub, bytes.as_slice())
                .await
            {
                Ok(()) => Ok(None),
                Err(Error::Mailbox(MailboxError::Aborted { code, .. })) => Err(refused(code)),
                Err(err) => return Err(format!("{}: {err}", show_mux(mux))),
            },
        })
    });
    let iface = &args.iface;
    match result {
        Ok(Ok(read)) => match shown(
            &resolved,
            read.as_deref().or(data.as_deref()).unwrap_or_default(),
            read.is_none(),
        ) {
            Ok(line) => {
                print_stdout(&line);
                ExitCode::SUCCESS
            }
            Err(message) => {
                eprintln!("error: {iface}: {message}");
                ExitCode::from(1)
            }
        },
        Ok(Err(message)) => {
            eprintln!("error: {iface}: {message}");
            ExitCode::from(1)
        }
        Err(message) => fail(format!("{iface}: {message}")),
    }
}

/// The entry, its kind and its label from the command line and the ESI, if given.
fn resolve(args: &SdoArgs) -> Result<Resolved, String> {
    let Some(path) = &args.esi else {
        let mux = entry::resolve(&args.entry, None)?;
        let kind = match (&args.kind, args.size.as_deref()) {
            (Some(name), _) => Some(
                Kind::parse(name).ok_or_else(|| format!("--type {name} is not a type: {TYPES}"))?,
            ),
            (None, Some(size)) => match size.parse() {
                Ok(size @ (1 | 2 | 4 | 8)) => Some(Kind::Unsigned(size)),
                _ => return Err("--size is 1, 2, 4 or 8 bytes".into()),
            },
            (None, None) => None,
        };
        return Ok(Resolved {
            mux,
            kind,
            label: None,
        });
    };
    let read = crate::cmd::load(path, args.device.as_deref())?;
    if read.nothing_read || read.device.ethercat().is_none() {
        return Err(format!("{}: not an ESI device", path.display()));
    }
    let device: Device = read.device;
    let mux = entry::resolve(&args.entry, Some(&device))?;
    let (name, basic) = describe(&device, mux)
        .ok_or_else(|| format!("{} has no entry {}", path.display(), show_mux(mux)))?;
    let basic = basic.ok_or_else(|| {
        format!(
            "{} {name}: {} gives no data type this command can read",
            show_mux(mux),
            path.display()
        )
    })?;
    Ok(Resolved {
        mux,
        kind: Some(Kind::of(basic)),
        label: Some(format!("{} {name}", show_mux(mux))),
    })
}

/// The line printed for a value read, or (`written`) for the bytes written.
fn shown(resolved: &Resolved, bytes: &[u8], written: bool) -> Result<String, String> {
    let (index, sub) = (resolved.mux.index, resolved.mux.sub);
    let Some(label) = &resolved.label else {
        let kind = match resolved.kind {
            Some(kind @ Kind::Unsigned(_)) => kind,
            Some(_) if written => return Ok(format!("{index:04X}h:{sub:02X} := {}\n", hex(bytes))),
            Some(kind) => {
                return match kind.show(bytes) {
                    Ok(text) => Ok(format!("{index:04X}h:{sub:02X} = {text}\n")),
                    Err(message) => Err(format!(
                        "{index:04X}h:{sub:02X}: {message} ({})",
                        hex(bytes)
                    )),
                }
            }
            None if matches!(bytes.len(), 1 | 2 | 4 | 8) => Kind::Unsigned(bytes.len()),
            None => {
                return Ok(format!(
                    "{index:04X}h:{sub:02X} = {} ({})\n",
                    hex(bytes),
                    text_of(bytes)
                ))
            }
        };
        let size = kind.len().unwrap_or(4);
        if bytes.len() != size {
            return Err(format!(
                "{index:04X}h:{sub:02X}: {} byte(s) received where --size says {size} ({})",
                bytes.len(),
                hex(bytes)
            ));
        }
        let mut wide = [0u8; 8];
        wide[..size].copy_from_slice(bytes);
        let v = u64::from_le_bytes(wide);
        let width = 2 + 2 * size;
        return Ok(if written {
            format!("{index:04X}h:{sub:02X} := {v:#0width$x}\n")
        } else {
            format!("{index:04X}h:{sub:02X} = {v:#0width$x} ({v})\n")
        });
    };
    if written {
        return Ok(format!("{label} written\n"));
    }
    match resolved.kind.unwrap_or(Kind::Bytes).show(bytes) {
        Ok(text) => Ok(format!("{label} = {text}\n")),
        Err(message) => Err(format!("{label}: {message} ({})", hex(bytes))),
    }
}

/// Bytes of no known type as text: quoted, trailing NULs dropped, anything not printable ASCII
/// as `.`.
fn text_of(bytes: &[u8]) -> String {
    let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
    let text: String = bytes[..end]
        .iter()
        .map(|&b| {
            if (0x20..0x7F).contains(&b) {
                b as char
            } else {
                '.'
            }
        })
        .collect();
    format!("\"{text}\"")
}
