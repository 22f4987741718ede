//! Message Router requests (service, path, data) and responses (service with the reply bit,
//! general status, extended status words, data), with the services and general status codes
//! this crate's peers use.

use super::{u16_at, Emit, Error, Reader, Writer};

/// Service codes.
pub mod service {
    /// Get_Attributes_All.
    pub const GET_ATTRIBUTES_ALL: u8 = 0x01;
    /// Get_Attribute_Single.
    pub const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;
    /// Set_Attribute_Single.
    pub const SET_ATTRIBUTE_SINGLE: u8 = 0x10;
    /// Forward_Close (Connection Manager).
    pub const FORWARD_CLOSE: u8 = 0x4E;
    /// Forward_Open (Connection Manager).
    pub const FORWARD_OPEN: u8 = 0x54;
    /// Large_Forward_Open (Connection Manager).
    pub const LARGE_FORWARD_OPEN: u8 = 0x5B;
    /// The bit a response sets in the request's service code.
    pub const REPLY: u8 = 0x80;
}

/// CIP general status codes.
pub mod general {
    /// Success.
    pub const SUCCESS: u8 = 0x00;
    /// Connection failure (extended status says which).
    pub const CONNECTION_FAILURE: u8 = 0x01;
    /// Path segment error.
    pub const PATH_SEGMENT_ERROR: u8 = 0x04;
    /// Path destination unknown.
    pub const PATH_DESTINATION_UNKNOWN: u8 = 0x05;
    /// Service not supported.
    pub const SERVICE_NOT_SUPPORTED: u8 = 0x08;
    /// Invalid attribute value.
    pub const INVALID_ATTRIBUTE_VALUE: u8 = 0x09;
    /// Attribute not settable.
    pub const ATTRIBUTE_NOT_SETTABLE: u8 = 0x0E;
    /// Privilege violation.
    pub const PRIVILEGE_VIOLATION: u8 = 0x0F;
    /// Device state conflict.
    pub const DEVICE_STATE_CONFLICT: u8 = 0x10;
    /// Reply data too large (for the connection).
    pub const REPLY_DATA_TOO_LARGE: u8 = 0x11;
    /// Not enough data.
    pub const NOT_ENOUGH_DATA: u8 = 0x13;
    /// Attribute not supported.
    pub const ATTRIBUTE_NOT_SUPPORTED: u8 = 0x14;
    /// Too much data.
    pub const TOO_MUCH_DATA: u8 = 0x15;
    /// Object does not exist.
    pub const OBJECT_DOES_NOT_EXIST: u8 = 0x16;

    /// What a general status means, in a few words.
    pub fn text(code: u8) -> &'static str {
        match code {
            SUCCESS => "success",
            CONNECTION_FAILURE => "connection failure",
            PATH_SEGMENT_ERROR => "path segment error",
            PATH_DESTINATION_UNKNOWN => "path destination unknown",
            SERVICE_NOT_SUPPORTED => "service not supported",
            INVALID_ATTRIBUTE_VALUE => "invalid attribute value",
            ATTRIBUTE_NOT_SETTABLE => "attribute not settable",
            PRIVILEGE_VIOLATION => "privilege violation",
            DEVICE_STATE_CONFLICT => "device state conflict",
            REPLY_DATA_TOO_LARGE => "reply data too large",
            NOT_ENOUGH_DATA => "not enough data",
            ATTRIBUTE_NOT_SUPPORTED => "attribute not supported",
            TOO_MUCH_DATA => "too much data",
            OBJECT_DOES_NOT_EXIST => "object does not exist",
            _ => "error",
        }
    }
}

/// A Message Router request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RequestRepr<'a> {
    /// The service code.
    pub service: u8,
    /// The request path's bytes (an even number: the path is counted in words).
    pub path: &'a [u8],
    /// The service data.
    pub data: &'a [u8],
}

impl<'a> RequestRepr<'a> {
    /// The request in `bytes`; [`Error::Truncated`] when the path runs past them.
    pub fn parse(bytes: &'a [u8]) -> Result<RequestRepr<'a>, Error> {
        let mut r = Reader::new(bytes);
        let service = r.u8()?;
        let words = r.u8()?;
        let path = r.take(2 * usize::from(words))?;
        Ok(RequestRepr {
            service,
            path,
            data: r.rest(),
        })
    }
}

impl Emit for RequestRepr<'_> {
    fn buffer_len(&self) -> usize {
        2 + self.path.len() + self.data.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        if self.path.len() % 2 != 0 {
            return Err(Error::Malformed);
        }
        let words = u8::try_from(self.path.len() / 2).map_err(|_| Error::TooLong)?;
        let mut w = Writer::new(buf);
        w.u8(self.service)?;
        w.u8(words)?;
        w.bytes(self.path)?;
        w.bytes(self.data)?;
        Ok(w.done())
    }
}

/// A Message Router response.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResponseRepr<'a> {
    /// The request's service code (the reply bit is added on the wire).
    pub service: u8,
    /// The general status.
    pub status: u8,
    /// The extended status words, little-endian (two bytes each).
    pub extended: &'a [u8],
    /// The reply data.
    pub data: &'a [u8],
}

impl<'a> ResponseRepr<'a> {
    /// A response with `status` and no extended status or data.
    pub const fn status(service: u8, status: u8) -> ResponseRepr<'static> {
        ResponseRepr {
            service,
            status,
            extended: &[],
            data: &[],
        }
    }

    /// A successful response with `data`.
    pub const fn success(service: u8, data: &'a [u8]) -> ResponseRepr<'a> {
        ResponseRepr {
            service,
            status: general::SUCCESS,
            extended: &[],
            data,
        }
    }

    /// The response in `bytes`; [`Error::Truncated`] when the header or the extended status
    /// runs past them.
    pub fn parse(bytes: &'a [u8]) -> Result<ResponseRepr<'a>, Error> {
        let mut r = Reader::new(bytes);
        let service = r.u8()? & !service::REPLY;
        r.u8()?; // reserved
        let status = r.u8()?;
        let words = r.u8()?;
        let extended = r.take(2 * usize::from(words))?;
        Ok(ResponseRepr {
            service,
            status,
            extended,
            data: r.rest(),
        })
    }

    /// The extended status word `index`.
    pub fn extended_status(&self, index: usize) -> Option<u16> {
        u16_at(self.extended, 2 * index)
    }
}

impl Emit for ResponseRepr<'_> {
    fn buffer_len(&self) -> usize {
        4 + self.extended.len() + self.data.len()
    }

    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        if self.extended.len() % 2 != 0 {
            return Err(Error::Malformed);
        }
        let words = u8::try_from(self.extended.len() / 2).map_err(|_| Error::TooLong)?;
        let mut w = Writer::new(buf);
        w.u8(self.service | service::REPLY)?;
        w.u8(0)?;
        w.u8(self.status)?;
        w.u8(words)?;
        w.bytes(self.extended)?;
        w.bytes(self.data)?;
        Ok(w.done())
    }
}
