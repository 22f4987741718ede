//! Entry rules: the key table of a VAR entry, name, data type, access, and the standard
//! record types.

use super::limits::{limits, nodeid_ranges};
use super::{missing_var_keys, MAX_NAME};
use crate::diag::Diagnostic;
use crate::model::{BasicType, Device, Object, ObjectType, SubObject};
use crate::rules;
use crate::validate::EntryName;

/// Whether an entry is described by the key table as a VAR (needs DataType and AccessType).
fn needs_var_keys(o: &Object, sub: &SubObject) -> bool {
    !sub.implicit
        && match o.object_type {
            ObjectType::Var | ObjectType::DefType => true,
            ObjectType::Array | ObjectType::Record | ObjectType::DefStruct => true,
            ObjectType::Domain | ObjectType::Null => false,
        }
}

pub(super) fn entry(device: &Device, o: &Object, sub: &SubObject, out: &mut Vec<Diagnostic>) {
    let name = EntryName::new(device, o.index, sub.sub_index);
    if o.object_type.has_subs() && !sub.implicit
        // A name of at most MAX_NAME bytes has at most MAX_NAME characters: most are not counted.
        && sub.name.len() > MAX_NAME
        && sub.name.chars().count() > MAX_NAME
    {
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
    if needs_var_keys(o, sub) && !device.source.format.is_coe() {
        let missing = missing_var_keys(sub);
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
