//! The Connection Manager's services (class 6, instance 1): Forward_Open and
//! Large_Forward_Open (32-bit network connection parameters), their successful reply,
//! Forward_Close, the connection triad the replies echo, and the extended status codes.

use super::message::service;
use super::{Emit, Error, Reader, Writer};

/// The request path of the Connection Manager, `20 06 24 01`.
pub const PATH: [u8; 4] = [0x20, 0x06, 0x24, 0x01];

/// Priority/time tick and timeout ticks an originator sends: 1 ms ticks, 14 of them.
pub const DEFAULT_TICKS: (u8, u8) = (0x0A, 0x0E);

/// Connection Manager extended status codes.
pub mod extended {
    /// Connection in use or duplicate Forward_Open.
    pub const CONNECTION_IN_USE: u16 = 0x0100;
    /// Transport class and trigger combination not supported.
    pub const TRANSPORT_NOT_SUPPORTED: u16 = 0x0103;
    /// Ownership conflict.
    pub const OWNERSHIP_CONFLICT: u16 = 0x0106;
    /// Connection not found (Forward_Close).
    pub const CONNECTION_NOT_FOUND: u16 = 0x0107;
    /// Invalid network connection parameter.
    pub const INVALID_NETWORK_PARAMETER: u16 = 0x0108;
    /// Invalid connection size.
    pub const INVALID_SIZE: u16 = 0x0109;
    /// RPI not supported.
    pub const RPI_NOT_SUPPORTED: u16 = 0x0111;
    /// Vendor ID or product code mismatch.
    pub const PRODUCT_MISMATCH: u16 = 0x0114;
    /// Device type mismatch.
    pub const DEVICE_TYPE_MISMATCH: u16 = 0x0115;
    /// Revision mismatch.
    pub const REVISION_MISMATCH: u16 = 0x0116;
    /// Invalid O→T connection size (the size expected follows).
    pub const INVALID_O_T_SIZE: u16 = 0x0127;
    /// Invalid T→O connection size (the size expected follows).
    pub const INVALID_T_O_SIZE: u16 = 0x0128;
    /// Invalid configuration application path.
    pub const INVALID_CONFIG_PATH: u16 = 0x0129;
    /// Invalid consuming application path.
    pub const INVALID_CONSUMING_PATH: u16 = 0x012A;
    /// Invalid producing application path.
    pub const INVALID_PRODUCING_PATH: u16 = 0x012B;
    /// Invalid segment in the connection path.
    pub const INVALID_SEGMENT: u16 = 0x0315;

    /// What an extended status means, in a few words.
    pub fn text(code: u16) -> &'static str {
        match code {
            CONNECTION_IN_USE => "connection in use or duplicate Forward_Open",
            TRANSPORT_NOT_SUPPORTED => "transport class and trigger not supported",
            OWNERSHIP_CONFLICT => "ownership conflict",
            CONNECTION_NOT_FOUND => "connection not found",
            INVALID_NETWORK_PARAMETER => "invalid network connection parameter",
            INVALID_SIZE => "invalid connection size",
            RPI_NOT_SUPPORTED => "RPI not supported",
            PRODUCT_MISMATCH => "vendor ID or product code mismatch",
            DEVICE_TYPE_MISMATCH => "device type mismatch",
            REVISION_MISMATCH => "revision mismatch",
            INVALID_O_T_SIZE => "invalid O→T size",
            INVALID_T_O_SIZE => "invalid T→O size",
            INVALID_CONFIG_PATH => "invalid configuration application path",
            INVALID_CONSUMING_PATH => "invalid consuming application path",
            INVALID_PRODUCING_PATH => "invalid producing application path",
            INVALID_SEGMENT => "invalid segment in the connection path",
            _ => "connection failure",
        }
    }
}

/// The triad naming a connection: connection serial number, originator vendor ID, originator
/// serial number.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Triad {
    /// Connection serial number.
    pub serial: u16,
    /// Originator vendor ID.
    pub vendor: u16,
    /// Originator serial number.
    pub originator_serial: u32,
}

