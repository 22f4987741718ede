//! A process image and the dictionary entries it maps: packing the mapped objects' values into
//! the image bytes (LSB first) and unpacking image bytes into them, for a SubDevice's inputs and
//! outputs and for a card's drive behind them. The entries are [`place`]d in the dictionary
//! once, when the mapping is laid out, so that a cycle neither searches nor allocates.

use super::device::Mapped;
use crate::canopen::RuntimeDictionary;
use edsgen_runtime::ObjectDictionary;

/// One mapped entry as a cycle reaches it: where the dictionary keeps its value (`None` for
/// padding, or an object the dictionary does not have: its bits are zeros) and its bit length.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Placed {
    position: Option<usize>,
    bits: usize,
}

/// `entries` as they are found in `od`.
pub fn place(od: &RuntimeDictionary, entries: &[Mapped]) -> Vec<Placed> {
    entries
        .iter()
        .map(|&(index, sub, bits)| Placed {
            position: (index != 0).then(|| od.locate(index, sub).ok()).flatten(),
            bits: usize::from(bits),
        })
        .collect()
}

/// The image's length in bytes.
pub fn image_len(entries: &[Placed]) -> usize {
    entries.iter().map(|e| e.bits).sum::<usize>().div_ceil(8)
}

/// Writes the image of `entries` from the dictionary into `image`, bit by bit (LSB first); the
/// bits past its end are left out, the bytes past the entries are zeros.
pub fn pack(od: &RuntimeDictionary, entries: &[Placed], image: &mut [u8]) {
    image.fill(0);
    let mut at = 0;
    for entry in entries {
        let (len, Some(position)) = (entry.bits, entry.position) else {
            at += entry.bits;
            continue;
        };
        let whole = (at % 8 == 0 && len % 8 == 0)
            .then(|| image.get_mut(at / 8..(at + len) / 8))
            .flatten();
        match whole {
            // Whole bytes at a byte boundary, as most mapped entries are.
            Some(bytes) => {
                let _ = od.read_at(position, 0, bytes);
            }
            None => {
                let mut value = EntryBytes::new(len);
                let _ = od.read_at(position, 0, value.bytes_mut());
                let value = value.bytes();
                for bit in 0..len {
                    let target = at + bit;
                    if value[bit / 8] >> (bit % 8) & 1 != 0 {
                        if let Some(byte) = image.get_mut(target / 8) {
                            *byte |= 1 << (target % 8);
                        }
                    }
                }
            }
        }
        at += len;
    }
}

/// Writes `image` into the dictionary's entries as `entries` lay it out (a value the
/// dictionary refuses is left as it was; bits past the image's end are zeros).
pub fn unpack(od: &mut RuntimeDictionary, entries: &[Placed], image: &[u8]) {
    let mut at = 0;
    for entry in entries {
        let (len, Some(position)) = (entry.bits, entry.position) else {
            at += entry.bits;
            continue;
        };
        let whole = (at % 8 == 0 && len % 8 == 0)
            .then(|| image.get(at / 8..(at + len) / 8))
            .flatten();
        match whole {
            Some(bytes) => {
                let _ = od.write_at(position, bytes);
            }
            None => {
                let mut value = EntryBytes::new(len);
                let bytes = value.bytes_mut();
                for bit in 0..len {
                    let source = at + bit;
                    if image
                        .get(source / 8)
                        .is_some_and(|b| b >> (source % 8) & 1 != 0)
                    {
                        bytes[bit / 8] |= 1 << (bit % 8);
                    }
                }
                let _ = od.write_at(position, value.bytes());
            }
        }
        at += len;
    }
}

/// One mapped entry's value, zeroed: on the stack up to 8 bytes (every scalar), else on the
/// heap (a string or domain mapped whole at an odd bit).
enum EntryBytes {
    Small([u8; 8], usize),
    Large(Vec<u8>),
}

impl EntryBytes {
    fn new(bits: usize) -> Self {
        let len = bits.div_ceil(8);
        if len <= 8 {
            EntryBytes::Small([0; 8], len)
        } else {
            EntryBytes::Large(vec![0; len])
        }
    }

    fn bytes(&self) -> &[u8] {
        match self {
            EntryBytes::Small(bytes, len) => &bytes[..*len],
            EntryBytes::Large(bytes) => bytes,
        }
    }

    fn bytes_mut(&mut self) -> &mut [u8] {
        match self {
            EntryBytes::Small(bytes, len) => &mut bytes[..*len],
            EntryBytes::Large(bytes) => bytes,
        }
    }
}
