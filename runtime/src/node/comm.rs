//! The CiA 301 rules for SDO writes to communication objects (1003h–1029h, 1200h–1BFFh): the
//! PDO mapping procedure, the COB-ID rules (valid bit, restricted CAN-IDs), SYNC, heartbeat
//! consumer and store/restore signatures.
//!
//! [`CommGuard`] is the dictionary the SDO server runs on: it implements [`ObjectDictionary`],
//! delegates everything, and runs [`CommGuard::check`] on each write to a communication object
//! before it reaches the OD. The node applies an accepted write to its running state afterwards.
//!
//! Why a wrapper rather than a check the node calls before handing the request on: the server
//! decides when a write happens (an expedited download at once, a segmented or block one at its
//! last segment, by index or by table position) and answers it in the same step, so a check
//! outside would need the server to stop before every write and wait for a verdict, a second
//! contract for every user of the server. Standing in the server's place as its dictionary, the
//! rules see every write on every path, in one function, and the server stays the same whoever
//! serves it. Strings and domains, which stream (`write_part`), have no rule to pass.

use super::pdo::{self, Mapping};
use super::{read_uint, read_uint_or, NodeHooks};
use crate::od::{EntryDescriptor, EntryKind, ObjectDictionary, SdoAbort, Services};
use crate::wire::pdo::CobIdEntry;
use crate::wire::sdo::{SDO_REQUEST_BASE, SDO_RESPONSE_BASE};

/// The "save" signature for 1010h (CiA 301 §7.5.2.13), as the little-endian bytes of 65766173h.
pub const SAVE_SIGNATURE: [u8; 4] = *b"save";
/// The "load" signature for 1011h (CiA 301 §7.5.2.14), as the little-endian bytes of 64616F6Ch.
pub const LOAD_SIGNATURE: [u8; 4] = *b"load";

/// The OD as the SDO server sees it: writes to communication objects are checked first.
pub(crate) struct CommGuard<'a, O: ?Sized, H> {
    pub od: &'a mut O,
    pub hooks: &'a mut H,
    pub node_id: u8,
}

/// What a write that passed the rules still needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Checked {
    /// The value goes into the OD.
    Write,
    /// The rule did what the write asks (store, restore): nothing to write.
    Done,
}

/// The first four bytes of a written value (fewer for a shorter one) as a little-endian number.
fn value_u32(data: &[u8]) -> u32 {
    data.iter()
        .take(4)
        .rev()
        .fold(0, |value, &byte| value << 8 | u32::from(byte))
}

/// CAN-IDs CiA 301 §7.3.5 restricts (NMT, the node-0 SYNC/EMCY/TIME range, the default SDO,
/// LSS and error-control ranges): no configurable COB-ID (1005h, 1012h, 1014h, SDO and PDO
/// parameters) may use them. 080h (SYNC), 100h (TIME), 700h and the PDOs' default ranges are
/// not among them.
fn restricted(can_id: u16) -> bool {
    matches!(
        can_id,
        0x000..=0x07F | 0x101..=0x180 | 0x581..=0x5FF | 0x601..=0x67F | 0x6E0..=0x6FF | 0x701..=0x7FF
    )
}

/// The bit of a COB-ID entry that marks its CAN-ID in use, for [`check_cob_id`]: the valid bit
/// (bit 31, set: not valid) of EMCY (1014h), SDO and PDO parameters, whose valid entries use
/// their CAN-ID; bit 30 of SYNC (1005h), set while the node produces SYNC; none for TIME
/// (1012h), whose CAN-ID may always change. One rule for the three rather than a function each.
fn in_use_bit(index: u16) -> u32 {
    match index {
        0x1005 => CobIdEntry::BIT30,
        0x1012 => 0,
        _ => CobIdEntry::INVALID,
    }
}

