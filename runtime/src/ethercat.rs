//! EtherCAT devices as generated code describes them (from an ESI file): the identity a SubDevice
//! reports, the SyncManager layout, the distributed-clock modes, and [`ProcessData`], the
//! contract of generated PDO and process-image structs (bit-exact, any length, little-endian as
//! EtherCAT lays them out).
//!
//! With the `ethercrab` feature, generated process-image structs are also ethercrab-wire types
//! (`subdevice.inputs_raw()` bytes decode into them, they pack into `outputs_raw_mut()`), and
//! `ethercrab::SdoExt` reads and writes typed addresses (`od::CONTROL_WORD`) over CoE.

#[cfg(feature = "ethercat-subdevice")]
pub mod al;
#[cfg(feature = "ethercat-subdevice")]
pub mod esc;
#[cfg(feature = "ethercrab")]
pub mod ethercrab;
#[cfg(feature = "ethercat-subdevice")]
pub mod sdo;
#[cfg(feature = "ethercat-subdevice")]
pub mod sii;
#[cfg(feature = "ethercat-subdevice")]
pub mod subdevice;
#[cfg(feature = "ethercat-wire")]
pub mod wire;

use crate::od::typed::PdoError;

/// What a SubDevice reports in its SII and 1018h: vendor ID, product code and revision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Identity {
    /// Vendor ID (1018h sub 1).
    pub vendor_id: u32,
    /// Product code (1018h sub 2).
    pub product_code: u32,
    /// Revision number (1018h sub 3).
    pub revision: u32,
}

impl Identity {
    /// Whether a discovered device is this one: same vendor and product code. The revision is
    /// compared by [`Identity::matches_exactly`] only (a newer firmware revision usually keeps
    /// the layout).
    pub const fn matches(&self, vendor_id: u32, product_code: u32) -> bool {
        self.vendor_id == vendor_id && self.product_code == product_code
    }

    /// Whether vendor, product code and revision are all the same.
    pub const fn matches_exactly(&self, vendor_id: u32, product_code: u32, revision: u32) -> bool {
        self.matches(vendor_id, product_code) && self.revision == revision
    }
}

/// What a SyncManager carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SmKind {
    /// Mailbox, master to device (`MBoxOut`).
    MailboxOut,
    /// Mailbox, device to master (`MBoxIn`).
    MailboxIn,
    /// Process data outputs (the assigned RxPDOs).
    Outputs,
    /// Process data inputs (the assigned TxPDOs).
    Inputs,
    /// Anything else the description names.
    Other,
}

/// One SyncManager as the description sets it up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SyncManager {
    /// What it carries.
    pub kind: SmKind,
    /// Start address in the device's memory.
    pub start_address: u16,
    /// Default size in bytes (0 when the description gives none: the master sizes it from the
    /// assigned PDOs).
    pub default_size: u16,
    /// The control register value.
    pub control_byte: u8,
    /// Whether it is enabled.
    pub enable: bool,
}

/// One distributed-clock operation mode (`Dc/OpMode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct OpMode {
    /// Its name in the description.
    pub name: &'static str,
    /// Its description.
    pub description: &'static str,
    /// The `AssignActivate` word (0 for free run; 0300h activates SYNC0).
    pub assign_activate: u16,
    /// SYNC0 cycle time in ns (0 when it follows the bus cycle).
    pub cycle_time_sync0: u32,
}

/// The CoE mailbox's services (`Mailbox/CoE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Coe {
    /// The SDO information service (the dictionary can be browsed at run time).
    pub sdo_info: bool,
    /// PDO assignment (1C12h/1C13h) can be changed.
    pub pdo_assign: bool,
    /// PDO mappings can be changed.
    pub pdo_config: bool,
    /// SDO complete access.
    pub complete_access: bool,
    /// Segmented SDO transfers.
    pub segmented_sdo: bool,
}

/// A typed block of process data: one PDO or a SyncManager's whole image. Fields are packed
/// least significant bit first from `bit_offset`, multi-byte values little-endian, padding left
/// as it is on write and skipped on read.
pub trait ProcessData: Sized {
    /// The length in bits.
    const BITS: usize;
    /// The length in bytes (`BITS` rounded up).
    const LEN: usize;

    /// Writes the fields into `buf` from bit `bit_offset`. `WrongLength` if `buf` is too short,
    /// `OutOfRange` if a field does not fit its mapped bits (nothing is written then).
    fn write_to(&self, buf: &mut [u8], bit_offset: usize) -> Result<(), PdoError>;

    /// Reads the fields from `buf` at bit `bit_offset`; `WrongLength` if `buf` is too short.
    fn read_from(buf: &[u8], bit_offset: usize) -> Result<Self, PdoError>;
}

