//! The PNIO blocks inside the RPC argument (IEC 61158-6-10; the names are the standard's):
//! every block starts with a BlockHeader (BlockType, BlockLength counting the bytes after the
//! length field, BlockVersionHigh/Low) and is big-endian. The Connect's ARBlockReq, IOCRBlockReq,
//! AlarmCRBlockReq and ExpectedSubmoduleBlockReq and their answers (ARBlockRes, IOCRBlockRes,
//! AlarmCRBlockRes, ModuleDiffBlock), the record access headers (IODReadReq/Res,
//! IODWriteReq/Res), IODControlReq/Res (PrmEnd, ApplicationReady, Release) and the
//! RealIdentificationData record. Each parses and emits; parsing never panics. The block
//! framing (header, cursor, the blocks of an argument) and the record access and control
//! blocks are the runtime's views ([`edsgen_runtime::profinet::wire::block`],
//! [`edsgen_runtime::profinet::wire::records`], re-exported here); the owned structs of the
//! Connect are still to move.

use alloc::vec::Vec;

use super::records::RESPONSE_BIT;
use super::rpc::Uuid;
use super::Mac;

/// ARBlockReq.
pub const AR_BLOCK_REQ: u16 = 0x0101;
/// IOCRBlockReq.
pub const IOCR_BLOCK_REQ: u16 = 0x0102;
/// AlarmCRBlockReq.
pub const ALARM_CR_BLOCK_REQ: u16 = 0x0103;
/// ExpectedSubmoduleBlockReq.
pub const EXPECTED_SUBMODULE_BLOCK_REQ: u16 = 0x0104;
/// RealIdentificationData.
pub const REAL_IDENTIFICATION_DATA: u16 = 0x0013;
/// I&M0.
pub const IM0: u16 = 0x0020;
/// ModuleDiffBlock.
pub const MODULE_DIFF_BLOCK: u16 = 0x8104;

/// IOCRType input (device to controller).
pub const IOCR_INPUT: u16 = 1;
/// IOCRType output (controller to device).
pub const IOCR_OUTPUT: u16 = 2;

/// ModuleState: no module.
pub const MODULE_NO: u16 = 0;
/// ModuleState: wrong module.
pub const MODULE_WRONG: u16 = 1;
/// ModuleState: proper module (with submodule differences).
pub const MODULE_PROPER: u16 = 2;
/// SubmoduleState (format 1): IdentInfo OK.
pub const SUBMODULE_OK: u16 = 0x8000;
/// SubmoduleState (format 1): IdentInfo wrong submodule.
pub const SUBMODULE_WRONG: u16 = 0x8000 | (2 << 11);
/// SubmoduleState (format 1): IdentInfo no submodule.
pub const SUBMODULE_NO: u16 = 0x8000 | (3 << 11);

pub use super::block::{Block, Reader};

/// Splits an argument into its blocks ([`edsgen_runtime::profinet::wire::block::blocks`]);
/// `Err(offset)` where a header is short, a BlockLength below 2, or a block runs past the end.
pub fn split(args: &[u8]) -> Result<Vec<Block<'_>>, usize> {
    super::block::blocks(args).collect()
}

/// Appends a block of `block_type`, version 1.`low`, whose content `body` writes.
pub fn emit_block(out: &mut Vec<u8>, block_type: u16, low: u8, body: impl FnOnce(&mut Vec<u8>)) {
    let start = out.len();
    out.extend_from_slice(&block_type.to_be_bytes());
    out.extend_from_slice(&[0, 0, 1, low]);
    body(out);
    let len = u16::try_from(out.len() - start - 4).unwrap_or(u16::MAX);
    out[start + 2..start + 4].copy_from_slice(&len.to_be_bytes());
}

fn put16(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_be_bytes());
}

fn put32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_be_bytes());
}

/// ARBlockReq.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArBlockReq {
    /// ARType (1 IOCARSingle, 6 IOSAR, ...).
    pub ar_type: u16,
    /// ARUUID.
    pub ar_uuid: Uuid,
    /// SessionKey.
    pub session_key: u16,
    /// CMInitiatorMacAdd.
    pub initiator_mac: Mac,
    /// CMInitiatorObjectUUID.
    pub initiator_object: Uuid,
    /// ARProperties.
    pub properties: u32,
    /// CMInitiatorActivityTimeoutFactor (100 ms units).
    pub timeout_factor: u16,
    /// CMInitiatorUDPRTPort.
    pub udp_rt_port: u16,
    /// CMInitiatorStationName.
    pub station_name: Vec<u8>,
}

