//! The alarm frames of the AlarmCR (IEC 61158-6-10, acyclic real time, "RTA"): on EtherType
//! 0x8892 behind a VLAN priority tag, FrameID 0xFC01 (high priority) or 0xFE01 (low), the
//! RTA-PDU header (AlarmDstEndpoint, AlarmSrcEndpoint, PDUType with its version, AddFlags with
//! the window size and TACK, SendSeqNum, AckSeqNum, VarPartLen) and its variable part; the
//! AlarmAck-PDU (0x8001/0x8002) a DATA PDU carries. Views and emitters into the caller's buffer:
//! a frame too short, or whose VarPartLen runs past its end, is `None`; the AlarmNotification-PDU
//! and the (Ext)ChannelDiagnosis entries its payload carries. A simulator that queues alarms
//! keeps their payloads in owned structs of its own (`edsgen_sim::profinet::wire::alarm`).

use super::block::{blocks, emit_block, Reader};
use super::rpc::PnioStatus;
use super::{put, BufferTooSmall, Ethernet, Mac, ETHERTYPE_PROFINET, ETHERTYPE_VLAN};

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

/// Writes a whole alarm frame at the start of `buf`: the Ethernet header with a VLAN tag of
/// `tci` (the AlarmCR's tag header: priority and VLAN ID), `frame_id`, the header and
/// `var_part` (unpadded); its length.
pub fn emit_frame(
    buf: &mut [u8],
    addresses: (Mac, Mac),
    tci: u16,
    frame_id: u16,
    header: &RtaHeader,
    var_part: &[u8],
) -> Result<usize, BufferTooSmall> {
    let (dst, src) = addresses;
    let at = put(buf, 0, &dst)?;
    let at = put(buf, at, &src)?;
    let at = put(buf, at, &ETHERTYPE_VLAN.to_be_bytes())?;
    let at = put(buf, at, &tci.to_be_bytes())?;
    let at = put(buf, at, &ETHERTYPE_PROFINET.to_be_bytes())?;
    let at = put(buf, at, &frame_id.to_be_bytes())?;
    let at = put(buf, at, &header.dst.to_be_bytes())?;
    let at = put(buf, at, &header.src.to_be_bytes())?;
    let at = put(
        buf,
        at,
        &[
            (header.version << 4) | (header.pdu_type & 0x0F),
            header.add_flags,
        ],
    )?;
    let len = u16::try_from(var_part.len()).map_err(|_| BufferTooSmall)?;
    let at = put(buf, at, &header.send_seq.to_be_bytes())?;
    let at = put(buf, at, &header.ack_seq.to_be_bytes())?;
    let at = put(buf, at, &len.to_be_bytes())?;
    put(buf, at, var_part)
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
    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let block = if self.high {
            BLOCK_ACK_HIGH
        } else {
            BLOCK_ACK_LOW
        };
        emit_block(buf, block, 0, |b| {
            let s = &self.source;
            let at = put(b, 0, &s.alarm_type.to_be_bytes())?;
            let at = put(b, at, &s.api.to_be_bytes())?;
            let at = put(b, at, &s.slot.to_be_bytes())?;
            let at = put(b, at, &s.subslot.to_be_bytes())?;
            let at = put(b, at, &s.specifier.to_be_bytes())?;
            put(b, at, &self.status.0)
        })
    }

    /// Reads a DATA PDU's variable part: `None` unless it is one whole AlarmAck block.
    pub fn parse(var_part: &[u8]) -> Option<AlarmAck> {
        let mut all = blocks(var_part);
        let block = all.next()?.ok()?;
        if all.next().is_some() {
            return None;
        }
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

/// The AlarmNotification-PDU as a view: an alarm of a device, with its AlarmPayload borrowed
/// from the frame it was read from (or to be written into one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmNotificationRepr<'a> {
    /// High priority (block 0x0001) or low (0x0002).
    pub high: bool,
    /// Type, place and specifier.
    pub source: AlarmSource,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// The AlarmPayload: UserStructureIdentifier and its data, if any.
    pub payload: Option<(u16, &'a [u8])>,
}

impl<'a> AlarmNotificationRepr<'a> {
    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let block = if self.high {
            BLOCK_NOTIFICATION_HIGH
        } else {
            BLOCK_NOTIFICATION_LOW
        };
        emit_block(buf, block, 0, |b| {
            let s = &self.source;
            let at = put(b, 0, &s.alarm_type.to_be_bytes())?;
            let at = put(b, at, &s.api.to_be_bytes())?;
            let at = put(b, at, &s.slot.to_be_bytes())?;
            let at = put(b, at, &s.subslot.to_be_bytes())?;
            let at = put(b, at, &self.module_ident.to_be_bytes())?;
            let at = put(b, at, &self.submodule_ident.to_be_bytes())?;
            let at = put(b, at, &s.specifier.to_be_bytes())?;
            match self.payload {
                Some((usi, data)) => {
                    let at = put(b, at, &usi.to_be_bytes())?;
                    put(b, at, data)
                }
                None => Ok(at),
            }
        })
    }

    /// Reads a DATA PDU's variable part: `None` unless it is one whole AlarmNotification
    /// block (a payload too short for its UserStructureIdentifier included).
    pub fn parse(var_part: &'a [u8]) -> Option<AlarmNotificationRepr<'a>> {
        let mut all = blocks(var_part);
        let block = all.next()?.ok()?;
        if all.next().is_some() {
            return None;
        }
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
            _ => Some((r.u16()?, r.rest())),
        };
        Some(AlarmNotificationRepr {
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

/// One ChannelDiagnosis (USI 0x8000) or ExtChannelDiagnosis (USI 0x8002) entry of an alarm's
/// payload or a diagnosis record.
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

    /// Writes the entry at the start of `buf`; its length (6 bytes, 12 with `ext`).
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let at = put(buf, 0, &self.channel.to_be_bytes())?;
        let at = put(buf, at, &self.properties.to_be_bytes())?;
        let at = put(buf, at, &self.error_type.to_be_bytes())?;
        match self.ext {
            Some((ext_type, add_value)) => {
                let at = put(buf, at, &ext_type.to_be_bytes())?;
                put(buf, at, &add_value.to_be_bytes())
            }
            None => Ok(at),
        }
    }

    /// The entries of an alarm payload with `usi`, read as they are iterated: `None` for another
    /// USI or a length that is not a whole number of entries.
    pub fn parse_all(usi: u16, data: &[u8]) -> Option<ChannelDiagnoses<'_>> {
        let size = match usi {
            USI_CHANNEL_DIAGNOSIS => 6,
            USI_EXT_CHANNEL_DIAGNOSIS => 12,
            _ => return None,
        };
        (data.len() % size == 0).then(|| ChannelDiagnoses(data.chunks_exact(size)))
    }

    fn parse(entry: &[u8]) -> Option<ChannelDiagnosis> {
        let mut r = Reader::new(entry);
        let channel = r.u16()?;
        let properties = r.u16()?;
        let error_type = r.u16()?;
        let ext = match r.rest().len() {
            0 => None,
            _ => Some((r.u16()?, r.u32()?)),
        };
        Some(ChannelDiagnosis {
            channel,
            properties,
            error_type,
            ext,
        })
    }
}

/// The (Ext)ChannelDiagnosis entries of a payload ([`ChannelDiagnosis::parse_all`]).
#[derive(Debug, Clone)]
pub struct ChannelDiagnoses<'a>(core::slice::ChunksExact<'a, u8>);

