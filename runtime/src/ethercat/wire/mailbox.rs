//! The EtherCAT mailbox header (ETG.1000.6 §5.6): 6 bytes before a mailbox message's data: the
//! length of what follows, the address, channel and priority, and the type (low 4 bits of byte
//! 5) with the counter (bits 4–6). [`Mailbox`] views a SyncManager's buffer, [`MailboxRepr`]
//! is the header's fields, and [`emit_error`] writes the reply a device sends for a protocol it
//! does not serve.

use super::{le16, set_le16, WireError};

/// The mailbox header's length.
pub const HEADER_LEN: usize = 6;
/// Mailbox type: error reply.
pub const TYPE_ERROR: u8 = 0;
/// Mailbox type: CAN application protocol over EtherCAT.
pub const TYPE_COE: u8 = 3;
/// Mailbox error detail: the protocol is not supported.
pub const ERROR_UNSUPPORTED_PROTOCOL: u16 = 0x0002;
/// The service word of a mailbox error reply.
const ERROR_SERVICE: u16 = 0x0001;

/// A view over a mailbox message: the header and as much data as its length says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mailbox<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Mailbox<T> {
    /// A view over `buffer` (a SyncManager's whole buffer, say) if it holds the header and the
    /// data its length says.
    pub fn new_checked(buffer: T) -> Result<Self, WireError> {
        let mailbox = Mailbox { buffer };
        let len = mailbox.buffer.as_ref().len();
        if len < HEADER_LEN || len < HEADER_LEN + mailbox.length() {
            return Err(WireError::Truncated);
        }
        Ok(mailbox)
    }

    /// The bytes under the view.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    fn bytes(&self) -> &[u8] {
        self.buffer.as_ref()
    }

    /// The length of the data after the header.
    pub fn length(&self) -> usize {
        usize::from(le16(self.bytes(), 0))
    }

    /// The address field (the station address of a source or destination, 0 for the master).
    pub fn address(&self) -> u16 {
        le16(self.bytes(), 2)
    }

    /// The channel (bits 0–5 of byte 4).
    pub fn channel(&self) -> u8 {
        self.bytes().get(4).map_or(0, |b| b & 0x3F)
    }

    /// The priority (bits 6–7 of byte 4).
    pub fn priority(&self) -> u8 {
        self.bytes().get(4).map_or(0, |b| b >> 6)
    }

    /// The type (low 4 bits of byte 5): [`TYPE_COE`], [`TYPE_ERROR`], ...
    pub fn kind(&self) -> u8 {
        self.bytes().get(5).map_or(0, |b| b & 0x0F)
    }

    /// The counter (bits 4–6 of byte 5), 1–7 and wrapping; 0 says "not counted".
    pub fn counter(&self) -> u8 {
        self.bytes().get(5).map_or(0, |b| (b >> 4) & 0x07)
    }

    /// The data after the header, as long as the header's length says.
    pub fn data(&self) -> &[u8] {
        self.bytes()
            .get(HEADER_LEN..HEADER_LEN + self.length())
            .unwrap_or_default()
    }
}

/// A mailbox header's fields.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MailboxRepr {
    /// The length of the data after the header.
    pub length: u16,
    /// The address field.
    pub address: u16,
    /// The channel (6 bits).
    pub channel: u8,
    /// The priority (2 bits).
    pub priority: u8,
    /// The type (4 bits).
    pub kind: u8,
    /// The counter (3 bits).
    pub counter: u8,
}

impl MailboxRepr {
    /// The header of `mailbox`.
    pub fn parse<T: AsRef<[u8]>>(mailbox: &Mailbox<T>) -> Self {
        MailboxRepr {
            length: mailbox.length() as u16,
            address: mailbox.address(),
            channel: mailbox.channel(),
            priority: mailbox.priority(),
            kind: mailbox.kind(),
            counter: mailbox.counter(),
        }
    }

    /// A header of `kind` and `counter` before `length` bytes, address, channel and priority 0.
    pub const fn new(kind: u8, counter: u8, length: u16) -> Self {
        MailboxRepr {
            length,
            address: 0,
            channel: 0,
            priority: 0,
            kind,
            counter,
        }
    }

