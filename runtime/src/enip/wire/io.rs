//! Connected data: a class-0/1 datagram on UDP 2222 (a sequenced address item with the
//! connection ID and the encapsulation sequence number, then a connected data item, for
//! class 1 starting with its 16-bit sequence count) and a class-3 message in SendUnitData's
//! data (a connected address item, then a connected data item: sequence count and a Message
//! Router request or response).

use super::cpf::{item, CpfRepr, Item, Items};
use super::{length_u16, u16_at, u32_at, Emit, Error, Writer};

/// A class-0/1 datagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoDatagram<'a> {
    /// The connection ID the data is produced with.
    pub connection: u32,
    /// The encapsulation sequence number.
    pub sequence: u32,
    /// The connected data item's data (class 1: the 16-bit sequence count first).
    pub data: &'a [u8],
}

impl<'a> IoDatagram<'a> {
    /// The datagram in `bytes`: [`Error::Malformed`] without both items,
    /// [`Error::Truncated`] for a short address.
    pub fn parse(bytes: &'a [u8]) -> Result<IoDatagram<'a>, Error> {
        let items = Items::parse(bytes)?;
        let address = items.find(item::SEQUENCED_ADDRESS);
        let data = items.find(item::CONNECTED_DATA);
        let (Some(address), Some(data)) = (address, data) else {
            return Err(Error::Malformed);
        };
        Ok(IoDatagram {
            connection: u32_at(address, 0).ok_or(Error::Truncated)?,
            sequence: u32_at(address, 4).ok_or(Error::Truncated)?,
            data,
        })
    }

    /// The class-1 sequence count: the data's first word.
    pub fn sequence_count(&self) -> Option<u16> {
        u16_at(self.data, 0)
    }

    fn address(&self) -> [u8; 8] {
        let mut address = [0; 8];
        address[..4].copy_from_slice(&self.connection.to_le_bytes());
        address[4..].copy_from_slice(&self.sequence.to_le_bytes());
        address
    }
}

impl Emit for IoDatagram<'_> {
    fn buffer_len(&self) -> usize {
        2 + 4 + 8 + 4 + self.data.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let address = self.address();
        CpfRepr {
            items: &[
                Item::new(item::SEQUENCED_ADDRESS, &address),
                Item::new(item::CONNECTED_DATA, self.data),
            ],
        }
        .emit(buf)
    }
}

/// A class-3 message: SendUnitData's data, a request on its way to the target or a response
/// on its way back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConnectedMessage<'a> {
    /// The connection ID: the O→T one for a request, the T→O one for a response.
    pub connection: u32,
    /// The sequence count (a response echoes the request's).
    pub sequence: u16,
    /// The Message Router request or response.
    pub message: &'a [u8],
}

impl<'a> ConnectedMessage<'a> {
    /// The message in SendUnitData's `data`: [`Error::Malformed`] without both items or with
    /// an address other than four bytes, [`Error::Truncated`] when short.
    pub fn parse(data: &'a [u8]) -> Result<ConnectedMessage<'a>, Error> {
        let items = Items::parse_send_data(data)?;
        let address = items.find(item::CONNECTED_ADDRESS);
        let payload = items.find(item::CONNECTED_DATA);
        let (Some(address), Some(payload)) = (address, payload) else {
            return Err(Error::Malformed);
        };
        let (Some(connection), Some(sequence), 4) =
            (u32_at(address, 0), u16_at(payload, 0), address.len())
        else {
            return Err(Error::Malformed);
        };
        Ok(ConnectedMessage {
            connection,
            sequence,
            message: payload.get(2..).unwrap_or(&[]),
        })
    }

    /// The connected data item's size: the sequence count and the message (what a
    /// connection's size limits).
    pub fn payload_len(&self) -> usize {
        2 + self.message.len()
    }
}

impl Emit for ConnectedMessage<'_> {
    fn buffer_len(&self) -> usize {
        6 + 2 + 8 + 4 + self.payload_len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let mut w = Writer::new(buf);
        w.u32(0)?; // interface handle: CIP
        w.u16(0)?; // timeout
        w.u16(2)?;
        w.u16(item::CONNECTED_ADDRESS)?;
        w.u16(4)?;
        w.u32(self.connection)?;
        w.u16(item::CONNECTED_DATA)?;
        w.u16(length_u16(self.payload_len())?)?;
        w.u16(self.sequence)?;
        w.bytes(self.message)?;
        Ok(w.done())
    }
}
