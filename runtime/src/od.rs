//! The object-dictionary interface between the protocol cores and a device's data.
//!
//! Generated code implements [`ObjectDictionary`] for each device struct: [`EntryDescriptor`]s
//! by position (sorted by index and sub-index) plus `read`/`write` by (index, sub) into byte buffers. The OD checks
//! what only it can know (lengths, LowLimit/HighLimit, value ranges of odd-width integers); the
//! protocols check access rights against the descriptor (an SDO write to a `ro` entry, a PDO
//! mapping of a non-mappable one), so the same OD serves SDO, PDO and the node's own updates.
//!
//! What builds on the contract lives beside it: [`entry`] (typed addresses of entries and the
//! values they hold), [`access`] (the access rights in an address's type), [`image`] (the
//! packed value image a generated OD keeps its values in), [`stage`] (where a download collects until it completes) and [`typed`] (the values' byte and
//! bit encodings, for PDO payloads). What only generated code calls is gathered in the crate's
//! hidden `support` module.

pub mod access;
pub mod entry;
pub mod image;
mod services;
pub mod stage;
pub mod typed;

pub use self::services::Services;

/// A CiA 301 data type, as the runtime needs it (the wire size and how a value is checked).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum DataType {
    Boolean,
    Integer8,
    Integer16,
    Integer24,
    Integer32,
    Integer40,
    Integer48,
    Integer56,
    Integer64,
    Unsigned8,
    Unsigned16,
    Unsigned24,
    Unsigned32,
    Unsigned40,
    Unsigned48,
    Unsigned56,
    Unsigned64,
    Real32,
    Real64,
    VisibleString,
    OctetString,
    UnicodeString,
    TimeOfDay,
    TimeDifference,
    Domain,
}

impl DataType {
    /// The fixed size in bytes, or `None` for strings and DOMAIN (variable length).
    pub const fn fixed_size(self) -> Option<usize> {
        // By the variants' order above; 0 for the variable-length ones. A table, not a match:
        // every size check asks, and a lookup is a few bytes where a jump table is seventy.
        const SIZES: [u8; 25] = [
            1, 1, 2, 3, 4, 5, 6, 7, 8, // BOOLEAN, INTEGER8..INTEGER64
            1, 2, 3, 4, 5, 6, 7, 8, // UNSIGNED8..UNSIGNED64
            4, 8, // REAL32, REAL64
            0, 0, 0, // VISIBLE_STRING, OCTET_STRING, UNICODE_STRING
            6, 6, // TIME_OF_DAY, TIME_DIFFERENCE
            0, // DOMAIN
        ];
        match SIZES[self as usize] {
            0 => None,
            size => Some(size as usize),
        }
    }
}

/// Access rights of an entry (CiA 306 spelling).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Access {
    /// Read only.
    Ro,
    /// Write only.
    Wo,
    /// Read and write.
    Rw,
    /// Read and write; TPDO-mappable.
    Rwr,
    /// Read and write; RPDO-mappable.
    Rww,
    /// Constant.
    Const,
}

impl Access {
    /// Whether an SDO client may read the entry.
    pub const fn readable(self) -> bool {
        !matches!(self, Access::Wo)
    }
    /// Whether an SDO client may write the entry.
    pub const fn writable(self) -> bool {
        matches!(self, Access::Wo | Access::Rw | Access::Rwr | Access::Rww)
    }
}

/// What the protocols need to know about one entry, without touching its value: its index and
/// sub-index and its [`EntryKind`] (5 bytes, packed). The size is the data type's
/// ([`DataType::fixed_size`]); a string's, octet string's or domain's capacity comes from
/// [`ObjectDictionary::capacity`].
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[repr(C, packed)]
pub struct EntryDescriptor {
    index: u16,
    sub: u8,
    kind: EntryKind,
}

/// The kind of an entry: its data type, its access rights and whether it is PDO-mappable: what
/// the SDO server and the PDOs ask of an entry they have located ([`ObjectDictionary::kind`]).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct EntryKind {
    data_type: DataType,
    rights: Rights,
}

/// An entry's [`Access`] (its position in the enum, bits 0-2) and whether it is PDO-mappable
/// (bit 7), in one byte.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Rights(u8);

impl Rights {
    const MAPPABLE: u8 = 0x80;

