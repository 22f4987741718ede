//! The alarm frames of the AlarmCR (IEC 61158-6-10, acyclic real time, "RTA"): on EtherType
//! 0x8892 behind a VLAN priority tag, FrameID 0xFC01 (high priority) or 0xFE01 (low), the
//! RTA-PDU header (AlarmDstEndpoint, AlarmSrcEndpoint, PDUType with its version, AddFlags with
//! the window size and TACK, SendSeqNum, AckSeqNum, VarPartLen) and its variable part: for a
//! DATA PDU one block, the AlarmNotification-PDU (0x0001/0x0002) or the AlarmAck-PDU
//! (0x8001/0x8002); for an ERR PDU a PNIOStatus; nothing for ACK and NACK. The diagnosis data an
//! alarm carries (ChannelDiagnosis, USI 0x8000; ExtChannelDiagnosis, USI 0x8002) is here too.
//! Parsing never panics: a frame too short, or whose VarPartLen runs past its end, is `None`.

use super::blocks::{emit_block, split, Reader};
use super::rpc::PnioStatus;
use super::{Ethernet, Mac, ETHERTYPE_PROFINET, ETHERTYPE_VLAN};

/// FrameID of high-priority alarm frames.
pub const FRAME_ID_HIGH: u16 = 0xFC01;
/// FrameID of low-priority alarm frames.
pub const FRAME_ID_LOW: u16 = 0xFE01;

/// PDUType DATA: carries a block, asks for a transport ACK when TACK is set.
pub const PDU_DATA: u8 = 1;
/// PDUType NACK: a DATA out of sequence.
pub const PDU_NACK: u8 = 2;
/// PDUType ACK: the transport acknowledgement.
pub const PDU_ACK: u8 = 3;
/// PDUType ERR: the AlarmCR (and its AR) is over; carries a PNIOStatus.
pub const PDU_ERR: u8 = 4;
/// The RTA version this module speaks (PDUType's high nibble).
pub const RTA_VERSION: u8 = 1;

/// AddFlags: WindowSize 1 (bits 0-3).
pub const WINDOW_1: u8 = 0x01;
/// AddFlags: TACK, the receiver is to answer with an ACK (bit 4).
pub const TACK: u8 = 0x10;

/// The first SendSeqNum of each side, and the value the last one "acknowledged" has before it.
pub const SEQ_FIRST: u16 = 0xFFFF;
/// AckSeqNum before anything was received.
pub const SEQ_NONE: u16 = 0xFFFE;
/// Sequence numbers count modulo 0x8000 after the first.
pub const SEQ_MASK: u16 = 0x7FFF;

/// AlarmNotification-PDU, high priority.
pub const BLOCK_NOTIFICATION_HIGH: u16 = 0x0001;
/// AlarmNotification-PDU, low priority.
pub const BLOCK_NOTIFICATION_LOW: u16 = 0x0002;
/// AlarmAck-PDU, high priority.
pub const BLOCK_ACK_HIGH: u16 = 0x8001;
/// AlarmAck-PDU, low priority.
pub const BLOCK_ACK_LOW: u16 = 0x8002;

/// AlarmType Diagnosis (a diagnosis appears).
pub const ALARM_DIAGNOSIS: u16 = 0x0001;
/// AlarmType Diagnosis disappears.
pub const ALARM_DIAGNOSIS_DISAPPEARS: u16 = 0x000C;

/// UserStructureIdentifier of ChannelDiagnosis data.
pub const USI_CHANNEL_DIAGNOSIS: u16 = 0x8000;
/// UserStructureIdentifier of ExtChannelDiagnosis data.
pub const USI_EXT_CHANNEL_DIAGNOSIS: u16 = 0x8002;
/// ChannelNumber of a diagnosis of the whole submodule.
pub const CHANNEL_SUBMODULE: u16 = 0x8000;
/// ChannelProperties.Specifier (bits 11-12): the diagnosis appears.
pub const CHANNEL_APPEARS: u16 = 1 << 11;
/// ChannelProperties.Specifier (bits 11-12): the diagnosis disappears (no other remains).
pub const CHANNEL_DISAPPEARS: u16 = 2 << 11;