impl Iterator for ChannelDiagnoses<'_> {
    type Item = ChannelDiagnosis;

    fn next(&mut self) -> Option<ChannelDiagnosis> {
        ChannelDiagnosis::parse(self.0.next()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ACK: AlarmAck = AlarmAck {
        high: true,
        source: AlarmSource {
            alarm_type: ALARM_DIAGNOSIS,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: SPEC_CHANNEL_DIAGNOSIS | 3,
        },
        status: PnioStatus([0; 4]),
    };

    #[test]
    fn an_alarm_ack_is_written_into_the_buffer_and_read_back() {
        let mut buf = [0u8; 32];
        let n = ACK.emit(&mut buf).expect("fits");
        #[rustfmt::skip]
        assert_eq!(
            buf[..n],
            [
                0x80, 0x01, 0x00, 0x12, 0x01, 0x00, // AlarmAck high, BlockLength 18
                0x00, 0x01, 0x00, 0x00, 0x00, 0x00, // Diagnosis, API 0
                0x00, 0x01, 0x00, 0x01, 0x08, 0x03, // slot 1, subslot 1, specifier
                0x00, 0x00, 0x00, 0x00,             // PNIOStatus
            ]
        );
        assert_eq!(AlarmAck::parse(&buf[..n]), Some(ACK));
        assert_eq!(AlarmAck::parse(&buf[..n - 1]), None);
        assert_eq!(ACK.emit(&mut buf[..n - 1]), Err(BufferTooSmall));
    }

    #[test]
    fn an_alarm_notification_is_written_into_the_buffer_and_read_back() {
        let payload = [0x80, 0x00, 0x80, 0x00];
        let alarm = AlarmNotificationRepr {
            high: false,
            source: AlarmSource {
                alarm_type: ALARM_DIAGNOSIS,
                api: 0,
                slot: 1,
                subslot: 1,
                specifier: SPEC_CHANNEL_DIAGNOSIS | 2,
            },
            module_ident: 0x10,
            submodule_ident: 0x20,
            payload: Some((USI_CHANNEL_DIAGNOSIS, &payload)),
        };
        let mut buf = [0u8; 40];
        let n = alarm.emit(&mut buf).expect("fits");
        #[rustfmt::skip]
        assert_eq!(
            buf[..n],
            [
                0x00, 0x02, 0x00, 0x1C, 0x01, 0x00, // AlarmNotification low, BlockLength 28
                0x00, 0x01, 0x00, 0x00, 0x00, 0x00, // Diagnosis, API 0
                0x00, 0x01, 0x00, 0x01,             // slot 1, subslot 1
                0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x20, // module, submodule
                0x08, 0x02, 0x80, 0x00,             // specifier, USI
                0x80, 0x00, 0x80, 0x00,             // the USI's data
            ]
        );
        assert_eq!(AlarmNotificationRepr::parse(&buf[..n]), Some(alarm));
        assert_eq!(AlarmNotificationRepr::parse(&buf[..n - 1]), None);
        assert_eq!(alarm.emit(&mut buf[..n - 1]), Err(BufferTooSmall));
        let bare = AlarmNotificationRepr {
            payload: None,
            ..alarm
        };
        let n = bare.emit(&mut buf).expect("fits");
        assert_eq!((n, buf[3]), (26, 0x16));
        assert_eq!(AlarmNotificationRepr::parse(&buf[..n]), Some(bare));
        // An AlarmAck block is not a notification.
        let n = ACK.emit(&mut buf).expect("fits");
        assert_eq!(AlarmNotificationRepr::parse(&buf[..n]), None);
    }

    #[test]
    fn a_frame_is_written_whole_or_not_at_all() {
        let header = RtaHeader {
            dst: 2,
            src: 1,
            pdu_type: PDU_ACK,
            version: RTA_VERSION,
            add_flags: WINDOW_1,
            send_seq: SEQ_NONE,
            ack_seq: SEQ_FIRST,
        };
        let (dst, src) = ([2, 0, 0, 0, 0, 2], [2, 0, 0, 0, 0, 1]);
        let mut buf = [0u8; 64];
        let n =
            emit_frame(&mut buf, (dst, src), 0xC000, FRAME_ID_HIGH, &header, &[]).expect("fits");
        #[rustfmt::skip]
        assert_eq!(
            buf[12..n],
            [
                0x81, 0x00, 0xC0, 0x00, 0x88, 0x92, 0xFC, 0x01, // VLAN, PROFINET, high
                0x00, 0x02, 0x00, 0x01, 0x13, 0x01,             // endpoints, ACK v1, window 1
                0xFF, 0xFE, 0xFF, 0xFF, 0x00, 0x00,             // sequence numbers, no var part
            ]
        );
        let frame = RtaFrame::parse(&buf[..n]).expect("an alarm frame");
        assert_eq!(
            (frame.header, frame.var_part, frame.high()),
            (header, &[][..], true)
        );
        assert_eq!(RtaFrame::parse(&buf[..n - 1]), None);
        assert_eq!(
            emit_frame(
                &mut buf[..31],
                (dst, src),
                0xC000,
                FRAME_ID_HIGH,
                &header,
                &[]
            ),
            Err(BufferTooSmall)
        );
    }

    #[test]
    fn channel_diagnoses_are_written_and_read_back_entry_by_entry() {
        let ext = ChannelDiagnosis {
            channel: CHANNEL_SUBMODULE,
            properties: CHANNEL_APPEARS,
            error_type: 0x0100,
            ext: Some((0x8000, 0x0000_0007)),
        };
        let mut buf = [0u8; 24];
        assert_eq!(ext.emit(&mut buf), Ok(12));
        assert_eq!(
            buf[..12],
            [0x80, 0x00, 0x08, 0x00, 0x01, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x07]
        );
        assert_eq!(ext.emit(&mut buf[..11]), Err(BufferTooSmall));
        buf.copy_within(..12, 12);
        let read: Vec<_> = ChannelDiagnosis::parse_all(USI_EXT_CHANNEL_DIAGNOSIS, &buf)
            .expect("two whole entries")
            .collect();
        assert_eq!(read, [ext, ext]);
        let plain: Vec<_> = ChannelDiagnosis::parse_all(USI_CHANNEL_DIAGNOSIS, &buf[..12])
            .expect("two whole entries")
            .collect();
        assert_eq!(plain[0].ext, None);
        let disappears = ChannelDiagnosis {
            channel: CHANNEL_SUBMODULE,
            properties: CHANNEL_DISAPPEARS,
            error_type: 0x0100,
            ext: None,
        };
        assert_eq!(disappears.usi(), USI_CHANNEL_DIAGNOSIS);
        assert_eq!(disappears.emit(&mut buf), Ok(6));
        assert_eq!(buf[..6], [0x80, 0x00, 0x10, 0x00, 0x01, 0x00]);
        assert_eq!((plain[0].channel, plain[1].channel), (0x8000, 0x8000));
        assert!(ChannelDiagnosis::parse_all(USI_EXT_CHANNEL_DIAGNOSIS, &buf[..13]).is_none());
        assert!(ChannelDiagnosis::parse_all(0x0001, &buf[..12]).is_none());
    }
}
