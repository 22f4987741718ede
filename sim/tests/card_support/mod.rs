//! Shared by the card tests (`sim/tests/card_*.rs`), which check each bundled EDS against its manual:
//! reading a card, the table row that states what a manual says about one entry and its check,
//! default values, PDO mappings and frames, the diagnostics above info, and a portable dump.
// Each card test is a crate of its own and uses only some of these helpers.
#![allow(dead_code)]

pub mod pkw_pzd_drive;

use std::fmt::Debug;
use std::path::{Path, PathBuf};

use edsgen_model::diag::{Diagnostic, Severity};
use edsgen_model::model::{AccessType, BasicType, Device, SubObject, Value};
use edsgen_model::read::{read_file, Read};

/// The workspace root, where the bundled cards are (`eds/`); the tests run in `sim/`.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Reads a bundled card; `path` is relative to the workspace root (`eds/cp301.eds`).
pub fn read(path: &str) -> Read {
    let full = root().join(path);
    read_file(&full).unwrap_or_else(|e| panic!("{path} is readable: {e:?}"))
}

/// The model dump of a card read with [`read`]. The dump names the file as given (an absolute
/// path); it is named `path` here so that snapshots do not depend on where the workspace is.
pub fn dump(device: &Device, path: &str) -> serde_json::Value {
    let mut dump = edsgen_model::dump::to_json(device);
    dump["file"] = path.into();
    dump
}