    const fn new(access: Access, pdo_mappable: bool) -> Self {
        let code = match access {
            Access::Ro => 0,
            Access::Wo => 1,
            Access::Rw => 2,
            Access::Rwr => 3,
            Access::Rww => 4,
            Access::Const => 5,
        };
        Rights(if pdo_mappable {
            code | Self::MAPPABLE
        } else {
            code
        })
    }

    const fn access(self) -> Access {
        match self.0 & 0x07 {
            0 => Access::Ro,
            1 => Access::Wo,
            2 => Access::Rw,
            3 => Access::Rwr,
            4 => Access::Rww,
            _ => Access::Const,
        }
    }

    const fn pdo_mappable(self) -> bool {
        self.0 & Self::MAPPABLE != 0
    }
}

impl EntryKind {
    /// A kind from its parts.
    pub const fn new(data_type: DataType, access: Access, pdo_mappable: bool) -> Self {
        EntryKind {
            data_type,
            rights: Rights::new(access, pdo_mappable),
        }
    }

    /// Data type.
    #[inline]
    pub const fn data_type(&self) -> DataType {
        self.data_type
    }

    /// Access rights.
    #[inline]
    pub const fn access(&self) -> Access {
        self.rights.access()
    }

    /// Whether the entry may be mapped into a PDO.
    #[inline]
    pub const fn pdo_mappable(&self) -> bool {
        self.rights.pdo_mappable()
    }
}

impl core::fmt::Debug for EntryKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("EntryKind")
            .field("data_type", &self.data_type())
            .field("access", &self.access())
            .field("pdo_mappable", &self.pdo_mappable())
            .finish()
    }
}

impl EntryDescriptor {
    /// A descriptor from its parts (the compact form generated tables use).
    pub const fn new(
        index: u16,
        sub: u8,
        data_type: DataType,
        access: Access,
        pdo_mappable: bool,
    ) -> Self {
        Self::of_kind(index, sub, EntryKind::new(data_type, access, pdo_mappable))
    }

    /// A descriptor from its address and kind.
    pub const fn of_kind(index: u16, sub: u8, kind: EntryKind) -> Self {
        EntryDescriptor { index, sub, kind }
    }

    /// OD index.
    #[inline]
    pub const fn index(&self) -> u16 {
        self.index
    }

    /// Sub-index.
    #[inline]
    pub const fn sub(&self) -> u8 {
        self.sub
    }

    /// The entry's kind: data type, access and PDO mappability.
    #[inline]
    pub const fn kind(&self) -> EntryKind {
        self.kind
    }

    /// Data type.
    #[inline]
    pub const fn data_type(&self) -> DataType {
        self.kind.data_type
    }

    /// Access rights.
    #[inline]
    pub const fn access(&self) -> Access {
        self.kind.rights.access()
    }

    /// Whether the entry may be mapped into a PDO.
    #[inline]
    pub const fn pdo_mappable(&self) -> bool {
        self.kind.rights.pdo_mappable()
    }
}

impl core::fmt::Debug for EntryDescriptor {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("EntryDescriptor")
            .field("index", &self.index())
            .field("sub", &self.sub())
            .field("data_type", &self.data_type())
            .field("access", &self.access())
            .field("pdo_mappable", &self.pdo_mappable())
            .finish()
    }
}

