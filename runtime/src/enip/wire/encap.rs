//! The encapsulation: the 24-byte header every message over TCP or UDP 44818 starts with, its
//! commands and status codes, and the data of RegisterSession and of a ListIdentity reply's
//! identity item.

use super::{length_u16, u16_at, u32_at, Emit, Error, Reader, Writer};

/// The header's size.
pub const HEADER_LEN: usize = 24;

/// Encapsulation commands.
pub mod command {
    /// NOP (no reply).
    pub const NOP: u16 = 0x0000;
    /// ListServices.
    pub const LIST_SERVICES: u16 = 0x0004;
    /// ListIdentity (TCP and UDP).
    pub const LIST_IDENTITY: u16 = 0x0063;
    /// ListInterfaces.
    pub const LIST_INTERFACES: u16 = 0x0064;
    /// RegisterSession.
    pub const REGISTER_SESSION: u16 = 0x0065;
    /// UnRegisterSession (no reply).
    pub const UNREGISTER_SESSION: u16 = 0x0066;
    /// SendRRData: unconnected explicit messages.
    pub const SEND_RR_DATA: u16 = 0x006F;
    /// SendUnitData: connected (class 3) explicit messages.
    pub const SEND_UNIT_DATA: u16 = 0x0070;
}

/// Encapsulation status codes.
pub mod status {
    /// Success.
    pub const SUCCESS: u32 = 0x0000;
    /// The command is not one the receiver knows.
    pub const INVALID_COMMAND: u32 = 0x0001;
    /// Malformed data in the command.
    pub const INCORRECT_DATA: u32 = 0x0003;
    /// The session handle is not one the receiver issued.
    pub const INVALID_SESSION: u32 = 0x0064;
    /// The length does not match the data.
    pub const INVALID_LENGTH: u32 = 0x0065;
    /// The protocol version is not supported.
    pub const UNSUPPORTED_PROTOCOL: u32 = 0x0069;
}

/// Why bytes are no whole encapsulation message (on a TCP stream: read more).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EncapError {
    /// Fewer than 24 bytes: wait for more.
    Incomplete,
    /// The header's length goes past the bytes given: wait for more (`needed` in all).
    Truncated {
        /// The whole message's size.
        needed: usize,
    },
}

/// A view of an encapsulation message: the header's fields and the data after it. The
/// accessors never panic; on a buffer [`check_len`](Self::check_len) refused they read zeros.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EncapPacket<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> EncapPacket<T> {
    /// A view of `buffer`, its length unchecked.
    pub const fn new_unchecked(buffer: T) -> Self {
        EncapPacket { buffer }
    }

    /// A view of `buffer` once it holds the header and all the data the header announces.
    pub fn new_checked(buffer: T) -> Result<Self, EncapError> {
        let packet = Self::new_unchecked(buffer);
        packet.check_len()?;
        Ok(packet)
    }

    /// Whether the buffer holds the header and its data.
    pub fn check_len(&self) -> Result<(), EncapError> {
        let len = self.buffer.as_ref().len();
        if len < HEADER_LEN {
            return Err(EncapError::Incomplete);
        }
        let needed = self.total_len();
        if len < needed {
            return Err(EncapError::Truncated { needed });
        }
        Ok(())
    }

    /// The buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    fn u16(&self, at: usize) -> u16 {
        u16_at(self.buffer.as_ref(), at).unwrap_or(0)
    }

    fn u32(&self, at: usize) -> u32 {
        u32_at(self.buffer.as_ref(), at).unwrap_or(0)
    }

    /// The command.
    pub fn command(&self) -> u16 {
        self.u16(0)
    }

    /// The data's length as the header says it.
    pub fn length(&self) -> u16 {
        self.u16(2)
    }

    /// The session handle.
    pub fn session(&self) -> u32 {
        self.u32(4)
    }

    /// The status.
    pub fn status(&self) -> u32 {
        self.u32(8)
    }

    /// The sender context, echoed in replies.
    pub fn context(&self) -> [u8; 8] {
        let mut context = [0; 8];
        if let Some(bytes) = self.buffer.as_ref().get(12..20) {
            context.copy_from_slice(bytes);
        }
        context
    }

    /// The options word.
    pub fn options(&self) -> u32 {
        self.u32(20)
    }

    /// The whole message's size: header and data.
    pub fn total_len(&self) -> usize {
        HEADER_LEN + usize::from(self.length())
    }

    /// The data (as much of it as the buffer holds).
    pub fn data(&self) -> &[u8] {
        let bytes = self.buffer.as_ref();
        let end = self.total_len().min(bytes.len());
        bytes.get(HEADER_LEN..end).unwrap_or(&[])
    }
}

/// An encapsulation message: header fields and data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EncapRepr<'a> {
    /// The command.
    pub command: u16,
    /// The session handle.
    pub session: u32,
    /// The status.
    pub status: u32,
    /// The sender context, echoed in replies.
    pub context: [u8; 8],
    /// The options word.
    pub options: u32,
    /// The command's data.
    pub data: &'a [u8],
}

