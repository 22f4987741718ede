//! CIP paths (EPATH, CIP Vol. 1 C-1): the hex bytes an ODVA EDS writes for a connection's or a
//! parameter's path, and their segments (port, class, instance, attribute, connection point,
//! data).

/// One segment of a decoded EPATH.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathSegment {
    /// A port segment: port number and link address byte(s) length.
    Port(u16),
    /// Logical class.
    Class(u32),
    /// Logical instance.
    Instance(u32),
    /// Logical member.
    Member(u32),
    /// Logical connection point.
    ConnectionPoint(u32),
    /// Logical attribute.
    Attribute(u32),
    /// An electronic key (vendor, device type, product code, major and minor revision).
    Key,
    /// A data segment of this many bytes.
    Data(usize),
}

/// The bytes of a path written as hex bytes (`20 04 24 97 2C 96 2C 64`); `Err` with the index
/// of the first token that is not a hex byte.
pub fn path_bytes(text: &str) -> Result<Vec<u8>, usize> {
    text.split_whitespace()
        .enumerate()
        .map(|(i, token)| match u8::from_str_radix(token, 16) {
            Ok(b) if token.len() <= 2 => Ok(b),
            _ => Err(i),
        })
        .collect()
}

/// Decodes a path written as hex bytes (`20 04 24 97 2C 96 2C 64`); `Err` with the byte offset
/// where decoding failed (a token that is not a hex byte, a segment type it does not know, or a
/// truncated segment).
pub fn decode_path(text: &str) -> Result<Vec<PathSegment>, usize> {
    let bytes = path_bytes(text)?;
    let mut out = Vec::new();
    let mut at = 0;
    let byte = |i: usize| bytes.get(i).copied().ok_or(i);
    while at < bytes.len() {
        let seg = bytes[at];
        let logical = |kind: u8, value: u32| match kind {
            0 => Some(PathSegment::Class(value)),
            1 => Some(PathSegment::Instance(value)),
            2 => Some(PathSegment::Member(value)),
            3 => Some(PathSegment::ConnectionPoint(value)),
            4 => Some(PathSegment::Attribute(value)),
            _ => None,
        };
        match seg >> 5 {
            0 => {
                // Port segment: bit 4 extended link address, bits 0-3 port.
                let port = u16::from(seg & 0x0F);
                if seg & 0x10 != 0 {
                    let len = usize::from(byte(at + 1)?);
                    at += 2 + len + (len % 2);
                } else {
                    at += 2;
                }
                out.push(PathSegment::Port(port));
            }
            1 => {
                let kind = (seg >> 2) & 7;
                let (value, len) = match seg & 3 {
                    0 => (u32::from(byte(at + 1)?), 2),
                    // Padded (a zero pad byte, then the value) as EDS files should write
                    // it; a non-zero byte after the segment type is the packed form.
                    1 if byte(at + 1)? == 0 => (
                        u32::from(u16::from_le_bytes([byte(at + 2)?, byte(at + 3)?])),
                        4,
                    ),
                    1 => (
                        u32::from(u16::from_le_bytes([byte(at + 1)?, byte(at + 2)?])),
                        3,
                    ),
                    2 => (
                        u32::from_le_bytes([
                            byte(at + 2)?,
                            byte(at + 3)?,
                            byte(at + 4)?,
                            byte(at + 5)?,
                        ]),
                        6,
                    ),
                    _ => return Err(at),
                };
                if seg == 0x34 {
                    // Electronic key: format 4, ten bytes in all.
                    byte(at + 9)?;
                    out.push(PathSegment::Key);
                    at += 10;
                    continue;
                }
                out.push(logical(kind, value).ok_or(at)?);
                at += len;
            }
            4 if seg == 0x80 => {
                let words = usize::from(byte(at + 1)?);
                if at + 2 + 2 * words > bytes.len() {
                    return Err(at);
                }
                out.push(PathSegment::Data(2 * words));
                at += 2 + 2 * words;
            }
            _ => return Err(at),
        }
    }
    if at > bytes.len() {
        return Err(bytes.len());
    }
    Ok(out)
}
