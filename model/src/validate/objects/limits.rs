//! Limits and `$NODEID` values: low/high limits against each other and the default, and values
//! that overflow for some or every node-ID.

use crate::diag::{Diagnostic, Severity};
use crate::model::{BasicType, Object, ObjectType, SubObject, Value, ValueSource};
use crate::rules;

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

pub(super) fn limits(
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
        let ends = [1, 127];
        let nodes: &[i128] = match &node_id {
            Some(n) if relative => std::slice::from_ref(n),
            _ if relative => &ends,
            _ => &ends[..1],
        };
        for &node in nodes {
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

pub(super) fn nodeid_ranges(
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
