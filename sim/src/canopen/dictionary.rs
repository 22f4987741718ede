//! The run-time object dictionary: any device the readers read (EDS, DCF, XDD, XDC), served by
//! the runtime's `Node` without generated code. Each entry's type, access, limits and initial
//! value come from [`edsgen_model::values`], as the code generator's do, so it answers exactly as
//! the `Od` generated from the same file would; only the storage differs (one `Vec<u8>` per
//! entry).
//!
//! Capacities: a string or octet string holds what the generated `Od` would hold (its overlay's
//! capacity, else the longest of its DefaultValue and ParameterValue, and at least
//! [`MIN_WRITABLE_CAPACITY`](edsgen_model::model::layout::MIN_WRITABLE_CAPACITY) bytes when it
//! is writable). A DOMAIN holds up to [`DOMAIN_CAPACITY`] bytes (a firmware image or a log fits;
//! the bytes are allocated only as written).

use edsgen_model::model::layout::{Number, RustType};
use edsgen_model::model::{AccessType, BasicType, Device};
use edsgen_model::values::{stored_values, Initial};
use edsgen_runtime::od::typed::read_bytes;
use edsgen_runtime::{
    Access, DataType, EntryDescriptor, NodeHooks, ObjectDictionary, ResetKind, SdoAbort,
};

/// The most bytes a DOMAIN entry holds (64 KiB).
pub const DOMAIN_CAPACITY: usize = 0x1_0000;

/// An object dictionary built at run time from a device model.
#[derive(Debug, Clone, PartialEq)]
pub struct RuntimeDictionary {
    entries: Vec<EntryDescriptor>,
    slots: Vec<Slot>,
    left_out: Vec<(u16, String)>,
    /// The SDO download open in the dictionary, if one is: the entry's position and the pieces
    /// streamed so far ([`ObjectDictionary::write_part`]), applied with every check by
    /// [`ObjectDictionary::commit_write`] and dropped by [`ObjectDictionary::abort_write`].
    download: Option<(usize, Vec<u8>)>,
}

/// One entry's value and what a write must respect.
#[derive(Debug, Clone, PartialEq)]
struct Slot {
    value: Vec<u8>,
    /// The value after power-on and after a reset: the DCF's ParameterValue, else the default,
    /// with `$NODEID` resolved.
    initial: Vec<u8>,
    /// A fixed-size value's size, or a string's, octet string's or domain's capacity.
    size: usize,
    limits: Option<(Number, Number)>,
    /// A `$NODEID` default's offset: `initial` is recomputed when the node-ID changes (an LSS
    /// master gives an unconfigured node one).
    node_offset: Option<u64>,
}

impl RuntimeDictionary {
    /// Every entry's descriptor, sorted by (index, sub-index): positions are indices here.
    pub fn entries(&self) -> &[EntryDescriptor] {
        &self.entries
    }

    /// Every object of `device` from 1000h on, with `$NODEID` defaults computed for `node_id`.
    /// An object the generated code could not represent either (an entry without a basic data
    /// type, a default that does not fit its type) is left out whole; see
    /// [`left_out`](Self::left_out).
    pub fn new(device: &Device, node_id: u8) -> Self {
        let values = stored_values(device);
        let mut entries = Vec::with_capacity(values.len());
        let mut slots = Vec::with_capacity(values.len());
        for entry in &values {
            let size = match entry.ty {
                RustType::Scalar(_, wire) => wire,
                RustType::Bytes(_) if entry.basic == BasicType::Domain => DOMAIN_CAPACITY,
                RustType::Bytes(capacity) => capacity,
            };
            let initial = match &entry.init {
                Initial::Raw(bits) => bits.to_le_bytes()[..size].to_vec(),
                // The node-ID is added within the entry's width; a carry out of it is dropped,
                // as the generated `Od::new` does.
                Initial::NodeRelative(offset) => {
                    offset.wrapping_add(u64::from(node_id)).to_le_bytes()[..size].to_vec()
                }
                Initial::Bytes(bytes) => bytes.clone(),
            };
            entries.push(EntryDescriptor::new(
                entry.index,
                entry.sub,
                data_type(entry.basic),
                access(entry.access),
                entry.pdo_mappable,
            ));
            let node_offset = match &entry.init {
                Initial::NodeRelative(offset) => Some(*offset),
                _ => None,
            };
            slots.push(Slot {
                value: initial.clone(),
                initial,
                size,
                limits: entry.limits,
                node_offset,
            });
        }
        let left_out = device
            .objects
            .values()
            .filter(|o| o.index >= 0x1000 && !o.subs.is_empty())
            .filter(|o| {
                entries
                    .binary_search_by_key(&o.index, |e| e.index())
                    .is_err()
            })
            .map(|o| (o.index, o.name.clone()))
            .collect();
        RuntimeDictionary {
            entries,
            slots,
            left_out,
            download: None,
        }
    }

