//! The alarm frames of the AlarmCR: the RTA-PDU header, the frame and the AlarmAck-PDU are the
//! runtime's views ([`edsgen_runtime::profinet::wire::alarm`]); here the AlarmNotification-PDU
//! (0x0001/0x0002, whose payload the device's alarm machine queues, owned) and the diagnosis
//! data an alarm carries (ChannelDiagnosis, USI 0x8000; ExtChannelDiagnosis, USI 0x8002), and
//! a whole frame as a `Vec`. Parsing never panics.

pub use edsgen_runtime::profinet::wire::alarm::*;

use super::blocks::{emit_block, split, Reader};
use super::Mac;

/// A whole alarm frame (see the runtime's `emit_frame`), padded to Ethernet's minimum.
pub fn emit_frame(
    dst: Mac,
    src: Mac,
    tci: u16,
    frame_id: u16,
    header: &RtaHeader,
    var_part: &[u8],
) -> Vec<u8> {
    let mut out = vec![0; 34 + var_part.len()];
    let written = edsgen_runtime::profinet::wire::alarm::emit_frame(
        &mut out,
        (dst, src),
        tci,
        frame_id,
        header,
        var_part,
    )
    .unwrap_or(0);
    out.truncate(written);
    super::pad(&mut out);
    out
}

/// The AlarmAck-PDU `ack` appended to `out`.
pub fn append_ack(out: &mut Vec<u8>, ack: &AlarmAck) {
    super::append(out, |b| ack.emit(b));
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
