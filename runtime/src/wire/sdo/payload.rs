//! The data shapes both directions share: what an initiate message announces, a normal
//! transfer's segment data and a block transfer's sub-block segment.

use super::{command, frame, Frame, WireError, FRAME_LEN, SEGMENT_DATA_LEN};

/// What an initiate download request or an initiate upload response announces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitiatePayload {
    /// Expedited transfer with size indicated: the first `len` (1..=4) bytes of `data` are the value.
    Expedited {
        /// Bytes 4..8 of the frame; those past `len` are zero after parse and sent as zero.
        data: [u8; 4],
        /// How many of them are data (1..=4).
        len: u8,
    },
    /// Expedited transfer without size indicated: the receiver knows how many of the four count.
    ExpeditedUnsized {
        /// Bytes 4..8 of the frame.
        data: [u8; 4],
    },
    /// Normal (segmented) transfer of `size` bytes.
    Sized(u32),
    /// Normal (segmented) transfer, size not indicated.
    Unsized,
}

impl InitiatePayload {
    /// Bits 3..0 of the command byte (n, e, s) and bytes 4..8.
    pub(super) fn encode(self) -> (u8, [u8; 4]) {
        match self {
            InitiatePayload::Expedited { data, len } => {
                let len = len.clamp(1, 4);
                // Bytes past `len` are sent as zero.
                let mask = u32::MAX >> (8 * (4 - u32::from(len)));
                let bytes = (u32::from_le_bytes(data) & mask).to_le_bytes();
                (command::expedited_bits(len), bytes)
            }
            InitiatePayload::ExpeditedUnsized { data } => (0b10, data),
            InitiatePayload::Sized(size) => (command::SIZE_INDICATED, size.to_le_bytes()),
            InitiatePayload::Unsized => (0b00, [0; 4]),
        }
    }

    pub(super) fn decode(frame: Frame<'_>) -> Self {
        let data = frame.data();
        match (frame.expedited(), frame.size_indicated()) {
            (true, true) => {
                let len = frame.expedited_len();
                // Bytes past `len` carry no data: keep them as zero.
                let mask = u32::MAX >> (8 * (4 - u32::from(len)));
                InitiatePayload::Expedited {
                    data: (u32::from_le_bytes(data) & mask).to_le_bytes(),
                    len,
                }
            }
            (true, false) => InitiatePayload::ExpeditedUnsized { data },
            (false, true) => InitiatePayload::Sized(u32::from_le_bytes(data)),
            (false, false) => InitiatePayload::Unsized,
        }
    }
}

/// The data of one normal-transfer segment: up to 7 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SegmentData {
    bytes: [u8; SEGMENT_DATA_LEN],
    len: u8,
}

impl SegmentData {
    /// A segment holding `data`; `None` if it is longer than 7 bytes.
    pub fn new(data: &[u8]) -> Option<Self> {
        let mut bytes = [0u8; SEGMENT_DATA_LEN];
        bytes.get_mut(..data.len())?.copy_from_slice(data);
        Some(SegmentData {
            bytes,
            len: data.len() as u8,
        })
    }

    /// The data bytes.
    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len as usize]
    }

    /// The segment message (either direction: its specifier is 0) with these bytes.
    pub(super) fn encode(&self, toggle: bool, last: bool) -> [u8; FRAME_LEN] {
        let unused = SEGMENT_DATA_LEN as u8 - self.len;
        frame(command::segment_bits(toggle, unused, last), self.bytes)
    }

    pub(super) fn decode(frame: Frame<'_>) -> Self {
        let data = frame.segment_data();
        let mut bytes = [0u8; SEGMENT_DATA_LEN];
        bytes[..data.len()].copy_from_slice(data);
        SegmentData {
            bytes,
            len: data.len() as u8,
        }
    }
}

/// One segment of a block-transfer sub-block: a sequence number, the last-segment flag and
/// 7 data bytes (the unused bytes of the very last segment are announced by the end message).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockSegment {
    /// Sequence number within the sub-block (valid: 1..=127).
    pub seqno: u8,
    /// Whether this is the last segment of the whole transfer (c).
    pub last: bool,
    /// The segment's 7 bytes.
    pub data: [u8; SEGMENT_DATA_LEN],
}

impl BlockSegment {
    /// Parses a sub-block segment. Any 8 bytes are one; the sequence number is not checked here.
    pub fn parse(bytes: &[u8]) -> Result<Self, WireError> {
        let frame: &[u8; FRAME_LEN] = bytes.try_into().map_err(|_| WireError::Length)?;
        let mut data = [0u8; SEGMENT_DATA_LEN];
        data.copy_from_slice(&frame[1..]);
        Ok(BlockSegment {
            seqno: frame[0] & 0x7F,
            last: frame[0] & 0x80 != 0,
            data,
        })
    }

    /// The 8 bytes of this segment.
    pub fn emit(&self) -> [u8; FRAME_LEN] {
        let mut frame = [0u8; FRAME_LEN];
        frame[0] = (self.seqno & 0x7F) | if self.last { 0x80 } else { 0 };
        frame[1..].copy_from_slice(&self.data);
        frame
    }
}
