//! The IO controller's side of connection management, as far as the demo and the tests need it:
//! the requests (Connect with the IOCRs, AlarmCR and expected submodules of a configuration,
//! Read, Write, PrmEnd, Release; a ReadImplicit outside any AR), the answer to the device's
//! ApplicationReady, and the reading of the device's responses. The IOCR layout is the one profinet-py builds: in each CR the
//! data objects (data and IOPS) of the submodules that provide in that direction (a submodule
//! without IO data provides an IOPS in the input CR), then the IOCS of those that provide in the
//! other.

use super::ar::config::{DeviceConfig, RealSubmodule};
use super::ar::connect::AR_TYPE_IOC_SINGLE;
use super::wire::blocks::*;
use super::wire::rpc::*;
use super::wire::{append, rpc_pdu, Mac};

/// One AR of a controller.
#[derive(Debug, Clone)]
pub struct Controller {
    /// The ARBlockReq of the Connect.
    pub ar: ArBlockReq,
    /// The device's object UUID.
    pub object: Uuid,
    activity: Uuid,
    sequence: u32,
}

/// What the controller reads in the device's answer to its Connect.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Connected {
    /// The FrameIDs of the input and the output CR.
    pub frame_ids: (u16, u16),
    /// The ModuleDiffBlock, when the device sent one.
    pub diff: Option<ModuleDiffBlock>,
    /// The device's LocalAlarmReference (AlarmCRBlockRes), when it sent one.
    pub device_alarm_ref: Option<u16>,
}

impl Controller {
    /// An IO AR from a controller with `mac` to the device with `object`; `seed` makes the
    /// AR UUID and the activity (tests and the demo want the same bytes each run).
    pub fn new(mac: Mac, object: Uuid, seed: u8) -> Controller {
        Controller {
            ar: ArBlockReq {
                ar_type: AR_TYPE_IOC_SINGLE,
                ar_uuid: Uuid([seed; 16]),
                session_key: 1,
                initiator_mac: mac,
                initiator_object: Uuid::pnio_object(1, 0, 0),
                properties: 0x11,
                timeout_factor: 100,
                udp_rt_port: 0x8892,
                station_name: b"edsgen-controller".to_vec(),
            },
            object,
            activity: Uuid([seed ^ 0x5A; 16]),
            sequence: 0,
        }
    }

    fn request(&mut self, opnum: u16, args: &[u8]) -> Vec<u8> {
        let header = RpcHeader::request(
            self.object,
            Uuid::PNIO_DEVICE,
            self.activity,
            self.sequence,
            opnum,
        );
        self.sequence += 1;
        rpc_pdu(&header, &Ndr::request(4068, args.len() as u32, false), args)
    }

    /// The blocks of a Connect for `config` as it is (the expected configuration is the real
    /// one), every `scf` × `rr` × 31.25 µs, with DataHoldFactor `factor`.
    pub fn connect_blocks(&self, config: &DeviceConfig, scf: u16, rr: u16, factor: u16) -> Vec<u8> {
        let iocr = |input: bool| {
            let layout = CrLayout::of(config, input);
            let entry = |&(slot, subslot, offset, _): &(u16, u16, u16, u16)| FrameEntry {
                slot,
                subslot,
                offset,
            };
            IocrBlockReq {
                iocr_type: if input { IOCR_INPUT } else { IOCR_OUTPUT },
                reference: if input { 1 } else { 2 },
                lt: 0x8892,
                properties: 1,
                data_length: layout.length,
                frame_id: if input { 0xC001 } else { 0xFFFF },
                send_clock_factor: scf,
                reduction_ratio: rr,
                phase: 1,
                sequence: 0,
                frame_send_offset: 0xFFFF_FFFF,
                watchdog_factor: factor,
                data_hold_factor: factor,
                tag_header: 0xC000,
                multicast_mac: [0; 6],
                apis: vec![IocrApi {
                    api: 0,
                    data: layout.data.iter().map(entry).collect(),
                    iocs: layout.iocs.iter().map(entry).collect(),
                }],
            }
        };
        let mut out = Vec::new();
        append_block(&mut out, |b| self.ar.emit(b));
        append_block(&mut out, |b| iocr(true).emit(b));
        append_block(&mut out, |b| iocr(false).emit(b));
        append_block(&mut out, |b| alarm_cr().emit(b));
        let expected = ExpectedSubmoduleBlockReq {
            slots: config
                .slots
                .iter()
                .map(|s| ExpectedSlot {
                    api: 0,
                    slot: s.slot,
                    module_ident: s.module_ident,
                    module_properties: 0,
                    submodules: s.submodules.iter().map(expected).collect(),
                })
                .collect(),
        };
        append_block(&mut out, |b| expected.emit(b));
        out
    }

