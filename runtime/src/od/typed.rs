//! What generated device code builds on besides the value image ([`super::image`]):
//! fixed-capacity byte strings, the entry search, odd-width integer helpers, and the bit packing
//! of typed PDO payloads. Everything here is `no_std`, allocation-free and panic-free.

use crate::od::{EntryDescriptor, SdoAbort};

/// A VISIBLE_STRING, OCTET_STRING, UNICODE_STRING or DOMAIN value of at most `N` bytes.
///
/// The capacity is fixed at generation time; the current length may be anything up to it.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct FixedBytes<const N: usize> {
    len: usize,
    bytes: [u8; N],
}

impl<const N: usize> FixedBytes<N> {
    /// The capacity in bytes.
    pub const CAPACITY: usize = N;

    /// An empty value.
    pub const fn empty() -> Self {
        FixedBytes {
            len: 0,
            bytes: [0; N],
        }
    }

    /// A value holding the first `N` bytes of `src` (all of them when they fit).
    pub const fn from_slice(src: &[u8]) -> Self {
        let mut bytes = [0u8; N];
        let len = if src.len() < N { src.len() } else { N };
        let mut i = 0;
        while i < len {
            bytes[i] = src[i];
            i += 1;
        }
        FixedBytes { len, bytes }
    }

    /// Replaces the value; `LengthTooHigh` (and the value unchanged) if `src` exceeds the
    /// capacity.
    pub fn set(&mut self, src: &[u8]) -> Result<(), SdoAbort> {
        let target = self
            .bytes
            .get_mut(..src.len())
            .ok_or(SdoAbort::LengthTooHigh)?;
        target.copy_from_slice(src);
        self.len = src.len();
        Ok(())
    }

    /// The bytes currently held.
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or(&self.bytes)
    }

    /// The value as text, if it is valid UTF-8.
    pub fn as_str(&self) -> Option<&str> {
        core::str::from_utf8(self.as_bytes()).ok()
    }

    /// The current length in bytes.
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the value is empty.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl<const N: usize> Default for FixedBytes<N> {
    fn default() -> Self {
        Self::empty()
    }
}

impl<const N: usize> core::fmt::Debug for FixedBytes<N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.as_str() {
            Some(text) => write!(f, "{text:?}"),
            None => write!(f, "{:02x?}", self.as_bytes()),
        }
    }
}

/// Copies `value[offset..]` into `buf` and returns how many bytes were copied (0 when `offset`
/// is at or past the end).
#[inline]
pub fn read_bytes(value: &[u8], offset: usize, buf: &mut [u8]) -> usize {
    let rest = value.get(offset..).unwrap_or(&[]);
    let n = rest.len().min(buf.len());
    copy_value(&mut buf[..n], &rest[..n]);
    n
}

/// Copies `src` into `dst`, of the same length: the usual widths of a value (1, 2 and 4 bytes)
/// by one load and store, other lengths with `copy_from_slice`, whose `memcpy` call costs more
/// than the copy of a few bytes.
#[inline]
pub(crate) fn copy_value(dst: &mut [u8], src: &[u8]) {
    /// `src` into `dst` when both have `N` bytes.
    #[inline]
    fn copy_n<const N: usize>(dst: &mut [u8], src: &[u8]) {
        if let (Ok(dst), Ok(src)) = (<&mut [u8; N]>::try_from(dst), <&[u8; N]>::try_from(src)) {
            *dst = *src;
        }
    }
    match src.len() {
        1 => copy_n::<1>(dst, src),
        2 => copy_n::<2>(dst, src),
        4 => copy_n::<4>(dst, src),
        _ => dst.copy_from_slice(src),
    }
}

