//! Emergency frame layout (CiA 301 §7.2.7.3.1): eight bytes, the 16-bit emergency error code
//! (little-endian), the error register (1001h), then five manufacturer-specific bytes.

/// The function code of the pre-defined EMCY COB-ID: 80h + node-ID (1014h's default).
pub const EMCY_BASE: u16 = 0x080;

/// An emergency message.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct EmcyRepr {
    /// The emergency error code (0000h: error reset or no error).
    pub code: u16,
    /// The error register (1001h) at the time of the message.
    pub register: u8,
    /// Manufacturer-specific error field.
    pub manufacturer: [u8; 5],
}

impl EmcyRepr {
    /// Parses the data bytes. `None` unless there are exactly eight.
    pub fn parse(data: &[u8]) -> Option<Self> {
        let bytes: &[u8; 8] = data.try_into().ok()?;
        Some(EmcyRepr {
            code: u16::from_le_bytes([bytes[0], bytes[1]]),
            register: bytes[2],
            manufacturer: [bytes[3], bytes[4], bytes[5], bytes[6], bytes[7]],
        })
    }

    /// The eight data bytes.
    pub const fn emit(&self) -> [u8; 8] {
        let code = self.code.to_le_bytes();
        let m = self.manufacturer;
        [
            code[0],
            code[1],
            self.register,
            m[0],
            m[1],
            m[2],
            m[3],
            m[4],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn goodrive350_out1_fault_and_reset() {
        let fault = EmcyRepr {
            code: 0x3000,
            register: 0x04,
            manufacturer: [0x01, 0, 0, 0, 0],
        };
        assert_eq!(fault.emit(), [0x00, 0x30, 0x04, 0x01, 0, 0, 0, 0]);
        assert_eq!(EmcyRepr::parse(&fault.emit()), Some(fault));
        let reset = EmcyRepr {
            code: 0,
            register: 0,
            manufacturer: [0; 5],
        };
        assert_eq!(reset.emit(), [0; 8]);
    }

    #[test]
    fn short_emergency_is_rejected() {
        assert_eq!(EmcyRepr::parse(&[0x00, 0x30, 0x04]), None);
    }
}