/// A COB-ID entry may change its CAN-ID only while the CAN-ID is not in use (`in_use`, from
/// [`in_use_bit`]); a value that is not invalid must not use a restricted CAN-ID unless it is
/// in `exempt` (an SDO channel's pre-defined ones); 29-bit identifiers are not served.
fn check_cob_id(
    old: Option<u32>,
    new: u32,
    exempt: (u16, u16),
    in_use: u32,
) -> Result<(), SdoAbort> {
    // Bit 31 where it is the valid bit: a value that is not valid has no rule to pass.
    let invalid = in_use & CobIdEntry::INVALID;
    if new & invalid != 0 {
        return Ok(());
    }
    let id = CobIdEntry(new).can_id();
    if CobIdEntry(new).extended() || (restricted(id) && !(exempt.0 <= id && id <= exempt.1)) {
        return Err(SdoAbort::InvalidValue);
    }
    let used = |value: u32| (value ^ invalid) & in_use != 0;
    match old {
        Some(old) if used(old) && used(new) && CobIdEntry(old).can_id() != id => {
            Err(SdoAbort::InvalidValue)
        }
        _ => Ok(()),
    }
}

/// No exemption from the restricted CAN-IDs.
const NOT_EXEMPT: (u16, u16) = (1, 0);

/// The restricted CAN-IDs a COB-ID entry may use: an SDO parameter (1200h+n server, 1280h+n
/// client; `sub` 1 client to server, 2 server to client) the default server's (1200h) own
/// pre-defined pair, a client's any node's pre-defined pair (how it reaches another node's
/// default server); any other entry none.
fn sdo_exempt(index: u16, sub: u8, node_id: u8) -> (u16, u16) {
    let node = u16::from(node_id);
    let base = if sub == 1 {
        SDO_REQUEST_BASE
    } else {
        SDO_RESPONSE_BASE
    };
    match index {
        0x1200 => (base + node, base + node),
        0x1280..=0x12FF => (base + 1, base + 0x7F),
        _ => NOT_EXEMPT,
    }
}

impl<O: ObjectDictionary + ?Sized, H: NodeHooks<O>> CommGuard<'_, O, H> {
    /// Checks a write to a PDO's communication parameter (`index` 1400h+n or 1800h+n) or
    /// mapping (1600h+n or 1A00h+n): bit 11 of the index tells the directions apart, bit 9
    /// communication from mapping. Most rules look at whether the PDO is valid, so its COB-ID
    /// is read once for all of them.
    fn check_pdo(&self, index: u16, sub: u8, value: u32) -> Result<(), SdoAbort> {
        let valid =
            read_uint(self.od, index & !0x0200, 1).is_some_and(|cob| CobIdEntry(cob).valid());
        if index & 0x0200 == 0 {
            return match sub {
                2 => match value {
                    0..=240 | 254 | 255 => Ok(()),
                    // Only a TPDO is sent on RTR.
                    252 | 253 if index & 0x0800 != 0 => Ok(()),
                    _ => Err(SdoAbort::InvalidValue),
                },
                3 if valid => Err(SdoAbort::InvalidValue),
                6 if valid || value > 240 => Err(SdoAbort::InvalidValue),
                _ => Ok(()),
            };
        }
        if valid {
            return Err(SdoAbort::DeviceState);
        }
        // The checked mapping is not kept: the node reloads the PDO once the write is done.
        let mut checked = Mapping::EMPTY;
        pdo::check_mapping(self.od, index, sub, value, &mut checked)
    }

    fn check_heartbeat_consumer(&self, sub: u8, value: u32) -> Result<(), SdoAbort> {
        let node = (value >> 16) as u8;
        let time = value as u16;
        if node == 0 || time == 0 {
            return Ok(());
        }
        let count = read_uint_or(self.od, 0x1016, 0, 0) as u8;
        let duplicate = (1..u16::from(count) + 1)
            .map(|s| s as u8)
            .filter(|&s| s != sub)
            .any(|s| {
                read_uint(self.od, 0x1016, s)
                    .is_some_and(|other| (other >> 16) as u8 == node && other as u16 != 0)
            });
        if duplicate {
            Err(SdoAbort::ParameterIncompatible)
        } else {
            Ok(())
        }
    }

    /// Checks a write to a communication object against the rules.
    fn check(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<Checked, SdoAbort> {
        let value = value_u32(data);
        // The COB-ID entries (SYNC, TIME, EMCY, SDO and PDO parameters): one call.
        if matches!(
            (index, sub),
            (0x1005 | 0x1012 | 0x1014, _)
                | (0x1200..=0x12FF, 1 | 2)
                | (0x1400..=0x15FF | 0x1800..=0x19FF, 1)
        ) {
            let exempt = sdo_exempt(index, sub, self.node_id);
            let old = read_uint(self.od, index, sub);
            return check_cob_id(old, value, exempt, in_use_bit(index)).map(|()| Checked::Write);
        }
        match index {
            // No rule's code for the objects a dictionary lacks: they are never written.
            0x1003 if !self.od.services().error_history => Ok(Checked::Write),
            0x1019 if !self.od.services().sync_counter => Ok(Checked::Write),
            0x1003 if sub == 0 && value != 0 => Err(SdoAbort::InvalidValue),
            0x1003 if sub == 0 => {
                // Deleting the history: the codes go too, so the sub-indices read 0.
                let recorded = crate::od::descriptors(&*self.od)
                    .filter(|(_, e)| e.index() == 0x1003)
                    .count();
                for sub in 1..recorded.min(255) as u8 {
                    let _ = self.od.write(0x1003, sub, &[0; 4]);
                }
                Ok(Checked::Write)
            }
            0x1010 if sub >= 1 => {
                if data != SAVE_SIGNATURE.as_slice() {
                    return Err(SdoAbort::CannotStore);
                }
                self.hooks.save(sub, self.od).map(|()| Checked::Done)
            }
            0x1011 if sub >= 1 => {
                if data != LOAD_SIGNATURE.as_slice() {
                    return Err(SdoAbort::CannotStore);
                }
                self.hooks.restore_defaults(sub).map(|()| Checked::Done)
            }
            0x1016 if sub >= 1 => self
                .check_heartbeat_consumer(sub, value)
                .map(|()| Checked::Write),
            0x1019 => {
                if read_uint_or(self.od, 0x1006, 0, 0) != 0 {
                    Err(SdoAbort::DeviceState)
                } else if value == 1 || value > 240 {
                    Err(SdoAbort::InvalidValue)
                } else {
                    Ok(Checked::Write)
                }
            }
            0x1400..=0x1BFF => self.check_pdo(index, sub, value).map(|()| Checked::Write),
            _ => Ok(Checked::Write),
        }
    }
}