/// Where (index, sub) is in `entries` (sorted by index, then sub-index): a generated `read` or
/// `write` dispatches on this position. `NoObject` if the index is absent, `NoSubIndex` if only
/// the sub-index is.
///
/// Every SDO transfer starts here, so the search is in two steps that each load little: the
/// index's first entry by a binary search on the index alone, then the sub-index. Sub-indices
/// are sorted and distinct, so the entry is at most `sub` places further on: exactly there
/// when the sub-indices up to it are all present (sub-index 0, and most arrays and records),
/// which one comparison tells; else among the index's entries before that place, a short scan
/// (the sub-indices a sparse record leaves out are what makes it shorter than `sub`).
#[inline(never)]
pub fn position(entries: &[EntryDescriptor], index: u16, sub: u8) -> Result<usize, SdoAbort> {
    let first = entries.partition_point(|e| e.index() < index);
    let dense = first + usize::from(sub);
    if entries
        .get(dense)
        .is_some_and(|e| e.index() == index && e.sub() == sub)
    {
        return Ok(dense);
    }
    if entries.get(first).is_none_or(|e| e.index() != index) {
        return Err(SdoAbort::NoObject);
    }
    let rest = entries
        .get(first..dense)
        .unwrap_or_else(|| entries.get(first..).unwrap_or(&[]));
    for (k, e) in rest.iter().enumerate() {
        if e.index() != index || e.sub() > sub {
            break;
        }
        if e.sub() == sub {
            return Ok(first + k);
        }
    }
    Err(SdoAbort::NoSubIndex)
}

/// Where (index, sub) is among `count` entries sorted by (index, sub), `entry(p)` the one at
/// position `p`: a binary search, for a dictionary that has no table to search (the default
/// [`ObjectDictionary::locate`](crate::ObjectDictionary::locate)). `NoObject` if the index is
/// absent, `NoSubIndex` if only the sub-index is.
pub fn search(
    count: usize,
    entry: impl Fn(usize) -> Option<EntryDescriptor>,
    index: u16,
    sub: u8,
) -> Result<usize, SdoAbort> {
    let key = |p| entry(p).map(|e| (e.index(), e.sub()));
    let (mut low, mut high) = (0, count);
    while low < high {
        let mid = low + (high - low) / 2;
        if key(mid).is_some_and(|k| k < (index, sub)) {
            low = mid + 1;
        } else {
            high = mid;
        }
    }
    match key(low) {
        Some(k) if k == (index, sub) => Ok(low),
        Some((i, _)) if i == index => Err(SdoAbort::NoSubIndex),
        _ if low > 0 && key(low - 1).is_some_and(|(i, _)| i == index) => Err(SdoAbort::NoSubIndex),
        _ => Err(SdoAbort::NoObject),
    }
}

/// The low `bits` bits of `raw` read as a two's-complement number (`bits` in 1..=64).
#[inline]
pub const fn sign_extend(raw: u64, bits: u32) -> i64 {
    if bits == 0 || bits >= 64 {
        return raw as i64;
    }
    let shift = 64 - bits;
    ((raw << shift) as i64) >> shift
}

/// Whether `value` fits in `bits` unsigned bits.
#[inline]
pub const fn fits_unsigned(value: u64, bits: u32) -> bool {
    bits >= 64 || value >> bits == 0
}

/// Whether `value` fits in `bits` two's-complement bits.
#[inline]
pub const fn fits_signed(value: i64, bits: u32) -> bool {
    if bits >= 64 {
        return true;
    }
    if bits == 0 {
        return value == 0;
    }
    let min = -(1i64 << (bits - 1));
    let max = (1i64 << (bits - 1)) - 1;
    value >= min && value <= max
}

/// Writes the low `bits` bits of `value` into `buf` starting at bit `offset`, least significant
/// bit first (the CiA 301 PDO layout). Bits beyond `buf` are dropped.
#[inline]
pub fn put_bits(buf: &mut [u8], offset: usize, bits: u32, value: u64) {
    let bits = bits.min(64) as usize;
    let mut done = 0usize;
    while done < bits {
        let pos = offset + done;
        let shift = pos % 8;
        let take = (8 - shift).min(bits - done);
        let mask = (((1u16 << take) - 1) as u8) << shift;
        let chunk = ((value >> done) as u8) << shift;
        if let Some(byte) = buf.get_mut(pos / 8) {
            *byte = (*byte & !mask) | (chunk & mask);
        }
        done += take;
    }
}

