//! The mapping a PDO packs or unpacks (1600h–17FFh, 1A00h–1BFFh) and the checks a mapping entry
//! must pass (CiA 301 §7.4.7).

use crate::od::{ObjectDictionary, SdoAbort};
use crate::wire::pdo::MappingEntry;

/// The most objects one PDO can map.
pub const MAX_MAPPED: usize = 8;

/// One mapped object, checked: where its value is in the OD's table and how many bytes of the
/// payload it takes. Its position rather than its index and sub-index: packing and unpacking do
/// not search, and a mapping takes 4 bytes an object.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct MappedObject {
    /// Its position in the OD's table (found when the mapping was checked); [`DUMMY`] for a
    /// dummy entry.
    pub position: u16,
    pub len: u8,
}

/// [`MappedObject::position`] of a dummy entry, which has none: an RPDO skips its bytes, a TPDO
/// sends zeros there.
const DUMMY: u16 = u16::MAX;

/// The checked mapping of one PDO.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Mapping {
    pub objects: [MappedObject; MAX_MAPPED],
    pub count: u8,
    /// Payload length in bytes.
    pub len: u8,
}

impl Mapping {
    /// No objects, for [`Rpdo::OFF`](super::Rpdo::OFF), [`Tpdo::OFF`](super::Tpdo::OFF) and the
    /// mapping an SDO write is checked into.
    pub const EMPTY: Mapping = Mapping {
        objects: [MappedObject {
            position: 0,
            len: 0,
        }; MAX_MAPPED],
        count: 0,
        len: 0,
    };

    #[inline]
    pub fn objects(&self) -> &[MappedObject] {
        &self.objects[..self.count as usize]
    }

    /// Whether the object at `position` in the OD's table is mapped.
    #[inline]
    pub fn contains(&self, position: u16) -> bool {
        self.objects().iter().any(|o| o.position == position)
    }

    /// Reads the mapped objects into a payload (dummies give zeros).
    #[inline]
    pub fn pack<O: ObjectDictionary + ?Sized>(&self, od: &O) -> [u8; 8] {
        let mut data = [0u8; 8];
        let mut offset = 0usize;
        for object in self.objects() {
            let end = offset + object.len as usize;
            if object.position != DUMMY {
                if let Some(slot) = data.get_mut(offset..end) {
                    // A failed read leaves zeros: the mapping was checked, so this only happens
                    // when the OD refuses its own entry.
                    let _ = od.read_at(usize::from(object.position), 0, slot);
                }
            }
            offset = end;
        }
        data
    }

    /// Writes a payload's bytes into the mapped objects, all or none: if the OD refuses a value
    /// (a limit), the objects written before it get their previous values back and the refusal
    /// is returned. A single object at a known position is written straight to it: the OD
    /// leaves a refused value unchanged, so there is nothing to copy or restore.
    #[inline]
    pub fn unpack<O: ObjectDictionary + ?Sized>(
        &self,
        od: &mut O,
        data: &[u8],
    ) -> Result<(), SdoAbort> {
        // One object that is not a dummy (a PDO's most common mapping).
        let object = self.objects[0];
        if self.count == 1 && object.position != DUMMY {
            return match data.get(..usize::from(object.len)) {
                Some(bytes) => od.write_at(usize::from(object.position), bytes),
                None => Ok(()),
            };
        }
        self.unpack_any(od, data)
    }

    /// [`Mapping::unpack`] of any mapping (several objects, a dummy): the previous values are kept to restore. Cold, so that a speed-optimized build
    /// keeps it and its calls out of the one-object path, which then needs a small frame and is
    /// inlined; a size-optimized build inlines it at its one call, at no cost in flash.
    #[cold]
    fn unpack_any<O: ObjectDictionary + ?Sized>(
        &self,
        od: &mut O,
        data: &[u8],
    ) -> Result<(), SdoAbort> {
        let previous = self.pack(od);
        let mut outcome = Ok(());
        let (mut values, mut count) = (data, MAX_MAPPED);
        // If the OD refuses a value, a second pass writes the previous values back into the
        // objects written before it (they were accepted once; they are again). One call of
        // `write_objects` for both passes: 16 B less flash than a second call.
        while let Err((written, abort)) = self.write_objects(od, values, count) {
            if outcome.is_err() {
                break;
            }
            outcome = Err(abort);
            (values, count) = (&previous, written);
        }
        outcome
    }

    /// Writes the payload's bytes into the first `count` mapped objects (dummies skipped); on a
    /// refusal, how many objects come before the refused one, and why.
    fn write_objects<O: ObjectDictionary + ?Sized>(
        &self,
        od: &mut O,
        data: &[u8],
        count: usize,
    ) -> Result<(), (usize, SdoAbort)> {
        let mut offset = 0usize;
        for (n, object) in self.objects().iter().take(count).enumerate() {
            let end = offset + object.len as usize;
            if object.position != DUMMY {
                if let Some(bytes) = data.get(offset..end) {
                    od.write_at(usize::from(object.position), bytes)
                        .map_err(|abort| (n, abort))?;
                }
            }
            offset = end;
        }
        Ok(())
    }
}

