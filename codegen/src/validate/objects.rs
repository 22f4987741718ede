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

use super::{at, effective_int, entry_name, obj, set_value, value_span, EntryName, ObjName};
use crate::diag::{Diagnostic, Severity};
use crate::model::{
    AccessType, BasicType, Device, Format, Object, ObjectType, SubObject, Value, ValueSource,
};
use crate::rules;

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
    if device.source.format != Format::Esi {
        default_cob_ids(device, out);
    }
    entry_keys_on_records(device, out);
    obj_flags(device, out);
}

/// Whether an entry's sub-index 0 is a count that legitimately differs from the highest
/// sub-index (1003h error history, PDO mapping objects).
fn sub0_is_special(device: &Device, index: u16) -> bool {
    matches!(index, 0x1003 | 0x1600..=0x17FF | 0x1A00..=0x1BFF)
        // CoE PDO assignment (1C12h, 1C13h, ...): sub 0 counts the assigned PDOs.
        || (device.source.format == Format::Esi && matches!(index, 0x1C10..=0x1C2F))
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
        } else if o.name.chars().count() > MAX_NAME {
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
        let missing: Vec<&str> = [
            (element.data_type.is_none(), "DataType"),
            (element.access.is_none(), "AccessType"),
        ]
        .into_iter()
        .filter_map(|(m, k)| m.then_some(k))
        .collect();
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
                    super::short_list(&found)
                ),
            )
            .with_severity(Severity::Info)
            .with_label("DataType/AccessType/... belong in the sub-index sections")
            .with_help("remove these keys from the main section, or use CompactSubObj"),
        );
    }
}

/// One diagnostic per object for sub-objects without ParameterName: an error for a RECORD
/// (its fields are named from them), a warning for an ARRAY (elements are indexed, not named).
fn unnamed_subs(o: &Object, out: &mut Vec<Diagnostic>) {
    let unnamed: Vec<&SubObject> = o
        .subs
        .values()
        .filter(|s| !s.implicit && s.name.trim().is_empty())
        .collect();
    let Some(first) = unnamed.first() else { return };
    let list: Vec<String> = unnamed.iter().map(|s| s.sub_index.to_string()).collect();
    let array = o.object_type == ObjectType::Array;
    out.push(
        Diagnostic::new(
            &rules::MISSING_NAME,
            Some(first.span),
            format!(
                "{} has no ParameterName at sub-index {}",
                obj(o.index),
                super::short_list(&list)
            ),
        )
        .with_severity(if array {
            Severity::Warning
        } else {
            Severity::Error
        })
        .with_label("no ParameterName")
        .with_help(if array {
            "add `ParameterName=...`; tools show it, though ARRAY elements are generated by index"
        } else {
            "add `ParameterName=...`; the generated field name comes from it"
        }),
    );
}

/// The number of sub-objects written in the file (not implied), FFh not counted.
fn described_subs(o: &Object) -> usize {
    o.subs
        .values()
        .filter(|s| !s.implicit && s.sub_index != 0xFF)
        .count()
}

fn highest_sub(o: &Object) -> u8 {
    o.subs
        .keys()
        .copied()
        .filter(|s| *s != 0xFF)
        .max()
        .unwrap_or(0)
}

/// An ARRAY's sub 0 is its length, so a missing or non-UNSIGNED8 sub 0 is an error; a RECORD
/// whose sub 0 is a value (some vendors do this, e.g. INVT cards) still generates correctly, so
/// it is a warning.
fn sub0_severity(o: &Object) -> Severity {
    if o.object_type == ObjectType::Array {
        Severity::Error
    } else {
        Severity::Warning
    }
}