/// SDO abort codes (CiA 301 table 22).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum SdoAbort {
    /// Toggle bit not alternated.
    ToggleBit = 0x0503_0000,
    /// SDO protocol timed out.
    Timeout = 0x0504_0000,
    /// Client/server command specifier not valid or unknown.
    InvalidCommand = 0x0504_0001,
    /// Invalid block size (block mode only).
    InvalidBlockSize = 0x0504_0002,
    /// Invalid sequence number (block mode only).
    InvalidSequence = 0x0504_0003,
    /// CRC error (block mode only).
    CrcError = 0x0504_0004,
    /// Out of memory.
    OutOfMemory = 0x0504_0005,
    /// Unsupported access to an object.
    UnsupportedAccess = 0x0601_0000,
    /// Attempt to read a write-only object.
    WriteOnly = 0x0601_0001,
    /// Attempt to write a read-only object.
    ReadOnly = 0x0601_0002,
    /// Object does not exist in the object dictionary.
    NoObject = 0x0602_0000,
    /// Object cannot be mapped to the PDO.
    NotMappable = 0x0604_0041,
    /// The number and length of the objects to be mapped would exceed the PDO length.
    PdoTooLong = 0x0604_0042,
    /// General parameter incompatibility.
    ParameterIncompatible = 0x0604_0043,
    /// General internal incompatibility in the device.
    InternalIncompatible = 0x0604_0047,
    /// Access failed due to a hardware error.
    Hardware = 0x0606_0000,
    /// Data type does not match, length of service parameter does not match.
    LengthMismatch = 0x0607_0010,
    /// Data type does not match, length of service parameter too high.
    LengthTooHigh = 0x0607_0012,
    /// Data type does not match, length of service parameter too low.
    LengthTooLow = 0x0607_0013,
    /// Sub-index does not exist.
    NoSubIndex = 0x0609_0011,
    /// Invalid value for parameter (download only).
    InvalidValue = 0x0609_0030,
    /// Value of parameter written too high (download only).
    ValueTooHigh = 0x0609_0031,
    /// Value of parameter written too low (download only).
    ValueTooLow = 0x0609_0032,
    /// Maximum value is less than minimum value.
    MaxBelowMin = 0x0609_0036,
    /// Resource not available: SDO connection.
    NoResource = 0x060A_0023,
    /// General error.
    General = 0x0800_0000,
    /// Data cannot be transferred or stored to the application.
    CannotStore = 0x0800_0020,
    /// Data cannot be transferred or stored because of local control.
    LocalControl = 0x0800_0021,
    /// Data cannot be transferred or stored because of the present device state.
    DeviceState = 0x0800_0022,
    /// Object dictionary dynamic generation fails or no object dictionary is present.
    NoDictionary = 0x0800_0023,
    /// No data available.
    NoData = 0x0800_0024,
}

impl SdoAbort {
    /// The 32-bit abort code as sent on the wire.
    pub const fn code(self) -> u32 {
        self as u32
    }
}

/// An object dictionary the protocol cores can serve.
///
/// `read` and `write` do not check access rights: the caller (SDO server, PDO engine, the node
/// itself) does, using [`ObjectDictionary::find`]. They do check lengths and value limits.
pub trait ObjectDictionary {
    /// How many entries there are: their positions are `0..entry_count()`.
    fn entry_count(&self) -> usize;

    /// The descriptor of the entry at `position` (entries sorted by (index, sub)), `None` past
    /// the end.
    fn entry(&self, position: usize) -> Option<EntryDescriptor>;

    /// The kind of the entry at `position`: all a protocol that has located an entry needs to
    /// know of it (a generated dictionary answers without finding the entry's index).
    #[inline]
    fn kind(&self, position: usize) -> Option<EntryKind> {
        self.entry(position).map(|entry| entry.kind())
    }

    /// Which of the node's optional services the dictionary has the objects of ([`Services`]).
    /// A node builds no code for the others, so the answer must not change at run time: every
    /// service by default, the generated dictionaries' own objects (a constant).
    #[inline]
    fn services(&self) -> Services {
        Services::ALL
    }

    /// Where (index, sub) is among the entries: the position [`entry`](Self::entry),
    /// [`read_at`](Self::read_at) and [`write_at`](Self::write_at) take. `NoObject` if the
    /// index is absent, `NoSubIndex` if only the sub-index is. The default is a binary search
    /// through [`entry`](Self::entry).
    fn locate(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        crate::od::typed::search(self.entry_count(), |p| self.entry(p), index, sub)
    }

    /// The descriptor of (index, sub): `NoObject` if the index is absent, `NoSubIndex` if only
    /// the sub-index is.
    fn find(&self, index: u16, sub: u8) -> Result<EntryDescriptor, SdoAbort> {
        self.entry(self.locate(index, sub)?)
            .ok_or(SdoAbort::NoObject)
    }

    /// The most bytes the value of the entry at `position` can hold: its data type's fixed
    /// size, or a string's, octet string's or domain's capacity. The SDO server refuses a longer
    /// download as soon as it is announced or exceeded (0607 0012). The default knows fixed
    /// sizes only (`None` for the others, so that a too-long download is refused by
    /// [`write_part`](Self::write_part) when a piece passes the end); a dictionary holding
    /// strings or domains says their capacity.
    fn capacity(&self, position: usize) -> Option<usize> {
        self.kind(position)?.data_type().fixed_size()
    }

