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
        crate::wire::emcy::meaning(self.code)
    }
}