/// AlarmSpecifier bit 11: the alarm carries channel diagnosis data.
pub const SPEC_CHANNEL_DIAGNOSIS: u16 = 0x0800;
/// AlarmSpecifier bit 12: manufacturer-specific diagnosis.
pub const SPEC_MANUFACTURER: u16 = 0x1000;
/// AlarmSpecifier bit 13: the submodule has a diagnosis (after this alarm).
pub const SPEC_SUBMODULE_DIAGNOSIS: u16 = 0x2000;
/// AlarmSpecifier bit 15: a submodule of the AR has a diagnosis (after this alarm).
pub const SPEC_AR_DIAGNOSIS: u16 = 0x8000;
/// AlarmSpecifier bits 0-10: the alarm's sequence number.
pub const SPEC_SEQUENCE: u16 = 0x07FF;

/// The RTA-PDU header (12 bytes after the FrameID).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RtaHeader {
    /// AlarmDstEndpoint: the receiver's LocalAlarmReference.
    pub dst: u16,
    /// AlarmSrcEndpoint: the sender's LocalAlarmReference.
    pub src: u16,
    /// PDUType.Type (bits 0-3): [`PDU_DATA`], [`PDU_NACK`], [`PDU_ACK`], [`PDU_ERR`].
    pub pdu_type: u8,
    /// PDUType.Version (bits 4-7).
    pub version: u8,
    /// AddFlags: [`WINDOW_1`], [`TACK`].
    pub add_flags: u8,
    /// SendSeqNum.
    pub send_seq: u16,
    /// AckSeqNum: the last SendSeqNum received in sequence.
    pub ack_seq: u16,
}

/// One alarm frame's RTA-PDU: where it came from, its FrameID, header and variable part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RtaFrame<'a> {
    /// The Ethernet header.
    pub eth: Ethernet,
    /// [`FRAME_ID_HIGH`] or [`FRAME_ID_LOW`].
    pub frame_id: u16,
    /// The RTA-PDU header.
    pub header: RtaHeader,
    /// The VarPartLen bytes after the header (Ethernet padding after them is not part of it).
    pub var_part: &'a [u8],
}

impl<'a> RtaFrame<'a> {
    /// Reads an Ethernet frame: `None` unless it is a PROFINET frame with an alarm FrameID, a
    /// whole RTA-PDU header, and the VarPartLen bytes it announces.
    pub fn parse(frame: &'a [u8]) -> Option<RtaFrame<'a>> {
        let eth = Ethernet::parse(frame)?;
        if eth.ethertype != ETHERTYPE_PROFINET {
            return None;
        }
        let mut r = Reader::new(frame.get(eth.payload..)?);
        let frame_id = r.u16()?;
        if frame_id != FRAME_ID_HIGH && frame_id != FRAME_ID_LOW {
            return None;
        }
        let (dst, src, pdu_type, add_flags) = (r.u16()?, r.u16()?, r.u8()?, r.u8()?);
        let (send_seq, ack_seq, len) = (r.u16()?, r.u16()?, r.u16()?);
        let var_part = r.take(usize::from(len))?;
        Some(RtaFrame {
            eth,
            frame_id,
            header: RtaHeader {
                dst,
                src,
                pdu_type: pdu_type & 0x0F,
                version: pdu_type >> 4,
                add_flags,
                send_seq,
                ack_seq,
            },
            var_part,
        })
    }

    /// `true` for the high-priority FrameID.
    pub fn high(&self) -> bool {
        self.frame_id == FRAME_ID_HIGH
    }
}

/// Appends a whole alarm frame: the Ethernet header with a VLAN tag of `tci` (the AlarmCR's
/// tag header: priority and VLAN ID), `frame_id`, the header and `var_part`; padded to
/// Ethernet's minimum.
pub fn emit_frame(
    dst: Mac,
    src: Mac,
    tci: u16,
    frame_id: u16,
    header: &RtaHeader,
    var_part: &[u8],
) -> Vec<u8> {
    let mut out = Vec::with_capacity(34 + var_part.len());
    out.extend_from_slice(&dst);
    out.extend_from_slice(&src);
    out.extend_from_slice(&ETHERTYPE_VLAN.to_be_bytes());
    out.extend_from_slice(&tci.to_be_bytes());
    out.extend_from_slice(&ETHERTYPE_PROFINET.to_be_bytes());
    out.extend_from_slice(&frame_id.to_be_bytes());
    for v in [header.dst, header.src] {
        out.extend_from_slice(&v.to_be_bytes());
    }
    out.push((header.version << 4) | (header.pdu_type & 0x0F));
    out.push(header.add_flags);
    let len = u16::try_from(var_part.len()).unwrap_or(u16::MAX);
    for v in [header.send_seq, header.ack_seq, len] {
        out.extend_from_slice(&v.to_be_bytes());
    }
    out.extend_from_slice(var_part);
    super::pad(&mut out);
    out
}

/// Where an alarm is and what it is: the fields the AlarmNotification and the AlarmAck share.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmSource {
    /// AlarmType.
    pub alarm_type: u16,
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// AlarmSpecifier: sequence number (bits 0-10) and the diagnosis flags.
    pub specifier: u16,
}