    /// The objects of the model this dictionary does not hold (index and name): those whose
    /// data type or default cannot be represented (`edsgen generate` says why, EDS702/EDS703).
    pub fn left_out(&self) -> &[(u16, String)] {
        &self.left_out
    }

    /// Sets the entries `kind` re-initialises back to their initial values: all of them for
    /// reset node, the communication area (1000h–1FFFh) for reset communication.
    pub fn reset(&mut self, kind: ResetKind) {
        self.reset_to(kind, None);
    }

    /// [`reset`](Self::reset), to the `stored` values (one per entry) where given.
    fn reset_to(&mut self, kind: ResetKind, stored: Option<&[Vec<u8>]>) {
        for (position, (entry, slot)) in self.entries.iter().zip(&mut self.slots).enumerate() {
            if kind == ResetKind::Node || (0x1000..=0x1FFF).contains(&entry.index()) {
                let value = stored.and_then(|values| values.get(position));
                slot.value.clone_from(value.unwrap_or(&slot.initial));
            }
        }
    }

    /// Sets an unsigned entry's value and the value resets return to (a simulated device's own
    /// serial number, 1018h:04). `false` if the entry is absent or not 1 to 8 bytes.
    pub fn set_initial(&mut self, index: u16, sub: u8, value: u64) -> bool {
        let Ok(position) = self
            .entries
            .binary_search_by_key(&(index, sub), |e| (e.index(), e.sub()))
        else {
            return false;
        };
        let slot = &mut self.slots[position];
        if !(1..=8).contains(&slot.size) {
            return false;
        }
        slot.initial = value.to_le_bytes()[..slot.size].to_vec();
        slot.node_offset = None;
        slot.value.clone_from(&slot.initial);
        true
    }

    /// The current value of the entry at `position`, if there is one.
    pub fn value_at(&self, position: usize) -> Option<&[u8]> {
        self.slots.get(position).map(|slot| slot.value.as_slice())
    }
}

impl ObjectDictionary for RuntimeDictionary {
    fn entry_count(&self) -> usize {
        self.entries.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.entries.get(position).copied()
    }

    /// Recomputes the `$NODEID` defaults for `node_id` (the node-ID may have changed, by LSS)
    /// and sets the entries in `indices` to their initial values.
    fn restore_defaults(&mut self, indices: core::ops::RangeInclusive<u16>, node_id: u8) -> bool {
        for (entry, slot) in self.entries.iter().zip(&mut self.slots) {
            if let Some(offset) = slot.node_offset {
                let size = slot.size.min(8);
                slot.initial =
                    offset.wrapping_add(u64::from(node_id)).to_le_bytes()[..size].to_vec();
            }
            if indices.contains(&entry.index()) {
                slot.value.clone_from(&slot.initial);
            }
        }
        true
    }

    fn capacity(&self, position: usize) -> Option<usize> {
        self.slots.get(position).map(|slot| slot.size)
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        let slot = self.slots.get(self.locate(index, sub)?);
        Ok(slot.ok_or(SdoAbort::NoObject)?.value.len())
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.read_at(self.locate(index, sub)?, offset, buf)
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        self.write_at(self.locate(index, sub)?, data)
    }

