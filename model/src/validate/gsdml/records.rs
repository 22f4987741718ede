//! Parameter record fields (PN003, PN008, PN012, PN013): each field's data type and bits, and
//! its default and allowed values against its type's range and its value list.

use crate::diag::Diagnostic;
use crate::model::{PnDataType, Profinet, RecordField};
use crate::rules;

pub(super) fn field_type(field: &RecordField, out: &mut Vec<Diagnostic>) {
    match field.kind {
        None => out.push(
            Diagnostic::new(
                &rules::PN_UNKNOWN_TYPE,
                Some(field.data_type.span),
                format!("`{}` is not a GSDML data type", field.data_type.value),
            )
            .with_label("unknown type"),
        ),
        Some(PnDataType::OctetString | PnDataType::VisibleString | PnDataType::UnicodeString8)
            if field.length.is_none() =>
        {
            out.push(Diagnostic::new(
                &rules::PN_UNKNOWN_TYPE,
                Some(field.data_type.span),
                format!("a `{}` field without `Length`", field.data_type.value),
            ))
        }
        Some(PnDataType::Bit) if field.bit_offset.unwrap_or(0) > 7 => out.push(Diagnostic::new(
            &rules::PN_BIT_OUTSIDE,
            Some(field.span),
            format!(
                "a `Bit` field at BitOffset {}; a byte has bits 0..7",
                field.bit_offset.unwrap_or(0)
            ),
        )),
        _ => {}
    }
}

/// The range a field's type can hold, for the integer types.
fn type_range(field: &RecordField) -> Option<(i128, i128)> {
    use PnDataType::*;
    Some(match field.kind? {
        Bit | Boolean => (0, 1),
        BitArea => (0, (1i128 << field.bit_length.unwrap_or(1).min(64)) - 1),
        Unsigned8 => (0, 0xFF),
        Unsigned16 => (0, 0xFFFF),
        Unsigned32 => (0, 0xFFFF_FFFF),
        Unsigned64 => (0, i128::from(u64::MAX)),
        Integer8 => (-0x80, 0x7F),
        Integer16 => (-0x8000, 0x7FFF),
        Integer32 => (i128::from(i32::MIN), i128::from(i32::MAX)),
        Integer64 => (i128::from(i64::MIN), i128::from(i64::MAX)),
        _ => return None,
    })
}

pub(super) fn field_value(pn: &Profinet, field: &RecordField, out: &mut Vec<Diagnostic>) {
    if let Some(target) = &field.value_item {
        if !pn.value_lists.iter().any(|v| v.id == target.value) {
            out.push(
                Diagnostic::new(
                    &rules::PN_MISSING_VALUE_LIST,
                    Some(target.span),
                    format!("`ValueItemTarget` `{}` names no `ValueItem`", target.value),
                )
                .with_label("no such ValueItem"),
            );
        }
    }
    let (Some(default), Some((lo, hi))) = (&field.default, type_range(field)) else {
        return;
    };
    let Some(value) = crate::read::esi::values::parse_number(&default.value) else {
        out.push(Diagnostic::new(
            &rules::PN_DEFAULT_NOT_ALLOWED,
            Some(default.span),
            format!(
                "`DefaultValue` is `{}`, not a number for a `{}` field",
                default.value, field.data_type.value
            ),
        ));
        return;
    };
    if value < lo || value > hi {
        out.push(Diagnostic::new(
            &rules::PN_DEFAULT_NOT_ALLOWED,
            Some(default.span),
            format!(
                "`DefaultValue` {value} is outside a `{}` field's range {lo}..{hi}",
                field.data_type.value
            ),
        ));
    } else if !field.allowed_values.is_empty()
        && !field
            .allowed_values
            .iter()
            .any(|(a, b)| (*a..=*b).contains(&value))
    {
        let allowed: Vec<String> = field
            .allowed_values
            .iter()
            .map(|(a, b)| {
                if a == b {
                    a.to_string()
                } else {
                    format!("{a}..{b}")
                }
            })
            .collect();
        out.push(
            Diagnostic::new(
                &rules::PN_DEFAULT_NOT_ALLOWED,
                Some(default.span),
                format!(
                    "`DefaultValue` {value} is not among the `AllowedValues` {}",
                    allowed.join(" ")
                ),
            )
            .with_label("not allowed"),
        );
    }
}
