//! AlarmCRBlockReq and AlarmCRBlockRes: the AlarmCR a controller asks for in its Connect (the
//! endpoints, VLAN tags, RTA timeout and retries) and the device's answer, both of fixed size.

use super::super::block::{emit_block, Reader};
use super::super::records::RESPONSE_BIT;
use super::super::BufferTooSmall;
use super::{Writer, ALARM_CR_BLOCK_REQ};

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

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, ALARM_CR_BLOCK_REQ, 0, |b| {
            let mut w = Writer::new(b);
            w.u16(self.alarm_cr_type)?;
            w.u16(self.lt)?;
            w.u32(self.properties)?;
            for v in [
                self.rta_timeout_factor,
                self.rta_retries,
                self.local_alarm_reference,
                self.max_alarm_data_length,
                self.tag_header_high,
                self.tag_header_low,
            ] {
                w.u16(v)?;
            }
            Ok(w.len())
        })
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

    /// Writes the block at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        emit_block(buf, ALARM_CR_BLOCK_REQ | RESPONSE_BIT, 0, |b| {
            let mut w = Writer::new(b);
            for v in [
                self.alarm_cr_type,
                self.local_alarm_reference,
                self.max_alarm_data_length,
            ] {
                w.u16(v)?;
            }
            Ok(w.len())
        })
    }
}
