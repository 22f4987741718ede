//! A process image and the dictionary entries it maps: packing the mapped objects' values into
//! the image bytes (LSB first) and unpacking image bytes into them, for a SubDevice's inputs and
//! outputs and for a card's drive behind them.

use super::device::Mapped;
use crate::canopen::RuntimeDictionary;
use edsgen_runtime::ObjectDictionary;

/// The image of `entries` from the dictionary, bit by bit (LSB first).
pub fn pack(od: &RuntimeDictionary, entries: &[Mapped]) -> Vec<u8> {
    let bits: usize = entries.iter().map(|e| usize::from(e.2)).sum();
    let mut image = vec![0u8; bits.div_ceil(8)];
    let mut at = 0;
    for &(index, sub, len) in entries {
        let len = usize::from(len);
        let mut value = EntryBytes::new(len);
        if index != 0 {
            let _ = od.read(index, sub, 0, value.bytes_mut());
        }
        let value = value.bytes();
        if at % 8 == 0 && len % 8 == 0 {
            // Whole bytes at a byte boundary, as most mapped entries are.
            image[at / 8..(at + len) / 8].copy_from_slice(value);
        } else {
            for bit in 0..len {
                if value[bit / 8] >> (bit % 8) & 1 != 0 {
                    image[(at + bit) / 8] |= 1 << ((at + bit) % 8);
                }
            }
        }
        at += len;
    }
    image
}

/// Writes `image` into the dictionary's entries as `entries` lay it out (a value the
/// dictionary refuses is left as it was).
pub fn unpack(od: &mut RuntimeDictionary, entries: &[Mapped], image: &[u8]) {
    let mut at = 0;
    for &(index, sub, len) in entries {
        let len = usize::from(len);
        let mut value = EntryBytes::new(len);
        let whole = (at % 8 == 0 && len % 8 == 0)
            .then(|| image.get(at / 8..(at + len) / 8))
            .flatten();
        match whole {
            Some(bytes) => value.bytes_mut().copy_from_slice(bytes),
            None => {
                let value = value.bytes_mut();
                for bit in 0..len {
                    let source = at + bit;
                    if image
                        .get(source / 8)
                        .is_some_and(|b| b >> (source % 8) & 1 != 0)
                    {
                        value[bit / 8] |= 1 << (bit % 8);
                    }
                }
            }
        }
        if index != 0 {
            let _ = od.write(index, sub, value.bytes());
        }
        at += len;
    }
}

/// One mapped entry's value, zeroed: on the stack up to 8 bytes (every scalar), else on the
/// heap (a string or domain mapped whole).
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
