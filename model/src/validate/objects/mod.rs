//! Object and sub-object rules (EDS301..EDS322): names, the CiA 306 key table, SubNumber and
//! sub-index 0, ARRAY homogeneity, gaps, data types, limits, `$NODEID` ranges, default COB-IDs,
//! ObjFlags and CompactSubObj.
//!
//! Errors are what makes generated code wrong or impossible: no name, no data type or access, an
//! unknown data type, an ARRAY of mixed types, a sub-index 0 that is not UNSIGNED8, inverted limits,
//! a `$NODEID` value that overflows for every node-ID, reserved ObjFlags bits. SubNumber not
//! matching the sub-objects is a warning (edsgen uses the sections; common in vendor files).
//! RECORD gaps are legal (info); ARRAY gaps are warnings, as a client indexes an array's
//! elements 1..N.
//! Unparseable values and out-of-type-range values are the reader's (EDS012, EDS013).
//!
//! This module holds the object-level rules (names, key table, ObjFlags, CompactSubObj); the
//! sub-index structure, the entries, the limits and the default COB-IDs have a submodule each.

use super::{at, obj, ObjName};
use crate::diag::{Diagnostic, Severity};
use crate::model::{Device, Object, ObjectType, SubObject};
use crate::rules;
use cob_ids::default_cob_ids;
use entry::entry;
use subs::{array_homogeneity, described_subs, gaps, sub0_checks, sub0_severity, unnamed_subs};

mod cob_ids;
mod entry;
mod limits;
mod subs;

