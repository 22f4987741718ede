//! Value text to typed [`Value`]s, per CiA 306 section 4.6.3 and the dialects real files use.
//!
//! Shared by the EDS/DCF reader and the XDD/XDC reader. Parsing never evaluates `$NODEID`: a
//! formula stays [`Value::NodeRelative`]. Every dialect that is accepted is reported, and every
//! value that cannot be read gives a diagnostic and `None`; nothing here panics.

use crate::diag::{Diagnostic, Severity};
use crate::model::{BasicType, Span, Value};
use crate::rules;

mod non_integer;
use non_integer::{looks_like_float, parse_bytes, parse_real, parse_time};

/// Parses a CiA 306 integer: decimal, `0x`/`0X` hexadecimal (digits in any case), octal with a
/// leading `0` (`012` is 10; a bare `0` is zero), each optionally preceded by `-` (or `+`).
///
/// Surrounding whitespace is ignored. Returns `None` for anything else, including an empty text,
/// digits `8`/`9` after a leading `0`, and values that do not fit an `i128`.
pub fn parse_integer(raw: &str) -> Option<i128> {
    parse_integer_with_radix(raw).map(|(value, _)| value)
}

/// Why `raw` is no CiA 306 integer when the reason is its leading 0: decimal digits after a
/// leading `0` with an `8` or `9` among them, which CiA 306 reads as octal. The message (about
/// the literal) and the help (the decimal literal meant, without the leading zeros); `None` for
/// any other text.
pub fn octal_objection(raw: &str) -> Option<(String, String)> {
    let text = raw.trim();
    let (sign, digits) = match text.as_bytes().first() {
        Some(b'-' | b'+') => text.split_at(1),
        _ => ("", text),
    };
    if digits.len() < 2 || !digits.starts_with('0') || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let bad = digits.chars().find(|c| matches!(c, '8' | '9'))?;
    let meant = digits.trim_start_matches('0');
    let sign = if sign == "-" { "-" } else { "" };
    Some((
        format!(
            "`{text}` has a leading 0, which CiA 306 reads as octal, and {bad} is not an octal digit"
        ),
        format!("write `{sign}{meant}`"),
    ))
}

/// How an integer literal was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Radix {
    Decimal,
    Hex,
    Octal,
}

fn parse_integer_with_radix(raw: &str) -> Option<(i128, Radix)> {
    let text = trim(raw);
    let (negative, body) = match text.as_bytes().first() {
        Some(b'-') => (true, &text[1..]),
        Some(b'+') => (false, &text[1..]),
        _ => (false, text),
    };
    let (digits, radix) =
        if let Some(hex) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
            (hex, Radix::Hex)
        } else if body.len() > 1 && body.starts_with('0') {
            (&body[1..], Radix::Octal)
        } else {
            (body, Radix::Decimal)
        };
    let base = match radix {
        Radix::Decimal => 10,
        Radix::Hex => 16,
        Radix::Octal => 8,
    };
    if digits.is_empty() {
        return None;
    }
    let mut value: i128 = 0;
    if digits.len() <= 15 {
        // At most 15 digits cannot overflow 64 bits (16^15 = 2^60): skip the 128-bit checks.
        // Byte by byte: a digit is ASCII, and a byte of a non-ASCII character (80h..FFh as a
        // `char`) is no digit, as the character is not.
        let mut small: u64 = 0;
        for b in digits.bytes() {
            small = small * u64::from(base) + u64::from(char::from(b).to_digit(base)?);
        }
        value = i128::from(small);
    } else {
        for c in digits.chars() {
            let digit = c.to_digit(base)?;
            value = value
                .checked_mul(i128::from(base))?
                .checked_add(i128::from(digit))?;
        }
    }
    Some((if negative { -value } else { value }, radix))
}

/// Splits an inline `;` comment off a value: `("0x0007", Some("; Unsigned32"))` for
/// `0x0007 ; Unsigned32`. The value part is trimmed. Callers decide whether the value's type
/// allows stripping (never for strings).
pub fn split_inline_comment(raw: &str) -> (&str, Option<&str>) {
    // A byte search: values are a few bytes, and `;` is ASCII.
    match raw.bytes().position(|b| b == b';') {
        Some(at) => (trim(&raw[..at]), Some(&raw[at..])),
        None => (trim(raw), None),
    }
}

