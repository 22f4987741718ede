//! Values as the bench commands show and take them: the kind of an entry (from its EDS data type
//! or a `--type` name as CiA 309-3 spells them), its bytes shown as text, and text made bytes.

use edsgen_model::model::{BasicType, Value};

/// How a value's bytes read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// BOOLEAN.
    Boolean,
    /// An unsigned integer of this many bytes.
    Unsigned(usize),
    /// A signed integer of this many bytes.
    Signed(usize),
    /// REAL32.
    Real32,
    /// REAL64.
    Real64,
    /// VISIBLE_STRING: text.
    Text,
    /// OCTET_STRING, DOMAIN and anything else: bytes.
    Bytes,
}

impl Kind {
    /// The kind of an EDS basic type.
    pub fn of(basic: BasicType) -> Kind {
        let bytes = basic.bits().map_or(0, |b| b.div_ceil(8) as usize);
        match basic {
            BasicType::Boolean => Kind::Boolean,
            BasicType::Real32 => Kind::Real32,
            BasicType::Real64 => Kind::Real64,
            BasicType::VisibleString | BasicType::UnicodeString => Kind::Text,
            _ if basic.is_signed_integer() => Kind::Signed(bytes),
            _ if basic.is_unsigned_integer() => Kind::Unsigned(bytes),
            _ => Kind::Bytes,
        }
    }

    /// The kind named by `--type`: `u8`..`u64`, `i8`..`i64`, `r32`, `r64`, `b`, `vs`, `os`, `d`.
    pub fn parse(name: &str) -> Option<Kind> {
        let width = |bits: &str| match bits.parse::<usize>() {
            Ok(b @ (8 | 16 | 24 | 32 | 40 | 48 | 56 | 64)) => Some(b / 8),
            _ => None,
        };
        Some(match name {
            "b" | "bool" => Kind::Boolean,
            "r32" | "f32" => Kind::Real32,
            "r64" | "f64" => Kind::Real64,
            "vs" | "string" => Kind::Text,
            "os" | "d" | "bytes" => Kind::Bytes,
            _ => match name.split_at_checked(1)? {
                ("u", bits) => Kind::Unsigned(width(bits)?),
                ("i", bits) => Kind::Signed(width(bits)?),
                _ => return None,
            },
        })
    }

    /// The fixed length of the value in bytes, if it has one.
    pub fn len(self) -> Option<usize> {
        match self {
            Kind::Boolean => Some(1),
            Kind::Unsigned(n) | Kind::Signed(n) => Some(n),
            Kind::Real32 => Some(4),
            Kind::Real64 => Some(8),
            Kind::Text | Kind::Bytes => None,
        }
    }

    /// The value's bytes as text: integers in decimal with their hex, strings as text, bytes in
    /// hex. A length the kind does not allow is an error.
    pub fn show(self, bytes: &[u8]) -> Result<String, String> {
        if let Some(len) = self.len() {
            if bytes.len() != len {
                return Err(format!(
                    "{} bytes received where the data type has {len}",
                    bytes.len()
                ));
            }
        }
        let mut wide = [0u8; 8];
        wide[..bytes.len().min(8)].copy_from_slice(&bytes[..bytes.len().min(8)]);
        let raw = u64::from_le_bytes(wide);
        Ok(match self {
            Kind::Boolean => match raw {
                0 => "false".into(),
                1 => "true".into(),
                other => format!("{other} (not a BOOLEAN)"),
            },
            Kind::Unsigned(n) => format!("{raw} (0x{raw:0width$X})", width = 2 * n),
            Kind::Signed(n) => {
                let shift = 64 - 8 * n as u32;
                let value = ((raw << shift) as i64) >> shift;
                format!("{value} (0x{raw:0width$X})", width = 2 * n)
            }
            Kind::Real32 => format!("{}", f32::from_bits(raw as u32)),
            Kind::Real64 => format!("{}", f64::from_bits(raw)),
            Kind::Text => String::from_utf8_lossy(bytes).into_owned(),
            Kind::Bytes => hex(bytes),
        })
    }