    /// A Connect request carrying `blocks`.
    pub fn connect(&mut self, blocks: &[u8]) -> Vec<u8> {
        self.request(OP_CONNECT, blocks)
    }

    fn control(&mut self, opnum: u16, block_type: u16, command: u16) -> Vec<u8> {
        let mut args = Vec::new();
        let block = IodControl {
            block_type,
            ar_uuid: self.ar.ar_uuid,
            session_key: self.ar.session_key,
            command,
            properties: 0,
        };
        append(&mut args, |b| block.emit(b));
        self.request(opnum, &args)
    }

    /// The PrmEnd request.
    pub fn prm_end(&mut self) -> Vec<u8> {
        self.control(OP_CONTROL, PRM_END_REQ, CMD_PRM_END)
    }

    /// The Release request.
    pub fn release(&mut self) -> Vec<u8> {
        self.control(OP_RELEASE, RELEASE_REQ, CMD_RELEASE)
    }

    /// A Read request of record `index` of `slot`, `subslot`.
    pub fn read(&mut self, slot: u16, subslot: u16, index: u16) -> Vec<u8> {
        let mut args = Vec::new();
        let block = IodHeader::request(
            IOD_READ_REQ,
            0,
            self.ar.ar_uuid,
            (slot, subslot, index),
            4096,
        );
        append(&mut args, |b| block.emit(b));
        self.request(OP_READ, &args)
    }

    /// A Write request of `data` to record `index` of `slot`, `subslot`.
    pub fn write(&mut self, slot: u16, subslot: u16, index: u16, data: &[u8]) -> Vec<u8> {
        let mut args = Vec::new();
        let block = IodHeader::request(
            IOD_WRITE_REQ,
            0,
            self.ar.ar_uuid,
            (slot, subslot, index),
            data.len() as u32,
        );
        append(&mut args, |b| block.emit(b));
        args.extend_from_slice(data);
        self.request(OP_WRITE, &args)
    }

    /// The answer to the device's ApplicationReady request for this AR (Done), `None` for
    /// anything else.
    pub fn answer_ready(&self, pdu: &[u8]) -> Option<Vec<u8>> {
        let (header, body) = RpcHeader::parse(pdu)?;
        if header.packet_type != REQUEST || header.opnum != OP_CONTROL {
            return None;
        }
        let (ndr, args) = Ndr::parse(body, header.little_endian)?;
        let block = *split(args).ok()?.first()?;
        let req = IodControl::parse(block.block_type, block.body)?;
        if req.block_type != APPLICATION_READY_REQ || req.ar_uuid != self.ar.ar_uuid {
            return None;
        }
        let mut out = Vec::new();
        append(&mut out, |b| req.done().emit(b));
        let ndr = Ndr::response(
            PnioStatus::OK,
            out.len() as u32,
            ndr.args_maximum(),
            header.little_endian,
        );
        Some(rpc_pdu(&header.answer(RESPONSE), &ndr, &out))
    }
}

/// The AlarmCRBlockReq of every Connect: LocalAlarmReference 1, an RTA timeout of 100 ms and
/// 3 retries, priorities 6 (high) and 5 (low).
pub fn alarm_cr() -> AlarmCrBlockReq {
    AlarmCrBlockReq {
        alarm_cr_type: 1,
        lt: 0x8892,
        properties: 0,
        rta_timeout_factor: 1,
        rta_retries: 3,
        local_alarm_reference: 1,
        max_alarm_data_length: 200,
        tag_header_high: 0xC000,
        tag_header_low: 0xA000,
    }
}

/// Where each submodule's bytes are in one IOCR's C_SDU, as [`Controller::connect_blocks`]
/// lays it out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CrLayout {
    /// The submodules that provide data in this CR: slot, subslot, offset of the data, its
    /// length (the IOPS follows it).
    pub data: Vec<(u16, u16, u16, u16)>,
    /// The submodules that provide in the other CR: slot, subslot, offset of their IOCS (the
    /// last field is 0).
    pub iocs: Vec<(u16, u16, u16, u16)>,
    /// The C_SDU's length (40 at least).
    pub length: u16,
}