/// Reads `bits` bits of `buf` starting at bit `offset`, least significant bit first. Bits beyond
/// `buf` read as zero.
#[inline]
pub fn get_bits(buf: &[u8], offset: usize, bits: u32) -> u64 {
    let bits = bits.min(64) as usize;
    let mut value = 0u64;
    let mut done = 0usize;
    while done < bits {
        let pos = offset + done;
        let shift = pos % 8;
        let take = (8 - shift).min(bits - done);
        let byte = buf.get(pos / 8).copied().unwrap_or(0);
        let chunk = (byte >> shift) & (((1u16 << take) - 1) as u8);
        value |= u64::from(chunk) << done;
        done += take;
    }
    value
}

/// Why a typed PDO could not be encoded or decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PdoError {
    /// The payload does not have the mapping's length.
    WrongLength {
        /// The mapping's length in bytes.
        expected: usize,
        /// The payload's length in bytes.
        actual: usize,
    },
    /// A field's value does not fit the number of bits the mapping gives it.
    OutOfRange {
        /// The field's name.
        field: &'static str,
    },
}

impl core::fmt::Display for PdoError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PdoError::WrongLength { expected, actual } => {
                write!(
                    f,
                    "PDO payload of {actual} bytes, the mapping needs {expected}"
                )
            }
            PdoError::OutOfRange { field } => {
                write!(f, "value of `{field}` does not fit its mapped length")
            }
        }
    }
}

