//! EtherNet/IP byte layouts only, little-endian as CIP is: the encapsulation ([`encap`]), the
//! common packet format items ([`cpf`]), Message Router requests and responses ([`message`]),
//! EPATHs ([`epath`]), the Connection Manager's services ([`connection_manager`]) and
//! connected data, class 1 and class 3 ([`io`]). Each layout is a view or a `Repr` with `parse`
//! and an [`Emit`] into the caller's buffer; state machines never index bytes themselves.

pub mod connection_manager;
pub mod cpf;
pub mod encap;
pub mod epath;
pub mod io;
pub mod message;

#[cfg(test)]
mod tests;

/// Why bytes are not the layout asked for, or a layout does not fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error {
    /// The bytes end before the layout does.
    Truncated,
    /// Bytes follow where the layout has ended (a request with too much data).
    Trailing,
    /// A field holds a value the layout does not allow.
    Malformed,
    /// A length does not fit its field (more than 65535 bytes of data, 255 words of path).
    TooLong,
    /// The output buffer is shorter than [`Emit::buffer_len`].
    BufferTooSmall,
}

/// A layout written into the caller's buffer.
pub trait Emit {
    /// The bytes [`emit`](Emit::emit) writes.
    fn buffer_len(&self) -> usize;

    /// Writes the layout at the start of `buf`; the bytes written.
    fn emit(&self, buf: &mut [u8]) -> Result<usize, Error>;

    /// The layout as a new vector (with `std`).
    #[cfg(feature = "std")]
    fn to_vec(&self) -> Result<Vec<u8>, Error> {
        let mut buf = vec![0; self.buffer_len()];
        let written = self.emit(&mut buf)?;
        buf.truncate(written);
        Ok(buf)
    }
}

/// The little-endian `u16` at `at`; `None` past the end.
pub fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes([
        *b.get(at)?,
        *b.get(at.checked_add(1)?)?,
    ]))
}

/// The little-endian `u32` at `at`; `None` past the end.
pub fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    let bytes = b.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}

/// A cursor writing into a buffer, [`Error::BufferTooSmall`] past its end.
pub(crate) struct Writer<'a> {
    buf: &'a mut [u8],
    at: usize,
}

impl<'a> Writer<'a> {
    pub(crate) fn new(buf: &'a mut [u8]) -> Self {
        Writer { buf, at: 0 }
    }

    pub(crate) fn bytes(&mut self, bytes: &[u8]) -> Result<(), Error> {
        let end = self.at + bytes.len();
        self.buf
            .get_mut(self.at..end)
            .ok_or(Error::BufferTooSmall)?
            .copy_from_slice(bytes);
        self.at = end;
        Ok(())
    }

    pub(crate) fn u8(&mut self, value: u8) -> Result<(), Error> {
        self.bytes(&[value])
    }

    pub(crate) fn u16(&mut self, value: u16) -> Result<(), Error> {
        self.bytes(&value.to_le_bytes())
    }

    pub(crate) fn u32(&mut self, value: u32) -> Result<(), Error> {
        self.bytes(&value.to_le_bytes())
    }

    /// What [`Emit::emit`] returns: the bytes written.
    pub(crate) fn done(&self) -> usize {
        self.at
    }
}

/// A cursor reading from bytes, [`Error::Truncated`] past their end.
pub(crate) struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Reader { bytes, at: 0 }
    }

    pub(crate) fn take(&mut self, len: usize) -> Result<&'a [u8], Error> {
        let end = self.at.checked_add(len).ok_or(Error::Truncated)?;
        let taken = self.bytes.get(self.at..end).ok_or(Error::Truncated)?;
        self.at = end;
        Ok(taken)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, Error> {
        Ok(self.take(1)?[0])
    }

    pub(crate) fn u16(&mut self) -> Result<u16, Error> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    pub(crate) fn u32(&mut self) -> Result<u32, Error> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// The bytes not read yet.
    pub(crate) fn rest(&self) -> &'a [u8] {
        self.bytes.get(self.at..).unwrap_or(&[])
    }
}

/// `len` as a `u16` length field, [`Error::TooLong`] above 65535.
pub(crate) fn length_u16(len: usize) -> Result<u16, Error> {
    u16::try_from(len).map_err(|_| Error::TooLong)
}