/// [`str::trim`], with the answer for text that starts and ends with ASCII other than white
/// space (a value the lexer already trimmed) found without a walk over characters.
fn trim(text: &str) -> &str {
    let bytes = text.as_bytes();
    let settled =
        |b: Option<&u8>| b.is_some_and(|b| b.is_ascii() && !b.is_ascii_whitespace() && *b != 0x0B);
    if settled(bytes.first()) && settled(bytes.last()) {
        text
    } else {
        text.trim()
    }
}

/// Whether values of this type may carry an inline `;` comment that should be stripped: every type
/// whose text cannot contain `;` (numbers, booleans, octet strings, domains). `None` (unknown
/// type) and the string types are never stripped.
pub fn strips_inline_comment(data_type: Option<BasicType>) -> bool {
    match data_type {
        None => false,
        Some(BasicType::VisibleString | BasicType::UnicodeString) => false,
        Some(_) => true,
    }
}

/// Parses a value for a data type, pushing diagnostics (EDS012-EDS020) about it.
///
/// - An empty text means "no value": `None`, no diagnostic.
/// - `data_type == None` (unknown or complex type): a best effort without diagnostics, an integer
///   or a `$NODEID` formula if the text is one, else `None`.
/// - Integers and BOOLEAN: see [`parse_integer`]; octal is reported (EDS017) when it changes the
///   value, a signed type written as unsigned hex of the type width becomes two's complement
///   (EDS014), out-of-range values are errors (EDS013) and give `None`, a float literal with an
///   integral value is accepted (EDS020), `$NODEID` formulas give [`Value::NodeRelative`]
///   (postfix or other spellings: EDS016; malformed: EDS015).
/// - REAL32/REAL64: decimal or scientific text; a `0x` literal of the type's full width (8 or 16
///   digits) is an IEEE 754 bit pattern, a shorter one a number (both EDS019, except for zero,
///   which every reading agrees on).
/// - VISIBLE_STRING/UNICODE_STRING: kept as written; surrounding quotes are kept and reported
///   (EDS018).
/// - A C literal suffix (`LL`, `U`, `f`) on an integer or REAL is dropped (EDS025).
/// - OCTET_STRING/DOMAIN: hex digit pairs, spaces between bytes tolerated; a `0x` prefix before
///   an even number of hex digits is dropped and a DOMAIN `0` is empty (both EDS026).
/// - TIME_OF_DAY/TIME_DIFFERENCE: an integer (the 48-bit value), or `<days> <ms>` (Lely), stored as
///   `ms | days << 32`.
pub fn parse_value(
    raw: &str,
    data_type: Option<BasicType>,
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    let text = trim(raw);
    if text.is_empty() {
        return None;
    }
    let Some(ty) = data_type else {
        if contains_nodeid(text) {
            let mut scratch = Vec::new();
            return parse_nodeid(text, span, &mut scratch);
        }
        return parse_integer(text).map(Value::Integer);
    };
    match ty {
        BasicType::VisibleString | BasicType::UnicodeString => {
            if text.len() >= 2 && text.starts_with('"') && text.ends_with('"') {
                diags.push(
                    Diagnostic::new(
                        &rules::QUOTED_STRING,
                        Some(span),
                        format!("string value `{text}` is wrapped in quotes; the quotes are kept as part of the value"),
                    )
                    .with_help("CiA 306 stores strings without quotes; remove them unless they belong to the text"),
                );
            }
            Some(Value::Text(text.to_owned()))
        }
        BasicType::OctetString | BasicType::Domain => parse_bytes(text, ty, span, diags),
        BasicType::Real32 | BasicType::Real64 => parse_real(text, ty, span, diags),
        BasicType::TimeOfDay | BasicType::TimeDifference => parse_time(text, ty, span, diags),
        _ => parse_int_value(text, ty, span, diags),
    }
}

/// Rules whose instances in one file share one cause (the tool that wrote the file) and one fix:
/// [`aggregate_dialects`] folds them.
const FOLDED_DIALECTS: &[&str] = &["EDS003", "EDS013", "EDS016", "EDS025", "EDS026"];

