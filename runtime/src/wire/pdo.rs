//! PDO parameter layouts (CiA 301 §7.5.2.35–7.5.2.38): the 32-bit COB-ID entry of a PDO's
//! communication parameter and the 32-bit mapping entry (index, sub-index, length in bits).
//! PDO payloads themselves are the mapped values back to back and have no header.

/// The 32-bit COB-ID entry of a PDO, SYNC, EMCY or SDO communication parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CobIdEntry(pub u32);

impl CobIdEntry {
    /// Bit 31: the object does not exist / is not valid.
    pub const INVALID: u32 = 1 << 31;
    /// Bit 30: for a TPDO, no RTR allowed; for SYNC (1005h), this node produces SYNC.
    pub const BIT30: u32 = 1 << 30;
    /// Bit 29: 29-bit identifier.
    pub const EXTENDED: u32 = 1 << 29;

    /// Whether the object is valid (bit 31 clear).
    #[inline]
    pub const fn valid(self) -> bool {
        self.0 & Self::INVALID == 0
    }
    /// Bit 30.
    #[inline]
    pub const fn bit30(self) -> bool {
        self.0 & Self::BIT30 != 0
    }
    /// Whether the identifier is a 29-bit one (bit 29).
    #[inline]
    pub const fn extended(self) -> bool {
        self.0 & Self::EXTENDED != 0
    }
    /// The 11-bit CAN identifier.
    #[inline]
    pub const fn can_id(self) -> u16 {
        (self.0 & 0x7FF) as u16
    }
}

/// One PDO mapping entry: which object goes into the payload, and how many bits it takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MappingEntry {
    /// OD index of the mapped object (0001h–0007h: a dummy of that data type).
    pub index: u16,
    /// Sub-index of the mapped object.
    pub sub: u8,
    /// Length in bits.
    pub bits: u8,
}

impl MappingEntry {
    /// Splits a 32-bit mapping value.
    #[inline]
    pub const fn from_u32(value: u32) -> Self {
        MappingEntry {
            index: (value >> 16) as u16,
            sub: (value >> 8) as u8,
            bits: value as u8,
        }
    }

    /// The 32-bit mapping value.
    pub const fn to_u32(self) -> u32 {
        (self.index as u32) << 16 | (self.sub as u32) << 8 | self.bits as u32
    }

    /// Whether the entry is a dummy (a data-type index, 0001h–0007h).
    #[inline]
    pub const fn is_dummy(self) -> bool {
        self.index >= 0x0001 && self.index <= 0x0007
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mapping_entry_round_trips() {
        let entry = MappingEntry::from_u32(0x6040_0010);
        assert_eq!(
            entry,
            MappingEntry {
                index: 0x6040,
                sub: 0,
                bits: 16
            }
        );
        assert_eq!(entry.to_u32(), 0x6040_0010);
        assert!(!entry.is_dummy());
        assert!(MappingEntry::from_u32(0x0006_0010).is_dummy());
    }

    #[test]
    fn cob_id_bits() {
        let cob = CobIdEntry(0x8000_0183);
        assert!(!cob.valid());
        assert_eq!(cob.can_id(), 0x183);
        assert!(CobIdEntry(0x4000_0080).bit30());
        assert!(CobIdEntry(0x2000_0000).extended());
    }
}