/// Size in bits of a dummy-mapping data type (0002h–0007h); BOOLEAN (0001h) is bit-sized and
/// not supported.
fn dummy_bits(index: u16) -> Option<u8> {
    match index {
        0x0002 | 0x0005 => Some(8),
        0x0003 | 0x0006 => Some(16),
        0x0004 | 0x0007 => Some(32),
        _ => None,
    }
}

/// Checks one mapping entry against the OD: 0604 0041 if the object is absent, not mappable in
/// the direction (an RPDO's `receive` objects must be writable, a TPDO's readable), or its length
/// does not match. Dummy entries (0002h–0007h with their type's length) are accepted in both
/// directions.
fn check_entry<O: ObjectDictionary + ?Sized>(
    od: &O,
    entry: MappingEntry,
    receive: bool,
) -> Result<MappedObject, SdoAbort> {
    if entry.bits == 0 || entry.bits % 8 != 0 {
        return Err(SdoAbort::NotMappable);
    }
    let len = entry.bits / 8;
    if entry.is_dummy() {
        // CiA 301 defines dummies for RPDOs (bytes to skip); vendor EDS files also pad TPDOs
        // with them (the Goodrive350 card's TPDO1), which then carry zeros there.
        return match dummy_bits(entry.index) {
            Some(bits) if bits == entry.bits => Ok(MappedObject {
                position: DUMMY,
                len,
            }),
            _ => Err(SdoAbort::NotMappable),
        };
    }
    let position = od
        .locate(entry.index, entry.sub)
        .map_err(|_| SdoAbort::NotMappable)?;
    let descriptor = od.kind(position).ok_or(SdoAbort::NotMappable)?;
    let allowed = if receive {
        descriptor.access().writable()
    } else {
        descriptor.access().readable()
    };
    // A DOMAIN has no fixed size, so the length check refuses it too.
    let size = descriptor.data_type().fixed_size();
    if !descriptor.pdo_mappable() || !allowed || size != Some(len as usize) {
        return Err(SdoAbort::NotMappable);
    }
    // A table of more than 65,535 entries maps only its first 65,535.
    let position = u16::try_from(position)
        .ok()
        .filter(|&position| position != DUMMY)
        .ok_or(SdoAbort::NotMappable)?;
    Ok(MappedObject { position, len })
}

/// Checks the mapping record at `index` (1600h+n of an RPDO, 1A00h+n of a TPDO) as it is with
/// `value` in sub-index `sub` (CiA 301 §7.4.7): one check for a PDO's mapping at reset (`sub` 0,
/// `value` the record's count) and for an SDO write to the record.
/// - Sub 0, the number of mapped objects: entries 1 to `value` of the record must form a valid
///   mapping: 0604 0042 if there are too many or they exceed 8 bytes, 0604 0041 if one cannot
///   be mapped.
/// - Sub n, an entry: only while the mapping is deactivated (sub 0 is 0; 0800 0022 otherwise),
///   and the entry must be mappable (0604 0041) unless it is 0.
///
/// The mapping is written into `mapping`, which must be empty: its objects as they are checked,
/// its count and length once all passed, so that a refused mapping leaves it empty. In place
/// rather than returned, which would move the 50-byte mapping twice on its way into a PDO.
pub(crate) fn check_mapping<O: ObjectDictionary + ?Sized>(
    od: &O,
    index: u16,
    sub: u8,
    value: u32,
    mapping: &mut Mapping,
) -> Result<(), SdoAbort> {
    // Bit 11 of the index tells the directions apart.
    let receive = index & 0x0800 == 0;
    // How many entries to check: those of the record for sub 0, the one written otherwise.
    let count = if sub == 0 {
        value
    } else if crate::node::read_uint_or(od, index, 0, 0) != 0 {
        return Err(SdoAbort::DeviceState);
    } else {
        u32::from(value != 0)
    };
    if count as usize > MAX_MAPPED {
        return Err(SdoAbort::PdoTooLong);
    }
    let mut total = 0usize;
    // Half-open ranges here and in the node's other sub-index loops (1003h, 1016h): an
    // inclusive one carries an exhausted flag and steps through `RangeInclusive::next`, some
    // 240 B more flash over the four loops.
    for (slot, entry) in mapping.objects.iter_mut().zip(1..count as u8 + 1) {
        let raw = if sub == 0 {
            crate::node::read_uint(od, index, entry).ok_or(SdoAbort::NotMappable)?
        } else {
            value
        };
        *slot = check_entry(od, MappingEntry::from_u32(raw), receive)?;
        total += slot.len as usize;
        if total > 8 {
            return Err(SdoAbort::PdoTooLong);
        }
    }
    mapping.count = count as u8;
    mapping.len = total as u8;
    Ok(())
}
