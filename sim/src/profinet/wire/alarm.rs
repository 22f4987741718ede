//! The alarm frames of the AlarmCR: the RTA-PDU header, the frame, the AlarmAck-PDU and the
//! AlarmNotification-PDU are the runtime's views ([`edsgen_runtime::profinet::wire::alarm`]);
//! here the AlarmNotification the alarm machines queue and report (its payload owned, written
//! and read through the view), and a whole frame as a `Vec`. The diagnosis data an alarm
//! carries (ChannelDiagnosis, ExtChannelDiagnosis) is the runtime's too. Parsing never panics.

pub use edsgen_runtime::profinet::wire::alarm::*;

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

#[cfg(test)]
mod tests;