/// The AlarmNotification-PDU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AlarmNotification {
    /// High priority (block 0x0001) or low (0x0002).
    pub high: bool,
    /// Type, place and specifier.
    pub source: AlarmSource,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// The AlarmPayload: UserStructureIdentifier and its data, if any.
    pub payload: Option<(u16, Vec<u8>)>,
}

impl AlarmNotification {
    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        let block = if self.high {
            BLOCK_NOTIFICATION_HIGH
        } else {
            BLOCK_NOTIFICATION_LOW
        };
        emit_block(out, block, 0, |o| {
            let s = &self.source;
            o.extend_from_slice(&s.alarm_type.to_be_bytes());
            o.extend_from_slice(&s.api.to_be_bytes());
            o.extend_from_slice(&s.slot.to_be_bytes());
            o.extend_from_slice(&s.subslot.to_be_bytes());
            o.extend_from_slice(&self.module_ident.to_be_bytes());
            o.extend_from_slice(&self.submodule_ident.to_be_bytes());
            o.extend_from_slice(&s.specifier.to_be_bytes());
            if let Some((usi, data)) = &self.payload {
                o.extend_from_slice(&usi.to_be_bytes());
                o.extend_from_slice(data);
            }
        });
    }

    /// Reads a DATA PDU's variable part: `None` unless it is one AlarmNotification block.
    pub fn parse(var_part: &[u8]) -> Option<AlarmNotification> {
        let blocks = split(var_part).ok()?;
        let [block] = blocks.as_slice() else {
            return None;
        };
        let high = match block.block_type {
            BLOCK_NOTIFICATION_HIGH => true,
            BLOCK_NOTIFICATION_LOW => false,
            _ => return None,
        };
        let mut r = Reader::new(block.body);
        let alarm_type = r.u16()?;
        let (api, slot, subslot) = (r.u32()?, r.u16()?, r.u16()?);
        let (module_ident, submodule_ident, specifier) = (r.u32()?, r.u32()?, r.u16()?);
        let payload = match r.rest() {
            [] => None,
            rest => {
                let usi = r.u16()?;
                Some((usi, rest.get(2..)?.to_vec()))
            }
        };
        Some(AlarmNotification {
            high,
            source: AlarmSource {
                alarm_type,
                api,
                slot,
                subslot,
                specifier,
            },
            module_ident,
            submodule_ident,
            payload,
        })
    }
}