impl Triad {
    fn read(r: &mut Reader<'_>) -> Result<Triad, Error> {
        Ok(Triad {
            serial: r.u16()?,
            vendor: r.u16()?,
            originator_serial: r.u32()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<(), Error> {
        w.u16(self.serial)?;
        w.u16(self.vendor)?;
        w.u32(self.originator_serial)
    }

    /// What Forward_Close and a refused Forward_Open reply with: the triad, an application
    /// reply of size 0 and the reserved byte.
    pub fn reply(&self) -> [u8; 10] {
        let mut out = [0; 10];
        let mut w = Writer::new(&mut out);
        // Ten bytes fit ten bytes.
        let _ = self.write(&mut w);
        out
    }
}

/// A Forward_Open or Large_Forward_Open request's service data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardOpenRepr<'a> {
    /// Large_Forward_Open (32-bit network connection parameters) instead of Forward_Open.
    pub large: bool,
    /// Priority/time tick and timeout ticks.
    pub ticks: (u8, u8),
    /// The O→T connection ID the originator proposes (the target chooses; 0).
    pub o_t_id: u32,
    /// The T→O connection ID the originator chooses.
    pub t_o_id: u32,
    /// The connection's triad.
    pub triad: Triad,
    /// Timeout multiplier code (0 is ×4, 1 ×8, ... 7 ×512).
    pub multiplier: u8,
    /// O→T RPI in µs.
    pub o_t_rpi: u32,
    /// O→T network connection parameters (see [`network_params`]).
    pub o_t_params: u32,
    /// T→O RPI in µs.
    pub t_o_rpi: u32,
    /// T→O network connection parameters.
    pub t_o_params: u32,
    /// Transport class and trigger (0x01: class 1 cyclic; 0xA3: class 3 server).
    pub transport: u8,
    /// The connection path (configuration instance, O→T and T→O connection points), padded.
    pub path: &'a [u8],
}

impl<'a> ForwardOpenRepr<'a> {
    /// The service data of a Forward_Open (`large` false) or Large_Forward_Open request:
    /// [`Error::Truncated`] when short, [`Error::Trailing`] with bytes after the path.
    pub fn parse(data: &'a [u8], large: bool) -> Result<ForwardOpenRepr<'a>, Error> {
        let mut r = Reader::new(data);
        let ticks = (r.u8()?, r.u8()?);
        let o_t_id = r.u32()?;
        let t_o_id = r.u32()?;
        let triad = Triad::read(&mut r)?;
        let multiplier = r.u8()?;
        r.take(3)?;
        let params = |r: &mut Reader<'_>| match large {
            true => r.u32(),
            false => r.u16().map(u32::from),
        };
        let o_t_rpi = r.u32()?;
        let o_t_params = params(&mut r)?;
        let t_o_rpi = r.u32()?;
        let t_o_params = params(&mut r)?;
        let transport = r.u8()?;
        let words = r.u8()?;
        let path = r.take(2 * usize::from(words))?;
        if !r.rest().is_empty() {
            return Err(Error::Trailing);
        }
        Ok(ForwardOpenRepr {
            large,
            ticks,
            o_t_id,
            t_o_id,
            triad,
            multiplier,
            o_t_rpi,
            o_t_params,
            t_o_rpi,
            t_o_params,
            transport,
            path,
        })
    }

    /// The service code.
    pub const fn service(&self) -> u8 {
        match self.large {
            true => service::LARGE_FORWARD_OPEN,
            false => service::FORWARD_OPEN,
        }
    }

    /// The O→T connection size in bytes (bits 0-8 of the parameters, 0-15 when large).
    pub const fn o_t_size(&self) -> u16 {
        connection_size(self.large, self.o_t_params)
    }

    /// The T→O connection size in bytes.
    pub const fn t_o_size(&self) -> u16 {
        connection_size(self.large, self.t_o_params)
    }

    /// The connection timeout in µs: the multiplier times the O→T RPI (at least 1 ms).
    pub fn timeout_us(&self) -> u64 {
        u64::from(self.o_t_rpi.max(1000)) * (4u64 << self.multiplier.min(7))
    }
}

/// A network connection parameters' size field: bits 0-8, or 0-15 for Large_Forward_Open.
pub const fn connection_size(large: bool, params: u32) -> u16 {
    match large {
        true => (params & 0xFFFF) as u16,
        false => (params & 0x01FF) as u16,
    }
}

/// The whole Message Router request: service, the Connection Manager's path, service data.
impl Emit for ForwardOpenRepr<'_> {
    fn buffer_len(&self) -> usize {
        let word = if self.large { 4 } else { 2 };
        2 + PATH.len() + 32 + 2 * word + self.path.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let words = path_words(self.path)?;
        let mut w = Writer::new(buf);
        w.u8(self.service())?;
        w.u8((PATH.len() / 2) as u8)?;
        w.bytes(&PATH)?;
        w.u8(self.ticks.0)?;
        w.u8(self.ticks.1)?;
        w.u32(self.o_t_id)?;
        w.u32(self.t_o_id)?;
        self.triad.write(&mut w)?;
        w.bytes(&[self.multiplier, 0, 0, 0])?;
        for (rpi, params) in [
            (self.o_t_rpi, self.o_t_params),
            (self.t_o_rpi, self.t_o_params),
        ] {
            w.u32(rpi)?;
            match self.large {
                true => w.u32(params)?,
                false => w.u16(u16::try_from(params).map_err(|_| Error::Malformed)?)?,
            }
        }
        w.u8(self.transport)?;
        w.u8(words)?;
        w.bytes(self.path)?;
        Ok(w.done())
    }
}

fn path_words(path: &[u8]) -> Result<u8, Error> {
    if path.len() % 2 != 0 {
        return Err(Error::Malformed);
    }
    u8::try_from(path.len() / 2).map_err(|_| Error::TooLong)
}

/// A successful Forward_Open reply's data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardOpenReply {
    /// The O→T connection ID (the target's choice).
    pub o_t_id: u32,
    /// The T→O connection ID (the originator's).
    pub t_o_id: u32,
    /// The connection's triad.
    pub triad: Triad,
    /// The actual O→T packet interval, µs.
    pub o_t_api: u32,
    /// The actual T→O packet interval, µs.
    pub t_o_api: u32,
}

