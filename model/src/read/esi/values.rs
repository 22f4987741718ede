//! ESI value texts: `#x` hex and decimal numbers, hex byte strings, booleans, and `DefaultData`
//! bytes as typed values.

use crate::model::{BasicType, Value};

/// The hex digits of `#x1A00` or `0x1A00`.
pub(crate) fn hex_digits(text: &str) -> Option<&str> {
    ["#x", "#X", "0x", "0X"]
        .iter()
        .find_map(|p| text.strip_prefix(p))
}

/// An ESI number: `#x` (or `0x`) hex, else decimal, optionally negative.
pub fn parse_number(text: &str) -> Option<i128> {
    let t = text.trim();
    let (negative, t) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t),
    };
    let value = match hex_digits(t) {
        Some(hex) if !hex.is_empty() => i128::from_str_radix(hex, 16).ok()?,
        Some(_) => return None,
        None if !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) => t.parse().ok()?,
        None => return None,
    };
    Some(if negative { -value } else { value })
}

/// Hex bytes as `DefaultData` and `InitCmd/Data` write them (`6C020000`), in written order.
pub(super) fn parse_hex_bytes(text: &str) -> Option<Vec<u8>> {
    let t: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if !t.len().is_multiple_of(2) || !t.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    (0..t.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&t[i..i + 2], 16).ok())
        .collect()
}

/// `1`/`true` and `0`/`false`.
pub(super) fn parse_bool(text: &str) -> Option<bool> {
    crate::read::xml::parse_xml_bool(&text.trim().to_ascii_lowercase())
}

/// `DefaultData` bytes (little-endian) as a value of `basic`; `None` when the byte count does not
/// fit the type.
pub(super) fn data_value(bytes: &[u8], basic: BasicType) -> Option<Value> {
    match basic {
        BasicType::VisibleString | BasicType::UnicodeString => {
            let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
            Some(Value::Text(
                bytes[..end].iter().map(|&b| char::from(b)).collect(),
            ))
        }
        BasicType::OctetString | BasicType::Domain => Some(Value::Bytes(bytes.to_vec())),
        BasicType::Real32 => {
            let raw: [u8; 4] = bytes.try_into().ok()?;
            Some(Value::Real(f64::from(f32::from_le_bytes(raw))))
        }
        BasicType::Real64 => {
            let raw: [u8; 8] = bytes.try_into().ok()?;
            Some(Value::Real(f64::from_le_bytes(raw)))
        }
        _ => {
            let bits = basic.bits()?;
            let width = usize::try_from(bits.div_ceil(8)).ok()?;
            if bytes.is_empty() || bytes.len() > width {
                return None;
            }
            let mut value: i128 = 0;
            for (i, b) in bytes.iter().enumerate() {
                value |= i128::from(*b) << (8 * i);
            }
            if basic.is_signed_integer() && bytes.len() == width && value >> (bits - 1) & 1 == 1 {
                value -= 1i128 << bits;
            }
            let (low, high) = basic.integer_range()?;
            (low..=high)
                .contains(&value)
                .then_some(Value::Integer(value))
        }
    }
}

/// A `#xFFFD` written for a signed type: the two's-complement value (-3 for an INT), as the
/// type's bit pattern means; other values unchanged.
pub(super) fn twos_complement(value: i128, basic: BasicType) -> i128 {
    match (basic.integer_range(), basic.bits()) {
        (Some((_, high)), Some(bits)) if basic.is_signed_integer() && value > high => {
            if value < 1i128 << bits {
                value - (1i128 << bits)
            } else {
                value
            }
        }
        _ => value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_hex_with_a_hash_x_or_decimal() {
        assert_eq!(parse_number("#x1A00"), Some(0x1A00));
        assert_eq!(parse_number(" 0x0F3F "), Some(0xF3F));
        assert_eq!(parse_number("560"), Some(560));
        assert_eq!(parse_number("-5"), Some(-5));
        assert_eq!(parse_number("#x"), None);
        assert_eq!(parse_number("1A"), None);
    }

    #[test]
    fn default_data_is_little_endian() {
        assert_eq!(
            data_value(&[0x6C, 0x02, 0, 0], BasicType::Unsigned32),
            Some(Value::Integer(0x26C))
        );
        assert_eq!(
            data_value(&[0xFF, 0xFF], BasicType::Integer16),
            Some(Value::Integer(-1))
        );
        assert_eq!(data_value(&[1, 2, 3], BasicType::Unsigned16), None);
        assert_eq!(twos_complement(0xFFFD, BasicType::Integer16), -3);
        assert_eq!(twos_complement(0xFFFD, BasicType::Unsigned16), 0xFFFD);
        assert_eq!(
            data_value(b"EL1004\0", BasicType::VisibleString),
            Some(Value::Text("EL1004".to_owned()))
        );
    }
}
