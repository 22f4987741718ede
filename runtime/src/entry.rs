//! Typed entry addresses: `Entry<u16>` names (index, sub) and the Rust type of its value.
//!
//! Generated code declares one constant per entry (`pub const CONTROLWORD: Entry<u16> = ...`), so a
//! master's typed read returns the right type and a mistyped write does not compile.

use core::marker::PhantomData;

/// The address of an object-dictionary entry whose value has the Rust type `T`.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct Entry<T> {
    /// OD index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    _value: PhantomData<fn() -> T>,
}

impl<T> Clone for Entry<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Entry<T> {}

impl<T> Entry<T> {
    /// The entry at (index, sub).
    pub const fn new(index: u16, sub: u8) -> Self {
        Entry {
            index,
            sub,
            _value: PhantomData,
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
}

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
od_value_int!(u8, u16, u32, u64, i8, i16, i32, i64, f32, f64);

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

impl<const N: usize> OdValue for crate::typed::FixedBytes<N> {
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
    use crate::typed::FixedBytes;

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