/// Folds repeated dialect warnings of one kind (same rule, severity and message shape) into the
/// first one, which keeps its span and names the lines of the others. Errors and infos are never
/// folded; EDS013 is folded only as the warning for limits beyond the type.
pub fn aggregate_dialects(diags: &mut Vec<Diagnostic>) {
    let shape = |d: &Diagnostic| -> Option<(&'static str, String)> {
        if d.severity != Severity::Warning || !FOLDED_DIALECTS.contains(&d.code()) {
            return None;
        }
        // Quoted text and free-standing numbers vary; words (type names like UNSIGNED16, with
        // their digits) do not.
        let mut shape = String::new();
        let mut quoted = false;
        let mut in_word = false;
        for c in d.message.chars() {
            if c == '`' {
                quoted = !quoted;
                shape.push(c);
            } else if !quoted && (!c.is_ascii_digit() || in_word) {
                shape.push(c);
            }
            in_word = c.is_ascii_alphabetic() || (in_word && c.is_ascii_alphanumeric());
        }
        Some((d.code(), shape))
    };
    crate::diag::fold(diags, shape, "the same on");
    // REAL values written as bit patterns: one finding per file, whatever the values.
    crate::diag::fold(
        diags,
        |d| (d.code() == "EDS019" && d.severity == Severity::Warning).then_some(d.code()),
        "likewise on",
    );
}

fn contains_nodeid(text: &str) -> bool {
    const NEEDLE: &[u8] = b"$nodeid";
    text.as_bytes()
        .windows(NEEDLE.len())
        .any(|w| w.eq_ignore_ascii_case(NEEDLE))
}

/// Parses a `$NODEID` formula into its offset. Accepted: `$NODEID`, `$NODEID+n{+n}` with optional
/// spaces (the spec form), other spellings of `$NODEID` and the postfix `n+$NODEID` (EDS016).
fn parse_nodeid(text: &str, span: Span, diags: &mut Vec<Diagnostic>) -> Option<Value> {
    let malformed = |diags: &mut Vec<Diagnostic>| {
        diags.push(
            Diagnostic::new(
                &rules::NODEID_FORMULA,
                Some(span),
                format!("`{text}` is not a `$NODEID + number` formula"),
            )
            .with_help("CiA 306 allows only `$NODEID` followed by `+ number` terms"),
        );
        None
    };
    let terms: Vec<&str> = text.split('+').map(str::trim).collect();
    let mut nodeid_position = None;
    let mut offset: i128 = 0;
    for (position, term) in terms.iter().enumerate() {
        if term.eq_ignore_ascii_case("$NODEID") {
            if nodeid_position.is_some() {
                return malformed(diags);
            }
            nodeid_position = Some((position, *term));
        } else {
            match parse_integer(term) {
                Some(n) if !term.starts_with(['-', '+']) => {
                    offset = match offset.checked_add(n) {
                        Some(sum) => sum,
                        None => return malformed(diags),
                    }
                }
                _ => return malformed(diags),
            }
        }
    }
    let Some((position, spelling)) = nodeid_position else {
        return malformed(diags);
    };
    let Ok(offset) = i64::try_from(offset) else {
        return malformed(diags);
    };
    if position != 0 {
        diags.push(
            Diagnostic::new(
                &rules::NODEID_DIALECT,
                Some(span),
                format!("`{text}` puts `$NODEID` after the offset"),
            )
            .with_help(format!("write `$NODEID+{}`", offset_text(offset))),
        );
    } else if spelling != "$NODEID" {
        diags.push(
            Diagnostic::new(
                &rules::NODEID_DIALECT,
                Some(span),
                format!("`{spelling}` is not spelled `$NODEID`"),
            )
            .with_help("CiA 306 spells the node-ID variable `$NODEID`"),
        );
    }
    Some(Value::NodeRelative(offset))
}

fn offset_text(offset: i64) -> String {
    format!("0x{offset:X}")
}