fn sub0_checks(
    device: &Device,
    o: &Object,
    sub0: &SubObject,
    compact: bool,
    out: &mut Vec<Diagnostic>,
) {
    if let Some(dt) = sub0.data_type {
        if device
            .basic_type(dt)
            .is_some_and(|t| t != BasicType::Unsigned8)
        {
            // Sub 0 is then a value, not a count: the access and value checks do not apply.
            out.push(
                Diagnostic::new(
                    &rules::SUB0_MISSING,
                    Some(sub0.key_spans.data_type.unwrap_or(sub0.span)),
                    format!(
                        "{} is {} but must be UNSIGNED8",
                        at(o.index, 0),
                        type_name(device, dt)
                    ),
                )
                .with_severity(sub0_severity(o))
                .with_label("sub 0 holds the number of entries")
                .with_help("set DataType=0x0005"),
            );
            return;
        }
    }
    if sub0_is_special(device, o.index) || compact {
        return;
    }
    if let Some(access) = sub0.access.filter(|a| a.writable()) {
        out.push(
            Diagnostic::new(
                &rules::SUB0_ACCESS,
                Some(sub0.key_spans.access.unwrap_or(sub0.span)),
                format!(
                    "{} is {} but sub-index 0 of an ARRAY/RECORD is read-only",
                    at(o.index, 0),
                    access.as_str()
                ),
            )
            .with_label("writable sub 0")
            .with_help("set AccessType=ro (or const)"),
        );
    }
    if let Some(count) = effective_int(sub0) {
        let highest = i128::from(highest_sub(o));
        if count != highest {
            out.push(
                Diagnostic::new(
                    &rules::SUB0_VALUE,
                    Some(value_span(sub0)),
                    format!(
                        "{} is {count} but the highest sub-index described is {highest}",
                        at(o.index, 0)
                    ),
                )
                .with_label(format!("expected {highest}"))
                .with_help(set_value(device, sub0, highest)),
            );
        }
    }
}

/// The CiA 301 complex (record) data types 0020h..0023h: standard structures, but an entry
/// cannot have one as its DataType unless the file describes it.
fn standard_record_type(dt: u16) -> Option<&'static str> {
    match dt {
        0x0020 => Some("PDO_COMMUNICATION_PARAMETER"),
        0x0021 => Some("PDO_MAPPING"),
        0x0022 => Some("SDO_PARAMETER"),
        0x0023 => Some("IDENTITY"),
        _ => None,
    }
}

fn array_homogeneity(device: &Device, o: &Object, out: &mut Vec<Diagnostic>) {
    let elements: Vec<&SubObject> = o
        .subs
        .values()
        .filter(|s| s.sub_index != 0 && s.sub_index != 0xFF)
        .collect();
    let Some(first) = elements.first() else {
        return;
    };
    if let Some(odd) = elements.iter().find(|s| {
        s.data_type.is_some() && first.data_type.is_some() && s.data_type != first.data_type
    }) {
        let (a, b) = (
            first.data_type.unwrap_or_default(),
            odd.data_type.unwrap_or_default(),
        );
        out.push(
            Diagnostic::new(
                &rules::ARRAY_MIXED_TYPES,
                Some(odd.key_spans.data_type.unwrap_or(odd.span)),
                format!(
                    "{} is {} but {} is {}; ARRAY elements share one type",
                    at(o.index, odd.sub_index),
                    type_name(device, b),
                    at(o.index, first.sub_index),
                    type_name(device, a)
                ),
            )
            .with_label("different element type")
            .with_help(
                "make the elements one type, or declare the object a RECORD (ObjectType=0x9)",
            ),
        );
    }
    if let Some(odd) = elements
        .iter()
        .find(|s| s.access != first.access || s.pdo_mapping != first.pdo_mapping)
    {
        let access = |s: &SubObject| s.access.map_or("missing", AccessType::as_str);
        let (key, what) = if odd.access != first.access {
            (
                odd.key_spans.access,
                format!("AccessType {} vs {}", access(odd), access(first)),
            )
        } else {
            (
                odd.key_spans.pdo_mapping,
                format!(
                    "PDOMapping {} vs {}",
                    u8::from(odd.pdo_mapping),
                    u8::from(first.pdo_mapping)
                ),
            )
        };
        out.push(
            Diagnostic::new(
                &rules::ARRAY_MIXED_ACCESS,
                Some(key.unwrap_or(odd.span)),
                format!(
                    "{} differs from {} in {what}",
                    at(o.index, odd.sub_index),
                    at(o.index, first.sub_index)
                ),
            )
            .with_label("different access or mapping")
            .with_help("give the elements the same AccessType and PDOMapping, or declare a RECORD"),
        );
    }
}

