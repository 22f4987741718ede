//! The PNIO blocks of the Connect (IEC 61158-6-10; the names are the standard's): ARBlockReq,
//! IOCRBlockReq, AlarmCRBlockReq and ExpectedSubmoduleBlockReq and their answers (ARBlockRes,
//! IOCRBlockRes, AlarmCRBlockRes, ModuleDiffBlock), and the RealIdentificationData record of
//! the same shape ([`submodules`]). Each reads a block's body (after BlockHeader and version)
//! and writes the whole block into the caller's buffer; nothing panics.
//!
//! The blocks of fixed size are plain `Copy` reprs. A block holding a list has a checked view
//! (`*Packet`, its lists as iterators) that needs no allocation; its owned repr, lists in `Vec`s
//! (what the device keeps of an accepted Connect, what a controller builds), is behind the
//! `alloc` feature.

#[cfg(feature = "alloc")]
use alloc::vec::Vec;

pub(crate) use super::block::Writer;
use super::block::{emit_block, Reader};
use super::records::RESPONSE_BIT;
use super::rpc::Uuid;
use super::{BufferTooSmall, Mac};

pub mod submodules;
pub use submodules::*;

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

/// A checked view of an ARBlockReq's body: the fixed fields and the station name fit.
#[derive(Debug, Clone, Copy)]
pub struct ArBlockReqPacket<T: AsRef<[u8]>> {
    body: T,
}

impl<T: AsRef<[u8]>> ArBlockReqPacket<T> {
    const NAME_LEN_AT: usize = 50;

    /// The view, or `None` when the body is shorter than its fields and station name.
    pub fn new_checked(body: T) -> Option<Self> {
        let b = body.as_ref();
        let len = usize::from(u16::from_be_bytes(
            b.get(Self::NAME_LEN_AT..Self::NAME_LEN_AT + 2)?
                .try_into()
                .ok()?,
        ));
        b.get(..Self::NAME_LEN_AT + 2 + len)?;
        Some(ArBlockReqPacket { body })
    }

    fn reader(&self) -> Reader<'_> {
        Reader::new(self.body.as_ref())
    }

    /// The fixed fields, in the `ArBlockReq`'s order (without the station name).
    pub fn fields(&self) -> ArBlockReqFields {
        ArBlockReqFields::read(&mut self.reader()).unwrap_or_default()
    }

    /// CMInitiatorStationName.
    pub fn station_name(&self) -> &[u8] {
        let mut r = self.reader();
        let _ = r.take(Self::NAME_LEN_AT);
        let len = r.u16().unwrap_or(0);
        r.take(usize::from(len)).unwrap_or(&[])
    }
}

/// An ARBlockReq's fields but the station name (see `ArBlockReq` for each).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[allow(missing_docs)]
pub struct ArBlockReqFields {
    pub ar_type: u16,
    pub ar_uuid: Uuid,
    pub session_key: u16,
    pub initiator_mac: Mac,
    pub initiator_object: Uuid,
    pub properties: u32,
    pub timeout_factor: u16,
    pub udp_rt_port: u16,
}

impl ArBlockReqFields {
    fn read(r: &mut Reader<'_>) -> Option<ArBlockReqFields> {
        Some(ArBlockReqFields {
            ar_type: r.u16()?,
            ar_uuid: r.uuid()?,
            session_key: r.u16()?,
            initiator_mac: r.mac()?,
            initiator_object: r.uuid()?,
            properties: r.u32()?,
            timeout_factor: r.u16()?,
            udp_rt_port: r.u16()?,
        })
    }

    /// Writes the ARBlockReq with `station_name` at the start of `buf`; its length.
    pub fn emit(&self, station_name: &[u8], buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, AR_BLOCK_REQ, 0, |b| {
            let mut w = Writer::new(b);
            w.u16(self.ar_type)?;
            w.bytes(&self.ar_uuid.0)?;
            w.u16(self.session_key)?;
            w.bytes(&self.initiator_mac)?;
            w.bytes(&self.initiator_object.0)?;
            w.u32(self.properties)?;
            w.u16(self.timeout_factor)?;
            w.u16(self.udp_rt_port)?;
            w.count(station_name.len())?;
            w.bytes(station_name)?;
            Ok(w.len())
        })
    }
}

/// ARBlockReq.
#[cfg(feature = "alloc")]
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

