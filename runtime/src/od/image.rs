//! The value image: how a generated object dictionary stores its values.
//!
//! A generated `Od` keeps every value in one byte array, little-endian, at an offset fixed at
//! generation time: a fixed-size value in exactly its wire size; a string, octet string or domain
//! as its current length (2 bytes) followed by room for its capacity. A [`Layout`] in flash (the
//! descriptors, each entry's offset and the LowLimit/HighLimit table) then serves every entry with
//! one table-driven read and one write: no code per entry. On a microcontroller that is the
//! difference between a few hundred bytes of flash and two match arms per entry (about 16 bytes
//! each); the SDO server and the PDOs move bytes without knowing types, and the application's
//! typed [`Layout::get`]/[`Layout::set`] go through the same checks as an SDO write.

use crate::od::entry::{Entry, OdValue};
use crate::od::typed::{copy_value, position, read_bytes};
use crate::od::{DataType, EntryDescriptor, EntryKind, SdoAbort};

/// An entry's LowLimit and HighLimit, as keys whose signed order is the numeric order of the
/// entry's data type (REAL32/REAL64 by sign and magnitude), computed when the generated table is
/// built. A write then turns only its value into a key and compares integers, so no
/// floating-point code is needed (a Cortex-M4F has no double-precision unit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limit {
    // Bytes rather than `i64`s: a table row is 18 bytes, not 24 (no 8-byte alignment).
    low: [u8; 8],
    high: [u8; 8],
}

impl Limit {
    /// Limits from their keys; a missing key (a NaN limit) allows everything on its side.
    const fn from_keys(low: Option<i64>, high: Option<i64>) -> Self {
        let low = match low {
            Some(key) => key,
            None => i64::MIN,
        };
        let high = match high {
            Some(key) => key,
            None => i64::MAX,
        };
        Limit {
            low: low.to_le_bytes(),
            high: high.to_le_bytes(),
        }
    }

    /// The limits of an unsigned integer (or TIME_OF_DAY/TIME_DIFFERENCE) entry.
    pub const fn unsigned(low: u64, high: u64) -> Self {
        Self::from_keys(
            order_key(DataType::Unsigned64, low),
            order_key(DataType::Unsigned64, high),
        )
    }

    /// The limits of a signed integer entry.
    pub const fn signed(low: i64, high: i64) -> Self {
        Self::from_keys(Some(low), Some(high))
    }

    /// The limits of a REAL32 entry. A NaN limit allows everything on its side.
    pub const fn real32(low: f32, high: f32) -> Self {
        Self::from_keys(
            order_key(DataType::Real32, low.to_bits() as u64),
            order_key(DataType::Real32, high.to_bits() as u64),
        )
    }

    /// The limits of a REAL64 entry. A NaN limit allows everything on its side.
    pub const fn real64(low: f64, high: f64) -> Self {
        Self::from_keys(
            order_key(DataType::Real64, low.to_bits()),
            order_key(DataType::Real64, high.to_bits()),
        )
    }

    /// Checks the little-endian `data` of a `data_type` value (exactly its size, at most 8
    /// bytes as every fixed-size type is): `ValueTooLow` below the low limit, `ValueTooHigh`
    /// above the high one. A NaN value passes, as it compares neither below nor above.
    fn check(self, data_type: DataType, data: &[u8]) -> Result<(), SdoAbort> {
        // Widened to 64 bits, a signed value sign-extended byte by byte (a 64-bit shift by a
        // variable amount is a library call on a Cortex-M).
        let negative =
            is_signed_integer(data_type) && data.last().is_some_and(|&top| top & 0x80 != 0);
        let mut value = [if negative { 0xFF } else { 0 }; 8];
        if let Some(low) = value.get_mut(..data.len()) {
            low.copy_from_slice(data);
        }
        let Some(value) = order_key(data_type, u64::from_le_bytes(value)) else {
            return Ok(());
        };
        if value < i64::from_le_bytes(self.low) {
            return Err(SdoAbort::ValueTooLow);
        }
        if value > i64::from_le_bytes(self.high) {
            return Err(SdoAbort::ValueTooHigh);
        }
        Ok(())
    }
}

