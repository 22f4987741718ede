//! The EMCY consumer: an emergency message from any node decoded into its error code, error
//! register and manufacturer bytes, with the code's meaning from CiA 301 (and CiA 402 for drives).

use crate::frame::CanFrame;
use crate::wire::emcy::EmcyRepr;

/// An emergency message received from a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Emergency {
    /// The sender (from the default COB-ID 80h + node-ID).
    pub node_id: u8,
    /// The emergency error code (0000h: error reset or no error).
    pub code: u16,
    /// The error register (1001h) at the time.
    pub register: u8,
    /// The manufacturer-specific error field.
    pub manufacturer: [u8; 5],
}

impl Emergency {
    /// The emergency in `frame`, if it is one on a default EMCY COB-ID (81h..=FFh) with 8 bytes.
    pub fn from_frame(frame: &CanFrame) -> Option<Self> {
        let id = frame.std_id()?;
        if frame.is_remote() || !(0x81..=0xFF).contains(&id) {
            return None;
        }
        let repr = EmcyRepr::parse(frame.data())?;
        Some(Emergency {
            node_id: (id - 0x80) as u8,
            code: repr.code,
            register: repr.register,
            manufacturer: repr.manufacturer,
        })
    }

    /// What the error code means.
    pub const fn meaning(&self) -> &'static str {
        emcy_meaning(self.code)
    }
}

/// The meaning of an emergency error code: the CiA 402 drive code or CiA 301 code it is, else
/// the CiA 301 class it falls in.
pub const fn emcy_meaning(code: u16) -> &'static str {
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
