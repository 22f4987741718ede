//! The alarm frames of the AlarmCR: the RTA-PDU header, the frame, the AlarmAck-PDU and the
//! AlarmNotification-PDU are the runtime's views ([`edsgen_runtime::profinet::wire::alarm`]);
//! here the AlarmNotification the alarm machines queue and report (its payload owned, written
//! and read through the view) and the diagnosis data an alarm carries (ChannelDiagnosis, USI 0x8000; ExtChannelDiagnosis, USI 0x8002), and
//! a whole frame as a `Vec`. Parsing never panics.

pub use edsgen_runtime::profinet::wire::alarm::*;

use super::blocks::Reader;
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
    /// The runtime's view of it, borrowing its payload.
    pub fn repr(&self) -> AlarmNotificationRepr<'_> {
        AlarmNotificationRepr {
            high: self.high,
            source: self.source,
            module_ident: self.module_ident,
            submodule_ident: self.submodule_ident,
            payload: self
                .payload
                .as_ref()
                .map(|(usi, data)| (*usi, data.as_slice())),
        }
    }

    /// Appends the block.
    pub fn emit(&self, out: &mut Vec<u8>) {
        super::append(out, |b| self.repr().emit(b));
    }

    /// Reads a DATA PDU's variable part: `None` unless it is one AlarmNotification block.
    pub fn parse(var_part: &[u8]) -> Option<AlarmNotification> {
        let view = AlarmNotificationRepr::parse(var_part)?;
        Some(AlarmNotification {
            high: view.high,
            source: view.source,
            module_ident: view.module_ident,
            submodule_ident: view.submodule_ident,
            payload: view.payload.map(|(usi, data)| (usi, data.to_vec())),
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
