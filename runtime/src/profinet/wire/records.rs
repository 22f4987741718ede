//! The record access headers (IODReadReq/Res, IODWriteReq/Res: one 64-byte shape with a tail
//! that differs) and IODControlReq/Res (PrmEnd, ApplicationReady, Release and their Done), with
//! their block types and control commands: views written into the caller's buffer and read
//! from a block's body, never panicking.

use super::block::{emit_block, Reader};
use super::put;
use super::rpc::{PnioStatus, Uuid};
use super::BufferTooSmall;

/// IODWriteReqHeader.
pub const IOD_WRITE_REQ: u16 = 0x0008;
/// IODReadReqHeader.
pub const IOD_READ_REQ: u16 = 0x0009;
/// IODControlReq for PrmEnd.
pub const PRM_END_REQ: u16 = 0x0110;
/// IODControlReq for ApplicationReady (the device's CControl).
pub const APPLICATION_READY_REQ: u16 = 0x0112;
/// IODReleaseReq.
pub const RELEASE_REQ: u16 = 0x0114;
/// A response's block type: the request's with bit 15 set.
pub const RESPONSE_BIT: u16 = 0x8000;

/// ControlCommand PrmEnd.
pub const CMD_PRM_END: u16 = 0x0001;
/// ControlCommand ApplicationReady.
pub const CMD_APPLICATION_READY: u16 = 0x0002;
/// ControlCommand Release.
pub const CMD_RELEASE: u16 = 0x0004;
/// ControlCommand Done.
pub const CMD_DONE: u16 = 0x0008;

/// IODReadReqHeader, IODReadResHeader, IODWriteReqHeader or IODWriteResHeader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IodHeader {
    /// BlockType (0x0008, 0x0009, 0x8008, 0x8009).
    pub block_type: u16,
    /// SeqNumber.
    pub sequence: u16,
    /// ARUUID.
    pub ar_uuid: Uuid,
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// Index.
    pub index: u16,
    /// RecordDataLength.
    pub record_length: u32,
    /// TargetARUUID (read request).
    pub target_ar_uuid: Uuid,
    /// AdditionalValue1 and 2 (responses).
    pub additional: (u16, u16),
    /// PNIOStatus (write response).
    pub status: PnioStatus,
}

impl IodHeader {
    /// A request header of `block_type` ([`IOD_READ_REQ`] or [`IOD_WRITE_REQ`]).
    pub fn request(
        block_type: u16,
        sequence: u16,
        ar_uuid: Uuid,
        at: (u16, u16, u16),
        len: u32,
    ) -> Self {
        IodHeader {
            block_type,
            sequence,
            ar_uuid,
            api: 0,
            slot: at.0,
            subslot: at.1,
            index: at.2,
            record_length: len,
            target_ar_uuid: Uuid::default(),
            additional: (0, 0),
            status: PnioStatus::OK,
        }
    }

    /// The response header to this request, for `len` bytes of record data and `status`.
    pub fn response(&self, len: u32, status: PnioStatus) -> Self {
        IodHeader {
            block_type: self.block_type | RESPONSE_BIT,
            record_length: len,
            target_ar_uuid: Uuid::default(),
            additional: (0, 0),
            status,
            ..*self
        }
    }

    /// Reads a header block's content (after the version) of `block_type`.
    pub fn parse(block_type: u16, body: &[u8]) -> Option<IodHeader> {
        let mut r = Reader::new(body);
        let mut h = IodHeader {
            block_type,
            sequence: r.u16()?,
            ar_uuid: r.uuid()?,
            api: r.u32()?,
            slot: r.u16()?,
            subslot: r.u16()?,
            index: 0,
            record_length: 0,
            target_ar_uuid: Uuid::default(),
            additional: (0, 0),
            status: PnioStatus::OK,
        };
        r.u16()?;
        h.index = r.u16()?;
        h.record_length = r.u32()?;
        match block_type {
            IOD_READ_REQ => {
                h.target_ar_uuid = r.uuid()?;
                r.take(8)?;
            }
            IOD_WRITE_REQ => {
                r.take(24)?;
            }
            t if t == IOD_READ_REQ | RESPONSE_BIT => {
                h.additional = (r.u16()?, r.u16()?);
                r.take(20)?;
            }
            t if t == IOD_WRITE_REQ | RESPONSE_BIT => {
                h.additional = (r.u16()?, r.u16()?);
                h.status = PnioStatus(r.take(4)?.try_into().ok()?);
                r.take(16)?;
            }
            _ => return None,
        }
        Some(h)
    }