impl ArBlockReq {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<ArBlockReq> {
        let mut r = Reader::new(body);
        let mut b = ArBlockReq {
            ar_type: r.u16()?,
            ar_uuid: r.uuid()?,
            session_key: r.u16()?,
            initiator_mac: r.mac()?,
            initiator_object: r.uuid()?,
            properties: r.u32()?,
            timeout_factor: r.u16()?,
            udp_rt_port: r.u16()?,
            station_name: Vec::new(),
        };
        let len = r.u16()?;
        b.station_name = r.take(usize::from(len))?.to_vec();
        Some(b)
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, AR_BLOCK_REQ, 0, |o| {
            put16(o, self.ar_type);
            o.extend_from_slice(&self.ar_uuid.0);
            put16(o, self.session_key);
            o.extend_from_slice(&self.initiator_mac);
            o.extend_from_slice(&self.initiator_object.0);
            put32(o, self.properties);
            put16(o, self.timeout_factor);
            put16(o, self.udp_rt_port);
            put16(o, self.station_name.len() as u16);
            o.extend_from_slice(&self.station_name);
        });
    }
}

/// ARBlockRes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ArBlockRes {
    /// ARType.
    pub ar_type: u16,
    /// ARUUID.
    pub ar_uuid: Uuid,
    /// SessionKey.
    pub session_key: u16,
    /// CMResponderMacAdd.
    pub responder_mac: Mac,
    /// ResponderUDPRTPort.
    pub udp_rt_port: u16,
}

impl ArBlockRes {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<ArBlockRes> {
        let mut r = Reader::new(body);
        Some(ArBlockRes {
            ar_type: r.u16()?,
            ar_uuid: r.uuid()?,
            session_key: r.u16()?,
            responder_mac: r.mac()?,
            udp_rt_port: r.u16()?,
        })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, AR_BLOCK_REQ | RESPONSE_BIT, 0, |o| {
            put16(o, self.ar_type);
            o.extend_from_slice(&self.ar_uuid.0);
            put16(o, self.session_key);
            o.extend_from_slice(&self.responder_mac);
            put16(o, self.udp_rt_port);
        });
    }
}

/// Where one submodule's data object or IOCS sits in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameEntry {
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// FrameOffset in the C_SDU.
    pub offset: u16,
}

/// One API of an IOCRBlockReq: its IO data objects and IOCS entries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IocrApi {
    /// API.
    pub api: u32,
    /// The IODataObjects.
    pub data: Vec<FrameEntry>,
    /// The IOCSs.
    pub iocs: Vec<FrameEntry>,
}

/// IOCRBlockReq.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IocrBlockReq {
    /// IOCRType ([`IOCR_INPUT`], [`IOCR_OUTPUT`], multicast ones).
    pub iocr_type: u16,
    /// IOCRReference.
    pub reference: u16,
    /// LT (0x8892).
    pub lt: u16,
    /// IOCRProperties (RTClass in bits 0-3).
    pub properties: u32,
    /// DataLength (the C_SDU).
    pub data_length: u16,
    /// FrameID (0xFFFF: the device chooses).
    pub frame_id: u16,
    /// SendClockFactor (31.25 µs units).
    pub send_clock_factor: u16,
    /// ReductionRatio.
    pub reduction_ratio: u16,
    /// Phase.
    pub phase: u16,
    /// Sequence.
    pub sequence: u16,
    /// FrameSendOffset.
    pub frame_send_offset: u32,
    /// WatchdogFactor.
    pub watchdog_factor: u16,
    /// DataHoldFactor.
    pub data_hold_factor: u16,
    /// IOCRTagHeader.
    pub tag_header: u16,
    /// IOCRMulticastMACAdd.
    pub multicast_mac: Mac,
    /// The APIs.
    pub apis: Vec<IocrApi>,
}

fn entries(r: &mut Reader<'_>) -> Option<Vec<FrameEntry>> {
    let n = r.u16()?;
    (0..n)
        .map(|_| {
            Some(FrameEntry {
                slot: r.u16()?,
                subslot: r.u16()?,
                offset: r.u16()?,
            })
        })
        .collect()
}

fn put_entries(o: &mut Vec<u8>, entries: &[FrameEntry]) {
    put16(o, entries.len() as u16);
    for e in entries {
        put16(o, e.slot);
        put16(o, e.subslot);
        put16(o, e.offset);
    }
}

