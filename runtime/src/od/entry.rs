//! Typed entry addresses: `Entry<u16>` names (index, sub) and the Rust type of its value.
//!
//! Generated code declares one constant per entry (`pub const CONTROLWORD: Entry<u16> = ...`), so a
//! master's typed read returns the right type and a mistyped write does not compile. The same
//! constants are the device application's keys into its own generated `Od` (`od.get(CONTROLWORD)`),
//! which is why a generated constant also records where the entry sits in that dictionary, and
//! carries that dictionary's type as its brand (`Entry<u16, Od>`): the `Od` reads a branded
//! address without a check that could fail. An address built by hand (`Entry::new`) names no
//! dictionary ([`AnyDictionary`]), and reading it takes the checked path.
//!
//! A third type parameter carries the entry's access rights as a zero-sized marker
//! (`Entry<u16, Od, ReadOnly>`, see [`access`]): a master's typed write of a read-only or
//! constant entry, or typed read of a write-only one, does not compile either.
//!
//! [`access`]: crate::od::access

use core::marker::PhantomData;

use crate::od::access::{Const, ReadOnly, ReadWrite, WriteOnly};

/// The brand of an address that names no particular dictionary: one built with
/// [`Entry::new`], or a generated one after [`Entry::unbranded`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AnyDictionary {}

/// The address of an object-dictionary entry whose value has the Rust type `T`, in the
/// dictionary `D`, with the access rights `A` (see the module documentation and
/// [`access`](crate::od::access)).
///
/// Two entries are equal when their index, sub-index and wire width are: the recorded position
/// (see [`Entry::at_position`]) is only a hint.
#[derive(Debug)]
pub struct Entry<T, D = AnyDictionary, A = ReadWrite> {
    /// OD index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    width: u8,
    position: u16,
    _value: PhantomData<Markers<T, D, A>>,
}

/// What an `Entry` holds of its type parameters: nothing (a function pointer type keeps the
/// address `Copy`, `Send` and `Sync` whatever they are).
type Markers<T, D, A> = fn() -> (T, D, A);

/// The `position` of an entry that records none.
const NO_POSITION: u16 = u16::MAX;

impl<T, D, A> PartialEq for Entry<T, D, A> {
    fn eq(&self, other: &Self) -> bool {
        (self.index, self.sub, self.width) == (other.index, other.sub, other.width)
    }
}
impl<T, D, A> Eq for Entry<T, D, A> {}

impl<T, D, A> core::hash::Hash for Entry<T, D, A> {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        (self.index, self.sub, self.width).hash(state);
    }
}

impl<T, D, A> Clone for Entry<T, D, A> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T, D, A> Copy for Entry<T, D, A> {}

impl<T> Entry<T> {
    /// The entry at (index, sub), of unknown access: a master may read and write it (the node
    /// answers an access it refuses with its SDO abort).
    pub const fn new(index: u16, sub: u8) -> Self {
        Entry {
            index,
            sub,
            width: 0,
            position: NO_POSITION,
            _value: PhantomData,
        }
    }

    /// The entry at (index, sub) whose value travels in `width` bytes, fewer than `T` holds
    /// (an INTEGER24 in an `i32`, an UNSIGNED48 in a `u64`).
    pub const fn with_width(index: u16, sub: u8, width: u8) -> Self {
        Entry {
            index,
            sub,
            width,
            position: NO_POSITION,
            _value: PhantomData,
        }
    }

    /// The same entry, read-only (`ro`): a master's typed `write` of it does not compile.
    pub const fn read_only(self) -> Entry<T, AnyDictionary, ReadOnly> {
        self.recast()
    }

    /// The same entry, write-only (`wo`): a master's typed `read` of it does not compile.
    pub const fn write_only(self) -> Entry<T, AnyDictionary, WriteOnly> {
        self.recast()
    }

    /// The same entry, constant (`const`): a master's typed `write` of it does not compile.
    pub const fn constant(self) -> Entry<T, AnyDictionary, Const> {
        self.recast()
    }
}

impl<T, A> Entry<T, AnyDictionary, A> {
    /// The same entry, recording that it is at `position` in its device's generated `Od`
    /// (`ENTRIES[position]`), so that the `Od`'s typed `get`/`set` find it without a search. A
    /// wrong position costs only that search.
    pub const fn at_position(self, position: u16) -> Self {
        Entry { position, ..self }
    }

    /// The same entry, branded as one of the dictionary `D`. For generated code, which brands
    /// each address of its module with the module's `Od` after [`Entry::at_position`]: that `Od`
    /// then reads it without a check. A false brand is not unsafe: such a read gives `T`'s
    /// default.
    pub const fn in_dictionary<D>(self) -> Entry<T, D, A> {
        self.recast()
    }
}

impl<T, D, A> Entry<T, D, A> {
    /// The same entry without its dictionary's brand (its access kept): for another dictionary
    /// (whose checked `get` then returns `None` if it does not hold it).
    pub const fn unbranded(self) -> Entry<T, AnyDictionary, A> {
        self.recast()
    }