fn parse_int_value(
    text: &str,
    ty: BasicType,
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    if contains_nodeid(text) {
        return parse_nodeid(text, span, diags);
    }
    let (min, max) = ty.integer_range()?;
    if ty == BasicType::Boolean {
        let lower = text.to_ascii_lowercase();
        if lower == "true" || lower == "false" {
            diags.push(
                Diagnostic::new(
                    &rules::BAD_BOOLEAN,
                    Some(span),
                    format!("BOOLEAN value `{text}` is not 0 or 1"),
                )
                .with_help("write 0 or 1"),
            );
            return Some(Value::Integer(i128::from(lower == "true")));
        }
    }
    let text = match strip_integer_suffix(text) {
        Some(stripped) => {
            push_suffix_warning(text, stripped, ty, span, diags);
            stripped
        }
        None => text,
    };
    let (value, radix) = match parse_integer_with_radix(text) {
        Some(parsed) => parsed,
        None => return parse_int_fallback(text, ty, (min, max), span, diags),
    };
    if radix == Radix::Octal {
        let decimal = text.trim_start_matches(['-', '+']).parse::<i128>().ok();
        if decimal.map(i128::abs) != Some(value.abs()) {
            diags.push(
                Diagnostic::new(
                    &rules::OCTAL_LITERAL,
                    Some(span),
                    format!("`{text}` has a leading 0 and is read as octal ({value})"),
                )
                .with_help(format!("write `{value}` or `0x{value:X}` if that is meant")),
            );
        }
    }
    if value >= min && value <= max {
        return Some(Value::Integer(value));
    }
    if ty.is_signed_integer() && radix == Radix::Hex && value > max {
        if let Some(bits) = ty.bits() {
            if value < (1i128 << bits) {
                let signed = value - (1i128 << bits);
                diags.push(Diagnostic::new(
                    &rules::TWOS_COMPLEMENT,
                    Some(span),
                    format!(
                        "`{text}` is read as the two's complement {signed} of the {} value",
                        ty.name()
                    ),
                ));
                return Some(Value::Integer(signed));
            }
        }
    }
    diags.push(
        Diagnostic::new(
            &rules::OUT_OF_RANGE,
            Some(span),
            format!(
                "`{text}` ({value}) is outside the range of {} ({min}..={max})",
                ty.name()
            ),
        )
        .with_label("out of range"),
    );
    None
}

/// An integer type's text that is not an integer literal: octal digits 8/9, a float literal, or
/// garbage.
fn parse_int_fallback(
    text: &str,
    ty: BasicType,
    (min, max): (i128, i128),
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    let unsigned = text.trim_start_matches(['-', '+']);
    if unsigned.len() > 1
        && unsigned.starts_with('0')
        && unsigned.bytes().all(|b| b.is_ascii_digit())
    {
        if let (Ok(decimal), Some((message, help))) = (text.parse::<i128>(), octal_objection(text))
        {
            diags.push(
                Diagnostic::new(
                    &rules::OCTAL_LITERAL,
                    Some(span),
                    format!("{message}; read as decimal {decimal}"),
                )
                .with_severity(Severity::Warning)
                .with_help(help),
            );
            return range_checked(text, decimal, ty, (min, max), span, diags);
        }
    }
    if looks_like_float(text) {
        if let Ok(float) = text.parse::<f64>() {
            if float.fract() == 0.0 && float.abs() < 1e30 {
                diags.push(
                    Diagnostic::new(
                        &rules::FLOAT_ON_INTEGER,
                        Some(span),
                        format!("float literal `{text}` on a {} value", ty.name()),
                    )
                    .with_help(format!("write `{}`", float as i128)),
                );
                return range_checked(text, float as i128, ty, (min, max), span, diags);
            }
        }
    }
    if text.starts_with('<') && text.ends_with('>') {
        diags.push(
            Diagnostic::new(
                &rules::BAD_VALUE,
                Some(span),
                format!(
                    "`{text}` is a template placeholder, not a {} value",
                    ty.name()
                ),
            )
            .with_label("placeholder")
            .with_help("this file is a template: fill in the placeholders before using it"),
        );
        return None;
    }
    diags.push(
        Diagnostic::new(
            &rules::BAD_VALUE,
            Some(span),
            format!("`{text}` cannot be read as {}", ty.name()),
        )
        .with_label("not an integer")
        .with_help(format!(
            "write a decimal, `0x` hexadecimal or `$NODEID+n` value for {}",
            ty.name()
        )),
    );
    None
}

/// The literal without a C integer suffix (`U`, `L`, `UL`, `LL`, `ULL`, any case) if it has one and
/// the rest is an integer literal.
fn strip_integer_suffix(text: &str) -> Option<&str> {
    let body = text.trim_end_matches(['u', 'U', 'l', 'L']);
    let suffix = text[body.len()..].to_ascii_lowercase();
    let is_c_suffix = ["u", "l", "ul", "lu", "ll", "ull", "llu"].contains(&suffix.as_str());
    (is_c_suffix && parse_integer_with_radix(body).is_some()).then_some(body)
}