impl IocrBlockReq {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<IocrBlockReq> {
        let mut r = Reader::new(body);
        let mut b = IocrBlockReq {
            iocr_type: r.u16()?,
            reference: r.u16()?,
            lt: r.u16()?,
            properties: r.u32()?,
            data_length: r.u16()?,
            frame_id: r.u16()?,
            send_clock_factor: r.u16()?,
            reduction_ratio: r.u16()?,
            phase: r.u16()?,
            sequence: r.u16()?,
            frame_send_offset: r.u32()?,
            watchdog_factor: r.u16()?,
            data_hold_factor: r.u16()?,
            tag_header: r.u16()?,
            multicast_mac: r.mac()?,
            apis: Vec::new(),
        };
        let n = r.u16()?;
        for _ in 0..n {
            let api = r.u32()?;
            let data = entries(&mut r)?;
            let iocs = entries(&mut r)?;
            b.apis.push(IocrApi { api, data, iocs });
        }
        Some(b)
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, IOCR_BLOCK_REQ, 0, |o| {
            for v in [self.iocr_type, self.reference, self.lt] {
                put16(o, v);
            }
            put32(o, self.properties);
            for v in [
                self.data_length,
                self.frame_id,
                self.send_clock_factor,
                self.reduction_ratio,
                self.phase,
                self.sequence,
            ] {
                put16(o, v);
            }
            put32(o, self.frame_send_offset);
            for v in [self.watchdog_factor, self.data_hold_factor, self.tag_header] {
                put16(o, v);
            }
            o.extend_from_slice(&self.multicast_mac);
            put16(o, self.apis.len() as u16);
            for api in &self.apis {
                put32(o, api.api);
                put_entries(o, &api.data);
                put_entries(o, &api.iocs);
            }
        });
    }
}

/// IOCRBlockRes: the type, reference and FrameID the device uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IocrBlockRes {
    /// IOCRType.
    pub iocr_type: u16,
    /// IOCRReference.
    pub reference: u16,
    /// FrameID.
    pub frame_id: u16,
}

impl IocrBlockRes {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<IocrBlockRes> {
        let mut r = Reader::new(body);
        Some(IocrBlockRes {
            iocr_type: r.u16()?,
            reference: r.u16()?,
            frame_id: r.u16()?,
        })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, IOCR_BLOCK_REQ | RESPONSE_BIT, 0, |o| {
            for v in [self.iocr_type, self.reference, self.frame_id] {
                put16(o, v);
            }
        });
    }
}

/// AlarmCRBlockReq.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmCrBlockReq {
    /// AlarmCRType (1).
    pub alarm_cr_type: u16,
    /// LT (0x8892 on layer 2, 0x0800 over UDP).
    pub lt: u16,
    /// AlarmCRProperties (bit 0 priority, bit 1 transport UDP).
    pub properties: u32,
    /// RTATimeoutFactor (100 ms units).
    pub rta_timeout_factor: u16,
    /// RTARetries.
    pub rta_retries: u16,
    /// LocalAlarmReference (the controller's).
    pub local_alarm_reference: u16,
    /// MaxAlarmDataLength.
    pub max_alarm_data_length: u16,
    /// AlarmCRTagHeaderHigh.
    pub tag_header_high: u16,
    /// AlarmCRTagHeaderLow.
    pub tag_header_low: u16,
}

impl AlarmCrBlockReq {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<AlarmCrBlockReq> {
        let mut r = Reader::new(body);
        Some(AlarmCrBlockReq {
            alarm_cr_type: r.u16()?,
            lt: r.u16()?,
            properties: r.u32()?,
            rta_timeout_factor: r.u16()?,
            rta_retries: r.u16()?,
            local_alarm_reference: r.u16()?,
            max_alarm_data_length: r.u16()?,
            tag_header_high: r.u16()?,
            tag_header_low: r.u16()?,
        })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, ALARM_CR_BLOCK_REQ, 0, |o| {
            put16(o, self.alarm_cr_type);
            put16(o, self.lt);
            put32(o, self.properties);
            for v in [
                self.rta_timeout_factor,
                self.rta_retries,
                self.local_alarm_reference,
                self.max_alarm_data_length,
                self.tag_header_high,
                self.tag_header_low,
            ] {
                put16(o, v);
            }
        });
    }
}

/// AlarmCRBlockRes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmCrBlockRes {
    /// AlarmCRType.
    pub alarm_cr_type: u16,
    /// LocalAlarmReference (the device's).
    pub local_alarm_reference: u16,
    /// MaxAlarmDataLength.
    pub max_alarm_data_length: u16,
}

impl AlarmCrBlockRes {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<AlarmCrBlockRes> {
        let mut r = Reader::new(body);
        Some(AlarmCrBlockRes {
            alarm_cr_type: r.u16()?,
            local_alarm_reference: r.u16()?,
            max_alarm_data_length: r.u16()?,
        })
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        emit_block(out, ALARM_CR_BLOCK_REQ | RESPONSE_BIT, 0, |o| {
            for v in [
                self.alarm_cr_type,
                self.local_alarm_reference,
                self.max_alarm_data_length,
            ] {
                put16(o, v);
            }
        });
    }
}

mod submodules;
pub use submodules::*;

#[cfg(test)]
mod tests;