fn gaps(o: &Object, out: &mut Vec<Diagnostic>) {
    if !o.subs.contains_key(&0) {
        return;
    }
    // PDO communication records implement sub 3, 5 and 6 at will (and sub 4 is reserved).
    if matches!(o.index, 0x1400..=0x15FF | 0x1800..=0x19FF) {
        return;
    }
    let missing: Vec<u8> = (1..highest_sub(o))
        .filter(|s| !o.subs.contains_key(s))
        .collect();
    let Some(first) = missing.first() else { return };
    let list: Vec<String> = missing.iter().map(u8::to_string).collect();
    let array = o.object_type == ObjectType::Array;
    out.push(
        Diagnostic::new(
            &rules::SUB_INDEX_GAPS,
            Some(o.span),
            format!(
                "{} has no sub-object at sub-index {} (below the highest, {})",
                obj(o.index),
                super::short_list(&list),
                highest_sub(o)
            ),
        )
        .with_severity(if array {
            Severity::Warning
        } else {
            Severity::Info
        })
        .with_label(format!("sub {first} missing"))
        .with_help(if array {
            "describe the missing elements (the generated `Od` has none: an SDO access to one is refused with 0609 0011), or declare a RECORD"
        } else {
            "gaps are legal in a RECORD; the generated `Od` has no entries for them"
        }),
    );
}

/// The CiA name of a data type index, or its number.
fn type_name(device: &Device, dt: u16) -> String {
    match device.basic_type(dt) {
        Some(t) if BasicType::from_index(dt).is_some() => t.name().to_owned(),
        Some(t) => format!("{dt:04X}h ({})", t.name()),
        None => format!("data type {dt:04X}h"),
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
                    super::short_list(&found)
                ),
            )
            .with_label("reserved bits set")
            .with_help(
                "only bit 0 (refuse write on download) and bit 1 (refuse read on scan) are defined",
            ),
        );
    }
}

/// Whether an entry is described by the key table as a VAR (needs DataType and AccessType).
fn needs_var_keys(o: &Object, sub: &SubObject) -> bool {
    !sub.implicit
        && match o.object_type {
            ObjectType::Var | ObjectType::DefType => true,
            ObjectType::Array | ObjectType::Record | ObjectType::DefStruct => true,
            ObjectType::Domain | ObjectType::Null => false,
        }
}

fn entry(device: &Device, o: &Object, sub: &SubObject, out: &mut Vec<Diagnostic>) {
    let name = EntryName::new(device, o.index, sub.sub_index);
    if o.object_type.has_subs() && !sub.implicit && sub.name.chars().count() > MAX_NAME {
        out.push(
            Diagnostic::new(
                &rules::LONG_NAME,
                Some(sub.span),
                format!(
                    "the ParameterName of {name} is {} characters long; CiA 306 allows {MAX_NAME}",
                    sub.name.chars().count()
                ),
            )
            .with_label("name too long"),
        );
    }
    // An ESI reader reports a type or access it cannot read itself (EDS805, EDS604).
    if needs_var_keys(o, sub) && device.source.format != Format::Esi {
        let missing: Vec<&str> = [
            (sub.data_type.is_none(), "DataType"),
            (sub.access.is_none(), "AccessType"),
        ]
        .into_iter()
        .filter_map(|(m, k)| m.then_some(k))
        .collect();
        if !missing.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::MISSING_KEY,
                    Some(sub.span),
                    format!("{name} has no valid {}", missing.join(" or ")),
                )
                .with_label(format!("{} missing", missing.join(" and ")))
                .with_help("every VAR entry needs DataType (e.g. 0x0007) and AccessType (ro, wo, rw, rwr, rww or const)"),
            );
        }
    }
    if o.object_type == ObjectType::Domain && sub.pdo_mapping && !sub.implicit {
        out.push(
            Diagnostic::new(
                &rules::KEY_NOT_ALLOWED,
                Some(sub.span),
                format!("{name} is a DOMAIN with PDOMapping=1"),
            )
            .with_label("a DOMAIN cannot be mapped")
            .with_help("remove PDOMapping"),
        );
    }

    let Some(dt) = sub.data_type else { return };
    if o.object_type == ObjectType::Domain {
        if dt != BasicType::Domain.index() {
            out.push(
                Diagnostic::new(
                    &rules::DOMAIN_DATA_TYPE,
                    Some(sub.key_spans.data_type.unwrap_or(sub.span)),
                    format!("{name} is a DOMAIN object with DataType {dt:04X}h"),
                )
                .with_label("expected 000Fh")
                .with_help(
                    "set DataType=0x000F, or ObjectType=0x7 (VAR) if it holds a typed value",
                ),
            );
        }
    } else if !data_type_known(device, dt) {
        let reserved = matches!(dt, 0x000E | 0x0017);
        out.push(
            Diagnostic::new(
                &rules::UNKNOWN_DATA_TYPE,
                Some(sub.key_spans.data_type.unwrap_or(sub.span)),
                if reserved {
                    format!("{name} has DataType {dt:04X}h, a reserved code")
                } else if is_deftype(device, dt) {
                    format!("{name} has DataType {dt:04X}h, a DEFTYPE that resolves to no basic type (it names itself, or a chain of DEFTYPEs that does not end at one)")
                } else if let Some(record) = standard_record_type(dt) {
                    format!("{name} has DataType {dt:04X}h, the CiA 301 record type {record}, which this file does not describe as a DEFSTRUCT")
                } else {
                    format!("{name} has DataType {dt:04X}h, which is not a basic type nor defined in this file")
                },
            )
            .with_label("unknown data type")
            .with_help("use a CiA 301 basic type (0x0001..0x001B), or describe the DEFTYPE/DEFSTRUCT object"),
        );
    }
    let Some(ty) = device.basic_type(dt) else {
        return;
    };
    let node_id = device
        .commissioning
        .as_ref()
        .and_then(|c| c.node_id.as_ref())
        .map(|n| i128::from(n.value))
        .filter(|n| (1..=127).contains(n));
    limits(&name, ty, o, sub, node_id, out);
    nodeid_ranges(&name, ty, sub, out);
}