/// Whether `data_type` is a signed integer.
const fn is_signed_integer(data_type: DataType) -> bool {
    matches!(
        data_type,
        DataType::Integer8
            | DataType::Integer16
            | DataType::Integer24
            | DataType::Integer32
            | DataType::Integer40
            | DataType::Integer48
            | DataType::Integer56
            | DataType::Integer64
    )
}

/// A key whose signed order is the numeric order of `raw`, a `data_type` value widened to 64
/// bits (a signed integer sign-extended, anything else zero-extended); `None` for a NaN.
const fn order_key(data_type: DataType, raw: u64) -> Option<i64> {
    let (sign, infinity) = match data_type {
        DataType::Real32 => (1 << 31, 0x7F80_0000),
        DataType::Real64 => (1 << 63, 0x7FF0_0000_0000_0000),
        _ if is_signed_integer(data_type) => return Some(raw as i64),
        _ => return Some((raw ^ 1 << 63) as i64),
    };
    // Sign and magnitude: -0 and +0 are equal.
    let magnitude = raw & (sign - 1);
    if magnitude > infinity {
        None
    } else if raw & sign != 0 {
        Some(-(magnitude as i64))
    } else {
        Some(magnitude as i64)
    }
}

/// Where each entry's value lives in a value image, and what a write must respect.
#[derive(Debug)]
pub struct Layout {
    entries: &'static [EntryDescriptor],
    offsets: &'static [u16],
    limits: &'static [(u16, Limit)],
    image_size: usize,
}

/// Where a value is: its data type, where it starts and its size (the capacity for a string,
/// octet string or domain, whose bytes follow a 2-byte length).
#[derive(Clone, Copy)]
struct Place {
    data_type: DataType,
    start: usize,
    size: usize,
}

impl Layout {
    /// The layout of `entries` (sorted by index and sub-index), whose values start at
    /// `offsets[i]` in an image of `image_size` bytes, in table order and without gaps: a
    /// value's room is up to the next value (or the end of the image), which for a fixed-size
    /// value must be its size and for a string, octet string or domain is its 2-byte current
    /// length and its capacity. `limits` holds (position, limits) for the entries that have limits, sorted by
    /// position.
    pub const fn new(
        entries: &'static [EntryDescriptor],
        offsets: &'static [u16],
        limits: &'static [(u16, Limit)],
        image_size: usize,
    ) -> Self {
        Layout {
            entries,
            offsets,
            limits,
            image_size,
        }
    }

    /// `ObjectDictionary::entry_count`.
    #[inline]
    pub const fn entry_count(&self) -> usize {
        self.entries.len()
    }