    fn read_at(&self, position: usize, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        let slot = self.slots.get(position).ok_or(SdoAbort::NoObject)?;
        Ok(read_bytes(&slot.value, offset, buf))
    }

    /// Opens a download: one at a time, as a generated `Od`'s stage (`NoResource` while
    /// another SDO channel's is open).
    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        if self.download.is_some() {
            return Err(SdoAbort::NoResource);
        }
        self.capacity(position).ok_or(SdoAbort::NoObject)?;
        self.download = Some((position, Vec::new()));
        Ok(())
    }

    /// Collects one piece of a segmented or block download; the value changes only when
    /// [`commit_write`](ObjectDictionary::commit_write) applies the whole of it.
    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let capacity = self.capacity(position).ok_or(SdoAbort::NoObject)?;
        if offset + data.len() > capacity {
            return Err(SdoAbort::LengthTooHigh);
        }
        match &mut self.download {
            Some((open, bytes)) if *open == position => {
                bytes.truncate(offset);
                bytes.extend_from_slice(data);
                Ok(())
            }
            _ => Err(SdoAbort::General),
        }
    }

    /// Applies the streamed download with [`write_at`](ObjectDictionary::write_at)'s checks.
    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        match self.download.take() {
            Some((open, mut value)) if open == position => {
                value.truncate(len);
                self.write_at(position, &value)
            }
            other => {
                self.download = other;
                Err(SdoAbort::General)
            }
        }
    }

    /// Drops the streamed download: the value stays as it was.
    fn abort_write(&mut self, position: usize) {
        if self
            .download
            .as_ref()
            .is_some_and(|(open, _)| *open == position)
        {
            self.download = None;
        }
    }

    /// The checks of the generated `Od` (`edsgen_runtime::od::image::Layout::write`): a fixed-size
    /// value takes exactly its size, a BOOLEAN only 0 or 1, a limited value only what its limits
    /// allow; a string, octet string or domain at most its capacity. On error nothing changes.
    fn write_at(&mut self, position: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let data_type = self
            .entries
            .get(position)
            .ok_or(SdoAbort::NoObject)?
            .data_type();
        let slot = self.slots.get_mut(position).ok_or(SdoAbort::NoObject)?;
        if data_type.fixed_size().is_none() {
            if data.len() > slot.size {
                return Err(SdoAbort::LengthTooHigh);
            }
        } else {
            if data.len() != slot.size {
                return Err(if data.len() > slot.size {
                    SdoAbort::LengthTooHigh
                } else {
                    SdoAbort::LengthTooLow
                });
            }
            if data_type == DataType::Boolean && data[0] > 1 {
                return Err(SdoAbort::InvalidValue);
            }
            if let Some((low, high)) = slot.limits {
                check_limits(data_type, data, low, high)?;
            }
        }
        slot.value.clear();
        slot.value.extend_from_slice(data);
        Ok(())
    }
}

/// Hooks for a `Node` serving a [`RuntimeDictionary`]: resets restore the initial values of the
/// area they re-initialise; "save" (1010h, any sub-index) keeps every current value in memory
/// for the next resets, and "load" (1011h) brings the initial values back at the next reset, as a
/// device with non-volatile storage would (nothing survives the process).
#[derive(Debug, Clone, Default)]
pub struct DictionaryHooks {
    /// Every entry's value when "save" was last written, until "load".
    stored: Option<Vec<Vec<u8>>>,
    /// The node-ID and bit timing an LSS master stored last.
    pub lss_stored: Option<(u8, Option<edsgen_runtime::node::BitTiming>)>,
}

impl NodeHooks<RuntimeDictionary> for DictionaryHooks {
    fn reset(&mut self, kind: ResetKind, od: &mut RuntimeDictionary) {
        od.reset_to(kind, self.stored.as_deref());
    }

    fn save(&mut self, _sub: u8, od: &RuntimeDictionary) -> Result<(), SdoAbort> {
        self.stored = Some(od.slots.iter().map(|slot| slot.value.clone()).collect());
        Ok(())
    }