/// Whether a DataType is a basic type, a DEFTYPE that resolves to one, or a DEFSTRUCT.
fn data_type_known(device: &Device, dt: u16) -> bool {
    device.basic_type(dt).is_some()
        || device
            .objects
            .get(&dt)
            .is_some_and(|d| d.object_type == ObjectType::DefStruct)
}

/// Whether a DataType names a DEFTYPE object (which may still resolve to no basic type).
fn is_deftype(device: &Device, dt: u16) -> bool {
    device
        .objects
        .get(&dt)
        .is_some_and(|d| d.object_type == ObjectType::DefType)
}

/// A value as a function of the node-ID: (constant, slope), i.e. `v = constant + slope * node`.
#[derive(Clone, Copy)]
enum Linear {
    Int(i128, i128),
    Real(f64),
}

fn linear(value: &Value) -> Option<Linear> {
    match value {
        Value::Integer(v) => Some(Linear::Int(*v, 0)),
        Value::NodeRelative(o) => Some(Linear::Int(i128::from(*o), 1)),
        Value::Real(r) => Some(Linear::Real(*r)),
        _ => None,
    }
}

/// `a < b` at the given node-ID; `None` if not comparable.
fn less(a: Linear, b: Linear, node: i128) -> Option<bool> {
    match (a, b) {
        (Linear::Int(c1, s1), Linear::Int(c2, s2)) => Some(c1 + s1 * node < c2 + s2 * node),
        (Linear::Real(x), Linear::Real(y)) => Some(x < y),
        (Linear::Int(c, s), Linear::Real(y)) => Some(((c + s * node) as f64) < y),
        (Linear::Real(x), Linear::Int(c, s)) => Some(x < (c + s * node) as f64),
    }
}

fn is_relative(a: Linear) -> bool {
    matches!(a, Linear::Int(_, 1))
}