impl CrLayout {
    /// The input CR's layout (`input`), or the output CR's, for `config`.
    pub fn of(config: &DeviceConfig, input: bool) -> CrLayout {
        let subs: Vec<(u16, &RealSubmodule)> = config
            .slots
            .iter()
            .flat_map(|s| s.submodules.iter().map(move |sub| (s.slot, sub)))
            .collect();
        let provides = |sub: &RealSubmodule, input: bool| {
            if input {
                sub.input_len > 0 || sub.output_len == 0
            } else {
                sub.output_len > 0
            }
        };
        let mut offset = 0u16;
        let mut data = Vec::new();
        let mut iocs = Vec::new();
        for &(slot, sub) in &subs {
            if provides(sub, input) {
                let len = if input { sub.input_len } else { sub.output_len };
                data.push((slot, sub.subslot, offset, len));
                offset = offset.saturating_add(len).saturating_add(1);
            }
        }
        for &(slot, sub) in &subs {
            if provides(sub, !input) {
                iocs.push((slot, sub.subslot, offset, 0));
                offset = offset.saturating_add(1);
            }
        }
        CrLayout {
            data,
            iocs,
            length: offset.max(40),
        }
    }
}

/// The expected submodule that matches `sub`.
fn expected(sub: &RealSubmodule) -> ExpectedSubmodule {
    let d = |direction, length| DataDescription {
        direction,
        length,
        iocs_len: 1,
        iops_len: 1,
    };
    let (properties, data) = match (sub.input_len, sub.output_len) {
        (0, 0) => (0, vec![d(DATA_INPUT, 0)]),
        (i, 0) => (1, vec![d(DATA_INPUT, i)]),
        (0, o) => (2, vec![d(DATA_OUTPUT, o)]),
        (i, o) => (3, vec![d(DATA_INPUT, i), d(DATA_OUTPUT, o)]),
    };
    ExpectedSubmodule {
        subslot: sub.subslot,
        ident: sub.ident,
        properties,
        data,
    }
}

/// A ReadImplicit request (a read without an AR: the NIL AR UUID) of record `at` (slot,
/// subslot, index) of the device with `object`, as the call `activity`.
pub fn read_implicit(object: Uuid, activity: Uuid, at: (u16, u16, u16)) -> Vec<u8> {
    let mut args = Vec::new();
    let header = IodHeader::request(IOD_READ_REQ, 0, Uuid::default(), at, 4096);
    append(&mut args, |b| header.emit(b));
    let header = RpcHeader::request(object, Uuid::PNIO_DEVICE, activity, 0, OP_READ_IMPLICIT);
    rpc_pdu(
        &header,
        &Ndr::request(4068, args.len() as u32, false),
        &args,
    )
}

/// The record data of a Read response's arguments (the IODReadResHeader, then the data, as
/// long as its RecordDataLength says); `None` when they are not that.
pub fn read_data(args: &[u8]) -> Option<&[u8]> {
    let mut r = Reader::new(args);
    let (block_type, len) = (r.u16()?, r.u16()?);
    let body = r.take(usize::from(len))?;
    if block_type != IOD_READ_REQ | RESPONSE_BIT {
        return None;
    }
    let header = IodHeader::parse(block_type, body.get(2..)?)?;
    let rest = r.take(usize::try_from(header.record_length).ok()?)?;
    Some(rest)
}

/// A response's PNIOStatus and argument bytes, `None` when `pdu` is no response.
pub fn response(pdu: &[u8]) -> Option<(PnioStatus, Vec<u8>)> {
    let (header, body) = RpcHeader::parse(pdu)?;
    if header.packet_type != RESPONSE {
        return None;
    }
    let (ndr, args) = Ndr::parse(body, header.little_endian)?;
    Some((ndr.status(), args.to_vec()))
}

/// The FrameIDs and any ModuleDiffBlock of a Connect's answer blocks.
pub fn connected(args: &[u8]) -> Option<Connected> {
    let blocks = split(args).ok()?;
    let frame_id = |t| {
        blocks
            .iter()
            .filter(|b| b.block_type == IOCR_BLOCK_REQ | RESPONSE_BIT)
            .filter_map(|b| IocrBlockRes::parse(b.body))
            .find(|r| r.iocr_type == t)
            .map(|r| r.frame_id)
    };
    Some(Connected {
        frame_ids: (frame_id(IOCR_INPUT)?, frame_id(IOCR_OUTPUT)?),
        diff: blocks
            .iter()
            .find(|b| b.block_type == MODULE_DIFF_BLOCK)
            .and_then(|b| ModuleDiffBlock::parse(b.body)),
        device_alarm_ref: blocks
            .iter()
            .find(|b| b.block_type == ALARM_CR_BLOCK_REQ | RESPONSE_BIT)
            .and_then(|b| AlarmCrBlockRes::parse(b.body))
            .map(|r| r.local_alarm_reference),
    })
}