    /// The bytes of `text` as a value of this kind.
    pub fn encode(self, text: &str) -> Result<Vec<u8>, String> {
        let bad = || format!("`{text}` is not a value of type {}", self.name());
        match self {
            Kind::Boolean => match text {
                "true" | "1" => Ok(vec![1]),
                "false" | "0" => Ok(vec![0]),
                _ => Err(bad()),
            },
            Kind::Unsigned(n) => {
                let value = parse_int(text).ok_or_else(bad)?;
                let fits = value >= 0 && (n == 8 || value < 1i128 << (8 * n));
                if !fits || value > i128::from(u64::MAX) {
                    return Err(format!("{text} does not fit {}", self.name()));
                }
                Ok((value as u64).to_le_bytes()[..n].to_vec())
            }
            Kind::Signed(n) => {
                let value = parse_int(text).ok_or_else(bad)?;
                let bound = 1i128 << (8 * n - 1);
                if !(-bound..bound).contains(&value) {
                    return Err(format!("{text} does not fit {}", self.name()));
                }
                Ok((value as i64).to_le_bytes()[..n].to_vec())
            }
            Kind::Real32 => Ok(text
                .parse::<f32>()
                .map_err(|_| bad())?
                .to_le_bytes()
                .to_vec()),
            Kind::Real64 => Ok(text
                .parse::<f64>()
                .map_err(|_| bad())?
                .to_le_bytes()
                .to_vec()),
            Kind::Text => Ok(text.as_bytes().to_vec()),
            Kind::Bytes => parse_hex(text).ok_or_else(bad),
        }
    }

    /// The kind as `--type` names it.
    pub fn name(self) -> String {
        match self {
            Kind::Boolean => "b".into(),
            Kind::Unsigned(n) => format!("u{}", 8 * n),
            Kind::Signed(n) => format!("i{}", 8 * n),
            Kind::Real32 => "r32".into(),
            Kind::Real64 => "r64".into(),
            Kind::Text => "vs".into(),
            Kind::Bytes => "os".into(),
        }
    }
}

/// The wire bytes of a description's value for an entry of `kind` on node `node_id`
/// (`$NODEID` values resolved); `None` for a value that does not fit the kind.
pub fn value_bytes(kind: Kind, value: &Value, node_id: u8) -> Option<Vec<u8>> {
    let integer = |v: i128| {
        let len = kind.len()?;
        let bytes = (v as u64).to_le_bytes();
        Some(bytes.get(..len)?.to_vec())
    };
    match (kind, value) {
        (Kind::Real32, Value::Real(v)) => Some((*v as f32).to_le_bytes().to_vec()),
        (Kind::Real64, Value::Real(v)) => Some(v.to_le_bytes().to_vec()),
        (_, Value::Integer(v)) => integer(*v),
        (_, Value::NodeRelative(offset)) => integer(i128::from(*offset) + i128::from(node_id)),
        (_, Value::Text(text)) => Some(text.trim_matches('"').as_bytes().to_vec()),
        (_, Value::Bytes(bytes)) => Some(bytes.clone()),
        _ => None,
    }
}

/// Bytes as `01 02 FF`.
pub fn hex(bytes: &[u8]) -> String {
    let parts: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
    parts.join(" ")
}

/// A decimal or `0x` hex integer, with an optional minus sign.
pub fn parse_int(text: &str) -> Option<i128> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    let magnitude = match digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        Some(hex) => i128::from_str_radix(hex, 16).ok()?,
        None => digits.parse::<i128>().ok()?,
    };
    Some(if negative { -magnitude } else { magnitude })
}

/// `01 02 ff`, `0102ff` or `0x0102ff`.
fn parse_hex(text: &str) -> Option<Vec<u8>> {
    let digits: String = text
        .strip_prefix("0x")
        .unwrap_or(text)
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    if !digits.len().is_multiple_of(2) {
        return None;
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(digits.get(i..i + 2)?, 16).ok())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_show_and_encode_by_kind() {
        assert_eq!(
            Kind::Unsigned(2).show(&[0x37, 0x02]).unwrap(),
            "567 (0x0237)"
        );
        assert_eq!(
            Kind::Signed(2).show(&[0x18, 0xFC]).unwrap(),
            "-1000 (0xFC18)"
        );
        assert_eq!(Kind::Text.show(b"CP301").unwrap(), "CP301");
        assert!(Kind::Unsigned(2).show(&[1]).is_err());
        assert_eq!(Kind::Signed(2).encode("-1000").unwrap(), [0x18, 0xFC]);
        assert_eq!(Kind::Unsigned(4).encode("0x191").unwrap(), [0x91, 1, 0, 0]);
        assert!(Kind::Unsigned(1).encode("256").is_err());
        assert!(Kind::Signed(1).encode("-129").is_err());
        assert_eq!(Kind::Bytes.encode("01 02 ff").unwrap(), [1, 2, 0xFF]);
        assert_eq!(Kind::parse("u24"), Some(Kind::Unsigned(3)));
        assert_eq!(Kind::parse("i64"), Some(Kind::Signed(8)));
        assert_eq!(Kind::parse("u12"), None);
    }
}
