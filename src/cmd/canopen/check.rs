//! `edsgen check --eds FILE --node N`: reads every readable entry of a live device and reports,
//! as diagnostics in the validator's format, where the device differs from its description,
//! with the boot-up check of its identity (1000h, 1018h:1–4) first.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::Transport;
use edsgen_model::diag::{self, Diagnostic, Severity};
use edsgen_model::model::{AccessType, Device, ObjectType, SubObject, Value};
use edsgen_model::render;
use edsgen_model::rules::{
    CHK_DEFAULT as CHK005, CHK_IDENTITY as CHK004, CHK_LENGTH as CHK002, CHK_MISSING as CHK001,
    CHK_UNREADABLE as CHK003,
};
use edsgen_runtime::master::{ExpectedIdentity, Mode, SdoError};
use edsgen_runtime::wire::sdo::abort_meaning;
use edsgen_runtime::wire::sdo::Multiplexer;

use super::sdo::{describe, show_mux};
use crate::cmd::value::{hex, Kind};
use crate::cmd::{fail, parse_node_id, BusArgs};

/// `edsgen check` options.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    bus: BusArgs,
    /// The device's description (EDS or DCF).
    #[arg(long, value_name = "FILE")]
    eds: PathBuf,
    /// The device's node-ID.
    #[arg(long, value_name = "N")]
    node: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// Treat warnings (values differing from defaults) as differences too (exit 1).
    #[arg(long)]
    deny_warnings: bool,
}

/// Output formats, as `edsgen validate` has them.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Format {
    /// Annotated source lines.
    Human,
    /// One JSON object per diagnostic.
    Json,
}

/// Runs `edsgen check`.
pub fn run(args: &CheckArgs) -> ExitCode {
    let node_id = match parse_node_id(&args.node) {
        Ok(id) => id,
        Err(message) => return fail(message),
    };
    let read = match crate::cmd::load(&args.eds, None) {
        Ok(read) => read,
        Err(e) => return fail(e),
    };
    let mut master = match args.bus.connect() {
        Ok(master) => master,
        Err(message) => return fail(message),
    };
    let diags = match check(&mut master, &read.device, node_id) {
        Ok(diags) => diags,
        Err(e) => {
            if let Some(note) = super::lss::unconfigured_note(&mut master) {
                eprintln!("note: {note}");
            }
            return fail(e);
        }
    };
    let what = format!("node {node_id}");
    report(
        args.format,
        &args.eds,
        &read.text,
        diags,
        &what,
        args.deny_warnings,
    )
}