/// Longest ParameterName CiA 306 allows.
const MAX_NAME: usize = 241;

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    for o in device.objects.values() {
        object(device, o, out);
        for sub in o.subs.values() {
            entry(device, o, sub, out);
        }
    }
    // EtherCAT has no COB-IDs.
    if !device.source.format.is_coe() {
        default_cob_ids(device, out);
    }
    entry_keys_on_records(device, out);
    obj_flags(device, out);
}
fn object(device: &Device, o: &Object, out: &mut Vec<Diagnostic>) {
    let name = ObjName(o.index);
    if !o.implicit {
        if o.name.trim().is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::MISSING_NAME,
                    Some(o.span),
                    format!("{name} has no ParameterName"),
                )
                .with_label("no ParameterName")
                .with_help("add `ParameterName=...`; the generated identifiers come from it"),
            );
        } else if o.name.len() > MAX_NAME && o.name.chars().count() > MAX_NAME {
            out.push(
                Diagnostic::new(
                    &rules::LONG_NAME,
                    Some(o.span),
                    format!("the ParameterName of {name} is {} characters long; CiA 306 allows {MAX_NAME}", o.name.chars().count()),
                )
                .with_label("name too long"),
            );
        }
    }

    let compact = o.compact_sub_obj.as_ref().filter(|c| c.value != 0);
    if let Some(c) = compact {
        if !o.object_type.has_subs() {
            out.push(
                Diagnostic::new(
                    &rules::COMPACT_SUB_OBJ_MISUSE,
                    Some(c.span),
                    format!(
                        "{name} is a {:?} but has CompactSubObj={}",
                        o.object_type, c.value
                    ),
                )
                .with_label("only ARRAY, RECORD and DEFSTRUCT can be compact")
                .with_help("remove CompactSubObj, or set ObjectType=0x8 (ARRAY)"),
            );
        } else if c.value > 254 {
            out.push(
                Diagnostic::new(
                    &rules::COMPACT_SUB_OBJ_MISUSE,
                    Some(c.span),
                    format!(
                        "{name} has CompactSubObj={}; at most 254 sub-objects fit",
                        c.value
                    ),
                )
                .with_label("above 254")
                .with_help("describe at most 254 sub-objects; sub-index FFh is reserved"),
            );
        }
    }

    if !o.object_type.has_subs() {
        let kind = if o.object_type == ObjectType::Domain {
            "DOMAIN"
        } else {
            "VAR"
        };
        let sub_number = o
            .sub_number
            .as_ref()
            .map(|n| n.span)
            .or_else(|| custom_key(o, "SubNumber").map(|_| o.span));
        if let Some(span) = sub_number {
            out.push(
                Diagnostic::new(
                    &rules::KEY_NOT_ALLOWED,
                    Some(span),
                    format!("{name} is a {kind} but has SubNumber"),
                )
                .with_label("SubNumber is only for ARRAY and RECORD")
                .with_help("remove SubNumber, or fix ObjectType"),
            );
        }
        if let Some(value) =
            custom_key(o, "CompactSubObj").filter(|v| super::parse_int(v).is_some_and(|n| n != 0))
        {
            out.push(
                Diagnostic::new(
                    &rules::COMPACT_SUB_OBJ_MISUSE,
                    Some(o.span),
                    format!("{name} is a {kind} but has CompactSubObj={value}"),
                )
                .with_label("only ARRAY, RECORD and DEFSTRUCT can be compact")
                .with_help("remove CompactSubObj, or set ObjectType=0x8 (ARRAY)"),
            );
        }
        return;
    }

    // ARRAY, RECORD, DEFSTRUCT from here on.
    unnamed_subs(o, out);
    if let (Some(c), Some(element)) = (compact, o.subs.get(&1).filter(|s| s.implicit)) {
        let missing = missing_var_keys(element);
        if !missing.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::MISSING_KEY,
                    Some(c.span),
                    format!(
                        "{name} uses CompactSubObj but has no valid {}",
                        missing.join(" or ")
                    ),
                )
                .with_label("the sub-objects take their type and access from this section")
                .with_help("add DataType and AccessType to the main section"),
            );
        }
    }
    let sub_number = o.sub_number.as_ref().filter(|n| n.value != 0);
    match (sub_number, compact) {
        (Some(n), Some(c)) => out.push(
            Diagnostic::new(
                &rules::SUBNUMBER_AND_COMPACT,
                Some(n.span),
                format!(
                    "{name} has both SubNumber={} and CompactSubObj={}",
                    n.value, c.value
                ),
            )
            .with_label("SubNumber must be 0 or absent with CompactSubObj")
            .with_help("keep one of the two"),
        ),
        (None, None) if !o.implicit && o.sub_number.is_none() => out.push(
            Diagnostic::new(
                &rules::MISSING_KEY,
                Some(o.span),
                format!(
                    "{name} is {} without SubNumber or CompactSubObj",
                    match o.object_type {
                        ObjectType::Array => "an ARRAY",
                        ObjectType::Record => "a RECORD",
                        _ => "a DEFSTRUCT",
                    }
                ),
            )
            .with_label("no SubNumber")
            .with_help(format!("add `SubNumber={}`", described_subs(o))),
        ),
        (Some(n), None) => {
            let described = described_subs(o);
            if n.value as usize != described {
                out.push(
                    Diagnostic::new(
                        &rules::SUBNUMBER_MISMATCH,
                        Some(n.span),
                        format!(
                            "{name} has SubNumber={} but {described} sub-objects are described",
                            n.value
                        ),
                    )
                    .with_label(format!("{described} described"))
                    .with_help(format!("set SubNumber={described}")),
                );
            }
        }
        _ => {}
    }

    // A sub FFh implied by CompactSubObj=255 is already EDS322's finding.
    if let Some(sub) = o.subs.get(&0xFF).filter(|s| !s.implicit) {
        out.push(
            Diagnostic::new(
                &rules::SUB_INDEX_RESERVED,
                Some(sub.span),
                format!(
                    "{} is described; sub-index FFh is reserved for the structure",
                    at(o.index, 0xFF)
                ),
            )
            .with_label("reserved sub-index")
            .with_help("remove this sub-object"),
        );
    }

    match o.subs.get(&0) {
        None if compact.is_none() => out.push(
            Diagnostic::new(
                &rules::SUB0_MISSING,
                Some(o.span),
                format!("{name} has no sub-index 0 (the number of entries)"),
            )
            .with_severity(sub0_severity(o))
            .with_label("no sub 0")
            .with_help(format!("add [{:X}sub0] with DataType=0x0005, AccessType=ro and the highest sub-index as DefaultValue", o.index)),
        ),
        None => {}
        Some(sub0) => sub0_checks(device, o, sub0, compact.is_some(), out),
    }

    if o.object_type == ObjectType::Array {
        array_homogeneity(device, o, out);
    }
    gaps(o, out);
}

