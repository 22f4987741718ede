//! The common packet format: an item count, then (type, length, data) items. SendRRData and
//! SendUnitData carry an interface handle and a timeout before them; class-0/1 datagrams are
//! items alone. Also the sockaddr info item's data.

use super::{length_u16, u16_at, Emit, Error, Reader, Writer};

/// CPF item types.
pub mod item {
    /// Null address (unconnected messages).
    pub const NULL_ADDRESS: u16 = 0x0000;
    /// Identity (ListIdentity reply).
    pub const IDENTITY: u16 = 0x000C;
    /// Connected address: a connection ID.
    pub const CONNECTED_ADDRESS: u16 = 0x00A1;
    /// Connected data (with a sequence count).
    pub const CONNECTED_DATA: u16 = 0x00B1;
    /// Unconnected data: a Message Router request or response.
    pub const UNCONNECTED_DATA: u16 = 0x00B2;
    /// ListServices reply item.
    pub const SERVICES: u16 = 0x0100;
    /// Sockaddr info, O→T.
    pub const SOCKADDR_O_T: u16 = 0x8000;
    /// Sockaddr info, T→O.
    pub const SOCKADDR_T_O: u16 = 0x8001;
    /// Sequenced address: connection ID and sequence number (class 0/1).
    pub const SEQUENCED_ADDRESS: u16 = 0x8002;
}

/// One CPF item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Item<'a> {
    /// The item type ([`item`]).
    pub kind: u16,
    /// Its data.
    pub data: &'a [u8],
}

impl<'a> Item<'a> {
    /// An item of `kind` with `data`.
    pub const fn new(kind: u16, data: &'a [u8]) -> Item<'a> {
        Item { kind, data }
    }
}

/// The items of a CPF, checked: every length within the bytes (bytes after the last item are
/// ignored, as receivers do).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Items<'a> {
    bytes: &'a [u8],
    count: u16,
}

impl<'a> Items<'a> {
    /// The items in `bytes`; [`Error::Truncated`] when the count or a length runs past them.
    pub fn parse(bytes: &'a [u8]) -> Result<Items<'a>, Error> {
        let count = u16_at(bytes, 0).ok_or(Error::Truncated)?;
        let mut r = Reader::new(bytes.get(2..).unwrap_or(&[]));
        for _ in 0..count {
            r.u16()?;
            let len = r.u16()?;
            r.take(usize::from(len))?;
        }
        Ok(Items { bytes, count })
    }

    /// The items of SendRRData or SendUnitData's data: after the interface handle (4 bytes)
    /// and the timeout (2).
    pub fn parse_send_data(data: &'a [u8]) -> Result<Items<'a>, Error> {
        Items::parse(data.get(6..).ok_or(Error::Truncated)?)
    }

    /// The items in order.
    pub fn iter(&self) -> ItemIter<'a> {
        ItemIter {
            reader: Reader::new(self.bytes.get(2..).unwrap_or(&[])),
            left: self.count,
        }
    }

    /// The data of the first item of `kind`.
    pub fn find(&self, kind: u16) -> Option<&'a [u8]> {
        self.iter().find(|i| i.kind == kind).map(|i| i.data)
    }
}

impl<'a> IntoIterator for Items<'a> {
    type Item = Item<'a>;
    type IntoIter = ItemIter<'a>;
    fn into_iter(self) -> ItemIter<'a> {
        self.iter()
    }
}

/// The items of [`Items`], in order.
pub struct ItemIter<'a> {
    reader: Reader<'a>,
    left: u16,
}

impl<'a> Iterator for ItemIter<'a> {
    type Item = Item<'a>;
    fn next(&mut self) -> Option<Item<'a>> {
        self.left = self.left.checked_sub(1)?;
        let kind = self.reader.u16().ok()?;
        let len = self.reader.u16().ok()?;
        let data = self.reader.take(usize::from(len)).ok()?;
        Some(Item { kind, data })
    }
}

/// Items to write: the count, then each item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CpfRepr<'a> {
    /// The items in order.
    pub items: &'a [Item<'a>],
}

impl Emit for CpfRepr<'_> {
    fn buffer_len(&self) -> usize {
        2 + self.items.iter().map(|i| 4 + i.data.len()).sum::<usize>()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let mut w = Writer::new(buf);
        w.u16(length_u16(self.items.len())?)?;
        for item in self.items {
            w.u16(item.kind)?;
            w.u16(length_u16(item.data.len())?)?;
            w.bytes(item.data)?;
        }
        Ok(w.done())
    }
}

/// SendRRData or SendUnitData's data: interface handle 0 (CIP), a timeout, the items.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SendDataRepr<'a> {
    /// The timeout in seconds (0: the originator keeps its own).
    pub timeout: u16,
    /// The items.
    pub items: &'a [Item<'a>],
}

impl Emit for SendDataRepr<'_> {
    fn buffer_len(&self) -> usize {
        6 + CpfRepr { items: self.items }.buffer_len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let mut w = Writer::new(buf);
        w.u32(0)?;
        w.u16(self.timeout)?;
        let at = w.done();
        let items = CpfRepr { items: self.items }.emit(buf.get_mut(at..).unwrap_or(&mut []))?;
        Ok(at + items)
    }
}

/// A sockaddr info item's data (items 0x8000/0x8001): family 2 (AF_INET), port and IPv4 address
/// big-endian, eight zero bytes. A scanner puts a T→O one in its Forward_Open to ask for T→O
/// data on another port than 2222.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sockaddr {
    /// The UDP port.
    pub port: u16,
    /// The IPv4 address (0.0.0.0: the sender's).
    pub address: [u8; 4],
}

impl Sockaddr {
    /// The item's data; [`Error::Malformed`] unless it is 16 bytes of family 2.
    pub fn parse(data: &[u8]) -> Result<Sockaddr, Error> {
        match data {
            [0, 2, p0, p1, a, b, c, d, ..] if data.len() == 16 => Ok(Sockaddr {
                port: u16::from_be_bytes([*p0, *p1]),
                address: [*a, *b, *c, *d],
            }),
            _ => Err(Error::Malformed),
        }
    }

    /// The item's 16 bytes.
    pub fn to_bytes(&self) -> [u8; 16] {
        let mut out = [0; 16];
        out[..2].copy_from_slice(&2u16.to_be_bytes());
        out[2..4].copy_from_slice(&self.port.to_be_bytes());
        out[4..8].copy_from_slice(&self.address);
        out
    }
}