    /// `ObjectDictionary::entry`: the descriptor of the entry at `position`.
    #[inline]
    pub fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.entries.get(position).copied()
    }

    /// `ObjectDictionary::kind`: the kind of the entry at `position`.
    #[inline]
    pub fn kind(&self, position: usize) -> Option<EntryKind> {
        Some(self.entries.get(position)?.kind())
    }

    /// `ObjectDictionary::locate`: where (index, sub) is.
    #[inline]
    pub fn locate(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        position(self.entries, index, sub)
    }

    /// `ObjectDictionary::capacity`: the size of the value at `position`, a string's, octet
    /// string's or domain's capacity.
    pub fn capacity(&self, position: usize) -> Option<usize> {
        self.place(position).ok().map(|place| place.size)
    }

    /// Where the value of the entry at `position` is. `NoObject` for a position past the end,
    /// or a string whose room the next offset contradicts (a malformed hand-built layout).
    #[inline]
    fn place(&self, position: usize) -> Result<Place, SdoAbort> {
        let (Some(entry), Some(&start)) = (self.entries.get(position), self.offsets.get(position))
        else {
            return Err(SdoAbort::NoObject);
        };
        let start = usize::from(start);
        // Values lie in table order without gaps, so a value's room is up to the next one: a
        // fixed-size value's size, or a string's 2-byte length and its capacity.
        let end = match self.offsets.get(position + 1) {
            Some(&next) => usize::from(next),
            None => self.image_size,
        };
        let reserved = if holds_bytes(entry.data_type()) { 2 } else { 0 };
        let size = end
            .checked_sub(start + reserved)
            .ok_or(SdoAbort::NoObject)?;
        Ok(Place {
            data_type: entry.data_type(),
            start,
            size,
        })
    }

    /// The bytes of the value at `position`: a fixed-size value's wire bytes, a string's or
    /// domain's current bytes.
    #[inline]
    pub fn value<'v>(&self, values: &'v [u8], position: usize) -> Result<&'v [u8], SdoAbort> {
        let Place {
            data_type,
            start,
            size,
        } = self.place(position)?;
        let range = if holds_bytes(data_type) {
            let len = match values.get(start..start + 2) {
                Some(&[low, high]) => usize::from(u16::from_le_bytes([low, high])),
                _ => 0,
            };
            start + 2..start + 2 + len.min(size)
        } else {
            start..start + size
        };
        values.get(range).ok_or(SdoAbort::NoObject)
    }

    /// `ObjectDictionary::read_at`: copies the value's bytes from `offset` on into `buf`.
    pub fn read(
        &self,
        values: &[u8],
        position: usize,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, SdoAbort> {
        Ok(read_bytes(self.value(values, position)?, offset, buf))
    }

    /// `ObjectDictionary::write_at`: replaces the value at `position` with `data`. A fixed-size
    /// value takes exactly its size (`LengthTooHigh`/`LengthTooLow`), a BOOLEAN only 0 or 1
    /// (`InvalidValue`), a limited value only what its limits allow (`ValueTooLow`/
    /// `ValueTooHigh`); a string, octet string or domain at most its capacity (`LengthTooHigh`).
    /// On error the image is unchanged.
    pub fn write(&self, values: &mut [u8], position: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let Place {
            data_type,
            start,
            size,
        } = self.place(position)?;
        let reserved = if holds_bytes(data_type) {
            if data.len() > size {
                return Err(SdoAbort::LengthTooHigh);
            }
            2
        } else {
            if data.len() != size {
                return Err(length_abort(data.len() > size));
            }
            if data_type == DataType::Boolean && data.first().is_some_and(|&byte| byte > 1) {
                return Err(SdoAbort::InvalidValue);
            }
            if !self.limits.is_empty() {
                self.check_limit(position, data_type, data)?;
            }
            0
        };
        // One copy for both: a string's bytes follow its 2-byte current length.
        let target = values
            .get_mut(start..start + reserved + data.len())
            .ok_or(SdoAbort::NoObject)?;
        let (len, bytes) = target.split_at_mut(reserved);
        if let Ok(len) = <&mut [u8; 2]>::try_from(len) {
            *len = (data.len() as u16).to_le_bytes();
        }
        copy_value(bytes, data);
        Ok(())
    }

    /// `ObjectDictionary::restore_defaults`: sets the values of the entries whose index is in
    /// `indices` to the defaults a generated `Od::new(node_id)` starts with (`runs` as for
    /// [`unpack_defaults`]). Values lie in table order, so those entries' values are one
    /// stretch of the image: it is cleared, and only the runs' bytes inside it are written.
    pub fn restore_defaults(
        &self,
        values: &mut [u8],
        runs: &[u8],
        node_id: u8,
        indices: core::ops::RangeInclusive<u16>,
    ) {
        let first = self
            .entries
            .partition_point(|e| e.index() < *indices.start());
        let end = self
            .entries
            .partition_point(|e| e.index() <= *indices.end());
        let offset = |position: usize| match self.offsets.get(position) {
            Some(&offset) => usize::from(offset),
            None => self.image_size,
        };
        unpack_defaults_within(values, runs, node_id, (offset(first), offset(end)));
    }

    /// `ObjectDictionary::value_len`: the current length of the value at `position`.
    pub fn value_len(&self, values: &[u8], position: usize) -> Result<usize, SdoAbort> {
        Ok(self.value(values, position)?.len())
    }

    /// Checks `data` against the limits of the entry at `position`, if it has any. Out of line:
    /// the search and the 64-bit comparisons would make every write save and restore the
    /// registers they need, limits or not.
    #[inline(never)]
    fn check_limit(
        &self,
        position: usize,
        data_type: DataType,
        data: &[u8],
    ) -> Result<(), SdoAbort> {
        match self.limit(position) {
            Some(limit) => limit.check(data_type, data),
            None => Ok(()),
        }
    }

    /// The limits of the entry at `position`, if it has any.
    fn limit(&self, position: usize) -> Option<Limit> {
        self.limits
            .iter()
            .find(|&&(p, _)| usize::from(p) == position)
            .map(|&(_, limit)| limit)
    }

    /// The position of `entry`: the one generated code recorded in it when that is right (a
    /// comparison the compiler folds away for a constant entry), else a search.
    #[inline]
    fn position_of<T, D, A>(&self, entry: &Entry<T, D, A>) -> Result<usize, SdoAbort> {
        if let Some(hint) = entry.position() {
            if self
                .entries
                .get(hint)
                .is_some_and(|e| e.index() == entry.index && e.sub() == entry.sub)
            {
                return Ok(hint);
            }
        }
        position(self.entries, entry.index, entry.sub)
    }

    /// The value of `entry`, typed; `None` if this dictionary has no such entry or its value
    /// does not decode as `T`.
    #[inline]
    pub fn get<T: OdValue, D, A>(&self, values: &[u8], entry: Entry<T, D, A>) -> Option<T> {
        let position = self.position_of(&entry).ok()?;
        entry.decode(self.value(values, position).ok()?)
    }

    /// Sets `entry` to `value`, with the checks of an SDO write (lengths, BOOLEAN, limits; a
    /// value that does not fit an odd-width entry is `InvalidValue`) but not access rights: the
    /// application may set a read-only entry. On error the image is unchanged.
    #[inline]
    pub fn set<T: OdValue, D, A>(
        &self,
        values: &mut [u8],
        entry: Entry<T, D, A>,
        value: &T,
    ) -> Result<(), SdoAbort> {
        let position = self.position_of(&entry)?;
        let Place {
            data_type,
            start,
            size,
        } = self.place(position)?;
        if !holds_bytes(data_type) {
            let mut scratch = [0u8; 8];
            let len = entry
                .encode(value, &mut scratch)
                .ok_or(SdoAbort::InvalidValue)?;
            return self.write(values, position, &scratch[..len]);
        }
        // Encoded in place: `encode` writes nothing when the value does not fit.
        let room = values
            .get_mut(start + 2..start + 2 + size)
            .ok_or(SdoAbort::NoObject)?;
        let len = entry.encode(value, room).ok_or(SdoAbort::LengthTooHigh)?;
        values[start..start + 2].copy_from_slice(&(len as u16).to_le_bytes());
        Ok(())
    }
}