/// The AlarmAck-PDU: the controller's acknowledgement of one alarm, with its PNIOStatus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmAck {
    /// High priority (block 0x8001) or low (0x8002).
    pub high: bool,
    /// The acknowledged alarm's type, place and specifier.
    pub source: AlarmSource,
    /// PNIOStatus (zero: acknowledged).
    pub status: PnioStatus,
}

impl AlarmAck {
    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        let block = if self.high {
            BLOCK_ACK_HIGH
        } else {
            BLOCK_ACK_LOW
        };
        emit_block(out, block, 0, |o| {
            let s = &self.source;
            o.extend_from_slice(&s.alarm_type.to_be_bytes());
            o.extend_from_slice(&s.api.to_be_bytes());
            o.extend_from_slice(&s.slot.to_be_bytes());
            o.extend_from_slice(&s.subslot.to_be_bytes());
            o.extend_from_slice(&s.specifier.to_be_bytes());
            o.extend_from_slice(&self.status.0);
        });
    }

    /// Reads a DATA PDU's variable part: `None` unless it is one whole AlarmAck block.
    pub fn parse(var_part: &[u8]) -> Option<AlarmAck> {
        let blocks = split(var_part).ok()?;
        let [block] = blocks.as_slice() else {
            return None;
        };
        let high = match block.block_type {
            BLOCK_ACK_HIGH => true,
            BLOCK_ACK_LOW => false,
            _ => return None,
        };
        let mut r = Reader::new(block.body);
        let source = AlarmSource {
            alarm_type: r.u16()?,
            api: r.u32()?,
            slot: r.u16()?,
            subslot: r.u16()?,
            specifier: r.u16()?,
        };
        let status = PnioStatus(r.take(4)?.try_into().ok()?);
        r.rest().is_empty().then_some(AlarmAck {
            high,
            source,
            status,
        })
    }
}

/// One ChannelDiagnosis (USI 0x8000) or ExtChannelDiagnosis (USI 0x8002) entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChannelDiagnosis {
    /// ChannelNumber ([`CHANNEL_SUBMODULE`] for the whole submodule).
    pub channel: u16,
    /// ChannelProperties: type, accumulative, maintenance, specifier, direction.
    pub properties: u16,
    /// ChannelErrorType (the GSDML's ChannelDiagItem ErrorType).
    pub error_type: u16,
    /// ExtChannelErrorType and ExtChannelAddValue, for ExtChannelDiagnosis.
    pub ext: Option<(u16, u32)>,
}

impl ChannelDiagnosis {
    /// The UserStructureIdentifier of a list of these (all of one kind).
    pub fn usi(&self) -> u16 {
        if self.ext.is_some() {
            USI_EXT_CHANNEL_DIAGNOSIS
        } else {
            USI_CHANNEL_DIAGNOSIS
        }
    }

    /// Appends the entry.
    pub fn emit(&self, out: &mut Vec<u8>) {
        for v in [self.channel, self.properties, self.error_type] {
            out.extend_from_slice(&v.to_be_bytes());
        }
        if let Some((ext_type, add_value)) = self.ext {
            out.extend_from_slice(&ext_type.to_be_bytes());
            out.extend_from_slice(&add_value.to_be_bytes());
        }
    }

    /// Reads the entries of an alarm payload with `usi`: `None` for another USI or a length
    /// that is not a whole number of entries.
    pub fn parse_all(usi: u16, data: &[u8]) -> Option<Vec<ChannelDiagnosis>> {
        let size = match usi {
            USI_CHANNEL_DIAGNOSIS => 6,
            USI_EXT_CHANNEL_DIAGNOSIS => 12,
            _ => return None,
        };
        if !data.len().is_multiple_of(size) {
            return None;
        }
        data.chunks_exact(size)
            .map(|c| {
                let mut r = Reader::new(c);
                Some(ChannelDiagnosis {
                    channel: r.u16()?,
                    properties: r.u16()?,
                    error_type: r.u16()?,
                    ext: match size {
                        12 => Some((r.u16()?, r.u32()?)),
                        _ => None,
                    },
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests;