fn limits(
    name: &dyn std::fmt::Display,
    ty: BasicType,
    o: &Object,
    sub: &SubObject,
    node_id: Option<i128>,
    out: &mut Vec<Diagnostic>,
) {
    let non_numeric = ty.bits().is_none() || o.object_type == ObjectType::Domain;
    if non_numeric {
        for (key, limit) in [("LowLimit", &sub.low_limit), ("HighLimit", &sub.high_limit)] {
            if let Some(l) = limit.as_ref().filter(|l| !l.raw.is_empty()) {
                out.push(
                    Diagnostic::new(
                        &rules::LIMITS_ON_NON_NUMERIC,
                        Some(l.span),
                        format!("{name} is {} but has {key}", ty.name()),
                    )
                    .with_label("limits apply to numbers only")
                    .with_help(format!("remove {key}")),
                );
            }
        }
        return;
    }
    let lin = |v: &Option<ValueSource>| v.as_ref().and_then(|v| v.value.as_ref()).and_then(linear);
    let (low, high) = (lin(&sub.low_limit), lin(&sub.high_limit));
    if let (Some(lo), Some(hi), Some(lo_src), Some(hi_src)) =
        (low, high, sub.low_limit.as_ref(), sub.high_limit.as_ref())
    {
        if less(hi, lo, 1) == Some(true) || less(hi, lo, 127) == Some(true) {
            // A hex limit on a signed type is ambiguous when two's complement made it negative
            // (0xFF is -1 for INTEGER8), or when it is a negative two's-complement pattern of a
            // narrower width (0xEC78 is -5000 in 16 bits, 60536 in INTEGER32): a warning that
            // says which reading was taken. Other inverted limits are errors.
            let ambiguity = |src: &ValueSource| -> Option<String> {
                let raw = src.raw.trim();
                let digits = raw.strip_prefix("0x").or_else(|| raw.strip_prefix("0X"))?;
                let Some(Value::Integer(v)) = src.value else {
                    return None;
                };
                if v < 0 {
                    return Some(format!("`{raw}` is read as the two's complement {v}"));
                }
                let bits = u32::try_from(digits.len()).ok()?.checked_mul(4)?;
                let narrower = bits < ty.bits().unwrap_or(0) && bits > 0 && bits < 127;
                (narrower && v >= 1i128 << (bits - 1)).then(|| {
                    format!(
                        "`{raw}` is {v} in {}, though as a {bits}-bit two's complement it would be {}",
                        ty.name(),
                        v - (1i128 << bits)
                    )
                })
            };
            let why = if ty.is_signed_integer() {
                ambiguity(lo_src).or_else(|| ambiguity(hi_src))
            } else {
                None
            };
            let mut diag = Diagnostic::new(
                &rules::LIMITS_INVERTED,
                Some(lo_src.span),
                format!(
                    "{name} has LowLimit {} above HighLimit {}",
                    lo_src.raw, hi_src.raw
                ),
            )
            .with_label("above HighLimit");
            diag = match why {
                Some(why) => diag
                    .with_severity(Severity::Warning)
                    .with_help(format!("{why}; write the limits in decimal")),
                None => diag.with_help("swap the limits"),
            };
            out.push(diag);
            return;
        }
    }
    for (key, value) in [
        ("DefaultValue", &sub.default),
        ("ParameterValue", &sub.parameter_value),
    ] {
        let Some(src) = value else { continue };
        let Some(v) = src.value.as_ref().and_then(linear) else {
            continue;
        };
        let relative =
            is_relative(v) || low.is_some_and(is_relative) || high.is_some_and(is_relative);
        let nodes: Vec<i128> = match node_id {
            Some(n) if relative => vec![n],
            _ if relative => vec![1, 127],
            _ => vec![1],
        };
        for &node in &nodes {
            let below = low.and_then(|lo| less(v, lo, node)) == Some(true);
            let above = high.and_then(|hi| less(hi, v, node)) == Some(true);
            if !(below || above) {
                continue;
            }
            let (side, limit) = if below {
                ("below LowLimit", sub.low_limit.as_ref())
            } else {
                ("above HighLimit", sub.high_limit.as_ref())
            };
            let for_node = if relative {
                format!(" for node-ID {node}")
            } else {
                String::new()
            };
            out.push(
                Diagnostic::new(
                    &rules::VALUE_OUTSIDE_LIMITS,
                    Some(src.span),
                    format!(
                        "{key} {} of {name} is {side} {}{for_node}",
                        src.raw,
                        limit.map_or("", |l| l.raw.as_str())
                    ),
                )
                .with_label(side)
                .with_help("fix the value or the limits"),
            );
            break;
        }
    }
}