/// Prints the diagnostics a live check found in the description at `path` (its `text`),
/// sorted, in `format`; the human format ends with a line counting them for `what` was checked.
/// Exit code 1 when there are errors (or warnings with `deny_warnings`), else 0.
pub fn report(
    format: Format,
    path: &Path,
    text: &str,
    mut diags: Vec<Diagnostic>,
    what: &str,
    deny_warnings: bool,
) -> ExitCode {
    diag::sort(&mut diags);
    let name = path.display().to_string();
    let count = |severity| diags.iter().filter(|d| d.severity == severity).count();
    let (errors, warnings) = (count(Severity::Error), count(Severity::Warning));
    match format {
        Format::Human => {
            let color = std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none();
            print!("{}", render::human(&name, text, &diags, color));
            println!("{what} checked against {name}: {errors} error(s), {warnings} warning(s)");
        }
        Format::Json => {
            let list = render::json(&name, &diags);
            println!(
                "{}",
                serde_json::to_string_pretty(&list).unwrap_or_else(|_| "[]".into())
            );
        }
    }
    if errors > 0 || (deny_warnings && warnings > 0) {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Compares node `node_id` with `device`; an error only when the bus fails or the node does
/// not answer at all.
pub fn check<T: Transport>(
    master: &mut Master<T>,
    device: &Device,
    node_id: u8,
) -> Result<Vec<Diagnostic>, String> {
    let mut diags = identity_check(master, device, node_id)?;
    for object in device.objects.values() {
        if object.index < 0x1000
            || matches!(
                object.object_type,
                ObjectType::DefType | ObjectType::DefStruct
            )
        {
            continue;
        }
        for sub in object.subs.values() {
            let readable = !matches!(sub.access, Some(AccessType::Wo) | None);
            if !readable {
                continue;
            }
            let mux = Multiplexer::new(object.index, sub.sub_index);
            match master.upload(node_id, mux, Mode::Normal) {
                Ok(bytes) => diags.extend(compare(device, node_id, mux, sub, &bytes)),
                Err(MasterError::Sdo {
                    error: SdoError::Server(0x0602_0000),
                    ..
                }) => {
                    let message = format!("object {:04X}h is missing on node {node_id}", mux.index);
                    diags.push(Diagnostic::new(&CHK001, Some(object.span), message));
                    break;
                }
                Err(MasterError::Sdo {
                    error: SdoError::Server(code),
                    ..
                }) => {
                    let (rule, message) = if code == 0x0609_0011 {
                        (
                            &CHK001,
                            format!("{} is missing on node {node_id}", show_mux(mux)),
                        )
                    } else {
                        let meaning = abort_meaning(code).unwrap_or("unknown abort code");
                        let message = format!(
                            "node {node_id} refuses to read {}: {code:08X}h ({meaning})",
                            show_mux(mux)
                        );
                        (&CHK003, message)
                    };
                    diags.push(Diagnostic::new(rule, Some(sub.span), message));
                }
                Err(e @ MasterError::Sdo { .. }) => return Err(e.to_string()),
                Err(e) => return Err(e.to_string()),
            }
        }
    }
    Ok(diags)
}

/// The boot-up check: 1000h and 1018h:1–3 against the description (a vendor-ID, product code or
/// revision of 0 is not checked, as in CiA 302's 1F85h–1F87h).
fn identity_check<T: Transport>(
    master: &mut Master<T>,
    device: &Device,
    node_id: u8,
) -> Result<Vec<Diagnostic>, String> {
    let nonzero = |v: Option<u32>| v.filter(|v| *v != 0);
    let info = &device.device_info;
    let device_type = device.entry(0x1000, 0).and_then(|sub| match &sub.default {
        Some(source) => match source.value {
            Some(Value::Integer(v)) => u32::try_from(v).ok(),
            _ => None,
        },
        None => None,
    });
    let expected = ExpectedIdentity {
        device_type,
        vendor_id: nonzero(info.vendor_number.as_ref().map(|v| v.value)),
        product_code: nonzero(info.product_number.as_ref().map(|v| v.value)),
        revision_number: nonzero(info.revision_number.as_ref().map(|v| v.value)),
        serial_number: None,
    };
    let mismatches = master
        .check_identity(node_id, &expected)
        .map_err(|e| e.to_string())?;
    Ok(mismatches
        .into_iter()
        .map(|m| {
            let mux = Multiplexer::new(m.entry.index, m.entry.sub);
            let actual = match (m.actual, m.abort) {
                (Some(v), _) => format!("0x{v:08X}"),
                (None, Some(code)) => format!("unreadable ({code:08X}h)"),
                (None, None) => "unreadable".into(),
            };
            let span = device.entry(mux.index, mux.sub).map(|s| s.span);
            Diagnostic::new(
                &CHK004,
                span,
                format!(
                    "{} of node {node_id} is {actual}, the description says 0x{:08X}",
                    show_mux(mux),
                    m.expected
                ),
            )
        })
        .collect())
}

/// The differences of one value read from the device.
fn compare(
    device: &Device,
    node_id: u8,
    mux: Multiplexer,
    sub: &SubObject,
    bytes: &[u8],
) -> Option<Diagnostic> {
    let who = format!("node {node_id}");
    length_differs(device, &who, mux, sub, bytes)
        .or_else(|| default_differs(device, &who, node_id, mux, sub, bytes))
}

/// CHK002 when `bytes`, read from `who` (`node 3`, `SubDevice 0`), are not as long as the
/// entry's data type.
pub fn length_differs(
    device: &Device,
    who: &str,
    mux: Multiplexer,
    sub: &SubObject,
    bytes: &[u8],
) -> Option<Diagnostic> {
    let basic = sub.data_type.and_then(|t| device.basic_type(t))?;
    let len = basic.bits()?.div_ceil(8) as usize;
    if bytes.len() == len {
        return None;
    }
    let message = format!(
        "{} of {who} is {} byte(s) long, its data type {} has {len}",
        show_mux(mux),
        bytes.len(),
        basic.name()
    );
    Some(Diagnostic::new(&CHK002, Some(sub.span), message))
}

/// CHK005 when `bytes`, read from `who`, differ from the entry's ParameterValue or default
/// (`$NODEID` is `node_id`): an error for a constant, else a warning.
pub fn default_differs(
    device: &Device,
    who: &str,
    node_id: u8,
    mux: Multiplexer,
    sub: &SubObject,
    bytes: &[u8],
) -> Option<Diagnostic> {
    let basic = sub.data_type.and_then(|t| device.basic_type(t));
    let expected = sub.parameter_value.as_ref().or(sub.default.as_ref())?;
    let matches = match expected.value.as_ref()? {
        Value::Integer(v) => integer_matches(*v, bytes),
        Value::NodeRelative(offset) => {
            integer_matches(i128::from(*offset) + i128::from(node_id), bytes)
        }
        // A NaN default (as DefaultData bytes may give) is matched by any NaN.
        Value::Real(v) => match bytes.len() {
            4 => {
                let read = f32::from_le_bytes(bytes.try_into().ok()?);
                read == *v as f32 || (read.is_nan() && v.is_nan())
            }
            8 => {
                let read = f64::from_le_bytes(bytes.try_into().ok()?);
                read == *v || (read.is_nan() && v.is_nan())
            }
            _ => false,
        },
        Value::Text(text) => {
            let text = text.trim_matches('"');
            bytes == text.as_bytes()
        }
        Value::Bytes(expected) => bytes == expected.as_slice(),
    };
    if matches {
        return None;
    }
    let severity = if sub.access == Some(AccessType::Const) {
        Severity::Error
    } else {
        Severity::Warning
    };
    // Typed as `sdo read --eds` shows it; raw bytes only where the type is unknown.
    let shown = basic
        .map(Kind::of)
        .and_then(|kind| match kind {
            Kind::Text => Some(format!("{:?}", String::from_utf8_lossy(bytes))),
            kind => kind.show(bytes).ok(),
        })
        .unwrap_or_else(|| hex(bytes));
    let label = match describe(device, mux) {
        Some((name, _)) => format!("{} {name}", show_mux(mux)),
        None => show_mux(mux),
    };
    let message = format!(
        "{label} of {who} holds {shown}, the description's default is {}",
        expected.raw
    );
    Some(Diagnostic::new(&CHK005, Some(expected.span), message).with_severity(severity))
}

/// Whether little-endian `bytes` hold `value` (two's complement for negative values).
fn integer_matches(value: i128, bytes: &[u8]) -> bool {
    if bytes.is_empty() || bytes.len() > 8 {
        return false;
    }
    let mut wide = [0u8; 8];
    wide[..bytes.len()].copy_from_slice(bytes);
    let raw = u64::from_le_bytes(wide);
    let mask = if bytes.len() == 8 {
        u64::MAX
    } else {
        (1u64 << (8 * bytes.len())) - 1
    };
    (value as u64) & mask == raw
}
