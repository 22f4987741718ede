//! Padded EPATHs: the logical segments (class, instance, attribute, connection point; 8, 16 or
//! 32 bits) a request or connection path names, with port, electronic key and simple data
//! segments skipped.

use super::{u16_at, u32_at, Emit, Error, Writer};

/// The most connection points a [`Path`] holds (a connection path names two).
pub const MAX_POINTS: usize = 4;

/// A path's logical class, instance, attribute and connection points.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Path {
    /// Class.
    pub class: Option<u32>,
    /// Instance.
    pub instance: Option<u32>,
    /// Attribute.
    pub attribute: Option<u32>,
    points: [u32; MAX_POINTS],
    point_count: u8,
}

impl Path {
    /// The path in `bytes`: [`Error::Truncated`] for a segment cut short, [`Error::Malformed`]
    /// for a segment type other than port, logical, key or simple data, a reserved logical
    /// type or format, or more than [`MAX_POINTS`] connection points.
    pub fn parse(bytes: &[u8]) -> Result<Path, Error> {
        let mut path = Path::default();
        let mut at = 0;
        while let Some(&seg) = bytes.get(at) {
            let len = match seg >> 5 {
                // Port segment: the port in the low four bits, a link address of one byte, or
                // with bit 4 a length and that many bytes, padded.
                0 if seg & 0x10 != 0 => {
                    let n = usize::from(*bytes.get(at + 1).ok_or(Error::Truncated)?);
                    2 + n + n % 2
                }
                0 => 2,
                // Electronic key: format 4, ten bytes.
                1 if seg == 0x34 => 10,
                1 => {
                    let (value, len) = match seg & 3 {
                        0 => (bytes.get(at + 1).map(|v| u32::from(*v)), 2),
                        1 => (u16_at(bytes, at + 2).map(u32::from), 4),
                        2 => (u32_at(bytes, at + 2), 6),
                        _ => return Err(Error::Malformed),
                    };
                    let value = value.ok_or(Error::Truncated)?;
                    match (seg >> 2) & 7 {
                        0 => path.class = Some(value),
                        1 => path.instance = Some(value),
                        3 => path.push_point(value)?,
                        4 => path.attribute = Some(value),
                        _ => return Err(Error::Malformed),
                    }
                    len
                }
                // Simple data segment: a word count, that many words.
                4 if seg == 0x80 => {
                    2 + 2 * usize::from(*bytes.get(at + 1).ok_or(Error::Truncated)?)
                }
                _ => return Err(Error::Malformed),
            };
            if bytes.len() < at + len {
                return Err(Error::Truncated);
            }
            at += len;
        }
        Ok(path)
    }

    fn push_point(&mut self, point: u32) -> Result<(), Error> {
        let slot = self
            .points
            .get_mut(usize::from(self.point_count))
            .ok_or(Error::Malformed)?;
        *slot = point;
        self.point_count += 1;
        Ok(())
    }

    /// The connection points, in order.
    pub fn points(&self) -> &[u32] {
        &self.points[..usize::from(self.point_count)]
    }
}

/// Logical segment types.
mod logical {
    pub const CLASS: u8 = 0x20;
    pub const INSTANCE: u8 = 0x24;
    pub const ATTRIBUTE: u8 = 0x30;
}

/// A request path to write: class, instance and an optional attribute, each in the shortest
/// logical format its value fits (8 bits, 16 or 32, padded).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogicalPath {
    /// Class.
    pub class: u32,
    /// Instance.
    pub instance: u32,
    /// Attribute.
    pub attribute: Option<u32>,
}

impl LogicalPath {
    /// The Connection Manager (class 6, instance 1).
    pub const CONNECTION_MANAGER: LogicalPath = LogicalPath {
        class: 6,
        instance: 1,
        attribute: None,
    };

    /// The Message Router (class 2, instance 1): class-3 connections' target.
    pub const MESSAGE_ROUTER: LogicalPath = LogicalPath {
        class: 2,
        instance: 1,
        attribute: None,
    };

    /// An assembly's data (class 4, attribute 3).
    pub const fn assembly_data(instance: u32) -> LogicalPath {
        LogicalPath {
            class: 4,
            instance,
            attribute: Some(3),
        }
    }

    fn segments(&self) -> impl Iterator<Item = (u8, u32)> {
        [
            Some((logical::CLASS, self.class)),
            Some((logical::INSTANCE, self.instance)),
            self.attribute.map(|a| (logical::ATTRIBUTE, a)),
        ]
        .into_iter()
        .flatten()
    }
}

fn segment_len(value: u32) -> usize {
    match value {
        0..=0xFF => 2,
        0x100..=0xFFFF => 4,
        _ => 6,
    }
}

impl Emit for LogicalPath {
    fn buffer_len(&self) -> usize {
        self.segments().map(|(_, v)| segment_len(v)).sum()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let mut w = Writer::new(buf);
        for (kind, value) in self.segments() {
            match (u8::try_from(value), u16::try_from(value)) {
                (Ok(v), _) => w.bytes(&[kind, v])?,
                (_, Ok(v)) => {
                    w.bytes(&[kind | 1, 0])?;
                    w.u16(v)?;
                }
                _ => {
                    w.bytes(&[kind | 2, 0])?;
                    w.u32(value)?;
                }
            }
        }
        Ok(w.done())
    }
}