fn nodeid_ranges(
    name: &dyn std::fmt::Display,
    ty: BasicType,
    sub: &SubObject,
    out: &mut Vec<Diagnostic>,
) {
    let Some((min, max)) = ty.integer_range() else {
        return;
    };
    for (key, value) in [
        ("DefaultValue", &sub.default),
        ("ParameterValue", &sub.parameter_value),
    ] {
        let Some(src) = value else { continue };
        let Some(Value::NodeRelative(offset)) = src.value else {
            continue;
        };
        let at_node = |n: i128| i128::from(offset) + n;
        let fits = |n: i128| (min..=max).contains(&at_node(n));
        let (fits_low, fits_high) = (fits(1), fits(127));
        if fits_low && fits_high {
            continue;
        }
        let all = !fits_low && !fits_high;
        let bad_node = if fits_low { 127 } else { 1 };
        out.push(
            Diagnostic::new(
                &rules::NODEID_OVERFLOW,
                Some(src.span),
                format!(
                    "{key} {} of {name} is {} for node-ID {bad_node}, outside {} ({min}..{max})",
                    src.raw,
                    at_node(bad_node),
                    ty.name()
                ),
            )
            .with_severity(if all {
                Severity::Error
            } else {
                Severity::Warning
            })
            .with_label(if all {
                "out of range for every node-ID"
            } else {
                "out of range for some node-IDs"
            })
            .with_help("check the offset added to $NODEID, or the data type"),
        );
    }
}

/// The predefined connection set: (index, sub, CAN-ID base, what).
const PREDEFINED: [(u16, u8, u32, &str); 11] = [
    (0x1014, 0, 0x080, "EMCY"),
    (0x1200, 1, 0x600, "SDO server receive (client to server)"),
    (0x1200, 2, 0x580, "SDO server transmit (server to client)"),
    (0x1400, 1, 0x200, "RPDO1"),
    (0x1401, 1, 0x300, "RPDO2"),
    (0x1402, 1, 0x400, "RPDO3"),
    (0x1403, 1, 0x500, "RPDO4"),
    (0x1800, 1, 0x180, "TPDO1"),
    (0x1801, 1, 0x280, "TPDO2"),
    (0x1802, 1, 0x380, "TPDO3"),
    (0x1803, 1, 0x480, "TPDO4"),
];

fn default_cob_ids(device: &Device, out: &mut Vec<Diagnostic>) {
    // A master's PDOs carry the COB-IDs of the slaves it talks to, not its own defaults.
    let master = device.device_info.simple_boot_up_master
        || device
            .commissioning
            .as_ref()
            .is_some_and(|c| c.canopen_manager);
    if master {
        return;
    }
    for (index, sub_index, base, what) in PREDEFINED {
        let Some(sub) = device.entry(index, sub_index) else {
            continue;
        };
        let Some(src) = sub.default.as_ref() else {
            continue;
        };
        let name = entry_name(device, index, sub_index);
        let problem = match src.value {
            Some(Value::NodeRelative(offset)) => {
                let id = (offset as u32) & 0x3FFF_FFFF;
                (id != base).then(|| format!("is $NODEID+{id:#X}, not $NODEID+{base:#X}"))
            }
            Some(Value::Integer(v)) => {
                let v = v as u32;
                if v & 0x8000_0000 != 0 {
                    None // not valid: the COB-ID must be written before use anyway.
                } else {
                    let id = v & 0x7FF;
                    Some(if id > base && id <= base + 127 {
                        format!("is the fixed value {v:#X} (the COB-ID for node-ID {}), not $NODEID+{base:#X}", id - base)
                    } else {
                        format!("is the fixed value {v:#X}, not $NODEID+{base:#X}")
                    })
                }
            }
            _ => None,
        };
        if let Some(problem) = problem {
            out.push(
                Diagnostic::new(
                    &rules::DEFAULT_COB_ID,
                    Some(src.span),
                    format!("the default COB-ID of {name} ({what}) {problem}"),
                )
                .with_label("not the predefined connection set")
                .with_help(format!(
                    "write `DefaultValue=$NODEID+{base:#X}` so the COB-ID follows the node-ID"
                )),
            );
        }
    }
}