impl ForwardOpenReply {
    /// The reply's data (an application reply after it is ignored).
    pub fn parse(data: &[u8]) -> Result<ForwardOpenReply, Error> {
        let mut r = Reader::new(data);
        Ok(ForwardOpenReply {
            o_t_id: r.u32()?,
            t_o_id: r.u32()?,
            triad: Triad::read(&mut r)?,
            o_t_api: r.u32()?,
            t_o_api: r.u32()?,
        })
    }
}

/// The data: as parsed, an application reply of size 0 and the reserved byte.
impl Emit for ForwardOpenReply {
    fn buffer_len(&self) -> usize {
        26
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let mut w = Writer::new(buf);
        w.u32(self.o_t_id)?;
        w.u32(self.t_o_id)?;
        self.triad.write(&mut w)?;
        w.u32(self.o_t_api)?;
        w.u32(self.t_o_api)?;
        w.bytes(&[0, 0])?;
        Ok(w.done())
    }
}

/// A Forward_Close request naming a connection by its triad, with its connection path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardCloseRepr<'a> {
    /// Priority/time tick and timeout ticks.
    pub ticks: (u8, u8),
    /// The connection's triad.
    pub triad: Triad,
    /// The connection path, padded (a target may leave it unchecked).
    pub path: &'a [u8],
}

impl<'a> ForwardCloseRepr<'a> {
    /// The service data: the triad is needed, the path is taken when it is all there (a
    /// target finds the connection by its triad).
    pub fn parse(data: &'a [u8]) -> Result<ForwardCloseRepr<'a>, Error> {
        let mut r = Reader::new(data);
        let ticks = (r.u8()?, r.u8()?);
        let triad = Triad::read(&mut r)?;
        let words = r.u8().unwrap_or(0);
        let _reserved = r.u8();
        let path = r.take(2 * usize::from(words)).unwrap_or(&[]);
        Ok(ForwardCloseRepr { ticks, triad, path })
    }
}

/// The whole Message Router request: service, the Connection Manager's path, service data.
impl Emit for ForwardCloseRepr<'_> {
    fn buffer_len(&self) -> usize {
        2 + PATH.len() + 12 + self.path.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let words = path_words(self.path)?;
        let mut w = Writer::new(buf);
        w.u8(service::FORWARD_CLOSE)?;
        w.u8((PATH.len() / 2) as u8)?;
        w.bytes(&PATH)?;
        w.u8(self.ticks.0)?;
        w.u8(self.ticks.1)?;
        self.triad.write(&mut w)?;
        w.u8(words)?;
        w.u8(0)?;
        w.bytes(self.path)?;
        Ok(w.done())
    }
}

/// A Forward_Open's network connection parameters: the connection type (1 multicast, 2
/// point-to-point), the priority (0 low, 1 high, 2 scheduled, 3 urgent), fixed or variable
/// size and the size in bytes; 16 bits (size in bits 0-8) or, for Large_Forward_Open, 32
/// (size in bits 0-15).
pub const fn network_params(large: bool, kind: u8, priority: u8, variable: bool, size: u16) -> u32 {
    let (kind, priority, variable) = (kind as u32 & 3, priority as u32 & 3, variable as u32);
    if large {
        kind << 29 | priority << 26 | variable << 25 | size as u32
    } else {
        kind << 13 | priority << 10 | variable << 9 | (size as u32 & 0x01FF)
    }
}
