//! The values of GSD keywords: numbers (decimal or `0x` hex), byte lists, quoted strings,
//! ranges, parameter type lines and slot lines.

use crate::model::{PrmType, PrmValues};

/// `Key = value` split at the first `=` outside quotes; a line without one is all key.
pub fn split_key(text: &str) -> (&str, Option<&str>) {
    let mut quoted = false;
    for (i, c) in text.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '=' if !quoted => return (text[..i].trim(), Some(text[i + 1..].trim())),
            _ => {}
        }
    }
    (text.trim(), None)
}

/// A number: decimal (with a sign) or `0x` hexadecimal.
pub fn number(text: &str) -> Option<i64> {
    let text = text.trim();
    if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        return i64::from_str_radix(hex, 16).ok();
    }
    text.parse().ok()
}

/// Numbers separated by commas or whitespace.
pub fn numbers(text: &str) -> Option<Vec<i64>> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(number)
        .collect()
}

/// The text of a leading `"quoted"` string, and what follows it.
fn quoted_rest(text: &str) -> Option<(String, &str)> {
    let rest = text.trim_start().strip_prefix('"')?;
    let end = rest.find('"')?;
    Some((rest[..end].to_owned(), &rest[end + 1..]))
}

/// A `"quoted"` string's text (what follows is ignored).
pub fn quoted(text: &str) -> Option<String> {
    quoted_rest(text).map(|(s, _)| s)
}

/// `"name" bytes`: a module header.
pub fn module_header(text: &str) -> Option<(String, Vec<u8>)> {
    let (name, rest) = quoted_rest(text)?;
    let bytes = numbers(rest)?
        .into_iter()
        .map(|n| u8::try_from(n).ok())
        .collect::<Option<Vec<u8>>>()?;
    Some((name, bytes))
}

/// `reference "name"`.
pub fn number_and_name(text: &str) -> Option<(u32, String)> {
    let at = text.find('"')?;
    let reference = u32::try_from(number(&text[..at])?).ok()?;
    Some((reference, quoted(&text[at..])?))
}

/// `first-last` of non-negative numbers.
pub fn range(text: &str) -> Option<(u32, u32)> {
    let (a, b) = text.split_once('-')?;
    Some((
        u32::try_from(number(a)?).ok()?,
        u32::try_from(number(b)?).ok()?,
    ))
}

/// `min-max` (signed numbers allowed: `-100-100`) or `a,b,c`.
fn allowed(text: &str) -> Option<PrmValues> {
    let text = text.trim();
    if text.is_empty() {
        return Some(PrmValues::Any);
    }
    let dash = text
        .char_indices()
        .skip(1)
        .find(|&(i, c)| c == '-' && !text[..i].ends_with(['-', ',']));
    if let Some((i, _)) = dash {
        if !text.contains(',') {
            return Some(PrmValues::Range(
                number(&text[..i])?,
                number(&text[i + 1..])?,
            ));
        }
    }
    numbers(text).map(PrmValues::List)
}

/// A parameter type line: `Bit(2) 0 0-1`, `BitArea(0-3) 1 0-15`, `Unsigned8 1 1-255`,
/// `Signed16 0 -100-100`, `Unsigned8 0 0,1,2`, `Unsigned16 5`.
pub fn prm_type_line(text: &str) -> Option<(PrmType, i64, PrmValues)> {
    let (type_text, rest) = match text.find(')') {
        Some(close) if text[..close].contains('(') => (&text[..=close], &text[close + 1..]),
        _ => text.split_once(char::is_whitespace).unwrap_or((text, "")),
    };
    let lower = type_text.to_ascii_lowercase().replace(' ', "");
    let data_type = if let Some(arg) = lower.strip_prefix("bitarea(") {
        let (a, b) = range(arg.strip_suffix(')')?)?;
        PrmType::BitArea(u8::try_from(a).ok()?, u8::try_from(b).ok()?)
    } else if let Some(arg) = lower.strip_prefix("bit(") {
        PrmType::Bit(u8::try_from(number(arg.strip_suffix(')')?)?).ok()?)
    } else {
        match lower.as_str() {
            "unsigned8" => PrmType::Unsigned(1),
            "unsigned16" => PrmType::Unsigned(2),
            "unsigned32" => PrmType::Unsigned(4),
            "signed8" => PrmType::Signed(1),
            "signed16" => PrmType::Signed(2),
            "signed32" => PrmType::Signed(4),
            _ => return None,
        }
    };
    if let PrmType::Bit(b) | PrmType::BitArea(_, b) = data_type {
        if b > 7 {
            return None;
        }
    }
    let rest = rest.trim();
    let (default, values) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
    Some((data_type, number(default)?, allowed(values)?))
}