    /// The same address under other type parameters (one of the markers changed).
    const fn recast<E, B>(self) -> Entry<T, E, B> {
        Entry {
            index: self.index,
            sub: self.sub,
            width: self.width,
            position: self.position,
            _value: PhantomData,
        }
    }

    /// Whether `event` says an SDO client wrote this entry (`Event::Written` of its index and
    /// sub-index): `Event::Written { .. } if od::CONTROLWORD.written_by(&event) => ...`.
    pub fn written_by(&self, event: &crate::Event) -> bool {
        matches!(event, crate::Event::Written { index, sub } if (*index, *sub) == (self.index, self.sub))
    }

    /// The position recorded by [`Entry::at_position`].
    pub const fn position(&self) -> Option<usize> {
        if self.position == NO_POSITION {
            None
        } else {
            Some(self.position as usize)
        }
    }

    /// The wire width in bytes when it is narrower than `T` (see [`Entry::with_width`]).
    pub const fn wire_width(&self) -> Option<usize> {
        if self.width == 0 {
            None
        } else {
            Some(self.width as usize)
        }
    }
}

impl<T: OdValue, D, A> Entry<T, D, A> {
    /// Writes `value` as this entry's wire bytes; `None` if `buf` is too short or the value does
    /// not fit the entry's width (a 24-bit entry refuses `1 << 23` in an `i32`).
    pub fn encode(&self, value: &T, buf: &mut [u8]) -> Option<usize> {
        match self.wire_width() {
            None => value.encode(buf),
            Some(width) => value.encode_width(width, buf),
        }
    }

    /// Reads this entry's value from exactly its wire bytes (sign-extending narrow signed ones).
    pub fn decode(&self, bytes: &[u8]) -> Option<T> {
        match self.wire_width() {
            None => T::decode(bytes),
            Some(width) => T::decode_width(width, bytes),
        }
    }
}

/// A value that travels as little-endian bytes in SDO and PDO payloads.
pub trait OdValue: Sized {
    /// Writes the value into `buf` and returns the number of bytes written, or `None` if `buf`
    /// is too short.
    fn encode(&self, buf: &mut [u8]) -> Option<usize>;
    /// Reads a value from exactly the bytes of one value; `None` if the length is wrong.
    fn decode(bytes: &[u8]) -> Option<Self>;

    /// Writes the value in exactly `width` bytes; `None` if it does not fit (or `buf` is too
    /// short). Integers override this for the odd CiA 301 widths.
    fn encode_width(&self, width: usize, buf: &mut [u8]) -> Option<usize> {
        let n = self.encode(buf)?;
        (n == width).then_some(n)
    }

    /// Reads a value from exactly `width` bytes.
    fn decode_width(width: usize, bytes: &[u8]) -> Option<Self> {
        if bytes.len() == width {
            Self::decode(bytes)
        } else {
            None
        }
    }
}

macro_rules! od_value_narrow {
    ($($t:ty => $signed:literal),*) => {$(
        impl OdValue for $t {
            fn encode(&self, buf: &mut [u8]) -> Option<usize> {
                let bytes = self.to_le_bytes();
                buf.get_mut(..bytes.len())?.copy_from_slice(&bytes);
                Some(bytes.len())
            }
            fn decode(bytes: &[u8]) -> Option<Self> {
                Some(<$t>::from_le_bytes(bytes.try_into().ok()?))
            }
            fn encode_width(&self, width: usize, buf: &mut [u8]) -> Option<usize> {
                if width == 0 || width > core::mem::size_of::<$t>() {
                    return None;
                }
                let bits = (width * 8) as u32;
                let fits = if $signed {
                    crate::od::typed::fits_signed(*self as i64, bits)
                } else {
                    crate::od::typed::fits_unsigned(*self as u64, bits)
                };
                if !fits {
                    return None;
                }
                let bytes = self.to_le_bytes();
                buf.get_mut(..width)?.copy_from_slice(bytes.get(..width)?);
                Some(width)
            }
            fn decode_width(width: usize, bytes: &[u8]) -> Option<Self> {
                if width == 0 || width > core::mem::size_of::<$t>() || bytes.len() != width {
                    return None;
                }
                let mut wide = [0u8; 8];
                wide.get_mut(..width)?.copy_from_slice(bytes);
                let raw = u64::from_le_bytes(wide);
                Some(if $signed {
                    crate::od::typed::sign_extend(raw, (width * 8) as u32) as $t
                } else {
                    raw as $t
                })
            }
        }
    )*};
}
od_value_narrow!(u32 => false, u64 => false, i32 => true, i64 => true);