/// Whether a value of `data_type` is a string, octet string or domain (its descriptor's size is
/// its capacity), rather than a fixed-size value (its size is the wire size).
fn holds_bytes(data_type: DataType) -> bool {
    matches!(
        data_type,
        DataType::VisibleString
            | DataType::OctetString
            | DataType::UnicodeString
            | DataType::Domain
    )
}

/// `LengthTooHigh` for too many bytes, else `LengthTooLow`.
fn length_abort(too_long: bool) -> SdoAbort {
    if too_long {
        SdoAbort::LengthTooHigh
    } else {
        SdoAbort::LengthTooLow
    }
}

/// The bit of a run's length byte that marks a `$NODEID` default (see [`unpack_defaults`]).
pub const NODE_RELATIVE: u8 = 0x80;

/// Writes the non-zero bytes of a default image into `values` (all zero before): how a generated
/// `Od::new(node_id)` starts. `runs` is a sequence of runs, each a gap (how many bytes after the
/// end of the previous run it starts, 0 to 255), a length (0 to 127) and that many bytes. A
/// length with [`NODE_RELATIVE`] set marks a `$NODEID` default: its bytes are the little-endian
/// number the node-ID is added to (`$NODEID+0x600` holds 0x600), a carry out of its width
/// dropped as in the entry's own arithmetic. Most default bytes are zero, so the runs take well
/// under half the image's flash (CP301: 383 bytes of image, 158 bytes of runs). Bytes that
/// would fall outside `values` or `runs` are skipped.
pub const fn unpack_defaults(values: &mut [u8], runs: &[u8], node_id: u8) {
    unpack_defaults_within(values, runs, node_id, (0, usize::MAX));
}

