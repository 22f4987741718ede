//! SDO frame layouts (CiA 301 §7.2.4.3): initiate, segment and block messages, and aborts.
//!
//! [`ClientRequest`] and [`ServerResponse`] are the typed forms of every SDO message, each with
//! `parse` and `emit`. Block-transfer sub-block segments carry no command specifier (their first
//! byte is a sequence number), so they have their own type, [`BlockSegment`], and the receiver
//! decides by its state which parser applies. Every SDO frame is 8 bytes long; reserved bits are
//! emitted as zero and ignored on parse.

/// The length of every SDO frame's data (CiA 301 requires DLC 8).
pub const FRAME_LEN: usize = 8;
/// Data bytes carried by one segment (normal or block transfer).
pub const SEGMENT_DATA_LEN: usize = 7;
/// The largest number of segments in a block-transfer sub-block.
pub const MAX_BLOCK_SIZE: u8 = 127;

/// Why bytes are not an SDO message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireError {
    /// The frame is not exactly 8 bytes long.
    Length,
    /// The command specifier (or its sub-command) is not one this direction defines.
    Command,
}

/// The (index, sub-index) an SDO transfer addresses.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Multiplexer {
    /// OD index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
}

impl Multiplexer {
    /// The multiplexer of (index, sub).
    pub const fn new(index: u16, sub: u8) -> Self {
        Multiplexer { index, sub }
    }

    fn read(frame: &[u8; FRAME_LEN]) -> Self {
        Multiplexer {
            index: u16::from_le_bytes([frame[1], frame[2]]),
            sub: frame[3],
        }
    }