impl<O: ObjectDictionary + ?Sized, H: NodeHooks<O>> ObjectDictionary for CommGuard<'_, O, H> {
    fn entry_count(&self) -> usize {
        self.od.entry_count()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.od.entry(position)
    }

    fn kind(&self, position: usize) -> Option<EntryKind> {
        self.od.kind(position)
    }

    #[inline]
    fn services(&self) -> Services {
        self.od.services()
    }

    fn locate(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.od.locate(index, sub)
    }

    fn find(&self, index: u16, sub: u8) -> Result<EntryDescriptor, SdoAbort> {
        self.od.find(index, sub)
    }

    fn capacity(&self, position: usize) -> Option<usize> {
        self.od.capacity(position)
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.od.value_len(index, sub)
    }

    fn value_len_at(&self, position: usize) -> Result<usize, SdoAbort> {
        self.od.value_len_at(position)
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.od.read(index, sub, offset, buf)
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let position = self.od.locate(index, sub)?;
        self.write_at(position, data)
    }

    fn read_at(&self, position: usize, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.od.read_at(position, offset, buf)
    }

    // Strings and domains: no communication-object rule applies to them.
    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        self.od.begin_write(position)
    }

    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        self.od.write_part(position, offset, data)
    }

    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        self.od.commit_write(position, len)
    }

    fn abort_write(&mut self, position: usize) {
        self.od.abort_write(position)
    }

    fn write_at(&mut self, position: usize, data: &[u8]) -> Result<(), SdoAbort> {
        let entry = self.od.entry(position).ok_or(SdoAbort::NoObject)?;
        // Range checks in the node are `matches!` patterns: `RangeInclusive::contains` is a
        // function call on the device, some 120 B more flash over its five uses.
        if matches!(entry.index(), 0x1000..=0x1FFF) {
            // A value of the wrong length gets the OD's length abort, not a rule's.
            let length_ok = entry
                .data_type()
                .fixed_size()
                .is_none_or(|size| size == data.len());
            if length_ok && self.check(entry.index(), entry.sub(), data)? == Checked::Done {
                return Ok(());
            }
        }
        self.od.write_at(position, data)
    }
}