/// `"name" default allowed` of a `Slot(n)` line; allowed is `a-b` or `a,b,c` or one number.
pub fn slot_value(text: &str) -> Option<(String, u32, Vec<u32>)> {
    let (name, rest) = quoted_rest(text)?;
    let rest = rest.trim();
    let (default, allowed_text) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
    let default = u32::try_from(number(default)?).ok()?;
    let allowed_text = allowed_text.replace(' ', "");
    let allowed = if allowed_text.is_empty() {
        vec![default]
    } else if let (Some((a, b)), false) = (range(&allowed_text), allowed_text.contains(',')) {
        if b < a || b - a > 4096 {
            return None;
        }
        (a..=b).collect()
    } else {
        numbers(&allowed_text)?
            .into_iter()
            .map(|n| u32::try_from(n).ok())
            .collect::<Option<Vec<u32>>>()?
    };
    Some((name, default, allowed))
}

/// `name(arg)` (lowercase key) → `arg`.
pub(super) fn call_arg<'a>(lower: &'a str, name: &str) -> Option<&'a str> {
    let rest = lower.strip_prefix(name)?.trim_start();
    rest.strip_prefix('(')?.strip_suffix(')').map(str::trim)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values() {
        assert_eq!(split_key("A = \"x=y\""), ("A", Some("\"x=y\"")));
        assert_eq!(split_key("EndModule"), ("EndModule", None));
        assert_eq!(number("0x4224"), Some(0x4224));
        assert_eq!(number("-5"), Some(-5));
        assert_eq!(numbers("0x00,0x01, 2 3"), Some(vec![0, 1, 2, 3]));
        assert_eq!(
            module_header("\"PPO 1\" 0xF3, 0xF1"),
            Some(("PPO 1".to_owned(), vec![0xF3, 0xF1]))
        );
        assert_eq!(number_and_name("1 \"a b\""), Some((1, "a b".to_owned())));
        assert_eq!(
            prm_type_line("Bit(2) 0 0-1"),
            Some((PrmType::Bit(2), 0, PrmValues::Range(0, 1)))
        );
        assert_eq!(
            prm_type_line("BitArea(0-3) 1 0-15"),
            Some((PrmType::BitArea(0, 3), 1, PrmValues::Range(0, 15)))
        );
        assert_eq!(
            prm_type_line("Signed16 0 -100-100"),
            Some((PrmType::Signed(2), 0, PrmValues::Range(-100, 100)))
        );
        assert_eq!(
            prm_type_line("Unsigned8 0 0,1,2"),
            Some((PrmType::Unsigned(1), 0, PrmValues::List(vec![0, 1, 2])))
        );
        assert_eq!(
            prm_type_line("Unsigned16 5"),
            Some((PrmType::Unsigned(2), 5, PrmValues::Any))
        );
        assert_eq!(prm_type_line("Bit(9) 0 0-1"), None);
        assert_eq!(prm_type_line("Float 0"), None);
        assert_eq!(
            slot_value("\"Slot 1\" 2 1-3"),
            Some(("Slot 1".to_owned(), 2, vec![1, 2, 3]))
        );
    }
}