    fn write(self, frame: &mut [u8; FRAME_LEN]) {
        let [lo, hi] = self.index.to_le_bytes();
        frame[1] = lo;
        frame[2] = hi;
        frame[3] = self.sub;
    }
}

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
    fn encode(self) -> (u8, [u8; 4]) {
        match self {
            InitiatePayload::Expedited { data, len } => {
                let len = len.clamp(1, 4);
                // Bytes past `len` are sent as zero.
                let mask = u32::MAX >> (8 * (4 - u32::from(len)));
                let bytes = (u32::from_le_bytes(data) & mask).to_le_bytes();
                (((4 - len) << 2) | 0b11, bytes)
            }
            InitiatePayload::ExpeditedUnsized { data } => (0b10, data),
            InitiatePayload::Sized(size) => (0b01, size.to_le_bytes()),
            InitiatePayload::Unsized => (0b00, [0; 4]),
        }
    }

    fn decode(command: u8, frame: &[u8; FRAME_LEN]) -> Self {
        let data = [frame[4], frame[5], frame[6], frame[7]];
        let expedited = command & 0b10 != 0;
        let size_indicated = command & 0b01 != 0;
        match (expedited, size_indicated) {
            (true, true) => {
                let len = 4 - ((command >> 2) & 0b11);
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

    /// Bits 3..1 of the command byte (n: bytes not containing data) and bytes 1..8.
    fn encode(&self) -> (u8, [u8; SEGMENT_DATA_LEN]) {
        ((SEGMENT_DATA_LEN as u8 - self.len) << 1, self.bytes)
    }

    fn decode(command: u8, frame: &[u8; FRAME_LEN]) -> Self {
        let unused = (command >> 1) & 0b111;
        let len = SEGMENT_DATA_LEN as u8 - unused;
        let mut bytes = [0u8; SEGMENT_DATA_LEN];
        for (byte, data) in bytes.iter_mut().zip(&frame[1..]).take(usize::from(len)) {
            *byte = *data;
        }
        SegmentData { bytes, len }
    }
}

/// A message from an SDO client to a server.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClientRequest {
    /// Initiate SDO download (ccs = 1).
    InitiateDownload {
        /// The entry to write.
        mux: Multiplexer,
        /// Expedited data or the announced size.
        payload: InitiatePayload,
    },
    /// Download SDO segment (ccs = 0).
    DownloadSegment {
        /// The toggle bit.
        toggle: bool,
        /// The segment's data.
        data: SegmentData,
        /// Whether no more segments follow (c).
        last: bool,
    },
    /// Initiate SDO upload (ccs = 2).
    InitiateUpload {
        /// The entry to read.
        mux: Multiplexer,
    },
    /// Upload SDO segment (ccs = 3).
    UploadSegment {
        /// The toggle bit.
        toggle: bool,
    },
    /// Abort SDO transfer (ccs = 4).
    Abort {
        /// The entry of the aborted transfer.
        mux: Multiplexer,
        /// The abort code (CiA 301 table 22; may be one this stack does not name).
        code: u32,
    },
    /// Initiate SDO block upload (ccs = 5, cs = 0).
    BlockUploadInitiate {
        /// The entry to read.
        mux: Multiplexer,
        /// Whether the client supports CRC (cc).
        crc: bool,
        /// Segments per sub-block the client accepts (valid: 1..=127).
        blksize: u8,
        /// Protocol switch threshold: a value of at most this many bytes may be sent by a normal
        /// upload instead (0: no switch).
        pst: u8,
    },
    /// Start SDO block upload (ccs = 5, cs = 3).
    BlockUploadStart,
    /// SDO block upload response: the client acknowledges a sub-block (ccs = 5, cs = 2).
    BlockUploadAck {
        /// The sequence number of the last segment received in order.
        ackseq: u8,
        /// Segments per sub-block for the next sub-block.
        blksize: u8,
    },
    /// End SDO block upload response (ccs = 5, cs = 1).
    BlockUploadEnd,
    /// Initiate SDO block download (ccs = 6, cs = 0).
    BlockDownloadInitiate {
        /// The entry to write.
        mux: Multiplexer,
        /// Whether the client supports CRC (cc).
        crc: bool,
        /// The announced size, if indicated.
        size: Option<u32>,
    },
    /// End SDO block download request (ccs = 6, cs = 1).
    BlockDownloadEnd {
        /// Bytes of the last segment that do not contain data (n).
        unused: u8,
        /// CRC of the whole value (0 when CRC is not in use).
        crc: u16,
    },
}

impl ClientRequest {
    /// Parses a request frame. Block-download sub-block segments are not requests: parse them
    /// with [`BlockSegment::parse`].
    pub fn parse(bytes: &[u8]) -> Result<Self, WireError> {
        let frame: &[u8; FRAME_LEN] = bytes.try_into().map_err(|_| WireError::Length)?;
        let command = frame[0];
        let mux = Multiplexer::read(frame);
        Ok(match command >> 5 {
            0 => ClientRequest::DownloadSegment {
                toggle: command & 0x10 != 0,
                data: SegmentData::decode(command, frame),
                last: command & 0x01 != 0,
            },
            1 => ClientRequest::InitiateDownload {
                mux,
                payload: InitiatePayload::decode(command, frame),
            },
            2 => ClientRequest::InitiateUpload { mux },
            3 => ClientRequest::UploadSegment {
                toggle: command & 0x10 != 0,
            },
            4 => ClientRequest::Abort {
                mux,
                code: u32::from_le_bytes([frame[4], frame[5], frame[6], frame[7]]),
            },
            5 => match command & 0b11 {
                0 => ClientRequest::BlockUploadInitiate {
                    mux,
                    crc: command & 0x04 != 0,
                    blksize: frame[4],
                    pst: frame[5],
                },
                1 => ClientRequest::BlockUploadEnd,
                2 => ClientRequest::BlockUploadAck {
                    ackseq: frame[1],
                    blksize: frame[2],
                },
                _ => ClientRequest::BlockUploadStart,
            },
            6 => {
                if command & 0x01 == 0 {
                    ClientRequest::BlockDownloadInitiate {
                        mux,
                        crc: command & 0x04 != 0,
                        size: (command & 0x02 != 0)
                            .then(|| u32::from_le_bytes([frame[4], frame[5], frame[6], frame[7]])),
                    }
                } else {
                    ClientRequest::BlockDownloadEnd {
                        unused: (command >> 2) & 0b111,
                        crc: u16::from_le_bytes([frame[1], frame[2]]),
                    }
                }
            }
            _ => return Err(WireError::Command),
        })
    }

    /// The 8 bytes of this request.
    pub fn emit(&self) -> [u8; FRAME_LEN] {
        let mut frame = [0u8; FRAME_LEN];
        match *self {
            ClientRequest::InitiateDownload { mux, payload } => {
                let (bits, data) = payload.encode();
                frame[0] = 0x20 | bits;
                mux.write(&mut frame);
                frame[4..].copy_from_slice(&data);
            }
            ClientRequest::DownloadSegment { toggle, data, last } => {
                let (bits, bytes) = data.encode();
                frame[0] = toggle_bit(toggle) | bits | u8::from(last);
                frame[1..].copy_from_slice(&bytes);
            }
            ClientRequest::InitiateUpload { mux } => {
                frame[0] = 0x40;
                mux.write(&mut frame);
            }
            ClientRequest::UploadSegment { toggle } => frame[0] = 0x60 | toggle_bit(toggle),
            ClientRequest::Abort { mux, code } => return abort_frame(mux, code),
            ClientRequest::BlockUploadInitiate {
                mux,
                crc,
                blksize,
                pst,
            } => {
                frame[0] = 0xA0 | crc_bit(crc);
                mux.write(&mut frame);
                frame[4] = blksize;
                frame[5] = pst;
            }
            ClientRequest::BlockUploadStart => frame[0] = 0xA3,
            ClientRequest::BlockUploadAck { ackseq, blksize } => {
                frame[0] = 0xA2;
                frame[1] = ackseq;
                frame[2] = blksize;
            }
            ClientRequest::BlockUploadEnd => frame[0] = 0xA1,
            ClientRequest::BlockDownloadInitiate { mux, crc, size } => {
                frame[0] = 0xC0 | crc_bit(crc) | if size.is_some() { 0x02 } else { 0 };
                mux.write(&mut frame);
                frame[4..].copy_from_slice(&size.unwrap_or(0).to_le_bytes());
            }
            ClientRequest::BlockDownloadEnd { unused, crc } => {
                frame[0] = 0xC1 | ((unused & 0b111) << 2);
                frame[1..3].copy_from_slice(&crc.to_le_bytes());
            }
        }
        frame
    }
}

/// A message from an SDO server to a client.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ServerResponse {
    /// Initiate SDO download response (scs = 3).
    InitiateDownload {
        /// The entry being written.
        mux: Multiplexer,
    },
    /// Download SDO segment response (scs = 1).
    DownloadSegment {
        /// The toggle bit of the acknowledged segment.
        toggle: bool,
    },
    /// Initiate SDO upload response (scs = 2).
    InitiateUpload {
        /// The entry being read.
        mux: Multiplexer,
        /// Expedited data or the size of a segmented upload.
        payload: InitiatePayload,
    },
    /// Upload SDO segment response (scs = 0).
    UploadSegment {
        /// The toggle bit.
        toggle: bool,
        /// The segment's data.
        data: SegmentData,
        /// Whether no more segments follow (c).
        last: bool,
    },
    /// Abort SDO transfer (cs = 4).
    Abort {
        /// The entry of the aborted transfer.
        mux: Multiplexer,
        /// The abort code.
        code: u32,
    },
    /// Initiate SDO block download response (scs = 5, ss = 0).
    BlockDownloadInitiate {
        /// The entry being written.
        mux: Multiplexer,
        /// Whether the server supports CRC (sc).
        crc: bool,
        /// Segments per sub-block the server accepts.
        blksize: u8,
    },
    /// SDO block download response: the server acknowledges a sub-block (scs = 5, ss = 2).
    BlockDownloadAck {
        /// The sequence number of the last segment received in order.
        ackseq: u8,
        /// Segments per sub-block for the next sub-block.
        blksize: u8,
    },
    /// End SDO block download response (scs = 5, ss = 1).
    BlockDownloadEnd,
    /// Initiate SDO block upload response (scs = 6, ss = 0).
    BlockUploadInitiate {
        /// The entry being read.
        mux: Multiplexer,
        /// Whether the server supports CRC (sc).
        crc: bool,
        /// The size of the value, if indicated.
        size: Option<u32>,
    },
    /// End SDO block upload request (scs = 6, ss = 1).
    BlockUploadEnd {
        /// Bytes of the last segment that do not contain data (n).
        unused: u8,
        /// CRC of the whole value (0 when CRC is not in use).
        crc: u16,
    },
}

