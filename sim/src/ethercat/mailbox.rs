//! The EtherCAT mailbox and CoE wire formats (ETG.1000.6 §5.6): the 6-byte mailbox header
//! (length of what follows, address, channel/priority, type in the low 4 bits and counter in
//! bits 4–6), the 2-byte CoE header (number in bits 0–8, service in bits 12–15), and the
//! mailbox error reply a device sends for a protocol it does not serve.

/// The mailbox header's length.
pub const HEADER_LEN: usize = 6;
/// Mailbox type: error reply.
pub const TYPE_ERROR: u8 = 0;
/// Mailbox type: CAN application protocol over EtherCAT.
pub const TYPE_COE: u8 = 3;
/// CoE service: SDO request.
pub const SERVICE_SDO_REQUEST: u8 = 2;
/// CoE service: SDO response.
pub const SERVICE_SDO_RESPONSE: u8 = 3;
/// Mailbox error detail: the protocol is not supported.
pub const ERROR_UNSUPPORTED_PROTOCOL: u16 = 0x0002;

/// A mailbox message, as received.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Message<'a> {
    /// The address field.
    pub address: u16,
    /// The type (low 4 bits of byte 5).
    pub kind: u8,
    /// The counter (bits 4–6 of byte 5).
    pub counter: u8,
    /// The data after the header, as long as the header's length says.
    pub data: &'a [u8],
}

/// Reads a mailbox message from a SyncManager's buffer; `None` when the header's length runs
/// past the buffer.
pub fn parse(buffer: &[u8]) -> Option<Message<'_>> {
    let header = buffer.get(..HEADER_LEN)?;
    let len = usize::from(u16::from_le_bytes([header[0], header[1]]));
    Some(Message {
        address: u16::from_le_bytes([header[2], header[3]]),
        kind: header[5] & 0x0F,
        counter: (header[5] >> 4) & 0x07,
        data: buffer.get(HEADER_LEN..HEADER_LEN + len)?,
    })
}

/// A mailbox message of `kind` with `counter` around `data`.
pub fn emit(kind: u8, counter: u8, data: &[u8]) -> Vec<u8> {
    let mut out = (data.len() as u16).to_le_bytes().to_vec();
    out.extend_from_slice(&[0, 0, 0, (kind & 0x0F) | ((counter & 0x07) << 4)]);
    out.extend_from_slice(data);
    out
}

/// A CoE message: its header's service and the rest.
pub fn coe(data: &[u8]) -> Option<(u8, &[u8])> {
    let header = data.get(..2)?;
    let word = u16::from_le_bytes([header[0], header[1]]);
    Some(((word >> 12) as u8, &data[2..]))
}

/// A CoE header of `service` (number 0) before `body`.
pub fn coe_message(service: u8, body: &[u8]) -> Vec<u8> {
    let mut out = (u16::from(service) << 12).to_le_bytes().to_vec();
    out.extend_from_slice(body);
    out
}

/// The mailbox error reply (type 0) with `detail`.
pub fn error_reply(counter: u8, detail: u16) -> Vec<u8> {
    let mut data = 0x0001u16.to_le_bytes().to_vec();
    data.extend_from_slice(&detail.to_le_bytes());
    emit(TYPE_ERROR, counter, &data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coe_message_round_trips() {
        let message = emit(
            TYPE_COE,
            5,
            &coe_message(SERVICE_SDO_REQUEST, &[0x40, 0x18, 0x10, 1]),
        );
        assert_eq!(
            message,
            [6, 0, 0, 0, 0, 0x53, 0x00, 0x20, 0x40, 0x18, 0x10, 1]
        );
        let mut buffer = message.clone();
        buffer.resize(32, 0);
        let parsed = parse(&buffer).unwrap();
        assert_eq!((parsed.kind, parsed.counter, parsed.data.len()), (3, 5, 6));
        assert_eq!(coe(parsed.data), Some((2, &[0x40, 0x18, 0x10, 1][..])));
    }

    #[test]
    fn a_length_past_the_buffer_is_no_message() {
        assert_eq!(parse(&[10, 0, 0, 0, 0, 3, 0, 0]), None);
        assert_eq!(parse(&[0, 0, 0]), None);
        assert_eq!(error_reply(1, 2), [4, 0, 0, 0, 0, 0x10, 1, 0, 2, 0]);
    }
}