    /// The current length in bytes of the value at (index, sub) (shorter than the capacity for a
    /// string or domain holding less). For a fixed-size data type it must be that size: the SDO
    /// server takes it from the descriptor without asking.
    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort>;

    /// [`value_len`](Self::value_len) of the entry at `position` among the entries,
    /// so that the SDO server, which has located the entry, uploads a string or domain without a
    /// second search. The default asks by the entry's (index, sub); the generated dictionaries
    /// answer from the position.
    fn value_len_at(&self, position: usize) -> Result<usize, SdoAbort> {
        let entry = self.entry(position).ok_or(SdoAbort::NoObject)?;
        self.value_len(entry.index(), entry.sub())
    }

    /// Copies the value's little-endian bytes, starting `offset` bytes into the value, into
    /// `buf`; returns how many bytes were copied (fewer than `buf.len()` at the end of the value).
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort>;

    /// Replaces the value at (index, sub) with `data` (little-endian), after checking its length
    /// and limits. On error the value is unchanged.
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort>;

    /// [`read`](Self::read) of the entry at `position` among the entries (from
    /// [`locate`](Self::locate)), so that a protocol that has looked an entry up reads it without
    /// a second search: the SDO server's expedited upload, a TPDO's mapped objects. The default
    /// reads by the entry's (index, sub); the generated dictionaries dispatch on the position.
    fn read_at(&self, position: usize, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let entry = self.entry(position).ok_or(SdoAbort::NoObject)?;
        self.read(entry.index(), entry.sub(), offset, buf)
    }

    /// Starts a download into the entry at `position` (a string, octet string or domain)
    /// streamed by [`write_part`](Self::write_part): one of the four steps of the streaming
    /// interface (begin, write, commit, abort) through which an SDO server writes a segmented or
    /// block download of a value whose length the data type does not fix. The server calls it
    /// once the entry is known to be writable, then `write_part` for each piece, and ends the
    /// download with exactly one of [`commit_write`](Self::commit_write) (the transfer
    /// completed, CRC checked) or [`abort_write`](Self::abort_write) (it ended any other way: an
    /// abort either side, a timeout, a new initiate, an NMT reset). A fixed-size value never
    /// streams: the server collects it and writes it whole.
    ///
    /// The contract is all or nothing: until `commit_write` the value reads as it was, and an
    /// aborted download leaves it so. The generated dictionaries and the run-time dictionary
    /// stage the pieces (in a buffer sized at generation time to their largest value) and
    /// write the value at `commit_write`. An application that keeps a domain outside the
    /// dictionary (a firmware image to flash, a file) writes the pieces where they go and, on
    /// `abort_write`, discards them (erases the half-written image), so that what was there
    /// before stays the value.
    ///
    /// A dictionary stages one download at a time: while one is open, `begin_write` for
    /// another (the second SDO channel's) answers `NoResource` (060A 0023), which the server
    /// sends as its abort. The default accepts every download and keeps no state, for a
    /// dictionary whose `write_part` and `commit_write` are its defaults.
    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        let _ = position;
        Ok(())
    }

    /// Takes `data`, the download's bytes from `offset` on, for the entry at `position` (see
    /// [`begin_write`](Self::begin_write)). Pieces come in order from offset 0, each within the
    /// entry's [`capacity`](Self::capacity). On error the server ends the download with
    /// [`abort_write`](Self::abort_write).
    ///
    /// The default writes the value through [`write_at`](Self::write_at) with the bytes so far,
    /// read back into a 32-byte buffer (a longer value is refused with 0504 0005, out of
    /// memory): enough for short values in a dictionary that implements nothing more, but not
    /// all or nothing, as each piece changes the value. A dictionary holding strings or domains
    /// implements the four steps.
    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let mut value = [0u8; 32];
        let end = offset + data.len();
        if end > value.len() {
            return Err(SdoAbort::OutOfMemory);
        }
        if self.read_at(position, 0, &mut value[..offset])? != offset {
            return Err(SdoAbort::General);
        }
        value[offset..end].copy_from_slice(data);
        self.write_at(position, &value[..end])
    }

    /// Ends a download streamed by [`write_part`](Self::write_part) that completed: the value
    /// becomes the `len` bytes written (0 when no piece came), with every check of
    /// [`write_at`](Self::write_at). The download is over whatever the result; on error the
    /// value is unchanged. The default writes an empty value for `len` 0 and otherwise has
    /// nothing left to do.
    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        if len == 0 {
            return self.write_at(position, &[]);
        }
        Ok(())
    }

    /// Ends a download streamed by [`write_part`](Self::write_part) that did not complete: the
    /// pieces are discarded and the value stays what it was before
    /// [`begin_write`](Self::begin_write). Called at most once per download, and never for a
    /// download that `begin_write` refused; a dictionary may still ignore a call with no
    /// download open. The default does nothing.
    fn abort_write(&mut self, position: usize) {
        let _ = position;
    }

    /// Sets every entry whose index is in `indices` to its power-on default, as a newly built
    /// dictionary for `node_id` holds it (`$NODEID` defaults computed from it). The node calls
    /// this on NMT resets (reset node: 0000h–FFFFh, reset communication: 1000h–1FFFh) through
    /// [`NodeHooks::restore_power_on`](crate::NodeHooks::restore_power_on). Returns `false` if
    /// the dictionary keeps no defaults (the default implementation: values stay as they are);
    /// the generated dictionaries restore their default image.
    fn restore_defaults(&mut self, indices: core::ops::RangeInclusive<u16>, node_id: u8) -> bool {
        let _ = (indices, node_id);
        false
    }

    /// [`write`](Self::write) of the entry at `position` among the entries, as
    /// [`read_at`](Self::read_at) reads: an RPDO's mapped objects, an SDO expedited download.
    fn write_at(&mut self, position: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let entry = self.entry(position).ok_or(SdoAbort::NoObject)?;
        self.write(entry.index(), entry.sub(), data)
    }
}

