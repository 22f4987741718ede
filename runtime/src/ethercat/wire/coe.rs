//! The CoE header (ETG.1000.6 §5.6.2): 2 bytes after the mailbox header, the number (bits 0–8,
//! used by emergency messages) and the service (bits 12–15: SDO request, SDO response, ...).
//! What follows an SDO service is CiA 301's 8-byte SDO message ([`crate::wire::sdo`]), and for
//! a normal transfer or a long segment the bytes after it.

use super::{le16, set_le16, WireError};

/// The CoE header's length.
pub const HEADER_LEN: usize = 2;
/// CoE service: emergency.
pub const SERVICE_EMERGENCY: u8 = 1;
/// CoE service: SDO request.
pub const SERVICE_SDO_REQUEST: u8 = 2;
/// CoE service: SDO response.
pub const SERVICE_SDO_RESPONSE: u8 = 3;
/// CoE service: SDO information.
pub const SERVICE_SDO_INFORMATION: u8 = 8;

/// A view over a CoE message (the mailbox's data).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Coe<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Coe<T> {
    /// A view over `buffer` if it holds the CoE header.
    pub fn new_checked(buffer: T) -> Result<Self, WireError> {
        if buffer.as_ref().len() < HEADER_LEN {
            return Err(WireError::Truncated);
        }
        Ok(Coe { buffer })
    }

    /// The bytes under the view.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The number (bits 0–8).
    pub fn number(&self) -> u16 {
        le16(self.buffer.as_ref(), 0) & 0x01FF
    }

    /// The service (bits 12–15).
    pub fn service(&self) -> u8 {
        (le16(self.buffer.as_ref(), 0) >> 12) as u8
    }

    /// What follows the header.
    pub fn payload(&self) -> &[u8] {
        self.buffer.as_ref().get(HEADER_LEN..).unwrap_or_default()
    }
}

/// A CoE header's fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoeRepr {
    /// The number (9 bits).
    pub number: u16,
    /// The service (4 bits).
    pub service: u8,
}

impl CoeRepr {
    /// The header of `coe`.
    pub fn parse<T: AsRef<[u8]>>(coe: &Coe<T>) -> Self {
        CoeRepr {
            number: coe.number(),
            service: coe.service(),
        }
    }

    /// A header of `service`, number 0.
    pub const fn service(service: u8) -> Self {
        CoeRepr { number: 0, service }
    }

    /// Writes the header into the first [`HEADER_LEN`] bytes of `buffer`.
    pub fn emit(&self, buffer: &mut [u8]) -> Result<(), WireError> {
        let header = buffer.get_mut(..HEADER_LEN).ok_or(WireError::Truncated)?;
        set_le16(
            header,
            0,
            (self.number & 0x01FF) | (u16::from(self.service & 0x0F) << 12),
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_sdo_request_round_trips() {
        let bytes = [0x00, 0x20, 0x40, 0x18, 0x10, 1];
        let coe = Coe::new_checked(&bytes[..]).unwrap();
        assert_eq!(CoeRepr::parse(&coe), CoeRepr::service(SERVICE_SDO_REQUEST));
        assert_eq!(coe.payload(), &[0x40, 0x18, 0x10, 1]);
        let mut out = [0u8; 2];
        CoeRepr::service(SERVICE_SDO_RESPONSE)
            .emit(&mut out)
            .unwrap();
        assert_eq!(out, [0x00, 0x30]);
        let emergency = CoeRepr {
            number: 0x1FF,
            service: SERVICE_EMERGENCY,
        };
        emergency.emit(&mut out).unwrap();
        assert_eq!(out, [0xFF, 0x11]);
        assert_eq!(
            CoeRepr::parse(&Coe::new_checked(&out[..]).unwrap()),
            emergency
        );
    }

    #[test]
    fn a_short_message_is_refused() {
        assert_eq!(Coe::new_checked(&[0x00][..]), Err(WireError::Truncated));
        assert_eq!(
            CoeRepr::service(2).emit(&mut [0u8; 1]),
            Err(WireError::Truncated)
        );
    }
}