    /// Writes the header into the first [`HEADER_LEN`] bytes of `buffer` (fields wider than
    /// their bits are cut to them).
    pub fn emit(&self, buffer: &mut [u8]) -> Result<(), WireError> {
        let header = buffer.get_mut(..HEADER_LEN).ok_or(WireError::Truncated)?;
        set_le16(header, 0, self.length);
        set_le16(header, 2, self.address);
        header[4] = (self.channel & 0x3F) | ((self.priority & 0x03) << 6);
        header[5] = (self.kind & 0x0F) | ((self.counter & 0x07) << 4);
        Ok(())
    }
}

/// The length of a mailbox error reply.
pub const ERROR_REPLY_LEN: usize = HEADER_LEN + 4;

/// Writes the mailbox error reply (type 0) with `detail` into `buffer`; returns its length.
pub fn emit_error(buffer: &mut [u8], counter: u8, detail: u16) -> Result<usize, WireError> {
    let reply = buffer
        .get_mut(..ERROR_REPLY_LEN)
        .ok_or(WireError::Truncated)?;
    MailboxRepr::new(TYPE_ERROR, counter, 4).emit(reply)?;
    set_le16(reply, HEADER_LEN, ERROR_SERVICE);
    set_le16(reply, HEADER_LEN + 2, detail);
    Ok(ERROR_REPLY_LEN)
}

#[cfg(test)]
mod tests {
    use super::*;

    const COE_UPLOAD: [u8; 12] = [6, 0, 0, 0, 0, 0x53, 0x00, 0x20, 0x40, 0x18, 0x10, 1];

    #[test]
    fn a_coe_message_round_trips() {
        let mut buffer = [0u8; 32];
        buffer[..12].copy_from_slice(&COE_UPLOAD);
        let mailbox = Mailbox::new_checked(&buffer[..]).unwrap();
        assert_eq!(
            (mailbox.kind(), mailbox.counter(), mailbox.length()),
            (3, 5, 6)
        );
        assert_eq!(mailbox.data(), &COE_UPLOAD[6..]);
        let repr = MailboxRepr::parse(&mailbox);
        assert_eq!(repr, MailboxRepr::new(TYPE_COE, 5, 6));
        let mut out = [0u8; HEADER_LEN];
        repr.emit(&mut out).unwrap();
        assert_eq!(out, COE_UPLOAD[..HEADER_LEN]);
    }

    #[test]
    fn channel_and_priority_share_byte_4() {
        let repr = MailboxRepr {
            channel: 0x3F,
            priority: 2,
            address: 0x1001,
            ..MailboxRepr::new(TYPE_COE, 1, 0)
        };
        let mut out = [0u8; HEADER_LEN];
        repr.emit(&mut out).unwrap();
        assert_eq!(out, [0, 0, 0x01, 0x10, 0xBF, 0x13]);
        assert_eq!(
            MailboxRepr::parse(&Mailbox::new_checked(&out[..]).unwrap()),
            repr
        );
    }

    #[test]
    fn a_length_past_the_buffer_is_no_message() {
        assert_eq!(
            Mailbox::new_checked(&[10, 0, 0, 0, 0, 3, 0, 0][..]),
            Err(WireError::Truncated)
        );
        assert_eq!(
            Mailbox::new_checked(&[0, 0, 0][..]),
            Err(WireError::Truncated)
        );
        assert_eq!(
            MailboxRepr::default().emit(&mut [0; 5]),
            Err(WireError::Truncated)
        );
    }

    #[test]
    fn the_error_reply_says_its_detail() {
        let mut out = [0u8; 16];
        assert_eq!(emit_error(&mut out, 1, ERROR_UNSUPPORTED_PROTOCOL), Ok(10));
        assert_eq!(out[..10], [4, 0, 0, 0, 0, 0x10, 1, 0, 2, 0]);
        assert_eq!(emit_error(&mut out[..9], 1, 2), Err(WireError::Truncated));
    }
}