/// Every entry of `od` with its position, in order.
pub fn descriptors<O: ObjectDictionary + ?Sized>(
    od: &O,
) -> impl Iterator<Item = (usize, EntryDescriptor)> + '_ {
    (0..od.entry_count()).filter_map(|position| Some((position, od.entry(position)?)))
}

#[cfg(test)]
mod tests {
    use super::DataType::{self, *};
    use super::{Access, EntryDescriptor};

    #[test]
    fn a_descriptor_is_five_bytes_and_gives_back_its_parts() {
        assert_eq!(core::mem::size_of::<EntryDescriptor>(), 5);
        let accesses = [
            Access::Ro,
            Access::Wo,
            Access::Rw,
            Access::Rwr,
            Access::Rww,
            Access::Const,
        ];
        for access in accesses {
            for mappable in [false, true] {
                let e = EntryDescriptor::new(0xA1B2, 0xFE, Domain, access, mappable);
                assert_eq!(
                    (
                        e.index(),
                        e.sub(),
                        e.data_type(),
                        e.access(),
                        e.pdo_mappable()
                    ),
                    (0xA1B2, 0xFE, Domain, access, mappable)
                );
            }
        }
        assert_eq!(
            format!(
                "{:?}",
                EntryDescriptor::new(0x1017, 0, Unsigned16, Access::Rw, true)
            ),
            "EntryDescriptor { index: 4119, sub: 0, data_type: Unsigned16, access: Rw, \
             pdo_mappable: true }"
        );
    }

    #[test]
    fn every_data_type_has_its_cia_301_size() {
        let sizes: [(DataType, Option<usize>); 25] = [
            (Boolean, Some(1)),
            (Integer8, Some(1)),
            (Integer16, Some(2)),
            (Integer24, Some(3)),
            (Integer32, Some(4)),
            (Integer40, Some(5)),
            (Integer48, Some(6)),
            (Integer56, Some(7)),
            (Integer64, Some(8)),
            (Unsigned8, Some(1)),
            (Unsigned16, Some(2)),
            (Unsigned24, Some(3)),
            (Unsigned32, Some(4)),
            (Unsigned40, Some(5)),
            (Unsigned48, Some(6)),
            (Unsigned56, Some(7)),
            (Unsigned64, Some(8)),
            (Real32, Some(4)),
            (Real64, Some(8)),
            (VisibleString, None),
            (OctetString, None),
            (UnicodeString, None),
            (TimeOfDay, Some(6)),
            (TimeDifference, Some(6)),
            (Domain, None),
        ];
        for (data_type, size) in sizes {
            assert_eq!(data_type.fixed_size(), size, "{data_type:?}");
        }
    }
}