/// An entry's default value as a manual gives it.
#[derive(Debug, Clone, Copy)]
pub enum DefaultValue {
    /// The manual gives none (the value lives in the device): no DefaultValue in the file.
    Absent,
    /// An integer.
    Int(i128),
    /// `$NODEID` plus this offset.
    NodeId(i64),
    /// A string.
    Text(&'static str),
}

impl DefaultValue {
    /// Whether `entry` has this default value.
    pub fn matches(self, entry: &SubObject) -> bool {
        let value = entry.default.as_ref().and_then(|d| d.value.clone());
        match self {
            DefaultValue::Absent => entry.default.is_none(),
            DefaultValue::Int(v) => value == Some(Value::Integer(v)),
            DefaultValue::NodeId(offset) => value == Some(Value::NodeRelative(offset)),
            DefaultValue::Text(text) => value == Some(Value::Text(text.to_string())),
        }
    }
}

/// One object-dictionary entry as a manual describes it.
pub struct Row {
    pub index: u16,
    pub sub: u8,
    /// The ParameterName, for the cards whose rows pin it.
    pub name: Option<&'static str>,
    pub data_type: BasicType,
    pub access: AccessType,
    pub default: DefaultValue,
    pub pdo_mapping: bool,
    /// Where the manual says so.
    pub source: &'static str,
}

/// A [`Row`] that does not pin the name.
pub const fn row(
    index: u16,
    sub: u8,
    data_type: BasicType,
    access: AccessType,
    default: DefaultValue,
    pdo_mapping: bool,
    source: &'static str,
) -> Row {
    Row {
        index,
        sub,
        name: None,
        data_type,
        access,
        default,
        pdo_mapping,
        source,
    }
}

impl Row {
    /// The same row, pinning the ParameterName too.
    pub const fn named(self, name: &'static str) -> Row {
        Row {
            name: Some(name),
            ..self
        }
    }
}

/// Checks every row against the device, and reports every mismatch in one failure.
pub fn check_rows(device: &Device, rows: &[Row]) {
    let mut mismatches = Vec::new();
    for r in rows {
        let at = format!("{:04X}h:{:02X} ({})", r.index, r.sub, r.source);
        let Some(entry) = device.entry(r.index, r.sub) else {
            mismatches.push(format!("{at}: missing"));
            continue;
        };
        let mut check = |what: &str, ok: bool, found: &dyn Debug, expected: &dyn Debug| {
            if !ok {
                mismatches.push(format!("{at}: {what} {found:?}, expected {expected:?}"));
            }
        };
        let name_ok = r.name.is_none_or(|name| entry.name == name);
        check("name", name_ok, &entry.name, &r.name);
        let data_type_ok = entry.data_type == Some(r.data_type.index());
        check("data type", data_type_ok, &entry.data_type, &r.data_type);
        check(
            "access",
            entry.access == Some(r.access),
            &entry.access,
            &r.access,
        );
        let pdo_ok = entry.pdo_mapping == r.pdo_mapping;
        check("PDO mapping", pdo_ok, &entry.pdo_mapping, &r.pdo_mapping);
        check(
            "default",
            r.default.matches(entry),
            &entry.default,
            &r.default,
        );
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

/// Checks that none of the entries exists; each comes with the reason it must not.
pub fn check_absent(device: &Device, entries: &[(u16, u8, &str)]) {
    for (index, sub, source) in entries {
        assert!(
            device.entry(*index, *sub).is_none(),
            "{index:04X}h:{sub:02X} must not exist ({source})"
        );
    }
}

/// The sub-indices of object `index`, ascending; the object must exist.
pub fn subs(device: &Device, index: u16) -> Vec<u8> {
    device.objects[&index].subs.keys().copied().collect()
}

/// The parsed DefaultValue of an entry, if it has one.
pub fn default_value(device: &Device, index: u16, sub: u8) -> Option<Value> {
    device.entry(index, sub)?.default.as_ref()?.value.clone()
}

/// The DefaultValue of an entry, if it is an integer.
pub fn integer_default(device: &Device, index: u16, sub: u8) -> Option<i128> {
    match default_value(device, index, sub)? {
        Value::Integer(v) => Some(v),
        _ => None,
    }
}

/// The `$NODEID`-relative DefaultValue of an entry, resolved for `node_id`.
pub fn node_relative(device: &Device, index: u16, sub: u8, node_id: u8) -> u32 {
    match default_value(device, index, sub) {
        Some(Value::NodeRelative(offset)) => (offset + i64::from(node_id)) as u32,
        other => panic!("{index:04X}h:{sub:02X} is not node-relative: {other:?}"),
    }
}

/// The default COB-ID (sub 1) of a PDO communication object, for `node_id`.
pub fn cob_id(device: &Device, comm_index: u16, node_id: u8) -> u32 {
    node_relative(device, comm_index, 1, node_id)
}

/// The (index, sub, bit length) triples a mapping object maps by default, as many as its sub0
/// says.
pub fn mapped(device: &Device, mapping_index: u16) -> Vec<(u16, u8, u8)> {
    let integer = |sub: u8| {
        integer_default(device, mapping_index, sub)
            .unwrap_or_else(|| panic!("{mapping_index:04X}h sub {sub} has no integer default"))
    };
    (1..=integer(0) as u8)
        .map(|sub| {
            let word = integer(sub);
            ((word >> 16) as u16, (word >> 8) as u8, word as u8)
        })
        .collect()
}

/// Whether a mapped (index, sub) is a dummy entry: a data-type index 1-7 with sub 0.
pub fn is_dummy(index: u16, sub: u8) -> bool {
    (1..=7).contains(&index) && sub == 0
}

/// Splits a PDO payload by the default mapping of `mapping_index`, checking that each mapped
/// entry exists, is mappable and has the mapped width (a dummy: is enabled and has its type's
/// width), and that the mapping fills the payload. Returns ((index, sub), value) per field, read
/// little-endian; a dummy comes back as its data-type index and sub 0.
pub fn decode(device: &Device, mapping_index: u16, payload: &[u8]) -> Vec<((u16, u8), u64)> {
    let mut bit = 0usize;
    let mut out = Vec::new();
    for (index, sub, bits) in mapped(device, mapping_index) {
        if is_dummy(index, sub) {
            let enabled = device.dummy_usage.get(&index);
            assert_eq!(enabled, Some(&true), "Dummy{index:04X}");
            let width = BasicType::from_index(index).and_then(BasicType::bits);
            assert_eq!(width, Some(u32::from(bits)), "Dummy{index:04X}");
        } else {
            let entry = device
                .entry(index, sub)
                .unwrap_or_else(|| panic!("{index:04X}h:{sub:02X} mapped but missing"));
            assert!(entry.pdo_mapping, "{index:04X}h:{sub:02X} not mappable");
            let width = entry
                .data_type
                .and_then(|t| device.basic_type(t))
                .and_then(BasicType::bits);
            assert_eq!(width, Some(u32::from(bits)), "{index:04X}h:{sub:02X}");
        }
        assert_eq!(bit % 8, 0, "byte-aligned mapping");
        let bytes = &payload[bit / 8..(bit + usize::from(bits)) / 8];
        let value = bytes
            .iter()
            .rev()
            .fold(0u64, |acc, b| (acc << 8) | u64::from(*b));
        out.push(((index, sub), value));
        bit += usize::from(bits);
    }
    assert_eq!(bit, payload.len() * 8, "PDO length = frame length");
    out
}

/// The bit rates the card declares, in kbit/s, ascending.
pub fn baud_rates(device: &Device) -> Vec<u32> {
    let rates = device.device_info.baud_rates.iter();
    let mut enabled: Vec<u32> = rates.filter(|(_, on)| *on).map(|(rate, _)| *rate).collect();
    enabled.sort_unstable();
    enabled
}

/// The 1-based number of the first line that reads `line` (trailing blanks aside).
pub fn line_of(text: &str, line: &str) -> u32 {
    let position = text.lines().position(|l| l.trim_end() == line);
    position.map(|i| i as u32 + 1).expect(line)
}

/// The line of the `key=` line in the section under `header` (which must exist).
pub fn key_line(text: &str, header: &str, key: &str) -> Option<u32> {
    let start = line_of(text, header);
    let prefix = format!("{key}=");
    let below = text.lines().skip(start as usize);
    below
        .take_while(|l| !l.starts_with('['))
        .position(|l| l.starts_with(&prefix))
        .map(|i| start + i as u32 + 1)
}

/// A diagnostic as the tests pin it: code, severity, line.
pub type Finding = (&'static str, Severity, Option<u32>);

/// The diagnostics above info, sorted by line, then code.
pub fn above_info<'a>(diagnostics: impl IntoIterator<Item = &'a Diagnostic>) -> Vec<Finding> {
    let mut found: Vec<Finding> = diagnostics
        .into_iter()
        .filter(|d| d.severity > Severity::Info)
        .map(|d| (d.rule.code, d.severity, d.span.map(|s| s.line)))
        .collect();
    found.sort_by_key(|(code, _, line)| (*line, *code));
    found
}

/// Everything reading and validating the card reports, infos included.
pub fn all_diagnostics(read: &Read) -> Vec<Diagnostic> {
    let validated = edsgen_model::validate::validate(&read.device);
    read.diagnostics.iter().cloned().chain(validated).collect()
}

/// What reading and validating the card reports above info.
pub fn warnings_and_errors(read: &Read) -> Vec<Finding> {
    above_info(&all_diagnostics(read))
}