#[cfg(feature = "alloc")]
impl ArBlockReq {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<ArBlockReq> {
        let view = ArBlockReqPacket::new_checked(body)?;
        let f = view.fields();
        Some(ArBlockReq {
            ar_type: f.ar_type,
            ar_uuid: f.ar_uuid,
            session_key: f.session_key,
            initiator_mac: f.initiator_mac,
            initiator_object: f.initiator_object,
            properties: f.properties,
            timeout_factor: f.timeout_factor,
            udp_rt_port: f.udp_rt_port,
            station_name: view.station_name().to_vec(),
        })
    }

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let fields = ArBlockReqFields {
            ar_type: self.ar_type,
            ar_uuid: self.ar_uuid,
            session_key: self.session_key,
            initiator_mac: self.initiator_mac,
            initiator_object: self.initiator_object,
            properties: self.properties,
            timeout_factor: self.timeout_factor,
            udp_rt_port: self.udp_rt_port,
        };
        fields.emit(&self.station_name, buf)
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

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, AR_BLOCK_REQ | RESPONSE_BIT, 0, |b| {
            let mut w = Writer::new(b);
            w.u16(self.ar_type)?;
            w.bytes(&self.ar_uuid.0)?;
            w.u16(self.session_key)?;
            w.bytes(&self.responder_mac)?;
            w.u16(self.udp_rt_port)?;
            Ok(w.len())
        })
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

/// The fixed fields of an IOCRBlockReq, before its APIs (see `IocrBlockReq` for each).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[allow(missing_docs)]
pub struct IocrFields {
    pub iocr_type: u16,
    pub reference: u16,
    pub lt: u16,
    pub properties: u32,
    pub data_length: u16,
    pub frame_id: u16,
    pub send_clock_factor: u16,
    pub reduction_ratio: u16,
    pub phase: u16,
    pub sequence: u16,
    pub frame_send_offset: u32,
    pub watchdog_factor: u16,
    pub data_hold_factor: u16,
    pub tag_header: u16,
    pub multicast_mac: Mac,
}

impl IocrFields {
    fn read(r: &mut Reader<'_>) -> Option<IocrFields> {
        Some(IocrFields {
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
        })
    }

    #[cfg(feature = "alloc")]
    fn write(&self, w: &mut Writer<'_>) -> Result<(), BufferTooSmall> {
        for v in [self.iocr_type, self.reference, self.lt] {
            w.u16(v)?;
        }
        w.u32(self.properties)?;
        for v in [
            self.data_length,
            self.frame_id,
            self.send_clock_factor,
            self.reduction_ratio,
            self.phase,
            self.sequence,
        ] {
            w.u16(v)?;
        }
        w.u32(self.frame_send_offset)?;
        for v in [self.watchdog_factor, self.data_hold_factor, self.tag_header] {
            w.u16(v)?;
        }
        w.bytes(&self.multicast_mac)
    }
}

/// A list of [`FrameEntry`]s (NumberOfIODataObjects or NumberOfIOCS, then the entries).
#[derive(Debug, Clone)]
pub struct FrameEntries<'a> {
    r: Reader<'a>,
    left: u16,
}

impl<'a> FrameEntries<'a> {
    /// Reads the count; the reader is left after the entries.
    fn read(r: &mut Reader<'a>) -> Option<FrameEntries<'a>> {
        let left = r.u16()?;
        let entries = FrameEntries {
            r: Reader::new(r.take(usize::from(left) * 6)?),
            left,
        };
        Some(entries)
    }
}

impl Iterator for FrameEntries<'_> {
    type Item = FrameEntry;
    fn next(&mut self) -> Option<FrameEntry> {
        self.left = self.left.checked_sub(1)?;
        Some(FrameEntry {
            slot: self.r.u16()?,
            subslot: self.r.u16()?,
            offset: self.r.u16()?,
        })
    }
}

/// One API of an IOCRBlockReq as a view: its IO data objects and IOCS entries.
#[derive(Debug, Clone)]
pub struct IocrApiView<'a> {
    /// API.
    pub api: u32,
    /// The IODataObjects.
    pub data: FrameEntries<'a>,
    /// The IOCSs.
    pub iocs: FrameEntries<'a>,
}

/// The APIs of an IOCRBlockReq.
#[derive(Debug, Clone)]
pub struct IocrApis<'a> {
    r: Reader<'a>,
    left: u16,
}