/// The keys of a VAR entry it has no (valid) value for: `DataType`, `AccessType`.
fn missing_var_keys(entry: &SubObject) -> Vec<&'static str> {
    [
        (entry.data_type.is_none(), "DataType"),
        (entry.access.is_none(), "AccessType"),
    ]
    .into_iter()
    .filter_map(|(m, k)| m.then_some(k))
    .collect()
}

/// The value of a key the reader kept uninterpreted in the object's `custom`, if non-empty.
fn custom_key<'a>(o: &'a Object, key: &str) -> Option<&'a str> {
    o.custom
        .iter()
        .find(|(k, v)| k.trim().eq_ignore_ascii_case(key) && !v.trim().is_empty())
        .map(|(_, v)| v.as_str())
}

/// Keys of the VAR table that an ARRAY/RECORD main section without CompactSubObj does not use.
const ENTRY_KEYS: [&str; 6] = [
    "DataType",
    "AccessType",
    "DefaultValue",
    "PDOMapping",
    "LowLimit",
    "HighLimit",
];

/// One info for the whole file: ARRAY/RECORD main sections carrying VAR keys (a common dialect
/// that CANeds reports as "no value allowed"; the keys are ignored).
fn entry_keys_on_records(device: &Device, out: &mut Vec<Diagnostic>) {
    let mut first = None;
    let mut found = Vec::new();
    for o in device.objects.values() {
        if !o.object_type.has_subs() || o.compact_sub_obj.as_ref().is_some_and(|c| c.value != 0) {
            continue;
        }
        let keys: Vec<&str> = ENTRY_KEYS
            .iter()
            .copied()
            .filter(|k| custom_key(o, k).is_some())
            .collect();
        if !keys.is_empty() {
            first.get_or_insert(o.span);
            found.push(format!("{} ({})", obj(o.index), keys.join(", ")));
        }
    }
    if !found.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::KEY_NOT_ALLOWED,
                first,
                format!(
                    "{} ARRAY/RECORD object(s) carry keys CiA 306 does not allow on them (ignored): {}",
                    found.len(),
                    crate::diag::short_list(&found)
                ),
            )
            .with_severity(Severity::Info)
            .with_label("DataType/AccessType/... belong in the sub-index sections")
            .with_help("remove these keys from the main section, or use CompactSubObj"),
        );
    }
}

/// One diagnostic per file for reserved ObjFlags bits (vendor tools write other flags there;
/// they change nothing edsgen generates).
fn obj_flags(device: &Device, out: &mut Vec<Diagnostic>) {
    let mut first = None;
    let mut found = Vec::new();
    for o in device.objects.values() {
        if o.obj_flags & !0b11 != 0 {
            first.get_or_insert(o.span);
            found.push(format!("{} ({:#X})", obj(o.index), o.obj_flags));
        }
        for sub in o.subs.values().filter(|_| o.object_type.has_subs()) {
            if sub.obj_flags & !0b11 != 0 {
                first.get_or_insert(sub.span);
                found.push(format!(
                    "{} ({:#X})",
                    at(o.index, sub.sub_index),
                    sub.obj_flags
                ));
            }
        }
    }
    if !found.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::OBJ_FLAGS_RESERVED,
                first,
                format!(
                    "ObjFlags with reserved bits 2..31 set on {} entr{}: {}",
                    found.len(),
                    if found.len() == 1 { "y" } else { "ies" },
                    crate::diag::short_list(&found)
                ),
            )
            .with_label("reserved bits set")
            .with_help(
                "only bit 0 (refuse write on download) and bit 1 (refuse read on scan) are defined",
            ),
        );
    }
}
