//! The ODVA EDS reader (EtherNet/IP, DeviceNet): the text ([`lex`]) into the CIP part of the model
//! ([`Cip`]): identity, parameters and enumerations, assemblies, connections, ports, capacity.
//!
//! Lenient and lossless as the other readers: a field that is not what its place needs is a CIP004
//! diagnostic and reads as absent; unknown sections and keys are kept (in
//! [`Cip::other_sections`], or as entries of their section) and reported once each (CIP002).
//! Judging the parts against each other (sizes, limits, references) is the validator's
//! (`validate::cip`), once the authors' dialects are read as they meant them (the private `dialect` module).

use std::collections::BTreeMap;
use std::path::Path;

use super::Read;
use crate::diag::Diagnostic;
use crate::model::*;
use crate::rules;

mod dialect;
pub mod lex;
mod parts;

/// Whether the text is an ODVA EDS: it has a `[File]` or `[Device]` section header (CiA 306 files
/// have `[FileInfo]` and `[DeviceInfo]`). Looks only at lines that start with `[`.
///
/// Every CiA 306 file goes through here, so it scans the bytes without decoding them: only the
/// `[` bytes are looked at, and a line with a non-ASCII byte before its `]` is decoded alone.
pub fn is_odva(bytes: &[u8]) -> bool {
    let mut from = 0;
    while let Some(at) = bytes
        .get(from..)
        .and_then(|rest| memchr::memchr(b'[', rest))
    {
        let bracket = from + at;
        let start = memchr::memrchr(b'\n', &bytes[..bracket]).map_or(0, |n| n + 1);
        let end = memchr::memchr(b'\n', &bytes[bracket..]).map_or(bytes.len(), |n| bracket + n);
        from = end;
        if line_is_odva_header(&bytes[start..end]) {
            return true;
        }
    }
    false
}

/// Whether one line (without its `\n`) is a `[File]` or `[Device]` header, leading white space
/// allowed: ASCII lines directly, others decoded as `String::from_utf8_lossy` would.
fn line_is_odva_header(line: &[u8]) -> bool {
    let name_end = line.iter().position(|&b| b == b']').unwrap_or(line.len());
    if !line[..name_end].is_ascii() {
        let text = String::from_utf8_lossy(line);
        let Some(rest) = text.trim_start().strip_prefix('[') else {
            return false;
        };
        let name = rest.split(']').next().unwrap_or("").trim();
        return name.eq_ignore_ascii_case("File") || name.eq_ignore_ascii_case("Device");
    }
    // White space as `char::is_whitespace` has it among ASCII bytes (with 0Bh, which
    // `u8::is_ascii_whitespace` leaves out).
    let space = |b: &u8| matches!(b, b'\t' | b'\n' | 0x0B | 0x0C | b'\r' | b' ');
    let Some(rest) = line[..name_end]
        .iter()
        .position(|b| !space(b))
        .and_then(|first| line[first..name_end].strip_prefix(b"["))
    else {
        return false;
    };
    let first = rest.iter().position(|b| !space(b)).unwrap_or(rest.len());
    let last = rest
        .iter()
        .rposition(|b| !space(b))
        .map_or(first, |l| l + 1);
    let name = &rest[first..last.max(first)];
    name.eq_ignore_ascii_case(b"File") || name.eq_ignore_ascii_case(b"Device")
}

/// Reads an ODVA EDS.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = super::text::decode(bytes);
    let mut device = super::eds::empty_device(path, Format::OdvaEds, encoding);
    let mut diags = Vec::new();
    let sections = lex::lex(&text, &mut diags);
    if sections.is_empty() {
        diags.push(Diagnostic::new(
            &rules::EMPTY_FILE,
            None,
            "the file holds no [sections]",
        ));
    }
    let mut cip = Cip::default();
    let mut seen: BTreeMap<String, Span> = BTreeMap::new();
    for section in sections {
        let lower = section.name.to_ascii_lowercase();
        if let Some(first) = seen.insert(lower.clone(), section.span) {
            diags.push(
                Diagnostic::new(
                    &rules::CIP_DUPLICATE,
                    Some(section.span),
                    format!(
                        "the section [{}] appears again (first at line {}); both are read, later entries win",
                        section.name, first.line
                    ),
                )
                .with_label("second header"),
            );
        }
        duplicate_keys(&section, &mut diags);
        let mut r = parts::Parts {
            cip: &mut cip,
            diags: &mut diags,
        };
        match lower.as_str() {
            "file" => r.file(&section),
            "device" => r.device(&section),
            "device classification" => r.classification(&section),
            "params" | "enumpar" => r.params(&section),
            "assembly" => r.assembly(&section),
            "connection manager" => r.connections(&section),
            "port" => r.ports(&section),
            "capacity" => r.capacity(&section),
            _ => {
                if !is_class_section(&section.name) {
                    let what = if section.name.is_empty() {
                        "entries before the first section".to_owned()
                    } else {
                        format!("the section [{}]", section.name)
                    };
                    let diag = Diagnostic::new(
                        &rules::CIP_UNKNOWN,
                        Some(section.span),
                        format!("{what} is not one this reader interprets (kept as written)"),
                    )
                    .with_label("kept, not interpreted");
                    let sections = SECTIONS.iter().map(|s| ((*s).to_owned(), *s));
                    diags.push(
                        match crate::did_you_mean::misspelt(&section.name, sections) {
                            Some(meant) => diag.with_help(format!("did you mean [{meant}]?")),
                            None => diag,
                        },
                    );
                }
                cip.other_sections.push(section);
            }
        }
    }
    dialect::member_sizes_in_bytes(&mut cip, &mut diags);
    let id = &cip.identity;
    device.device_info.vendor_name = id.vendor_name.clone();
    device.device_info.product_name = id.product_name.clone();
    device.device_info.order_code = id.catalog.clone();
    device.device_info.vendor_number = id
        .vendor_code
        .as_ref()
        .map(|v| Spanned::new(u32::from(v.value), v.span));
    device.device_info.product_number = id
        .product_code
        .as_ref()
        .map(|v| Spanned::new(u32::from(v.value), v.span));
    device.device_info.span = id.span;
    device.file_info.description = cip.file.desc_text.clone();
    device.file_info.file_revision = cip.file.revision.clone();
    device.file_info.span = cip.file.span;
    device.bus = Bus::Cip(cip);
    crate::diag::sort(&mut diags);
    Read {
        device,
        diagnostics: diags,
        text,
    }
}

