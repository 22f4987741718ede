//! The PNIO block framing inside the RPC argument and the alarm PDUs (IEC 61158-6-10): every
//! block starts with a BlockHeader (BlockType, BlockLength counting the bytes after the length
//! field, BlockVersionHigh/Low) and is big-endian. The blocks of an argument as an iterator over
//! views ([`blocks`]), a big-endian cursor to read a block's content ([`Reader`]), and a block
//! written into the caller's buffer ([`emit_block`], its content through a cursor too).

use super::rpc::Uuid;
use super::{put, BufferTooSmall, Mac};

/// A cursor over big-endian block bytes; every read is `None` past the end.
#[derive(Debug, Clone)]
pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    /// A reader at the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Reader { bytes, at: 0 }
    }
    /// The next `n` bytes.
    pub fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let b = self.bytes.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(b)
    }
    /// A byte.
    pub fn u8(&mut self) -> Option<u8> {
        Some(self.take(1)?[0])
    }
    /// A big-endian u16.
    pub fn u16(&mut self) -> Option<u16> {
        Some(u16::from_be_bytes(self.take(2)?.try_into().ok()?))
    }
    /// A big-endian u32.
    pub fn u32(&mut self) -> Option<u32> {
        Some(u32::from_be_bytes(self.take(4)?.try_into().ok()?))
    }
    /// A UUID (big-endian, as blocks carry them).
    pub fn uuid(&mut self) -> Option<Uuid> {
        Some(Uuid(self.take(16)?.try_into().ok()?))
    }
    /// A MAC address.
    pub fn mac(&mut self) -> Option<Mac> {
        self.take(6)?.try_into().ok()
    }
    /// The bytes not read yet.
    pub fn rest(&self) -> &'a [u8] {
        self.bytes.get(self.at..).unwrap_or(&[])
    }
}

/// A big-endian cursor writing into the caller's buffer.
pub(crate) struct Writer<'a> {
    buf: &'a mut [u8],
    at: usize,
}

impl<'a> Writer<'a> {
    pub(crate) fn new(buf: &'a mut [u8]) -> Self {
        Writer { buf, at: 0 }
    }
    pub(crate) fn bytes(&mut self, bytes: &[u8]) -> Result<(), BufferTooSmall> {
        self.at = put(self.buf, self.at, bytes)?;
        Ok(())
    }
    #[cfg(feature = "alloc")]
    pub(crate) fn u8(&mut self, v: u8) -> Result<(), BufferTooSmall> {
        self.bytes(&[v])
    }
    pub(crate) fn u16(&mut self, v: u16) -> Result<(), BufferTooSmall> {
        self.bytes(&v.to_be_bytes())
    }
    pub(crate) fn u32(&mut self, v: u32) -> Result<(), BufferTooSmall> {
        self.bytes(&v.to_be_bytes())
    }
    /// A count field: `BufferTooSmall` when it does not fit 16 bits (no block could hold it).
    pub(crate) fn count(&mut self, n: usize) -> Result<(), BufferTooSmall> {
        self.u16(u16::try_from(n).map_err(|_| BufferTooSmall)?)
    }
    pub(crate) fn len(&self) -> usize {
        self.at
    }
}

/// One block: its type, version and the bytes after the version.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block<'a> {
    /// BlockType.
    pub block_type: u16,
    /// BlockVersionHigh, BlockVersionLow.
    pub version: (u8, u8),
    /// The block's content after the header.
    pub body: &'a [u8],
}

/// The blocks of an argument, in order; `Err(offset)` where a header is short, a BlockLength
/// is below 2, or a block runs past the end (and nothing after it).
pub fn blocks(mut args: &[u8]) -> impl Iterator<Item = Result<Block<'_>, usize>> {
    let mut offset = 0;
    core::iter::from_fn(move || {
        if args.is_empty() {
            return None;
        }
        let mut r = Reader::new(args);
        let block = (|| {
            let (block_type, len) = (r.u16()?, usize::from(r.u16()?));
            let rest = r.take(len).filter(|_| len >= 2)?;
            Some((block_type, len, rest))
        })();
        let Some((block_type, len, rest)) = block else {
            args = &[];
            return Some(Err(offset));
        };
        args = &args[4 + len..];
        offset += 4 + len;
        Some(Ok(Block {
            block_type,
            version: (rest[0], rest[1]),
            body: &rest[2..],
        }))
    })
}

/// Writes a block of `block_type`, version 1.`low`, at the start of `buf`, its content written
/// by `body` into the rest of `buf` (returning its length); the block's length. On an error
/// what `buf` holds is unspecified.
pub fn emit_block(
    buf: &mut [u8],
    block_type: u16,
    low: u8,
    body: impl FnOnce(&mut [u8]) -> Result<usize, BufferTooSmall>,
) -> Result<usize, BufferTooSmall> {
    let at = put(buf, 0, &block_type.to_be_bytes())?;
    let at = put(buf, at, &[0, 0, 1, low])?;
    let len = at + body(buf.get_mut(at..).ok_or(BufferTooSmall)?)?;
    let block_length = u16::try_from(len - 4).map_err(|_| BufferTooSmall)?;
    put(buf, 2, &block_length.to_be_bytes())?;
    Ok(len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_split_and_stop_at_a_bad_header() {
        let args = [
            0x01, 0x10, 0x00, 0x04, 0x01, 0x00, 0xAA, 0xBB, // PrmEnd-like, body AA BB
            0x80, 0x01, 0x00, 0x02, 0x01, 0x01, // empty body
            0x00, 0x01, 0x00, 0x01, 0x00, // BlockLength 1
        ];
        let mut read = blocks(&args);
        assert_eq!(
            read.next(),
            Some(Ok(Block {
                block_type: 0x0110,
                version: (1, 0),
                body: &[0xAA, 0xBB][..]
            }))
        );
        assert_eq!(
            read.next(),
            Some(Ok(Block {
                block_type: 0x8001,
                version: (1, 1),
                body: &[][..]
            }))
        );
        assert_eq!((read.next(), read.next()), (Some(Err(14)), None));
        let mut short = blocks(&[0x01, 0x10, 0x00, 0x08, 0x01]);
        assert_eq!((short.next(), short.next()), (Some(Err(0)), None));
    }

    #[test]
    fn a_block_is_written_with_its_length() {
        let mut buf = [0u8; 10];
        let n = emit_block(&mut buf, 0x0110, 0, |b| put(b, 0, &[0xAA, 0xBB])).unwrap();
        assert_eq!(buf[..n], [0x01, 0x10, 0x00, 0x04, 0x01, 0x00, 0xAA, 0xBB]);
        let mut r = Reader::new(&buf[..n]);
        assert_eq!((r.u16(), r.u16(), r.u8()), (Some(0x0110), Some(4), Some(1)));
        assert_eq!((r.u32(), r.rest()), (None, &[0x00, 0xAA, 0xBB][..]));
        let too_long = emit_block(&mut buf, 0x0110, 0, |b| put(b, 0, &[0; 5]));
        assert_eq!(too_long, Err(BufferTooSmall));
    }
}
