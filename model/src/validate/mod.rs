//! The validator: the rules of `crate::rules` (EDS1xx..EDS5xx, EDS8xx for EtherCAT, CIP0xx for
//! ODVA EDS, PN0xx for PROFINET, and the generator's size limits EDS707) judged over the resolved
//! model.
//!
//! It never looks at the text: everything it knows comes from [`Device`], so the same rules serve
//! EDS, DCF, XDD and XDC. One submodule per area; each says which rules it owns and why a rule has
//! the severity it has. Policy: an error means the file breaks CiA 306/301 in a way that makes
//! generated code (or a master configuring the device) wrong; dialects real vendor files use are
//! warnings or infos. One diagnostic per distinct problem; rules that would fire on every object
//! for a cosmetic reason are aggregated into one diagnostic per file.
//!
//! Messages name entries as `1A00h sub 3`: the index in hex with an `h` suffix, the sub-index in
//! decimal. Spans point at the key's line where the model has one (values, SubNumber, DeviceInfo
//! numbers), else at the section header of the object or sub-object.

use crate::diag::{self, Diagnostic};
use crate::model::{Bus, Device, Format, RawSection, Span, SubObject, Value, ValueSource};
use crate::rules;

mod cip;
mod dcf;
mod device_info;
mod esi;
mod esi_assign;
mod file_info;
mod gsd;
mod gsdml;
mod object_lists;
mod objects;
mod pdo;
mod sections;
mod sizes;
pub use sizes::size_errors;

/// Judges a device model; the diagnostics come sorted by position.
pub fn validate(device: &Device) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    match (&device.bus, device.source.format) {
        // An ODVA EDS has no object dictionary: its rules are CIP's.
        (Bus::Cip(cip), _) => cip::check(cip, &mut out),
        // A GSDML file has no object dictionary, FileInfo or PDOs: only the PN0xx rules apply.
        (Bus::Profinet(profinet), _) => gsdml::check(profinet, &mut out),
        // A GSD file has no CANopen dictionary: only the DP rules apply.
        (Bus::Dp(dp), _) => gsd::check(dp, &mut out),
        // A file of those formats that could not be read: nothing to judge.
        (Bus::CanOpen, Format::OdvaEds | Format::Gsdml | Format::Gsd) => {}
        (Bus::CanOpen | Bus::EtherCat(_), _) => {
            dictionary(device, &mut out);
            // Values outside their limits come in dozens in a vendor's DCF: one finding, naming
            // the lines.
            diag::sort(&mut out);
            diag::fold(
                &mut out,
                |d| std::ptr::eq(d.rule, &rules::VALUE_OUTSIDE_LIMITS).then_some(d.severity),
                "likewise on",
            );
            return out;
        }
    }
    diag::sort(&mut out);
    out
}

/// The rules of an object dictionary (CANopen's, or an ESI's CoE dictionary) and its PDOs.
fn dictionary(device: &Device, out: &mut Vec<Diagnostic>) {
    file_info::check(device, out);
    device_info::check(device, out);
    object_lists::check(device, out);
    objects::check(device, out);
    match (&device.bus, device.source.format) {
        // EtherCAT has no PDO communication parameters (1400h/1800h), COB-IDs or CAN frame
        // limits: its PDOs are the RxPdo/TxPdo elements, judged against the SyncManagers.
        (Bus::EtherCat(ec), _) => esi::check(device, ec, out),
        // An ESI file without its device: no PDOs of either kind.
        (_, Format::Esi) => {}
        _ => pdo::check(device, out),
    }
    dcf::check(device, out);
    sections::check(device, out);
    // What the generator cannot hold, so that a clean validate means generate succeeds.
    out.extend(size_errors(device));
}

/// `1A00h`.
fn obj(index: u16) -> String {
    format!("{index:04X}h")
}

/// `1A00h sub 3`.
fn at(index: u16, sub: u8) -> String {
    format!("{index:04X}h sub {sub}")
}

/// `1A00h` for a VAR or DOMAIN entry (sub 0 of an object without subs), else `1A00h sub 3`.
fn entry_name(device: &Device, index: u16, sub: u8) -> String {
    match device.objects.get(&index) {
        Some(o) if !o.object_type.has_subs() && sub == 0 => obj(index),
        _ => at(index, sub),
    }
}