/// The sections this reader interprets, as the specification spells them (for "did you mean").
const SECTIONS: &[&str] = &[
    "File",
    "Device",
    "Device Classification",
    "Params",
    "EnumPar",
    "Assembly",
    "Connection Manager",
    "Port",
    "Capacity",
];

/// Class sections the EDS specification defines (`[Identity Class]`, `[TCP/IP Interface Class]`,
/// `[QoS Class]`, ...) and vendor classes (`[Class15_Vendor1]`): kept as written, not reported.
fn is_class_section(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(" class")
        || (lower.starts_with("class") && lower.contains("_vendor"))
        || matches!(
            lower.as_str(),
            "groups" | "modular" | "connection configuration"
        )
}

fn duplicate_keys(section: &CipSection, diags: &mut Vec<Diagnostic>) {
    let mut keys: BTreeMap<String, Span> = BTreeMap::new();
    for entry in &section.entries {
        if let Some(first) = keys.insert(entry.key.to_ascii_lowercase(), entry.span) {
            diags.push(
                Diagnostic::new(
                    &rules::CIP_DUPLICATE,
                    Some(entry.span),
                    format!(
                        "the key `{}` appears again in [{}] (first at line {}); the last one wins",
                        entry.key, section.name, first.line
                    ),
                )
                .with_label("second entry"),
            );
        }
    }
}

/// A number as EDS files write them: decimal, `0x` hex, `0b` binary, signed, or a real.
pub fn number(text: &str) -> Option<CipNumber> {
    let t = text.trim();
    let (neg, body) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let int = if let Some(hex) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        i128::from_str_radix(hex, 16).ok()
    } else if let Some(bin) = body.strip_prefix("0b").or_else(|| body.strip_prefix("0B")) {
        i128::from_str_radix(bin, 2).ok()
    } else if !body.is_empty() && body.bytes().all(|b| b.is_ascii_digit()) {
        body.parse::<i128>().ok()
    } else {
        None
    };
    if let Some(v) = int {
        return Some(CipNumber::Int(if neg { -v } else { v }));
    }
    let real_chars = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'-' | b'+');
    if !body.is_empty() && body.bytes().all(real_chars) && body.bytes().any(|b| b.is_ascii_digit())
    {
        let v: f64 = body.parse().ok()?;
        return Some(CipNumber::Real(if neg { -v } else { v }));
    }
    None
}

/// A field that names something: empty, a number, `ParamN`, `AssemN` (any case), or other text.
pub fn field_ref(field: &Field) -> FieldRef {
    let t = field.text.trim();
    if t.is_empty() {
        return FieldRef::Empty;
    }
    let numbered = |prefix: &str| -> Option<u32> {
        let head = t.get(..prefix.len())?;
        head.eq_ignore_ascii_case(prefix)
            .then(|| t[prefix.len()..].parse().ok())
            .flatten()
    };
    if let Some(n) = numbered("Param") {
        return FieldRef::Param(n);
    }
    if let Some(n) = numbered("Assem") {
        return FieldRef::Assem(n);
    }
    match number(t) {
        Some(CipNumber::Int(v)) if v >= 0 => {
            u64::try_from(v).map_or_else(|_| FieldRef::Other(t.to_owned()), FieldRef::Number)
        }
        _ => FieldRef::Other(t.to_owned()),
    }
}

/// The number N of a key `PrefixN` (case-insensitive), if it is one.
pub fn key_number(key: &str, prefix: &str) -> Option<u32> {
    let head = key.get(..prefix.len())?;
    if !head.eq_ignore_ascii_case(prefix) {
        return None;
    }
    let digits = &key[prefix.len()..];
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}