/// [`unpack_defaults`] into the bytes `window.0..window.1` only, which it sets whole: the runs'
/// bytes there, zero in the gaps (a reset restores part of an image that is not all zero).
const fn unpack_defaults_within(
    values: &mut [u8],
    runs: &[u8],
    node_id: u8,
    window: (usize, usize),
) {
    let end = if window.1 < values.len() {
        window.1
    } else {
        values.len()
    };
    // The window cleared, then each run's bytes that fall in it written (a run cut short by the
    // end of the runs is the last: its missing bytes stay zero).
    let mut at = window.0;
    while at < end {
        values[at] = 0;
        at += 1;
    }
    let (mut at, mut i) = (0usize, 0usize);
    while i + 1 < runs.len() {
        at += runs[i] as usize;
        let length = runs[i + 1];
        let run_end = i + 2 + (length & !NODE_RELATIVE) as usize;
        // Added byte by byte with its carry: the node-ID to a `$NODEID` run, nothing to others.
        let mut carry = if length & NODE_RELATIVE != 0 {
            node_id as u16
        } else {
            0
        };
        i += 2;
        while i < run_end && i < runs.len() {
            let sum = runs[i] as u16 + carry;
            if at >= window.0 && at < end {
                values[at] = sum as u8;
            }
            carry = sum >> 8;
            at += 1;
            i += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::od::typed::FixedBytes;
    use crate::od::Access;

    use DataType as D;
    const fn e(index: u16, sub: u8, data_type: DataType) -> EntryDescriptor {
        EntryDescriptor::new(index, sub, data_type, Access::Rw, true)
    }

    /// 2000h u16 (limited 10..=500), 2001h i24 (limited -100..=100), 2002h bool, 2003h REAL32
    /// (limited -1.5..=2.5), 2004h REAL64 (limited to 0.0.. with a NaN high limit), 2005h a
    /// 4-byte string, 2006h u8.
    static ENTRIES: [EntryDescriptor; 7] = [
        e(0x2000, 0, D::Unsigned16),
        e(0x2001, 0, D::Integer24),
        e(0x2002, 0, D::Boolean),
        e(0x2003, 0, D::Real32),
        e(0x2004, 0, D::Real64),
        e(0x2005, 0, D::VisibleString),
        e(0x2006, 0, D::Unsigned8),
    ];
    static OFFSETS: [u16; 7] = [0, 2, 5, 6, 10, 18, 24];
    static LIMITS: [(u16, Limit); 4] = [
        (0, Limit::unsigned(10, 500)),
        (1, Limit::signed(-100, 100)),
        (3, Limit::real32(-1.5, 2.5)),
        (4, Limit::real64(0.0, f64::NAN)),
    ];
    static LAYOUT: Layout = Layout::new(&ENTRIES, &OFFSETS, &LIMITS, 25);

    fn image() -> [u8; 25] {
        let mut values = [0u8; 25];
        // 2000h = 100, 2005h = "ab" (length 2).
        unpack_defaults(&mut values, &[0, 1, 100, 17, 4, 2, 0, b'a', b'b'], 0);
        values
    }

    #[test]
    fn the_node_id_is_added_with_carry_within_the_width() {
        // 0x600 + 5 (2 bytes), 0x800000FF + 5 carrying into the next byte (4 bytes), -1 + 5 in
        // one byte (the carry dropped), and a `$NODEID` run past the end of the image.
        let runs = [
            0, 0x82, 0x00, 0x06, 0, 0x84, 0xFF, 0x00, 0x00, 0x80, 0, 0x81, 0xFF, 0, 0x84, 0, 0, 0,
            0,
        ];
        let mut values = [0xEEu8; 8];
        unpack_defaults(&mut values, &runs, 5);
        assert_eq!(values, [0x05, 0x06, 0x04, 0x01, 0x00, 0x80, 0x04, 0x05]);
        // A plain run takes no node-ID.
        unpack_defaults(&mut values, &[1, 2, 0xFF, 0x06], 5);
        assert_eq!(values, [0, 0xFF, 0x06, 0, 0, 0, 0, 0]);
        const BUILT: [u8; 2] = {
            let mut values = [0; 2];
            unpack_defaults(&mut values, &[0, 0x82, 0x80, 0x05], 0x7F);
            values
        };
        assert_eq!(BUILT, [0xFF, 0x05]);
    }

    #[test]
    fn default_runs_unpack_and_malformed_ones_stop_at_the_edges() {
        let mut expected = [0u8; 25];
        expected[0] = 100;
        expected[18..22].copy_from_slice(&[2, 0, b'a', b'b']);
        assert_eq!(image(), expected);
        // A run past the end of the image and one cut short by the end of the runs.
        let mut values = [0u8; 4];
        unpack_defaults(&mut values, &[2, 5, 1, 2, 3, 4, 5], 9);
        assert_eq!(values, [0, 0, 1, 2]);
        let mut values = [0u8; 4];
        unpack_defaults(&mut values, &[1, 3, 9], 9);
        assert_eq!(values, [0, 9, 0, 0]);
        // A gap without its length: nothing but zeros (the image is set whole).
        unpack_defaults(&mut values, &[255], 9);
        assert_eq!(values, [0, 0, 0, 0]);
        // The same at compile time.
        const BUILT: [u8; 3] = {
            let mut values = [0u8; 3];
            unpack_defaults(&mut values, &[1, 2, 7, 8], 9);
            values
        };
        assert_eq!(BUILT, [0, 7, 8]);
    }

    #[test]
    fn restoring_defaults_sets_only_the_values_of_the_indices_given() {
        // 2000h holds a $NODEID default (100 + node-ID).
        const RUNS: [u8; 10] = [0, 0x82, 100, 0, 16, 4, 2, 0, b'a', b'b'];
        let mut values = [0xEEu8; 25];
        // 2001h..=2004h: their bytes 2..18 only, zeros from the gaps.
        LAYOUT.restore_defaults(&mut values, &RUNS, 3, 0x2001..=0x2004);
        assert!(values[..2].iter().chain(&values[18..]).all(|&b| b == 0xEE));
        assert!(values[2..18].iter().all(|&b| b == 0));
        // 2000h (with the node-ID added) and 2005h ("ab").
        LAYOUT.restore_defaults(&mut values, &RUNS, 3, 0x2000..=0x2005);
        let mut expected = image();
        expected[0] = 103;
        expected[24] = 0xEE;
        assert_eq!(values, expected);
    }

    #[test]
    fn reads_fixed_values_and_the_current_bytes_of_strings() {
        let values = image();
        assert_eq!(LAYOUT.value(&values, 0), Ok(&[100, 0][..]));
        assert_eq!(LAYOUT.value(&values, 5), Ok(&b"ab"[..]));
        assert_eq!(LAYOUT.value_len(&values, 5), Ok(2));
        let mut buf = [0u8; 1];
        assert_eq!(LAYOUT.read(&values, 5, 1, &mut buf), Ok(1));
        assert_eq!(buf, [b'b']);
        assert_eq!(
            LAYOUT.read(&values, 7, 0, &mut buf),
            Err(SdoAbort::NoObject)
        );
    }

    #[test]
    fn writes_check_length_boolean_and_capacity_and_leave_the_image_alone_on_error() {
        let mut values = image();
        let before = values;
        assert_eq!(
            LAYOUT.write(&mut values, 0, &[1, 2, 3]),
            Err(SdoAbort::LengthTooHigh)
        );
        assert_eq!(
            LAYOUT.write(&mut values, 0, &[1]),
            Err(SdoAbort::LengthTooLow)
        );
        assert_eq!(
            LAYOUT.write(&mut values, 2, &[2]),
            Err(SdoAbort::InvalidValue)
        );
        assert_eq!(
            LAYOUT.write(&mut values, 5, b"abcde"),
            Err(SdoAbort::LengthTooHigh)
        );
        assert_eq!(values, before);
        assert_eq!(LAYOUT.write(&mut values, 5, b"wxyz"), Ok(()));
        assert_eq!(LAYOUT.value(&values, 5), Ok(&b"wxyz"[..]));
        assert_eq!(LAYOUT.write(&mut values, 5, b""), Ok(()));
        assert_eq!(LAYOUT.value(&values, 5), Ok(&b""[..]));
        assert_eq!(LAYOUT.write(&mut values, 2, &[1]), Ok(()));
        assert_eq!(values[5], 1);
        assert_eq!(values[6..18], before[6..18]);
    }

    #[test]
    fn limits_order_unsigned_signed_and_real_values_numerically() {
        let mut values = image();
        let write = |values: &mut [u8], position, data: &[u8]| LAYOUT.write(values, position, data);
        assert_eq!(
            write(&mut values, 0, &9u16.to_le_bytes()),
            Err(SdoAbort::ValueTooLow)
        );
        assert_eq!(
            write(&mut values, 0, &501u16.to_le_bytes()),
            Err(SdoAbort::ValueTooHigh)
        );
        assert_eq!(write(&mut values, 0, &500u16.to_le_bytes()), Ok(()));
        // INTEGER24: -101 is FF FF 9B, below -100; -100 and 100 are in.
        assert_eq!(
            write(&mut values, 1, &[0x9B, 0xFF, 0xFF]),
            Err(SdoAbort::ValueTooLow)
        );
        assert_eq!(write(&mut values, 1, &[0x9C, 0xFF, 0xFF]), Ok(()));
        assert_eq!(
            write(&mut values, 1, &[101, 0, 0]),
            Err(SdoAbort::ValueTooHigh)
        );
        assert_eq!(write(&mut values, 1, &[100, 0, 0]), Ok(()));
        let real32 = |f: f32| f.to_le_bytes();
        assert_eq!(
            write(&mut values, 3, &real32(-1.75)),
            Err(SdoAbort::ValueTooLow)
        );
        assert_eq!(write(&mut values, 3, &real32(-1.5)), Ok(()));
        assert_eq!(write(&mut values, 3, &real32(-0.0)), Ok(()));
        assert_eq!(write(&mut values, 3, &real32(2.5)), Ok(()));
        assert_eq!(
            write(&mut values, 3, &real32(2.75)),
            Err(SdoAbort::ValueTooHigh)
        );
        assert_eq!(
            write(&mut values, 3, &real32(f32::INFINITY)),
            Err(SdoAbort::ValueTooHigh)
        );
        assert_eq!(
            write(&mut values, 3, &real32(f32::NAN)),
            Ok(()),
            "NaN compares neither way"
        );
        // REAL64 from 0.0 (so -0.0 is in) with no high limit (NaN).
        assert_eq!(write(&mut values, 4, &(-0.0f64).to_le_bytes()), Ok(()));
        assert_eq!(
            write(&mut values, 4, &(-1e-300f64).to_le_bytes()),
            Err(SdoAbort::ValueTooLow)
        );
        assert_eq!(write(&mut values, 4, &f64::MAX.to_le_bytes()), Ok(()));
        assert_eq!(write(&mut values, 6, &[255]), Ok(()), "no limits");
    }

    #[test]
    fn typed_get_and_set_use_the_position_hint_or_search() {
        let mut values = image();
        let hinted: Entry<u16> = Entry::new(0x2000, 0).at_position(0);
        let wrong_hint: Entry<u16> = Entry::new(0x2000, 0).at_position(3);
        let plain: Entry<u16> = Entry::new(0x2000, 0);
        assert_eq!(LAYOUT.get(&values, hinted), Some(100));
        assert_eq!(LAYOUT.get(&values, wrong_hint), Some(100));
        assert_eq!(LAYOUT.get(&values, plain), Some(100));
        assert_eq!(
            LAYOUT.set(&mut values, plain, &501),
            Err(SdoAbort::ValueTooHigh)
        );
        assert_eq!(LAYOUT.set(&mut values, wrong_hint, &42), Ok(()));
        assert_eq!(LAYOUT.get(&values, hinted), Some(42));
        let absent: Entry<u16> = Entry::new(0x3000, 0);
        assert_eq!(LAYOUT.get(&values, absent), None);
        assert_eq!(LAYOUT.set(&mut values, absent, &1), Err(SdoAbort::NoObject));
        let i24: Entry<i32> = Entry::with_width(0x2001, 0, 3);
        assert_eq!(LAYOUT.set(&mut values, i24, &-100), Ok(()));
        assert_eq!(LAYOUT.get(&values, i24), Some(-100));
        assert_eq!(
            LAYOUT.set(&mut values, i24, &(1 << 23)),
            Err(SdoAbort::InvalidValue)
        );
        let text: Entry<FixedBytes<4>> = Entry::new(0x2005, 0);
        assert_eq!(
            LAYOUT.set(&mut values, text, &FixedBytes::from_slice(b"xyz")),
            Ok(())
        );
        assert_eq!(LAYOUT.get(&values, text).map(|t| t.len()), Some(3));
        let long: Entry<FixedBytes<8>> = Entry::new(0x2005, 0);
        let before = values;
        assert_eq!(
            LAYOUT.set(&mut values, long, &FixedBytes::from_slice(b"toolong")),
            Err(SdoAbort::LengthTooHigh)
        );
        assert_eq!(values, before);
        // A wrongly typed entry at the right address: the length abort of an SDO write.
        let wide: Entry<u32> = Entry::new(0x2006, 0);
        assert_eq!(
            LAYOUT.set(&mut values, wide, &1),
            Err(SdoAbort::LengthTooHigh)
        );
        assert_eq!(LAYOUT.get(&values, wide), None);
    }

    #[test]
    fn capacities_are_the_room_up_to_the_next_value() {
        assert_eq!(LAYOUT.capacity(5), Some(4));
        assert_eq!(LAYOUT.capacity(0), Some(2));
        assert_eq!(LAYOUT.capacity(7), None);
        // The last entry's room ends with the image.
        static TAIL: [EntryDescriptor; 1] = [e(0x2000, 0, D::Domain)];
        assert_eq!(Layout::new(&TAIL, &[3], &[], 14).capacity(0), Some(9));
    }

    #[test]
    fn a_malformed_hand_built_layout_refuses_instead_of_panicking() {
        // A string whose room the next offset contradicts, a value past the end of the image
        // it is given, and a position with no entry.
        static BAD: [EntryDescriptor; 3] = [
            e(0x2000, 0, D::VisibleString),
            e(0x2001, 0, D::Unsigned8),
            e(0x2002, 0, D::Unsigned32),
        ];
        static BAD_LAYOUT: Layout = Layout::new(&BAD, &[4, 5, 6], &[], 10);
        let mut values = [0u8; 8];
        assert_eq!(BAD_LAYOUT.value(&values, 0), Err(SdoAbort::NoObject));
        assert_eq!(
            BAD_LAYOUT.write(&mut values, 0, b""),
            Err(SdoAbort::NoObject)
        );
        assert_eq!(BAD_LAYOUT.capacity(0), None);
        assert_eq!(BAD_LAYOUT.write(&mut values, 1, &[7]), Ok(()));
        assert_eq!(values[5], 7);
        assert_eq!(
            BAD_LAYOUT.write(&mut values, 2, &[1, 2, 3, 4]),
            Err(SdoAbort::NoObject)
        );
        assert_eq!(BAD_LAYOUT.value(&values, 2), Err(SdoAbort::NoObject));
        assert_eq!(
            BAD_LAYOUT.write(&mut values, 3, &[1]),
            Err(SdoAbort::NoObject)
        );
        // A stored length beyond the capacity (an image not written through the layout) reads
        // as the capacity.
        let mut image = image();
        image[18..20].copy_from_slice(&[0xFF, 0xFF]);
        assert_eq!(LAYOUT.value(&image, 5), Ok(&[b'a', b'b', 0, 0][..]));
    }

    #[test]
    fn entries_compare_without_their_position_hint() {
        let a: Entry<u16> = Entry::new(0x2000, 0).at_position(0);
        let b: Entry<u16> = Entry::new(0x2000, 0);
        assert_eq!(a, b);
        assert_eq!(a.position(), Some(0));
        assert_eq!(b.position(), None);
    }
}