impl<'a> Iterator for IocrApis<'a> {
    type Item = IocrApiView<'a>;
    fn next(&mut self) -> Option<IocrApiView<'a>> {
        self.left = self.left.checked_sub(1)?;
        Some(IocrApiView {
            api: self.r.u32()?,
            data: FrameEntries::read(&mut self.r)?,
            iocs: FrameEntries::read(&mut self.r)?,
        })
    }
}

/// A checked view of an IOCRBlockReq's body: its fields and every API's lists fit.
#[derive(Debug, Clone, Copy)]
pub struct IocrBlockReqPacket<T: AsRef<[u8]>> {
    body: T,
}

impl<T: AsRef<[u8]>> IocrBlockReqPacket<T> {
    /// The view, or `None` when the body is shorter than its fields and lists.
    pub fn new_checked(body: T) -> Option<Self> {
        let view = IocrBlockReqPacket { body };
        let mut r = Reader::new(view.body.as_ref());
        IocrFields::read(&mut r)?;
        for _ in 0..r.u16()? {
            r.u32()?;
            FrameEntries::read(&mut r)?;
            FrameEntries::read(&mut r)?;
        }
        Some(view)
    }

    /// The fixed fields.
    pub fn fields(&self) -> IocrFields {
        IocrFields::read(&mut Reader::new(self.body.as_ref())).unwrap_or_default()
    }

    /// The APIs, in order.
    pub fn apis(&self) -> IocrApis<'_> {
        let mut r = Reader::new(self.body.as_ref());
        let left = IocrFields::read(&mut r).and_then(|_| r.u16()).unwrap_or(0);
        IocrApis { r, left }
    }
}

/// One API of an IOCRBlockReq: its IO data objects and IOCS entries.
#[cfg(feature = "alloc")]
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
#[cfg(feature = "alloc")]
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

#[cfg(feature = "alloc")]
impl IocrBlockReq {
    /// Reads the block's content.
    pub fn parse(body: &[u8]) -> Option<IocrBlockReq> {
        let view = IocrBlockReqPacket::new_checked(body)?;
        let f = view.fields();
        Some(IocrBlockReq {
            iocr_type: f.iocr_type,
            reference: f.reference,
            lt: f.lt,
            properties: f.properties,
            data_length: f.data_length,
            frame_id: f.frame_id,
            send_clock_factor: f.send_clock_factor,
            reduction_ratio: f.reduction_ratio,
            phase: f.phase,
            sequence: f.sequence,
            frame_send_offset: f.frame_send_offset,
            watchdog_factor: f.watchdog_factor,
            data_hold_factor: f.data_hold_factor,
            tag_header: f.tag_header,
            multicast_mac: f.multicast_mac,
            apis: view
                .apis()
                .map(|a| IocrApi {
                    api: a.api,
                    data: a.data.collect(),
                    iocs: a.iocs.collect(),
                })
                .collect(),
        })
    }

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let fields = IocrFields {
            iocr_type: self.iocr_type,
            reference: self.reference,
            lt: self.lt,
            properties: self.properties,
            data_length: self.data_length,
            frame_id: self.frame_id,
            send_clock_factor: self.send_clock_factor,
            reduction_ratio: self.reduction_ratio,
            phase: self.phase,
            sequence: self.sequence,
            frame_send_offset: self.frame_send_offset,
            watchdog_factor: self.watchdog_factor,
            data_hold_factor: self.data_hold_factor,
            tag_header: self.tag_header,
            multicast_mac: self.multicast_mac,
        };
        emit_block(buf, IOCR_BLOCK_REQ, 0, |b| {
            let mut w = Writer::new(b);
            fields.write(&mut w)?;
            w.count(self.apis.len())?;
            for api in &self.apis {
                w.u32(api.api)?;
                for entries in [&api.data, &api.iocs] {
                    w.count(entries.len())?;
                    for e in entries {
                        for v in [e.slot, e.subslot, e.offset] {
                            w.u16(v)?;
                        }
                    }
                }
            }
            Ok(w.len())
        })
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

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, IOCR_BLOCK_REQ | RESPONSE_BIT, 0, |b| {
            let mut w = Writer::new(b);
            for v in [self.iocr_type, self.reference, self.frame_id] {
                w.u16(v)?;
            }
            Ok(w.len())
        })
    }
}

mod alarm_cr;
pub use alarm_cr::*;

#[cfg(all(test, feature = "alloc"))]
mod tests;
