//! The cyclic RT frame (RT_CLASS_1, IEC 61158-6-10): after the Ethernet header, the FrameID, the
//! C_SDU (the IO data objects, at least 40 bytes), and the APDU status: CycleCounter (2 bytes),
//! DataStatus and TransferStatus (Table 4-3 of the Goodrive350 manual shows the same fields).

use super::{put, BufferTooSmall};

/// The FrameIDs of RT_CLASS_1 frames (unicast and multicast).
pub const RT_CLASS_1: core::ops::RangeInclusive<u16> = 0xC000..=0xF7FF;
/// The smallest C_SDU: Ethernet's 60-byte minimum less the headers and the APDU status.
pub const MIN_C_SDU: usize = 40;

/// DataStatus bit 0: primary (not backup).
pub const STATE_PRIMARY: u8 = 0x01;
/// DataStatus bit 2: data valid.
pub const DATA_VALID: u8 = 0x04;
/// DataStatus bit 4: provider in RUN (else STOP).
pub const PROVIDER_RUN: u8 = 0x10;
/// DataStatus bit 5: no station problem.
pub const STATION_OK: u8 = 0x20;
/// The DataStatus of a device that runs and has no problem (0x35).
pub const DATA_STATUS_GOOD: u8 = STATE_PRIMARY | DATA_VALID | PROVIDER_RUN | STATION_OK;

/// One RT frame's PDU (after the Ethernet header), a view of the bytes it was read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RtFrame<'a> {
    /// FrameID.
    pub frame_id: u16,
    /// The C_SDU: the IO data objects and their status bytes, and padding.
    pub c_sdu: &'a [u8],
    /// CycleCounter (31.25 µs units).
    pub cycle_counter: u16,
    /// DataStatus.
    pub data_status: u8,
    /// TransferStatus (0: no error).
    pub transfer_status: u8,
}

impl<'a> RtFrame<'a> {
    /// Reads a PDU of `c_sdu_len` C_SDU bytes (the IOCR's length: the frame may carry Ethernet
    /// padding after the status); `None` when it is shorter.
    pub fn parse(pdu: &'a [u8], c_sdu_len: usize) -> Option<RtFrame<'a>> {
        let frame_id = u16::from_be_bytes([*pdu.first()?, *pdu.get(1)?]);
        let len = c_sdu_len.max(MIN_C_SDU);
        let c_sdu = pdu.get(2..2 + len)?;
        let status = pdu.get(2 + len..2 + len + 4)?;
        Some(RtFrame {
            frame_id,
            c_sdu,
            cycle_counter: u16::from_be_bytes([status[0], status[1]]),
            data_status: status[2],
            transfer_status: status[3],
        })
    }

    /// The PDU's length: the C_SDU padded to [`MIN_C_SDU`], the FrameID and the status.
    pub fn buffer_len(&self) -> usize {
        2 + self.c_sdu.len().max(MIN_C_SDU) + 4
    }

    /// Writes the PDU at the start of `buf`, padding the C_SDU to [`MIN_C_SDU`]; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, BufferTooSmall> {
        let out = buf.get_mut(..self.buffer_len()).ok_or(BufferTooSmall)?;
        let at = put(out, 0, &self.frame_id.to_be_bytes())?;
        let at = put(out, at, self.c_sdu)?;
        let padded = 2 + self.c_sdu.len().max(MIN_C_SDU);
        out[at..padded].fill(0);
        let at = put(out, padded, &self.cycle_counter.to_be_bytes())?;
        put(out, at, &[self.data_status, self.transfer_status])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_c_sdu_is_padded_to_40_and_read_back() {
        let frame = RtFrame {
            frame_id: 0xC001,
            c_sdu: &[1, 2, 3],
            cycle_counter: 0x0120,
            data_status: DATA_STATUS_GOOD,
            transfer_status: 0,
        };
        let mut out = [0xAA; 64];
        assert_eq!(frame.emit(&mut out), Ok(2 + 40 + 4));
        assert_eq!(out[..5], [0xC0, 0x01, 1, 2, 3]);
        assert_eq!(out[5..42], [0; 37]);
        assert_eq!(out[42..46], [0x01, 0x20, 0x35, 0x00]);
        let read = RtFrame::parse(&out[..46], 3).expect("a frame");
        assert_eq!(read.c_sdu.len(), 40);
        assert_eq!((read.cycle_counter, read.data_status), (0x0120, 0x35));
        assert_eq!(RtFrame::parse(&out[..45], 3), None);
        assert_eq!(frame.emit(&mut out[..45]), Err(BufferTooSmall));
    }
}