impl<'a> EncapRepr<'a> {
    /// The message `packet` holds.
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        packet: &EncapPacket<&'a T>,
    ) -> Result<EncapRepr<'a>, EncapError> {
        packet.check_len()?;
        let bytes: &'a [u8] = packet.buffer.as_ref();
        Ok(EncapRepr {
            command: packet.command(),
            session: packet.session(),
            status: packet.status(),
            context: packet.context(),
            options: packet.options(),
            data: bytes.get(HEADER_LEN..packet.total_len()).unwrap_or(&[]),
        })
    }

    /// The message at the start of `bytes`, and its size (the rest of a TCP stream follows).
    pub fn parse_prefix(bytes: &'a [u8]) -> Result<(EncapRepr<'a>, usize), EncapError> {
        let packet = EncapPacket::new_checked(bytes)?;
        Ok((Self::parse(&packet)?, packet.total_len()))
    }

    /// A request from an originator: status and options zero.
    pub const fn request(
        command: u16,
        session: u32,
        context: [u8; 8],
        data: &'a [u8],
    ) -> EncapRepr<'a> {
        EncapRepr {
            command,
            session,
            status: status::SUCCESS,
            context,
            options: 0,
            data,
        }
    }

    /// A reply to this message: same command, session and context.
    pub fn reply<'b>(&self, status: u32, data: &'b [u8]) -> EncapRepr<'b> {
        EncapRepr {
            command: self.command,
            session: self.session,
            status,
            context: self.context,
            options: 0,
            data,
        }
    }
}

impl Emit for EncapRepr<'_> {
    fn buffer_len(&self) -> usize {
        HEADER_LEN + self.data.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let mut w = Writer::new(buf);
        w.u16(self.command)?;
        w.u16(length_u16(self.data.len())?)?;
        w.u32(self.session)?;
        w.u32(self.status)?;
        w.bytes(&self.context)?;
        w.u32(self.options)?;
        w.bytes(self.data)?;
        Ok(w.done())
    }
}

/// RegisterSession's data: the protocol version (1) and options (0), both ways.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegisterSession {
    /// The encapsulation protocol version.
    pub protocol_version: u16,
    /// The options flags.
    pub options: u16,
}

impl RegisterSession {
    /// What an originator sends: version 1, no options.
    pub const REQUEST: RegisterSession = RegisterSession {
        protocol_version: 1,
        options: 0,
    };

    /// The data's four bytes; [`Error::Truncated`] or [`Error::Trailing`] for another length.
    pub fn parse(data: &[u8]) -> Result<RegisterSession, Error> {
        let mut r = Reader::new(data);
        let parsed = RegisterSession {
            protocol_version: r.u16()?,
            options: r.u16()?,
        };
        match r.rest() {
            [] => Ok(parsed),
            _ => Err(Error::Trailing),
        }
    }

    /// The four bytes.
    pub fn to_bytes(&self) -> [u8; 4] {
        let [a, b] = self.protocol_version.to_le_bytes();
        let [c, d] = self.options.to_le_bytes();
        [a, b, c, d]
    }
}

/// A ListIdentity reply's identity item (CPF item 0x0C): the Identity object's attributes and
/// the socket the device listens on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IdentityItem<'a> {
    /// The encapsulation protocol version (1).
    pub protocol_version: u16,
    /// The TCP port (big-endian on the wire, as in a sockaddr).
    pub port: u16,
    /// The IPv4 address.
    pub address: [u8; 4],
    /// Vendor ID.
    pub vendor: u16,
    /// Device type.
    pub device_type: u16,
    /// Product code.
    pub product_code: u16,
    /// Major and minor revision.
    pub revision: (u8, u8),
    /// Identity status word.
    pub status: u16,
    /// Serial number.
    pub serial: u32,
    /// Product name (a SHORT_STRING: at most 255 bytes).
    pub name: &'a [u8],
    /// State (3: operational).
    pub state: u8,
}

impl<'a> IdentityItem<'a> {
    /// The item's data. The state byte after the name may be missing (some devices leave it
    /// out): it reads as 0xFF.
    pub fn parse(data: &'a [u8]) -> Result<IdentityItem<'a>, Error> {
        let mut r = Reader::new(data);
        let protocol_version = r.u16()?;
        let sockaddr = r.take(16)?;
        let (port, address) = (
            u16::from_be_bytes([sockaddr[2], sockaddr[3]]),
            [sockaddr[4], sockaddr[5], sockaddr[6], sockaddr[7]],
        );
        let vendor = r.u16()?;
        let device_type = r.u16()?;
        let product_code = r.u16()?;
        let revision = (r.u8()?, r.u8()?);
        let status = r.u16()?;
        let serial = r.u32()?;
        let len = r.u8()?;
        let name = r.take(usize::from(len))?;
        let state = r.u8().unwrap_or(0xFF);
        Ok(IdentityItem {
            protocol_version,
            port,
            address,
            vendor,
            device_type,
            product_code,
            revision,
            status,
            serial,
            name,
            state,
        })
    }
}

impl Emit for IdentityItem<'_> {
    fn buffer_len(&self) -> usize {
        34 + self.name.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let name_len = u8::try_from(self.name.len()).map_err(|_| Error::TooLong)?;
        let mut w = Writer::new(buf);
        w.u16(self.protocol_version)?;
        w.bytes(&2u16.to_be_bytes())?; // AF_INET
        w.bytes(&self.port.to_be_bytes())?;
        w.bytes(&self.address)?;
        w.bytes(&[0; 8])?;
        w.u16(self.vendor)?;
        w.u16(self.device_type)?;
        w.u16(self.product_code)?;
        w.u8(self.revision.0)?;
        w.u8(self.revision.1)?;
        w.u16(self.status)?;
        w.u32(self.serial)?;
        w.u8(name_len)?;
        w.bytes(self.name)?;
        w.u8(self.state)?;
        Ok(w.done())
    }
}
