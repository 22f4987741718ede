//! The record access headers (IODReadReq/Res, IODWriteReq/Res: one 64-byte shape with a tail
//! that differs) and IODControlReq/Res (PrmEnd, ApplicationReady, Release and their Done).

use super::super::rpc::{PnioStatus, Uuid};
use super::{emit_block, put16, put32, Reader, IOD_READ_REQ, IOD_WRITE_REQ, RESPONSE_BIT};

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

    /// Appends the header block (64 bytes).
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, self.block_type, 0, |o| {
            put16(o, self.sequence);
            o.extend_from_slice(&self.ar_uuid.0);
            put32(o, self.api);
            put16(o, self.slot);
            put16(o, self.subslot);
            put16(o, 0);
            put16(o, self.index);
            put32(o, self.record_length);
            if self.block_type == IOD_READ_REQ {
                o.extend_from_slice(&self.target_ar_uuid.0);
                o.extend_from_slice(&[0; 8]);
            } else if self.block_type & RESPONSE_BIT == 0 {
                o.extend_from_slice(&[0; 24]);
            } else {
                put16(o, self.additional.0);
                put16(o, self.additional.1);
                if self.block_type == IOD_WRITE_REQ | RESPONSE_BIT {
                    o.extend_from_slice(&self.status.0);
                    o.extend_from_slice(&[0; 16]);
                } else {
                    o.extend_from_slice(&[0; 20]);
                }
            }
        });
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
            command: super::CMD_DONE,
            properties: 0,
            ..*self
        }
    }

    /// Appends the block (32 bytes).
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, self.block_type, 0, |o| {
            put16(o, 0);
            o.extend_from_slice(&self.ar_uuid.0);
            put16(o, self.session_key);
            put16(o, 0);
            put16(o, self.command);
            put16(o, self.properties);
        });
    }
}
