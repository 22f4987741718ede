//! Values that are not integers: REALs (decimal, hex bit patterns, C suffixes), byte strings
//! (VISIBLE_STRING, OCTET_STRING, UNICODE_STRING, DOMAIN and their dialects), and
//! TIME_OF_DAY/TIME_DIFFERENCE.

use super::{
    contains_nodeid, parse_integer, parse_integer_with_radix, push_suffix_warning,
    strip_float_suffix, Radix,
};
use crate::diag::Diagnostic;
use crate::model::{BasicType, Span, Value};
use crate::rules;

/// Decimal or scientific notation, without Rust's `inf`/`nan` words.
pub(super) fn looks_like_float(text: &str) -> bool {
    let body = text.trim_start_matches(['-', '+']);
    body.starts_with(|c: char| c.is_ascii_digit() || c == '.')
        && body
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+'))
}

pub(super) fn parse_real(
    text: &str,
    ty: BasicType,
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    if contains_nodeid(text) {
        diags.push(Diagnostic::new(
            &rules::NODEID_FORMULA,
            Some(span),
            format!("`$NODEID` formula `{text}` on a {} value", ty.name()),
        ));
        return None;
    }
    let text = match strip_float_suffix(text) {
        Some(stripped) => {
            push_suffix_warning(text, stripped, ty, span, diags);
            stripped
        }
        None => text,
    };
    let bits = if ty == BasicType::Real32 { 32 } else { 64 };
    if let Some((pattern, Radix::Hex)) = parse_integer_with_radix(text) {
        let digits = text.trim_start_matches(['-', '+'])[2..].len();
        if digits < bits / 4 && pattern != 0 {
            // Fewer digits than the type width: a number written in hex (Sevcon's
            // `HighLimit=0xFFFF`), not a bit pattern, which would be a meaningless denormal.
            let value = pattern as f64;
            diags.push(
                Diagnostic::new(
                    &rules::REAL_BIT_PATTERN,
                    Some(span),
                    format!(
                        "{} value `{text}` has fewer than {} hex digits: read as the number {value}, not as a bit pattern",
                        ty.name(),
                        bits / 4
                    ),
                )
                .with_help(format!("write `{value}` in decimal")),
            );
            return Some(Value::Real(value));
        }
        if pattern >= 0 && pattern < (1i128 << bits) {
            let value = if bits == 32 {
                f64::from(f32::from_bits(pattern as u32))
            } else {
                f64::from_bits(pattern as u64)
            };
            // Zero is 0.0 under both readings: nothing to report.
            if pattern == 0 {
                return Some(Value::Real(0.0));
            }
            diags.push(
                Diagnostic::new(
                    &rules::REAL_BIT_PATTERN,
                    Some(span),
                    format!(
                        "{} value `{text}` is read as an IEEE 754 bit pattern ({value})",
                        ty.name()
                    ),
                )
                .with_help(
                    "write the number in decimal (e.g. `1.5`) unless the bit pattern is meant",
                ),
            );
            return Some(Value::Real(value));
        }
    }
    if looks_like_float(text) {
        if let Ok(value) = text.parse::<f64>() {
            if bits == 32 && value.is_finite() && (value as f32).is_infinite() {
                diags.push(Diagnostic::new(
                    &rules::OUT_OF_RANGE,
                    Some(span),
                    format!("`{text}` is outside the range of REAL32"),
                ));
                return None;
            }
            if value.is_finite() {
                return Some(Value::Real(value));
            }
        }
    }
    diags.push(
        Diagnostic::new(
            &rules::BAD_VALUE,
            Some(span),
            format!("`{text}` cannot be read as {}", ty.name()),
        )
        .with_label("not a number"),
    );
    None
}

pub(super) fn parse_bytes(
    text: &str,
    ty: BasicType,
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    if ty == BasicType::Domain && text == "0" {
        diags.push(
            Diagnostic::new(
                &rules::BYTES_DIALECT,
                Some(span),
                "DOMAIN value `0` is read as empty (no bytes)".to_owned(),
            )
            .with_help("leave the value empty, or write the bytes as hex digit pairs (e.g. `00`)"),
        );
        return Some(Value::Bytes(Vec::new()));
    }
    let prefixed = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X"));
    if let Some(body) = prefixed {
        let digits: Vec<char> = body.chars().filter(|c| !c.is_whitespace()).collect();
        if !digits.is_empty()
            && digits.len().is_multiple_of(2)
            && digits.iter().all(char::is_ascii_hexdigit)
        {
            let shown = if body.chars().count() > 16 {
                format!("{}...", body.chars().take(16).collect::<String>())
            } else {
                body.to_owned()
            };
            diags.push(
                Diagnostic::new(
                    &rules::BYTES_DIALECT,
                    Some(span),
                    format!(
                        "{} value written as a `0x` literal; read as the bytes `{shown}` in written order",
                        ty.name()
                    ),
                )
                .with_help("drop the `0x`: CiA 306 writes bytes as hex digit pairs"),
            );
            return parse_bytes(body, ty, span, diags);
        }
    }
    let digits: Vec<char> = text.chars().filter(|c| !c.is_whitespace()).collect();
    let all_hex = digits.iter().all(char::is_ascii_hexdigit);
    if !all_hex || !digits.len().is_multiple_of(2) {
        let why = if all_hex {
            "an odd number of hex digits"
        } else {
            "characters that are not hex digits"
        };
        diags.push(
            Diagnostic::new(
                &rules::BAD_VALUE,
                Some(span),
                format!("{} value `{text}` has {why}", ty.name()),
            )
            .with_help("write two hex digits per byte, without `0x` (e.g. `01a1053c`)"),
        );
        return None;
    }
    let bytes = digits
        .chunks(2)
        .filter_map(|pair| {
            let high = pair.first()?.to_digit(16)?;
            let low = pair.get(1)?.to_digit(16)?;
            u8::try_from(high * 16 + low).ok()
        })
        .collect();
    Some(Value::Bytes(bytes))
}

pub(super) fn parse_time(
    text: &str,
    ty: BasicType,
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    let parts: Vec<&str> = text.split_whitespace().collect();
    let value = match parts.as_slice() {
        [single] => parse_integer(single),
        [days, ms] => match (parse_integer(days), parse_integer(ms)) {
            (Some(d), Some(m)) if (0..1 << 16).contains(&d) && (0..1 << 28).contains(&m) => {
                Some(m | d << 32)
            }
            _ => None,
        },
        _ => None,
    };
    match value {
        Some(v) if (0..1i128 << 48).contains(&v) => Some(Value::Integer(v)),
        _ => {
            diags.push(
                Diagnostic::new(
                    &rules::BAD_VALUE,
                    Some(span),
                    format!("`{text}` cannot be read as {}", ty.name()),
                )
                .with_help("write the 48-bit value as an integer, or `<days> <milliseconds>`"),
            );
            None
        }
    }
}