    fn restore_defaults(&mut self, _sub: u8) -> Result<(), SdoAbort> {
        self.stored = None;
        Ok(())
    }

    /// Keeps the LSS configuration in memory: the node starts with the stored node-ID after a
    /// reset node (the node keeps it), as a device with non-volatile storage would.
    fn store_lss(
        &mut self,
        node_id: u8,
        bit_timing: Option<edsgen_runtime::node::BitTiming>,
    ) -> Result<(), edsgen_runtime::wire::lss::LssError> {
        self.lss_stored = Some((node_id, bit_timing));
        Ok(())
    }
}

/// `ValueTooLow`/`ValueTooHigh` when the little-endian `data` of a `data_type` value lies
/// outside `low..=high`. A NaN passes, as it compares neither below nor above.
fn check_limits(
    data_type: DataType,
    data: &[u8],
    low: Number,
    high: Number,
) -> Result<(), SdoAbort> {
    let value = number(data_type, data);
    let below = |limit: Number| match (value, limit) {
        (Number::Integer(v), Number::Integer(l)) => v < l,
        (Number::Real(v), Number::Real(l)) => v < l,
        _ => false,
    };
    let above = |limit: Number| match (value, limit) {
        (Number::Integer(v), Number::Integer(h)) => v > h,
        (Number::Real(v), Number::Real(h)) => v > h,
        _ => false,
    };
    if below(low) {
        Err(SdoAbort::ValueTooLow)
    } else if above(high) {
        Err(SdoAbort::ValueTooHigh)
    } else {
        Ok(())
    }
}

/// The number a fixed-size little-endian value holds.
pub(crate) fn number(data_type: DataType, data: &[u8]) -> Number {
    let mut bytes = [0u8; 8];
    let n = data.len().min(8);
    bytes[..n].copy_from_slice(&data[..n]);
    let raw = u64::from_le_bytes(bytes);
    match data_type {
        DataType::Real32 => Number::Real(f64::from(f32::from_bits(raw as u32))),
        DataType::Real64 => Number::Real(f64::from_bits(raw)),
        _ if is_signed(data_type) && n > 0 => {
            let shift = 64 - 8 * n as u32;
            Number::Integer(i128::from(((raw << shift) as i64) >> shift))
        }
        _ => Number::Integer(i128::from(raw)),
    }
}

/// Whether `data_type` is a signed integer.
pub(crate) fn is_signed(data_type: DataType) -> bool {
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

/// The runtime's data type for a basic type of the model.
pub fn data_type(basic: BasicType) -> DataType {
    use BasicType as B;
    use DataType as D;
    match basic {
        B::Boolean => D::Boolean,
        B::Integer8 => D::Integer8,
        B::Integer16 => D::Integer16,
        B::Integer24 => D::Integer24,
        B::Integer32 => D::Integer32,
        B::Integer40 => D::Integer40,
        B::Integer48 => D::Integer48,
        B::Integer56 => D::Integer56,
        B::Integer64 => D::Integer64,
        B::Unsigned8 => D::Unsigned8,
        B::Unsigned16 => D::Unsigned16,
        B::Unsigned24 => D::Unsigned24,
        B::Unsigned32 => D::Unsigned32,
        B::Unsigned40 => D::Unsigned40,
        B::Unsigned48 => D::Unsigned48,
        B::Unsigned56 => D::Unsigned56,
        B::Unsigned64 => D::Unsigned64,
        B::Real32 => D::Real32,
        B::Real64 => D::Real64,
        B::VisibleString => D::VisibleString,
        B::OctetString => D::OctetString,
        B::UnicodeString => D::UnicodeString,
        B::TimeOfDay => D::TimeOfDay,
        B::TimeDifference => D::TimeDifference,
        B::Domain => D::Domain,
    }
}

fn access(access: AccessType) -> Access {
    match access {
        AccessType::Ro => Access::Ro,
        AccessType::Wo => Access::Wo,
        AccessType::Rw => Access::Rw,
        AccessType::Rwr => Access::Rwr,
        AccessType::Rww => Access::Rww,
        AccessType::Const => Access::Const,
    }
}