/// `WrongLength` unless `buf` holds `bits` bits from `bit_offset`: the check every
/// [`ProcessData`] access starts with.
#[doc(hidden)]
#[inline]
pub fn check_len(buf: &[u8], bit_offset: usize, bits: usize) -> Result<(), PdoError> {
    let needed = (bit_offset + bits).div_ceil(8);
    if buf.len() < needed {
        return Err(PdoError::WrongLength {
            expected: needed,
            actual: buf.len(),
        });
    }
    Ok(())
}

/// Makes a generated [`ProcessData`] struct an ethercrab-wire type when the runtime's `ethercrab`
/// feature is on; expands to nothing without it. Generated code invokes it once per struct.
#[cfg(feature = "ethercrab")]
#[doc(hidden)]
#[macro_export]
macro_rules! ethercrab_wire {
    ($ty:ty) => {
        impl $crate::ethercat::ethercrab::wire::EtherCrabWireRead for $ty {
            fn unpack_from_slice(
                buf: &[u8],
            ) -> ::core::result::Result<Self, $crate::ethercat::ethercrab::wire::WireError> {
                <$ty as $crate::ethercat::ProcessData>::read_from(buf, 0)
                    .map_err($crate::ethercat::ethercrab::read_error)
            }
        }
        impl $crate::ethercat::ethercrab::wire::EtherCrabWireWrite for $ty {
            fn pack_to_slice<'buf>(
                &self,
                buf: &'buf mut [u8],
            ) -> ::core::result::Result<&'buf [u8], $crate::ethercat::ethercrab::wire::WireError>
            {
                let len = <$ty as $crate::ethercat::ProcessData>::LEN;
                $crate::ethercat::ProcessData::write_to(self, buf, 0)
                    .map_err($crate::ethercat::ethercrab::write_error)?;
                Ok(buf.get(..len).unwrap_or_default())
            }
            fn pack_to_slice_unchecked<'buf>(&self, buf: &'buf mut [u8]) -> &'buf [u8] {
                let len = <$ty as $crate::ethercat::ProcessData>::LEN;
                // ethercrab-wire has no error to give here: a value out of its mapped range
                // leaves the buffer as it was (pack_to_slice reports it).
                let _ = $crate::ethercat::ProcessData::write_to(self, buf, 0);
                buf.get(..len).unwrap_or_default()
            }
            fn packed_len(&self) -> usize {
                <$ty as $crate::ethercat::ProcessData>::LEN
            }
        }
        impl $crate::ethercat::ethercrab::wire::EtherCrabWireSized for $ty {
            const PACKED_LEN: usize = <$ty as $crate::ethercat::ProcessData>::LEN;
            type Buffer = [u8; <$ty as $crate::ethercat::ProcessData>::LEN];
            fn buffer() -> Self::Buffer {
                [0; <$ty as $crate::ethercat::ProcessData>::LEN]
            }
        }
        impl $crate::ethercat::ethercrab::wire::EtherCrabWireWriteSized for $ty {
            fn pack(&self) -> Self::Buffer {
                let mut buf = [0; <$ty as $crate::ethercat::ProcessData>::LEN];
                // As pack_to_slice_unchecked: all zeros if a value is out of its mapped range.
                let _ = $crate::ethercat::ProcessData::write_to(self, &mut buf, 0);
                buf
            }
        }
    };
}

/// Without the runtime's `ethercrab` feature generated structs are not ethercrab-wire types.
#[cfg(not(feature = "ethercrab"))]
#[doc(hidden)]
#[macro_export]
macro_rules! ethercrab_wire {
    ($ty:ty) => {};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_len_counts_the_bits_from_the_offset() {
        assert_eq!(check_len(&[0; 21], 0, 168), Ok(()));
        assert_eq!(check_len(&[0; 22], 8, 168), Ok(()));
        assert_eq!(
            check_len(&[0; 21], 1, 168),
            Err(PdoError::WrongLength {
                expected: 22,
                actual: 21
            })
        );
        assert_eq!(check_len(&[], 0, 0), Ok(()));
    }

    #[test]
    fn identity_matches_vendor_and_product_and_optionally_revision() {
        let id = Identity {
            vendor_id: 0x4D8,
            product_code: 0x9252,
            revision: 1,
        };
        assert!(id.matches(0x4D8, 0x9252));
        assert!(!id.matches(0x4D8, 0x9253));
        assert!(id.matches_exactly(0x4D8, 0x9252, 1));
        assert!(!id.matches_exactly(0x4D8, 0x9252, 2));
    }
}
