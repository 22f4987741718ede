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

/// The meaning of an emergency error code: the CiA 402 drive code or CiA 301 code it is, else
/// the CiA 301 class it falls in.
pub const fn meaning(code: u16) -> &'static str {
    match code {
        0x0000 => "error reset or no error",
        // CiA 402 drive errors.
        0x2310 => "continuous over-current (device output side)",
        0x2320 => "short circuit or earth leakage (device output side)",
        0x3110 => "mains over-voltage",
        0x3120 => "mains under-voltage",
        0x3130 => "phase failure",
        0x3210 => "DC link over-voltage",
        0x3220 => "DC link under-voltage",
        0x4210 => "excess temperature (device)",
        0x4310 => "excess temperature (drive)",
        0x7121 => "motor blocked",
        0x7300 => "sensor",
        0x8311 => "excess torque",
        0x8400 => "velocity speed controller",
        0x8611 => "following error",
        0x8612 => "reference limit",
        // CiA 301 communication errors.
        0x8110 => "CAN overrun (objects lost)",
        0x8120 => "CAN in error passive mode",
        0x8130 => "life guard error or heartbeat error",
        0x8140 => "recovered from bus off",
        0x8150 => "CAN-ID collision",
        0x8210 => "PDO not processed due to length error",
        0x8220 => "PDO length exceeded",
        0x8230 => "DAM MPDO not processed, destination object not available",
        0x8240 => "unexpected SYNC data length",
        0x8250 => "RPDO timeout",
        _ => emcy_class(code),
    }
}

/// The CiA 301 class of an emergency error code.
const fn emcy_class(code: u16) -> &'static str {
    match code >> 8 {
        0x10 => "generic error",
        0x20 => "current",
        0x21 => "current, device input side",
        0x22 => "current inside the device",
        0x23 => "current, device output side",
        0x30 => "voltage",
        0x31 => "mains voltage",
        0x32 => "voltage inside the device",
        0x33 => "output voltage",
        0x40 => "temperature",
        0x41 => "ambient temperature",
        0x42 => "device temperature",
        0x50..=0x5F => "device hardware",
        0x60 => "device software",
        0x61 => "internal software",
        0x62 => "user software",
        0x63 => "data set",
        0x70..=0x7F => "additional modules",
        0x80 => "monitoring",
        0x81 => "communication",
        0x82 => "protocol error",
        0x83..=0x8F => "monitoring",
        0x90..=0x9F => "external error",
        0xF0..=0xFE => "additional functions",
        0xFF => "device specific",
        _ => "unknown error code",
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