/// The payload as an array of exactly `N` bytes, or `WrongLength`.
#[inline]
pub fn payload<const N: usize>(data: &[u8]) -> Result<[u8; N], PdoError> {
    data.try_into().map_err(|_| PdoError::WrongLength {
        expected: N,
        actual: data.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_round_trip_across_byte_boundaries() {
        let mut buf = [0u8; 3];
        put_bits(&mut buf, 4, 12, 0xABC);
        assert_eq!(buf, [0xC0, 0xAB, 0x00]);
        assert_eq!(get_bits(&buf, 4, 12), 0xABC);
        put_bits(&mut buf, 0, 4, 0x5);
        assert_eq!(buf, [0xC5, 0xAB, 0x00]);
    }

    #[test]
    fn bits_match_a_bit_by_bit_reference() {
        // Every offset/length pair over a 3-byte buffer, against a one-bit-at-a-time model.
        let pattern = 0xDEAD_BEEF_F00D_u64;
        for offset in 0..24usize {
            for bits in 1..=(24 - offset) as u32 {
                let mut buf = [0x5Au8; 3];
                let mut reference = buf;
                put_bits(&mut buf, offset, bits, pattern);
                for i in 0..bits as usize {
                    let pos = offset + i;
                    let bit = ((pattern >> i) & 1) as u8;
                    reference[pos / 8] =
                        (reference[pos / 8] & !(1 << (pos % 8))) | (bit << (pos % 8));
                }
                assert_eq!(buf, reference, "offset {offset} bits {bits}");
                let mask = if bits == 64 {
                    u64::MAX
                } else {
                    (1 << bits) - 1
                };
                assert_eq!(get_bits(&buf, offset, bits), pattern & mask);
            }
        }
        let mut wide = [0u8; 9];
        put_bits(&mut wide, 4, 64, u64::MAX);
        assert_eq!(wide, [0xF0, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x0F]);
        assert_eq!(get_bits(&wide, 4, 64), u64::MAX);
    }

    #[test]
    fn position_finds_entries_and_tells_missing_index_from_sub() {
        use crate::od::{Access, DataType};
        let entries = [
            EntryDescriptor::new(0x1000, 0, DataType::Unsigned32, Access::Ro, false),
            EntryDescriptor::new(0x1018, 0, DataType::Unsigned8, Access::Ro, false),
            EntryDescriptor::new(0x1018, 2, DataType::Unsigned32, Access::Ro, false),
            EntryDescriptor::new(0x6040, 0, DataType::Unsigned16, Access::Rw, true),
        ];
        assert_eq!(position(&entries, 0x1000, 0), Ok(0));
        assert_eq!(position(&entries, 0x1018, 2), Ok(2));
        assert_eq!(position(&entries, 0x6040, 0), Ok(3));
        assert_eq!(position(&entries, 0x1018, 1), Err(SdoAbort::NoSubIndex));
        assert_eq!(position(&entries, 0x6040, 1), Err(SdoAbort::NoSubIndex));
        assert_eq!(position(&entries, 0x1001, 0), Err(SdoAbort::NoObject));
        assert_eq!(position(&entries, 0x7000, 0), Err(SdoAbort::NoObject));
        assert_eq!(position(&[], 0x1000, 0), Err(SdoAbort::NoObject));
        // An index without sub-index 0: its sub-index 0 is missing, not the index.
        assert_eq!(
            position(&entries[2..], 0x1018, 0),
            Err(SdoAbort::NoSubIndex)
        );
        assert_eq!(position(&entries[2..], 0x1018, 2), Ok(0));
    }

    #[test]
    fn position_agrees_with_a_linear_search_for_every_table_length() {
        use crate::od::{Access, DataType};
        // Tables of 0..=40 entries: index 2000h + i / 3, sub (i % 3) * 2 (so odd subs are gaps).
        let all: Vec<EntryDescriptor> = (0..40u16)
            .map(|i| {
                let (index, sub) = (0x2000 + i / 3, (i % 3) as u8 * 2);
                EntryDescriptor::new(index, sub, DataType::Unsigned8, Access::Rw, false)
            })
            .collect();
        for len in 0..=all.len() {
            let entries = &all[..len];
            for index in 0x1FFF..=0x2010u16 {
                for sub in 0..=6u8 {
                    let linear = match entries
                        .iter()
                        .position(|e| (e.index(), e.sub()) == (index, sub))
                    {
                        Some(at) => Ok(at),
                        None if entries.iter().any(|e| e.index() == index) => {
                            Err(SdoAbort::NoSubIndex)
                        }
                        None => Err(SdoAbort::NoObject),
                    };
                    assert_eq!(
                        position(entries, index, sub),
                        linear,
                        "{len} {index:04X} {sub}"
                    );
                    let by_entry = |p: usize| entries.get(p).copied();
                    assert_eq!(
                        search(len, by_entry, index, sub),
                        linear,
                        "search {len} {index:04X} {sub}"
                    );
                }
            }
        }
    }

    #[test]
    fn odd_width_integers_sign_extend() {
        assert_eq!(sign_extend(0xFF_FFFF, 24), -1);
        assert_eq!(sign_extend(0x7F_FFFF, 24), 0x7F_FFFF);
        assert!(fits_signed(-8_388_608, 24) && !fits_signed(8_388_608, 24));
        assert!(fits_unsigned(0xFF_FFFF, 24) && !fits_unsigned(0x100_0000, 24));
    }

    #[test]
    fn fixed_bytes_refuse_overlong_writes() {
        let mut s = FixedBytes::<4>::from_slice(b"ab");
        assert_eq!(s.as_str(), Some("ab"));
        assert_eq!(s.set(b"abcde"), Err(SdoAbort::LengthTooHigh));
        assert_eq!(s.as_bytes(), b"ab");
        assert_eq!(s.set(b"wxyz"), Ok(()));
        assert_eq!(s.len(), 4);
    }
}