macro_rules! od_value_int {
    ($($t:ty),*) => {$(
        impl OdValue for $t {
            fn encode(&self, buf: &mut [u8]) -> Option<usize> {
                let bytes = self.to_le_bytes();
                buf.get_mut(..bytes.len())?.copy_from_slice(&bytes);
                Some(bytes.len())
            }
            fn decode(bytes: &[u8]) -> Option<Self> {
                Some(<$t>::from_le_bytes(bytes.try_into().ok()?))
            }
        }
    )*};
}
od_value_int!(u8, u16, i8, i16, f32, f64);

impl OdValue for bool {
    fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        *buf.first_mut()? = u8::from(*self);
        Some(1)
    }
    fn decode(bytes: &[u8]) -> Option<Self> {
        match bytes {
            [0] => Some(false),
            [1] => Some(true),
            _ => None,
        }
    }
}

impl<const N: usize> OdValue for crate::od::typed::FixedBytes<N> {
    fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        let bytes = self.as_bytes();
        buf.get_mut(..bytes.len())?.copy_from_slice(bytes);
        Some(bytes.len())
    }
    fn decode(bytes: &[u8]) -> Option<Self> {
        (bytes.len() <= N).then(|| Self::from_slice(bytes))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::od::typed::FixedBytes;

    #[test]
    fn narrow_entries_check_range_and_sign_extend() {
        let i24: Entry<i32> = Entry::with_width(0x2003, 1, 3);
        let mut buf = [0u8; 4];
        assert_eq!(i24.encode(&-2, &mut buf), Some(3));
        assert_eq!(&buf[..3], &[0xFE, 0xFF, 0xFF]);
        assert_eq!(i24.encode(&(1 << 23), &mut buf), None);
        assert_eq!(i24.decode(&[0x00, 0x00, 0x80]), Some(-(1 << 23)));
        assert_eq!(i24.decode(&[0, 0, 0, 0]), None);
        let u48: Entry<u64> = Entry::with_width(0x2003, 5, 6);
        let mut buf8 = [0u8; 8];
        assert_eq!(u48.encode(&0xFFFF_FFFF_FFFF, &mut buf8), Some(6));
        assert_eq!(u48.encode(&(1 << 48), &mut buf8), None);
        assert_eq!(u48.decode(&[1, 0, 0, 0, 0, 0x80]), Some(0x8000_0000_0001));
        let plain: Entry<u32> = Entry::new(0x1000, 0);
        assert_eq!(plain.wire_width(), None);
        assert_eq!(plain.encode(&0x0102_0304, &mut buf), Some(4));
        assert_eq!(plain.decode(&[4, 3, 2, 1]), Some(0x0102_0304));
    }

    #[test]
    fn brands_keep_the_address_and_written_events_match_it() {
        struct Dict;
        let plain: Entry<u16> = Entry::new(0x6040, 0).at_position(7);
        let branded: Entry<u16, Dict> = plain.in_dictionary();
        assert_eq!(
            (branded.index, branded.sub, branded.position()),
            (0x6040, 0, Some(7))
        );
        assert_eq!(branded.unbranded(), plain);
        let written = crate::Event::Written {
            index: 0x6040,
            sub: 0,
        };
        assert!(branded.written_by(&written));
        assert!(plain.written_by(&written));
        let other = crate::Event::Written {
            index: 0x6040,
            sub: 1,
        };
        assert!(!branded.written_by(&other));
        assert!(!branded.written_by(&crate::Event::RpdoReceived { pdo: 0 }));
    }

    #[test]
    fn access_markers_keep_the_address() {
        use crate::od::access::{Const, ReadOnly, WriteOnly};
        struct Dict;
        let status: Entry<u16, Dict, ReadOnly> = Entry::new(0x6041, 0)
            .read_only()
            .at_position(3)
            .in_dictionary();
        let limit: Entry<i32, AnyDictionary, Const> = Entry::with_width(0x2002, 1, 3).constant();
        let command: Entry<u8, AnyDictionary, WriteOnly> = Entry::new(0x2003, 0).write_only();
        assert_eq!(
            (status.index, status.sub, status.position()),
            (0x6041, 0, Some(3))
        );
        assert_eq!(status.unbranded(), Entry::new(0x6041, 0).read_only());
        assert_eq!(
            (limit.index, limit.sub, limit.wire_width()),
            (0x2002, 1, Some(3))
        );
        assert_eq!(limit.decode(&[0xFE, 0xFF, 0xFF]), Some(-2));
        assert_eq!((command.index, command.position()), (0x2003, None));
        assert_eq!(
            core::mem::size_of_val(&status),
            core::mem::size_of::<Entry<u16>>()
        );
    }

    #[test]
    fn fixed_bytes_travel_as_their_bytes() {
        let name = FixedBytes::<8>::from_slice(b"CP301");
        let mut buf = [0u8; 8];
        assert_eq!(name.encode(&mut buf), Some(5));
        assert_eq!(&buf[..5], b"CP301");
        assert_eq!(name.encode(&mut [0u8; 4]), None);
        assert_eq!(FixedBytes::<8>::decode(b"CP301"), Some(name));
        assert_eq!(FixedBytes::<4>::decode(b"CP301"), None);
    }
}