    /// Writes the header block (64 bytes) at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, self.block_type, 0, |b| {
            let at = put(b, 0, &self.sequence.to_be_bytes())?;
            let at = put(b, at, &self.ar_uuid.0)?;
            let at = put(b, at, &self.api.to_be_bytes())?;
            let at = put(b, at, &self.slot.to_be_bytes())?;
            let at = put(b, at, &self.subslot.to_be_bytes())?;
            let at = put(b, at, &[0, 0])?;
            let at = put(b, at, &self.index.to_be_bytes())?;
            let at = put(b, at, &self.record_length.to_be_bytes())?;
            if self.block_type == IOD_READ_REQ {
                let at = put(b, at, &self.target_ar_uuid.0)?;
                put(b, at, &[0; 8])
            } else if self.block_type & RESPONSE_BIT == 0 {
                put(b, at, &[0; 24])
            } else {
                let at = put(b, at, &self.additional.0.to_be_bytes())?;
                let at = put(b, at, &self.additional.1.to_be_bytes())?;
                if self.block_type == IOD_WRITE_REQ | RESPONSE_BIT {
                    let at = put(b, at, &self.status.0)?;
                    put(b, at, &[0; 16])
                } else {
                    put(b, at, &[0; 20])
                }
            }
        })
    }
}

/// IODControlReq/Res (and IODReleaseReq/Res, of the same shape).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IodControl {
    /// BlockType (0x0110 PrmEnd, 0x0112 ApplicationReady, 0x0114 Release, | 0x8000 answers).
    pub block_type: u16,
    /// ARUUID.
    pub ar_uuid: Uuid,
    /// SessionKey.
    pub session_key: u16,
    /// ControlCommand.
    pub command: u16,
    /// ControlBlockProperties.
    pub properties: u16,
}

impl IodControl {
    /// Reads the block's content.
    pub fn parse(block_type: u16, body: &[u8]) -> Option<IodControl> {
        let mut r = Reader::new(body);
        r.u16()?;
        let ar_uuid = r.uuid()?;
        let session_key = r.u16()?;
        r.u16()?;
        Some(IodControl {
            block_type,
            ar_uuid,
            session_key,
            command: r.u16()?,
            properties: r.u16()?,
        })
    }

    /// The answer to this request: the response block type, command Done.
    pub fn done(&self) -> IodControl {
        IodControl {
            block_type: self.block_type | RESPONSE_BIT,
            command: CMD_DONE,
            properties: 0,
            ..*self
        }
    }

    /// Writes the block (32 bytes) at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, self.block_type, 0, |b| {
            let at = put(b, 0, &[0, 0])?;
            let at = put(b, at, &self.ar_uuid.0)?;
            let at = put(b, at, &self.session_key.to_be_bytes())?;
            let at = put(b, at, &[0, 0])?;
            let at = put(b, at, &self.command.to_be_bytes())?;
            put(b, at, &self.properties.to_be_bytes())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profinet::wire::block::blocks;

    #[test]
    fn headers_are_written_whole_into_the_buffer_or_not_at_all_and_read_back() {
        let read = IodHeader::request(IOD_READ_REQ, 1, Uuid([7; 16]), (0, 1, 0xAFF0), 4096);
        let mut buf = [0u8; 64];
        assert_eq!(read.emit(&mut buf), Ok(64));
        let block = blocks(&buf).next().expect("a block").expect("whole");
        assert_eq!(IodHeader::parse(block.block_type, block.body), Some(read));
        assert_eq!(read.emit(&mut buf[..63]), Err(BufferTooSmall));
        let control = IodControl {
            block_type: RELEASE_REQ,
            ar_uuid: Uuid([7; 16]),
            session_key: 2,
            command: CMD_RELEASE,
            properties: 0,
        };
        let done = control.done();
        assert_eq!(done.emit(&mut buf), Ok(32));
        assert_eq!(buf[..2], [0x81, 0x14]);
        let block = blocks(&buf[..32]).next().expect("a block").expect("whole");
        assert_eq!(IodControl::parse(block.block_type, block.body), Some(done));
        assert_eq!(control.emit(&mut buf[..31]), Err(BufferTooSmall));
        assert_eq!(IodControl::parse(RELEASE_REQ, &buf[6..20]), None);
    }
}