impl ServerResponse {
    /// Parses a response frame. Block-upload sub-block segments are not responses: parse them
    /// with [`BlockSegment::parse`].
    pub fn parse(bytes: &[u8]) -> Result<Self, WireError> {
        let frame: &[u8; FRAME_LEN] = bytes.try_into().map_err(|_| WireError::Length)?;
        let command = frame[0];
        let mux = Multiplexer::read(frame);
        Ok(match command >> 5 {
            0 => ServerResponse::UploadSegment {
                toggle: command & 0x10 != 0,
                data: SegmentData::decode(command, frame),
                last: command & 0x01 != 0,
            },
            1 => ServerResponse::DownloadSegment {
                toggle: command & 0x10 != 0,
            },
            2 => ServerResponse::InitiateUpload {
                mux,
                payload: InitiatePayload::decode(command, frame),
            },
            3 => ServerResponse::InitiateDownload { mux },
            4 => ServerResponse::Abort {
                mux,
                code: u32::from_le_bytes([frame[4], frame[5], frame[6], frame[7]]),
            },
            5 => match command & 0b11 {
                0 => ServerResponse::BlockDownloadInitiate {
                    mux,
                    crc: command & 0x04 != 0,
                    blksize: frame[4],
                },
                1 => ServerResponse::BlockDownloadEnd,
                2 => ServerResponse::BlockDownloadAck {
                    ackseq: frame[1],
                    blksize: frame[2],
                },
                _ => return Err(WireError::Command),
            },
            6 => {
                if command & 0x01 == 0 {
                    ServerResponse::BlockUploadInitiate {
                        mux,
                        crc: command & 0x04 != 0,
                        size: (command & 0x02 != 0)
                            .then(|| u32::from_le_bytes([frame[4], frame[5], frame[6], frame[7]])),
                    }
                } else {
                    ServerResponse::BlockUploadEnd {
                        unused: (command >> 2) & 0b111,
                        crc: u16::from_le_bytes([frame[1], frame[2]]),
                    }
                }
            }
            _ => return Err(WireError::Command),
        })
    }