/// [`entry_name`] as a [`std::fmt::Display`]: the text is built only when a message uses it.
struct EntryName<'d> {
    device: &'d Device,
    index: u16,
    sub: u8,
}

impl<'d> EntryName<'d> {
    fn new(device: &'d Device, index: u16, sub: u8) -> Self {
        EntryName { device, index, sub }
    }
}

impl std::fmt::Display for EntryName<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&entry_name(self.device, self.index, self.sub))
    }
}

/// [`obj`] as a [`std::fmt::Display`]: the text is built only when a message uses it.
struct ObjName(u16);

impl std::fmt::Display for ObjName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&obj(self.0))
    }
}

/// Whether the file is an INI-style description (EDS or DCF), where the INI sections exist.
fn is_ini(device: &Device) -> bool {
    matches!(device.source.format, Format::Eds | Format::Dcf)
}

/// ObjFlags bit 1, "refuse read on scan": a configuration tool does not read the entry back, so
/// its ParameterValue (XDC `actualValue`) is not a value the device was seen to hold.
const REFUSE_READ_ON_SCAN: u32 = 0b10;

/// The value that counts for an entry: the DCF ParameterValue (XDC actualValue) if there is one
/// and the entry is read on scan, else the default.
fn effective(sub: &SubObject) -> Option<&ValueSource> {
    sub.parameter_value
        .as_ref()
        .filter(|v| v.value.is_some() && sub.obj_flags & REFUSE_READ_ON_SCAN == 0)
        .or(sub.default.as_ref())
}

/// The fix that sets [`effective`]'s value, in the file's own spelling: `DefaultValue=5`,
/// `ParameterValue=5`, or for XML `defaultValue="5"`, `actualValue="5"`.
fn set_value(device: &Device, sub: &SubObject, value: impl std::fmt::Display) -> String {
    let parameter = match (effective(sub), sub.parameter_value.as_ref()) {
        (Some(used), Some(parameter)) => std::ptr::eq(used, parameter),
        _ => false,
    };
    match (is_ini(device), parameter) {
        (true, true) => format!("set ParameterValue={value}"),
        (true, false) => format!("set DefaultValue={value}"),
        (false, true) => format!("set actualValue=\"{value}\""),
        (false, false) => format!("set defaultValue=\"{value}\""),
    }
}

/// The parsed value of [`effective`].
fn effective_value(sub: &SubObject) -> Option<&Value> {
    effective(sub)?.value.as_ref()
}

/// The effective value as a plain integer (not `$NODEID`-relative).
fn effective_int(sub: &SubObject) -> Option<i128> {
    match effective_value(sub)? {
        Value::Integer(v) => Some(*v),
        _ => None,
    }
}

/// The span of the effective value, else the entry's own span.
fn value_span(sub: &SubObject) -> Span {
    effective(sub).map_or(sub.span, |v| v.span)
}

/// An integer as CiA 306 writes it: decimal, `0x` hex, or octal with a leading `0`.
fn parse_int(text: &str) -> Option<i128> {
    let t = text.trim();
    let (neg, t) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t),
    };
    let v = if let Some(hex) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        i128::from_str_radix(hex, 16).ok()?
    } else if t.len() > 1 && t.starts_with('0') {
        i128::from_str_radix(&t[1..], 8).ok()?
    } else {
        t.parse::<i128>().ok()?
    };
    Some(if neg { -v } else { v })
}

/// The kept-verbatim section with this name (case-insensitive).
fn raw_section<'a>(device: &'a Device, name: &str) -> Option<&'a RawSection> {
    device
        .other_sections
        .iter()
        .find(|s| s.name.trim().eq_ignore_ascii_case(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_int_reads_cia306_forms() {
        assert_eq!(parse_int("10"), Some(10));
        assert_eq!(parse_int("0x1A"), Some(26));
        assert_eq!(parse_int("012"), Some(10));
        assert_eq!(parse_int("0"), Some(0));
        assert_eq!(parse_int("-5"), Some(-5));
        assert_eq!(parse_int("x"), None);
    }

    #[test]
    fn entry_names_use_one_format() {
        assert_eq!(at(0x1A00, 10), "1A00h sub 10");
        assert_eq!(obj(0x1000), "1000h");
    }
}