/// The literal without a C float suffix (`f`/`F`) if it has one and the rest is a decimal float.
fn strip_float_suffix(text: &str) -> Option<&str> {
    let body = text.strip_suffix(['f', 'F'])?;
    (looks_like_float(body) && body.parse::<f64>().is_ok()).then_some(body)
}

fn push_suffix_warning(
    text: &str,
    stripped: &str,
    ty: BasicType,
    span: Span,
    diags: &mut Vec<Diagnostic>,
) {
    diags.push(
        Diagnostic::new(
            &rules::C_LITERAL_SUFFIX,
            Some(span),
            format!(
                "{} value `{text}` has a C literal suffix; read as `{stripped}`",
                ty.name()
            ),
        )
        .with_help(format!(
            "write `{stripped}`: CiA 306 numbers have no suffix"
        )),
    );
}

fn range_checked(
    text: &str,
    value: i128,
    ty: BasicType,
    (min, max): (i128, i128),
    span: Span,
    diags: &mut Vec<Diagnostic>,
) -> Option<Value> {
    if value >= min && value <= max {
        Some(Value::Integer(value))
    } else {
        diags.push(Diagnostic::new(
            &rules::OUT_OF_RANGE,
            Some(span),
            format!(
                "`{text}` ({value}) is outside the range of {} ({min}..={max})",
                ty.name()
            ),
        ));
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quick_trim_is_str_trim() {
        for text in [
            "", " ", "7", "0x10", " 7", "7 ", "\x0B7", "7\x0B", "\t7\r", "\u{a0}7", "7\u{a0}", "é",
            "\x1F", "a ; b",
        ] {
            assert_eq!(trim(text), text.trim(), "{text:?}");
        }
        assert_eq!(split_inline_comment(" 5 ; five"), ("5", Some("; five")));
        assert_eq!(split_inline_comment("\u{a0}5\u{a0}"), ("5", None));
    }

    fn span() -> Span {
        Span::new(3, 14, 6)
    }

    fn parse(raw: &str, ty: BasicType) -> (Option<Value>, Vec<(&'static str, Severity)>) {
        let mut diags = Vec::new();
        let value = parse_value(raw, Some(ty), span(), &mut diags);
        for d in &diags {
            assert_eq!(d.span, Some(span()));
        }
        (
            value,
            diags.iter().map(|d| (d.code(), d.severity)).collect(),
        )
    }

    #[test]
    fn integer_syntax_of_cia306() {
        assert_eq!(parse_integer("0"), Some(0));
        assert_eq!(parse_integer("42"), Some(42));
        assert_eq!(parse_integer(" 0x1A "), Some(26));
        assert_eq!(parse_integer("0XfF"), Some(255));
        assert_eq!(parse_integer("012"), Some(10));
        assert_eq!(parse_integer("00"), Some(0));
        assert_eq!(parse_integer("-5"), Some(-5));
        assert_eq!(parse_integer("-0x7fff"), Some(-0x7fff));
        assert_eq!(parse_integer("+7"), Some(7));
        assert_eq!(parse_integer("09"), None);
        assert_eq!(parse_integer("0x"), None);
        assert_eq!(parse_integer(""), None);
        assert_eq!(parse_integer("-"), None);
        assert_eq!(parse_integer("1.0"), None);
        assert_eq!(parse_integer("0x1G"), None);
        assert_eq!(
            parse_integer("0xFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF"),
            None
        );
    }

    #[test]
    fn unsigned_values_and_ranges() {
        assert_eq!(
            parse("0x180", BasicType::Unsigned16),
            (Some(Value::Integer(0x180)), vec![])
        );
        assert_eq!(
            parse("0x10000", BasicType::Unsigned16),
            (None, vec![("EDS013", Severity::Error)])
        );
        assert_eq!(
            parse("-1", BasicType::Unsigned8),
            (None, vec![("EDS013", Severity::Error)])
        );
        assert_eq!(
            parse("0xFFFFFFFFFFFFFFFF", BasicType::Unsigned64),
            (Some(Value::Integer(u64::MAX as i128)), vec![])
        );
    }

    #[test]
    fn signed_hex_of_type_width_is_twos_complement() {
        assert_eq!(
            parse("0x80000000", BasicType::Integer32),
            (
                Some(Value::Integer(-0x8000_0000)),
                vec![("EDS014", Severity::Info)]
            )
        );
        assert_eq!(
            parse("0xFF", BasicType::Integer8),
            (Some(Value::Integer(-1)), vec![("EDS014", Severity::Info)])
        );
        assert_eq!(
            parse("0x7F", BasicType::Integer8),
            (Some(Value::Integer(127)), vec![])
        );
        assert_eq!(
            parse("0x100", BasicType::Integer8),
            (None, vec![("EDS013", Severity::Error)])
        );
        assert_eq!(
            parse("4294967295", BasicType::Integer32),
            (None, vec![("EDS013", Severity::Error)])
        );
        assert_eq!(
            parse("-0x80", BasicType::Integer8),
            (Some(Value::Integer(-128)), vec![])
        );
    }

    #[test]
    fn octal_is_reported_only_when_it_changes_the_value() {
        assert_eq!(
            parse("010", BasicType::Unsigned8),
            (Some(Value::Integer(8)), vec![("EDS017", Severity::Info)])
        );
        assert_eq!(
            parse("00", BasicType::Unsigned8),
            (Some(Value::Integer(0)), vec![])
        );
        assert_eq!(
            parse("07", BasicType::Unsigned8),
            (Some(Value::Integer(7)), vec![])
        );
        assert_eq!(
            parse("09", BasicType::Unsigned8),
            (Some(Value::Integer(9)), vec![("EDS017", Severity::Warning)])
        );
    }

    #[test]
    fn nodeid_forms() {
        let ty = BasicType::Unsigned32;
        assert_eq!(
            parse("$NODEID+0x180", ty),
            (Some(Value::NodeRelative(0x180)), vec![])
        );
        assert_eq!(
            parse("$NODEID + 0x180", ty),
            (Some(Value::NodeRelative(0x180)), vec![])
        );
        assert_eq!(parse("$NODEID", ty), (Some(Value::NodeRelative(0)), vec![]));
        assert_eq!(
            parse("$NODEID+0x80+0x100", ty),
            (Some(Value::NodeRelative(0x180)), vec![])
        );
        assert_eq!(
            parse("$NodeID+0x200", ty),
            (
                Some(Value::NodeRelative(0x200)),
                vec![("EDS016", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0x180+$NODEID", ty),
            (
                Some(Value::NodeRelative(0x180)),
                vec![("EDS016", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("$NODEID*2", ty),
            (None, vec![("EDS015", Severity::Error)])
        );
        assert_eq!(
            parse("$NODEID-1", ty),
            (None, vec![("EDS015", Severity::Error)])
        );
        assert_eq!(
            parse("$NODEID+$NODEID", ty),
            (None, vec![("EDS015", Severity::Error)])
        );
        assert_eq!(
            parse("$NODEID+0x180", BasicType::Real32),
            (None, vec![("EDS015", Severity::Error)])
        );
    }

    #[test]
    fn booleans() {
        assert_eq!(
            parse("1", BasicType::Boolean),
            (Some(Value::Integer(1)), vec![])
        );
        assert_eq!(
            parse("TRUE", BasicType::Boolean),
            (Some(Value::Integer(1)), vec![("EDS021", Severity::Warning)])
        );
        assert_eq!(
            parse("2", BasicType::Boolean),
            (None, vec![("EDS013", Severity::Error)])
        );
    }

    #[test]
    fn float_literal_on_integer() {
        assert_eq!(
            parse("0.0", BasicType::Unsigned32),
            (Some(Value::Integer(0)), vec![("EDS020", Severity::Warning)])
        );
        assert_eq!(
            parse("1.5", BasicType::Unsigned32),
            (None, vec![("EDS012", Severity::Error)])
        );
        assert_eq!(
            parse("abc", BasicType::Integer16),
            (None, vec![("EDS012", Severity::Error)])
        );
    }

    #[test]
    fn reals() {
        assert_eq!(
            parse("1.5", BasicType::Real32),
            (Some(Value::Real(1.5)), vec![])
        );
        assert_eq!(
            parse("-2e3", BasicType::Real64),
            (Some(Value::Real(-2000.0)), vec![])
        );
        assert_eq!(
            parse("3", BasicType::Real32),
            (Some(Value::Real(3.0)), vec![])
        );
        assert_eq!(
            parse("0x3F800000", BasicType::Real32),
            (Some(Value::Real(1.0)), vec![("EDS019", Severity::Warning)])
        );
        assert_eq!(
            parse("0x3FF0000000000000", BasicType::Real64),
            (Some(Value::Real(1.0)), vec![("EDS019", Severity::Warning)])
        );
        assert_eq!(
            parse("0x00000000", BasicType::Real32),
            (Some(Value::Real(0.0)), vec![])
        );
        // Fewer digits than the width: a number in hex, not a bit pattern.
        assert_eq!(
            parse("0xFFFF", BasicType::Real32),
            (
                Some(Value::Real(65535.0)),
                vec![("EDS019", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0x3F800000", BasicType::Real64),
            (
                Some(Value::Real(1_065_353_216.0)),
                vec![("EDS019", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0x0", BasicType::Real64),
            (Some(Value::Real(0.0)), vec![])
        );
        assert_eq!(
            parse("nan", BasicType::Real32),
            (None, vec![("EDS012", Severity::Error)])
        );
        assert_eq!(
            parse("1e300", BasicType::Real32),
            (None, vec![("EDS013", Severity::Error)])
        );
    }

    #[test]
    fn strings_keep_quotes() {
        assert_eq!(
            parse("abc; def", BasicType::VisibleString),
            (Some(Value::Text("abc; def".into())), vec![])
        );
        assert_eq!(
            parse("\"abc\"", BasicType::VisibleString),
            (
                Some(Value::Text("\"abc\"".into())),
                vec![("EDS018", Severity::Info)]
            )
        );
    }

    #[test]
    fn octet_strings_and_domains() {
        assert_eq!(
            parse("01a1053C", BasicType::OctetString),
            (Some(Value::Bytes(vec![0x01, 0xa1, 0x05, 0x3c])), vec![])
        );
        assert_eq!(
            parse("01 02 03", BasicType::Domain),
            (Some(Value::Bytes(vec![1, 2, 3])), vec![])
        );
        assert_eq!(
            parse("123", BasicType::OctetString),
            (None, vec![("EDS012", Severity::Error)])
        );
        assert_eq!(
            parse("0x12", BasicType::Domain),
            (
                Some(Value::Bytes(vec![0x12])),
                vec![("EDS026", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0x000400ff", BasicType::OctetString),
            (
                Some(Value::Bytes(vec![0x00, 0x04, 0x00, 0xff])),
                vec![("EDS026", Severity::Warning)]
            )
        );
        // Unicode whitespace between bytes: no slicing inside a character.
        assert_eq!(
            parse("0x001122334455667\u{3000}78899", BasicType::Domain),
            (
                Some(Value::Bytes(vec![
                    0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99
                ])),
                vec![("EDS026", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0x123", BasicType::Domain),
            (None, vec![("EDS012", Severity::Error)])
        );
        assert_eq!(
            parse("0", BasicType::Domain),
            (
                Some(Value::Bytes(vec![])),
                vec![("EDS026", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0", BasicType::OctetString),
            (None, vec![("EDS012", Severity::Error)])
        );
        assert_eq!(
            parse("@ABCD", BasicType::Domain),
            (None, vec![("EDS012", Severity::Error)])
        );
    }

    #[test]
    fn repeated_dialects_fold_into_the_first() {
        let at = |line| Span::new(line, 14, 3);
        let mut diags = Vec::new();
        for line in 1..=11 {
            parse_value(
                "0x80+$NODEID",
                Some(BasicType::Unsigned32),
                at(line),
                &mut diags,
            );
        }
        parse_value("$NodeId+1", Some(BasicType::Unsigned32), at(20), &mut diags);
        parse_value(
            "0x300+$NODEID",
            Some(BasicType::Unsigned32),
            at(21),
            &mut diags,
        );
        parse_value("-1", Some(BasicType::Unsigned8), at(22), &mut diags);
        parse_value("-1", Some(BasicType::Unsigned8), at(23), &mut diags);
        parse_value("1LL", Some(BasicType::Unsigned16), at(24), &mut diags);
        parse_value("2LL", Some(BasicType::Unsigned8), at(25), &mut diags);
        parse_value("3LL", Some(BasicType::Unsigned16), at(26), &mut diags);
        aggregate_dialects(&mut diags);
        let found: Vec<_> = diags
            .iter()
            .map(|d| (d.code(), d.severity, d.span.map_or(0, |s| s.line)))
            .collect();
        assert_eq!(
            found,
            vec![
                ("EDS016", Severity::Warning, 1),
                ("EDS016", Severity::Warning, 20),
                ("EDS013", Severity::Error, 22),
                ("EDS013", Severity::Error, 23),
                ("EDS025", Severity::Warning, 24),
                ("EDS025", Severity::Warning, 25),
            ]
        );
        // UNSIGNED16 and UNSIGNED8 are different kinds.
        assert_eq!(
            diags[4].message,
            "UNSIGNED16 value `1LL` has a C literal suffix; read as `1`; the same on 1 more line(s): 26"
        );
        assert_eq!(
            diags[0].message,
            "`0x80+$NODEID` puts `$NODEID` after the offset; the same on 11 more line(s): \
             2, 3, 4, 5, 6, 7, 8, 9 and 3 more"
        );
        assert_eq!(diags[1].message, "`$NodeId` is not spelled `$NODEID`");
    }

    #[test]
    fn unreadable_integers_say_why() {
        let mut diags = Vec::new();
        parse_value(
            "<!pole_pairs.16.0>",
            Some(BasicType::Unsigned16),
            span(),
            &mut diags,
        );
        parse_value("12abc", Some(BasicType::Unsigned16), span(), &mut diags);
        let messages: Vec<&str> = diags.iter().map(|d| d.message.as_str()).collect();
        assert_eq!(
            messages,
            vec![
                "`<!pole_pairs.16.0>` is a template placeholder, not a UNSIGNED16 value",
                "`12abc` cannot be read as UNSIGNED16",
            ]
        );
        assert_eq!(diags[0].code(), "EDS012");
        assert_eq!(diags[1].severity, Severity::Error);
    }

    #[test]
    fn c_literal_suffixes() {
        assert_eq!(
            parse("0x1234567890ABCDEFLL", BasicType::Integer64),
            (
                Some(Value::Integer(0x1234_5678_90AB_CDEF)),
                vec![("EDS025", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0xFFFFFFFFFFFFFFFFULL", BasicType::Unsigned64),
            (
                Some(Value::Integer(i128::from(u64::MAX))),
                vec![("EDS025", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("10u", BasicType::Unsigned8),
            (
                Some(Value::Integer(10)),
                vec![("EDS025", Severity::Warning)]
            )
        );
        assert_eq!(
            parse("0.0f", BasicType::Real32),
            (Some(Value::Real(0.0)), vec![("EDS025", Severity::Warning)])
        );
        assert_eq!(
            parse("-1.5F", BasicType::Real64),
            (Some(Value::Real(-1.5)), vec![("EDS025", Severity::Warning)])
        );
        // A hex REAL ending in the digit F is a bit pattern, not a suffix.
        assert_eq!(
            parse("0x3F80000F", BasicType::Real32).1,
            vec![("EDS019", Severity::Warning)]
        );
        assert_eq!(
            parse("10LLL", BasicType::Unsigned8),
            (None, vec![("EDS012", Severity::Error)])
        );
        assert_eq!(
            parse("L", BasicType::Unsigned8),
            (None, vec![("EDS012", Severity::Error)])
        );
    }

    #[test]
    fn time_types() {
        assert_eq!(
            parse("0", BasicType::TimeOfDay),
            (Some(Value::Integer(0)), vec![])
        );
        assert_eq!(
            parse("2 1000", BasicType::TimeDifference),
            (Some(Value::Integer(1000 | 2 << 32)), vec![])
        );
        assert_eq!(
            parse("x", BasicType::TimeOfDay),
            (None, vec![("EDS012", Severity::Error)])
        );
    }

    #[test]
    fn empty_is_missing_and_unknown_type_is_best_effort() {
        assert_eq!(parse("  ", BasicType::Unsigned8), (None, vec![]));
        let mut diags = Vec::new();
        assert_eq!(
            parse_value("0x20", None, span(), &mut diags),
            Some(Value::Integer(32))
        );
        assert_eq!(
            parse_value("$NodeId+1", None, span(), &mut diags),
            Some(Value::NodeRelative(1))
        );
        assert_eq!(parse_value("text", None, span(), &mut diags), None);
        assert!(diags.is_empty());
    }

    #[test]
    fn inline_comment_split() {
        assert_eq!(
            split_inline_comment("0x0007 ; Unsigned32"),
            ("0x0007", Some("; Unsigned32"))
        );
        assert_eq!(split_inline_comment(" 5 "), ("5", None));
        assert!(!strips_inline_comment(Some(BasicType::VisibleString)));
        assert!(strips_inline_comment(Some(BasicType::Unsigned8)));
        assert!(!strips_inline_comment(None));
    }
}