    /// The 8 bytes of this response.
    pub fn emit(&self) -> [u8; FRAME_LEN] {
        let mut frame = [0u8; FRAME_LEN];
        match *self {
            ServerResponse::InitiateDownload { mux } => {
                frame[0] = 0x60;
                mux.write(&mut frame);
            }
            ServerResponse::DownloadSegment { toggle } => frame[0] = 0x20 | toggle_bit(toggle),
            ServerResponse::InitiateUpload { mux, payload } => {
                let (bits, data) = payload.encode();
                frame[0] = 0x40 | bits;
                mux.write(&mut frame);
                frame[4..].copy_from_slice(&data);
            }
            ServerResponse::UploadSegment { toggle, data, last } => {
                let (bits, bytes) = data.encode();
                frame[0] = toggle_bit(toggle) | bits | u8::from(last);
                frame[1..].copy_from_slice(&bytes);
            }
            ServerResponse::Abort { mux, code } => return abort_frame(mux, code),
            ServerResponse::BlockDownloadInitiate { mux, crc, blksize } => {
                frame[0] = 0xA0 | crc_bit(crc);
                mux.write(&mut frame);
                frame[4] = blksize;
            }
            ServerResponse::BlockDownloadAck { ackseq, blksize } => {
                frame[0] = 0xA2;
                frame[1] = ackseq;
                frame[2] = blksize;
            }
            ServerResponse::BlockDownloadEnd => frame[0] = 0xA1,
            ServerResponse::BlockUploadInitiate { mux, crc, size } => {
                frame[0] = 0xC0 | crc_bit(crc) | if size.is_some() { 0x02 } else { 0 };
                mux.write(&mut frame);
                frame[4..].copy_from_slice(&size.unwrap_or(0).to_le_bytes());
            }
            ServerResponse::BlockUploadEnd { unused, crc } => {
                frame[0] = 0xC1 | ((unused & 0b111) << 2);
                frame[1..3].copy_from_slice(&crc.to_le_bytes());
            }
        }
        frame
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

const fn toggle_bit(toggle: bool) -> u8 {
    if toggle {
        0x10
    } else {
        0
    }
}

const fn crc_bit(crc: bool) -> u8 {
    if crc {
        0x04
    } else {
        0
    }
}

/// The abort frame for `mux` and `code` (the same layout in both directions).
pub fn abort_frame(mux: Multiplexer, code: u32) -> [u8; FRAME_LEN] {
    let mut frame = [0u8; FRAME_LEN];
    frame[0] = 0x80;
    mux.write(&mut frame);
    frame[4..].copy_from_slice(&code.to_le_bytes());
    frame
}

#[cfg(test)]
mod tests {
    use super::*;

    const MUX_1801_03: Multiplexer = Multiplexer::new(0x1801, 0x03);

    fn round_trip_request(request: ClientRequest, bytes: [u8; 8]) {
        assert_eq!(request.emit(), bytes, "emit {request:?}");
        assert_eq!(
            ClientRequest::parse(&bytes),
            Ok(request),
            "parse {bytes:02X?}"
        );
    }

    fn round_trip_response(response: ServerResponse, bytes: [u8; 8]) {
        assert_eq!(response.emit(), bytes, "emit {response:?}");
        assert_eq!(
            ServerResponse::parse(&bytes),
            Ok(response),
            "parse {bytes:02X?}"
        );
    }

    fn segment(data: &[u8]) -> SegmentData {
        SegmentData::new(data).unwrap()
    }

    #[test]
    fn expedited_download_of_two_bytes_matches_manual() {
        round_trip_request(
            ClientRequest::InitiateDownload {
                mux: MUX_1801_03,
                payload: InitiatePayload::Expedited {
                    data: [0xE8, 0x03, 0, 0],
                    len: 2,
                },
            },
            [0x2B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00],
        );
    }

    #[test]
    fn expedited_download_lengths_encode_n() {
        let cases: [(u8, u8, [u8; 4]); 4] = [
            (1, 0x2F, [1, 0, 0, 0]),
            (2, 0x2B, [1, 2, 0, 0]),
            (3, 0x27, [1, 2, 3, 0]),
            (4, 0x23, [1, 2, 3, 4]),
        ];
        for (len, command, data) in cases {
            round_trip_request(
                ClientRequest::InitiateDownload {
                    mux: Multiplexer::new(0x2000, 0),
                    payload: InitiatePayload::Expedited { data, len },
                },
                [
                    command, 0x00, 0x20, 0x00, data[0], data[1], data[2], data[3],
                ],
            );
        }
    }

    #[test]
    fn expedited_emit_zeroes_bytes_past_the_length() {
        let response = ServerResponse::InitiateUpload {
            mux: Multiplexer::new(0x2004, 0),
            payload: InitiatePayload::Expedited {
                data: [0xFE, 0xAA, 0xBB, 0xCC],
                len: 1,
            },
        };
        assert_eq!(response.emit(), [0x4F, 0x04, 0x20, 0x00, 0xFE, 0, 0, 0]);
    }

    #[test]
    fn expedited_download_without_size() {
        round_trip_request(
            ClientRequest::InitiateDownload {
                mux: Multiplexer::new(0x1017, 0),
                payload: InitiatePayload::ExpeditedUnsized {
                    data: [0xE8, 0x03, 0, 0],
                },
            },
            [0x22, 0x17, 0x10, 0x00, 0xE8, 0x03, 0x00, 0x00],
        );
    }

    #[test]
    fn segmented_download_initiate_with_and_without_size() {
        round_trip_request(
            ClientRequest::InitiateDownload {
                mux: Multiplexer::new(0x2006, 0),
                payload: InitiatePayload::Sized(300),
            },
            [0x21, 0x06, 0x20, 0x00, 0x2C, 0x01, 0x00, 0x00],
        );
        round_trip_request(
            ClientRequest::InitiateDownload {
                mux: Multiplexer::new(0x2006, 0),
                payload: InitiatePayload::Unsized,
            },
            [0x20, 0x06, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00],
        );
    }

    #[test]
    fn download_segments_carry_toggle_n_and_c() {
        round_trip_request(
            ClientRequest::DownloadSegment {
                toggle: false,
                data: segment(b"ABCDEFG"),
                last: false,
            },
            [0x00, b'A', b'B', b'C', b'D', b'E', b'F', b'G'],
        );
        round_trip_request(
            ClientRequest::DownloadSegment {
                toggle: true,
                data: segment(b"HI"),
                last: true,
            },
            [0x1B, b'H', b'I', 0, 0, 0, 0, 0],
        );
        round_trip_request(
            ClientRequest::DownloadSegment {
                toggle: false,
                data: segment(b""),
                last: true,
            },
            [0x0F, 0, 0, 0, 0, 0, 0, 0],
        );
    }

    #[test]
    fn upload_requests() {
        round_trip_request(
            ClientRequest::InitiateUpload {
                mux: Multiplexer::new(0x2002, 3),
            },
            [0x40, 0x02, 0x20, 0x03, 0, 0, 0, 0],
        );
        round_trip_request(
            ClientRequest::UploadSegment { toggle: false },
            [0x60, 0, 0, 0, 0, 0, 0, 0],
        );
        round_trip_request(
            ClientRequest::UploadSegment { toggle: true },
            [0x70, 0, 0, 0, 0, 0, 0, 0],
        );
    }

    #[test]
    fn abort_in_both_directions_matches_manual() {
        let mux = Multiplexer::new(0x6000, 0);
        round_trip_request(
            ClientRequest::Abort {
                mux,
                code: 0x0602_0000,
            },
            [0x80, 0x00, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06],
        );
        round_trip_response(
            ServerResponse::Abort {
                mux,
                code: 0x0602_0000,
            },
            [0x80, 0x00, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06],
        );
    }

    #[test]
    fn block_upload_requests() {
        round_trip_request(
            ClientRequest::BlockUploadInitiate {
                mux: Multiplexer::new(0x2006, 0),
                crc: true,
                blksize: 127,
                pst: 4,
            },
            [0xA4, 0x06, 0x20, 0x00, 0x7F, 0x04, 0, 0],
        );
        round_trip_request(
            ClientRequest::BlockUploadInitiate {
                mux: Multiplexer::new(0x2006, 0),
                crc: false,
                blksize: 10,
                pst: 0,
            },
            [0xA0, 0x06, 0x20, 0x00, 0x0A, 0x00, 0, 0],
        );
        round_trip_request(ClientRequest::BlockUploadStart, [0xA3, 0, 0, 0, 0, 0, 0, 0]);
        round_trip_request(
            ClientRequest::BlockUploadAck {
                ackseq: 5,
                blksize: 20,
            },
            [0xA2, 0x05, 0x14, 0, 0, 0, 0, 0],
        );
        round_trip_request(ClientRequest::BlockUploadEnd, [0xA1, 0, 0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn block_download_requests() {
        round_trip_request(
            ClientRequest::BlockDownloadInitiate {
                mux: Multiplexer::new(0x2006, 0),
                crc: true,
                size: Some(300),
            },
            [0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0],
        );
        round_trip_request(
            ClientRequest::BlockDownloadInitiate {
                mux: Multiplexer::new(0x2006, 0),
                crc: false,
                size: None,
            },
            [0xC0, 0x06, 0x20, 0x00, 0, 0, 0, 0],
        );
        round_trip_request(
            ClientRequest::BlockDownloadEnd {
                unused: 1,
                crc: 0x31C3,
            },
            [0xC5, 0xC3, 0x31, 0, 0, 0, 0, 0],
        );
    }

    #[test]
    fn reserved_bits_are_ignored_on_parse() {
        assert_eq!(
            ClientRequest::parse(&[0x5F, 0x02, 0x20, 0x03, 0xFF, 0xFF, 0xFF, 0xFF]),
            Ok(ClientRequest::InitiateUpload {
                mux: Multiplexer::new(0x2002, 3)
            })
        );
        assert_eq!(
            ClientRequest::parse(&[0x7F, 1, 2, 3, 4, 5, 6, 7]),
            Ok(ClientRequest::UploadSegment { toggle: true })
        );
    }

    #[test]
    fn unknown_command_and_wrong_length_are_errors() {
        assert_eq!(
            ClientRequest::parse(&[0xE0, 0, 0, 0, 0, 0, 0, 0]),
            Err(WireError::Command)
        );
        assert_eq!(
            ClientRequest::parse(&[0x40, 0, 0x10, 0]),
            Err(WireError::Length)
        );
        assert_eq!(ClientRequest::parse(&[]), Err(WireError::Length));
        assert_eq!(
            ServerResponse::parse(&[0xE0, 0, 0, 0, 0, 0, 0, 0]),
            Err(WireError::Command)
        );
        assert_eq!(
            ServerResponse::parse(&[0xA3, 0, 0, 0, 0, 0, 0, 0]),
            Err(WireError::Command)
        );
        assert_eq!(ServerResponse::parse(&[0x60; 9]), Err(WireError::Length));
        assert_eq!(BlockSegment::parse(&[0x01; 7]), Err(WireError::Length));
    }

    #[test]
    fn download_responses_match_manual() {
        round_trip_response(
            ServerResponse::InitiateDownload { mux: MUX_1801_03 },
            [0x60, 0x01, 0x18, 0x03, 0, 0, 0, 0],
        );
        round_trip_response(
            ServerResponse::DownloadSegment { toggle: false },
            [0x20, 0, 0, 0, 0, 0, 0, 0],
        );
        round_trip_response(
            ServerResponse::DownloadSegment { toggle: true },
            [0x30, 0, 0, 0, 0, 0, 0, 0],
        );
    }

    #[test]
    fn upload_responses_match_manual() {
        round_trip_response(
            ServerResponse::InitiateUpload {
                mux: MUX_1801_03,
                payload: InitiatePayload::Expedited {
                    data: [0xE8, 0x03, 0, 0],
                    len: 2,
                },
            },
            [0x4B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00],
        );
        round_trip_response(
            ServerResponse::InitiateUpload {
                mux: Multiplexer::new(0x1000, 0),
                payload: InitiatePayload::Expedited {
                    data: [0x92, 0x01, 0x02, 0x00],
                    len: 4,
                },
            },
            [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00],
        );
        round_trip_response(
            ServerResponse::InitiateUpload {
                mux: Multiplexer::new(0x1008, 0),
                payload: InitiatePayload::Sized(20),
            },
            [0x41, 0x08, 0x10, 0x00, 0x14, 0, 0, 0],
        );
        round_trip_response(
            ServerResponse::UploadSegment {
                toggle: true,
                data: segment(b"xyz"),
                last: true,
            },
            [0x19, b'x', b'y', b'z', 0, 0, 0, 0],
        );
        round_trip_response(
            ServerResponse::UploadSegment {
                toggle: false,
                data: segment(b"1234567"),
                last: false,
            },
            [0x00, b'1', b'2', b'3', b'4', b'5', b'6', b'7'],
        );
    }

    #[test]
    fn block_download_responses() {
        round_trip_response(
            ServerResponse::BlockDownloadInitiate {
                mux: Multiplexer::new(0x2006, 0),
                crc: true,
                blksize: 127,
            },
            [0xA4, 0x06, 0x20, 0x00, 0x7F, 0, 0, 0],
        );
        round_trip_response(
            ServerResponse::BlockDownloadAck {
                ackseq: 43,
                blksize: 127,
            },
            [0xA2, 0x2B, 0x7F, 0, 0, 0, 0, 0],
        );
        round_trip_response(
            ServerResponse::BlockDownloadEnd,
            [0xA1, 0, 0, 0, 0, 0, 0, 0],
        );
    }

    #[test]
    fn block_upload_responses() {
        round_trip_response(
            ServerResponse::BlockUploadInitiate {
                mux: Multiplexer::new(0x2006, 0),
                crc: true,
                size: Some(300),
            },
            [0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0],
        );
        round_trip_response(
            ServerResponse::BlockUploadEnd {
                unused: 6,
                crc: 0xBEEF,
            },
            [0xD9, 0xEF, 0xBE, 0, 0, 0, 0, 0],
        );
    }

    #[test]
    fn block_segments() {
        let segment = BlockSegment {
            seqno: 3,
            last: false,
            data: *b"segment",
        };
        let bytes = [0x03, b's', b'e', b'g', b'm', b'e', b'n', b't'];
        assert_eq!(segment.emit(), bytes);
        assert_eq!(BlockSegment::parse(&bytes), Ok(segment));
        let last = BlockSegment {
            seqno: 127,
            last: true,
            data: [9, 0, 0, 0, 0, 0, 0],
        };
        assert_eq!(last.emit(), [0xFF, 9, 0, 0, 0, 0, 0, 0]);
        assert_eq!(BlockSegment::parse(&last.emit()), Ok(last));
    }

    proptest::proptest! {
        #[test]
        fn any_parsed_request_emits_to_a_frame_that_parses_the_same(bytes in proptest::array::uniform8(0u8..)) {
            if let Ok(request) = ClientRequest::parse(&bytes) {
                proptest::prop_assert_eq!(ClientRequest::parse(&request.emit()), Ok(request));
            }
        }

        #[test]
        fn any_parsed_response_emits_to_a_frame_that_parses_the_same(bytes in proptest::array::uniform8(0u8..)) {
            if let Ok(response) = ServerResponse::parse(&bytes) {
                proptest::prop_assert_eq!(ServerResponse::parse(&response.emit()), Ok(response));
            }
        }

        #[test]
        fn block_segments_round_trip_exactly(bytes in proptest::array::uniform8(0u8..)) {
            let segment = BlockSegment::parse(&bytes).unwrap();
            proptest::prop_assert_eq!(segment.emit(), bytes);
        }
    }

    #[test]
    fn segment_data_rejects_more_than_seven_bytes() {
        assert_eq!(SegmentData::new(&[0; 8]), None);
        assert_eq!(SegmentData::new(&[1, 2]).unwrap().as_slice(), &[1, 2]);
    }
}
