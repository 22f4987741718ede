//! SDO frame layouts (CiA 301 §7.2.4.3): initiate, segment and block messages, and aborts.
//!
//! [`ClientRequest`] and [`ServerResponse`] are the typed forms of every SDO message, each with
//! `parse` and `emit`, built on the command byte's fields in [`command`]. A device's SDO server
//! reads the few fields it needs from there and writes its responses with [`frame`] and
//! [`mux_frame`] instead: the typed messages' general parser and encoder cost some 800 bytes of
//! Cortex-M flash. Block-transfer sub-block segments carry no command specifier (their first
//! byte is a sequence number), so they have their own type, [`BlockSegment`], and the receiver
//! decides by its state which parser applies. Every SDO frame is 8 bytes long; reserved bits are
//! emitted as zero and ignored on parse.

use command::{ccs, scs};

/// The function code of the default SDO server's requests: 600h + node-ID (1200h sub 01h).
pub const SDO_REQUEST_BASE: u16 = 0x600;
/// The function code of the default SDO server's responses: 580h + node-ID (1200h sub 02h).
pub const SDO_RESPONSE_BASE: u16 = 0x580;

/// The length of every SDO frame's data (CiA 301 requires DLC 8).
pub const FRAME_LEN: usize = 8;
/// Data bytes carried by one segment (normal or block transfer).
pub const SEGMENT_DATA_LEN: usize = 7;
/// The largest number of segments in a block-transfer sub-block.
pub const MAX_BLOCK_SIZE: u8 = 127;

/// The command byte, field by field (CiA 301 §7.2.4.3): the specifier in bits 7..5, then the
/// message's own bits.
pub mod command {
    /// Client command specifiers (ccs).
    pub mod ccs {
        /// Download SDO segment.
        pub const DOWNLOAD_SEGMENT: u8 = 0;
        /// Initiate SDO download.
        pub const INITIATE_DOWNLOAD: u8 = 1;
        /// Initiate SDO upload.
        pub const INITIATE_UPLOAD: u8 = 2;
        /// Upload SDO segment.
        pub const UPLOAD_SEGMENT: u8 = 3;
        /// Abort SDO transfer (the same in both directions).
        pub const ABORT: u8 = 4;
        /// SDO block upload (sub-command in bits 1..0).
        pub const BLOCK_UPLOAD: u8 = 5;
        /// SDO block download (sub-command in bit 0).
        pub const BLOCK_DOWNLOAD: u8 = 6;
    }

    /// Server command specifiers (scs).
    pub mod scs {
        /// Upload SDO segment.
        pub const UPLOAD_SEGMENT: u8 = 0;
        /// Download SDO segment.
        pub const DOWNLOAD_SEGMENT: u8 = 1;
        /// Initiate SDO upload.
        pub const INITIATE_UPLOAD: u8 = 2;
        /// Initiate SDO download.
        pub const INITIATE_DOWNLOAD: u8 = 3;
        /// Abort SDO transfer (the same in both directions).
        pub const ABORT: u8 = 4;
        /// SDO block download (sub-command in bits 1..0).
        pub const BLOCK_DOWNLOAD: u8 = 5;
        /// SDO block upload (sub-command in bit 0).
        pub const BLOCK_UPLOAD: u8 = 6;
    }

    /// The command specifier (bits 7..5).
    pub const fn specifier(command: u8) -> u8 {
        command >> 5
    }

    /// A command byte with `specifier` and the other bits zero.
    pub const fn of(specifier: u8) -> u8 {
        specifier << 5
    }

    /// The toggle bit of a segment message (t, bit 4).
    pub const fn toggle(command: u8) -> bool {
        command & 0x10 != 0
    }

    /// The toggle bit, in place.
    pub const fn toggle_bit(toggle: bool) -> u8 {
        if toggle {
            0x10
        } else {
            0
        }
    }

    /// How many of a segment's 7 bytes carry no data (n, bits 3..1).
    pub const fn segment_unused(command: u8) -> u8 {
        (command >> 1) & 0b111
    }

    /// Whether no segment follows (c, bit 0 of a segment message).
    pub const fn last(command: u8) -> bool {
        command & 0x01 != 0
    }

    /// The bits 4..0 of a segment message: toggle, unused bytes, last.
    pub const fn segment_bits(toggle: bool, unused: u8, last: bool) -> u8 {
        toggle_bit(toggle) | (unused & 0b111) << 1 | last as u8
    }

    /// Whether an initiate message is expedited (e, bit 1).
    pub const fn expedited(command: u8) -> bool {
        command & 0b10 != 0
    }

    /// Whether an initiate message indicates the size (s, bit 0).
    pub const fn size_indicated(command: u8) -> bool {
        command & SIZE_INDICATED != 0
    }

    /// The size-indicated bit (s) of a segmented initiate message, in place.
    pub const SIZE_INDICATED: u8 = 0b01;

    /// The size-indicated bit (s) of a block download request or block upload response, in
    /// place.
    pub const BLOCK_SIZE_INDICATED: u8 = 0b10;

    /// How many of an expedited message's 4 data bytes are data, when the size is indicated
    /// (4 - n, n in bits 3..2).
    pub const fn expedited_len(command: u8) -> u8 {
        4 - ((command >> 2) & 0b11)
    }

    /// The bits 3..0 of an expedited initiate message with `len` (1..=4) bytes indicated.
    pub const fn expedited_bits(len: u8) -> u8 {
        (4 - len) << 2 | 0b11
    }

    /// Whether a block initiate message announces CRC support (cc / sc, bit 2).
    pub const fn crc(command: u8) -> bool {
        command & 0x04 != 0
    }

    /// The CRC-support bit, in place.
    pub const fn crc_bit(crc: bool) -> u8 {
        if crc {
            0x04
        } else {
            0
        }
    }

    /// The sub-command of a block message (cs / ss, bits 1..0; only bit 0 in a block download
    /// request and a block upload response, whose bit 1 is [`block_size_indicated`]).
    pub const fn block_subcommand(command: u8) -> u8 {
        command & 0b11
    }

    /// Whether a block download request or block upload response indicates the size (s,
    /// bit 1).
    pub const fn block_size_indicated(command: u8) -> bool {
        command & BLOCK_SIZE_INDICATED != 0
    }

    /// How many bytes of a block transfer's last segment carry no data (n, bits 4..2 of the
    /// end message).
    pub const fn block_end_unused(command: u8) -> u8 {
        (command >> 2) & 0b111
    }

    /// The bits 4..2 of a block transfer's end message: `unused` bytes of its last segment.
    pub const fn block_end_bits(unused: u8) -> u8 {
        (unused & 0b111) << 2
    }
}

/// A frame of `command` and the 7 bytes after it.
pub const fn frame(command: u8, rest: [u8; SEGMENT_DATA_LEN]) -> [u8; FRAME_LEN] {
    let [a, b, c, d, e, f, g] = rest;
    [command, a, b, c, d, e, f, g]
}

/// A frame of `command`, the multiplexer and a 32-bit value in bytes 4..8: the initiate
/// messages and aborts.
pub const fn mux_frame(command: u8, mux: Multiplexer, value: u32) -> [u8; FRAME_LEN] {
    let [index_lo, index_hi] = mux.index.to_le_bytes();
    let [v0, v1, v2, v3] = value.to_le_bytes();
    [command, index_lo, index_hi, mux.sub, v0, v1, v2, v3]
}

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

    /// The multiplexer in bytes 1..4 of `frame`.
    pub const fn read(frame: &[u8; FRAME_LEN]) -> Self {
        Multiplexer {
            index: u16::from_le_bytes([frame[1], frame[2]]),
            sub: frame[3],
        }
    }
}

/// A view over the 8 bytes of an SDO frame, one accessor per field (the smoltcp manner): what a
/// field means depends on the message, which the command specifier and the receiver's state
/// say. [`ClientRequest::parse`], [`ServerResponse::parse`] and the SDO server read frames
/// through it; [`frame`], [`mux_frame`] and the `Repr`s' `emit` write them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame<'a>(&'a [u8; FRAME_LEN]);

impl<'a> Frame<'a> {
    /// A view over `bytes`.
    pub const fn new(bytes: &'a [u8; FRAME_LEN]) -> Self {
        Frame(bytes)
    }

    /// A view over `bytes`, if they are exactly 8 (CiA 301 requires DLC 8).
    pub fn new_checked(bytes: &'a [u8]) -> Result<Self, WireError> {
        bytes.try_into().map(Frame).map_err(|_| WireError::Length)
    }

    /// The command byte (byte 0).
    pub const fn command(&self) -> u8 {
        self.0[0]
    }

    /// The command specifier (bits 7..5 of byte 0).
    pub const fn specifier(&self) -> u8 {
        command::specifier(self.command())
    }

    /// The toggle bit of a segment message.
    pub const fn toggle(&self) -> bool {
        command::toggle(self.command())
    }

    /// Whether a segment message is the last (c).
    pub const fn last(&self) -> bool {
        command::last(self.command())
    }

    /// The data bytes of a normal-transfer segment (bytes 1..8 less the n unused).
    pub fn segment_data(&self) -> &'a [u8] {
        let unused = usize::from(command::segment_unused(self.command()));
        &self.0[1..FRAME_LEN - unused]
    }

    /// Whether an initiate message is expedited (e).
    pub const fn expedited(&self) -> bool {
        command::expedited(self.command())
    }

    /// Whether an initiate message indicates the size (s).
    pub const fn size_indicated(&self) -> bool {
        command::size_indicated(self.command())
    }

    /// How many of an expedited message's 4 data bytes are data, when the size is indicated.
    pub const fn expedited_len(&self) -> u8 {
        command::expedited_len(self.command())
    }

    /// The (index, sub-index) of an initiate message or an abort (bytes 1..4).
    pub const fn mux(&self) -> Multiplexer {
        Multiplexer::read(self.0)
    }

    /// Bytes 4..8 of an initiate message or an abort: expedited data, a size, an abort code.
    pub const fn data(&self) -> [u8; 4] {
        [self.0[4], self.0[5], self.0[6], self.0[7]]
    }

    /// Bytes 4..8 as a little-endian number.
    pub const fn value(&self) -> u32 {
        u32::from_le_bytes(self.data())
    }

    /// Whether a block initiate message announces CRC support (cc / sc).
    pub const fn crc_supported(&self) -> bool {
        command::crc(self.command())
    }

    /// The sub-command of a block message (cs / ss).
    pub const fn block_subcommand(&self) -> u8 {
        command::block_subcommand(self.command())
    }

    /// Whether a block download request or block upload response indicates the size.
    pub const fn block_size_indicated(&self) -> bool {
        command::block_size_indicated(self.command())
    }

    /// How many bytes of a block transfer's last segment carry no data (n of an end message).
    pub const fn block_end_unused(&self) -> u8 {
        command::block_end_unused(self.command())
    }

    /// The CRC of a block end message (bytes 1..3).
    pub const fn block_crc(&self) -> u16 {
        u16::from_le_bytes([self.0[1], self.0[2]])
    }

    /// The block size of an initiate block upload request or initiate block download
    /// response (byte 4).
    pub const fn initiate_block_size(&self) -> u8 {
        self.0[4]
    }

    /// The protocol switch threshold of an initiate block upload request (byte 5).
    pub const fn protocol_switch_threshold(&self) -> u8 {
        self.0[5]
    }

    /// The sequence number acknowledged by a sub-block response (byte 1).
    pub const fn ackseq(&self) -> u8 {
        self.0[1]
    }

    /// The block size for the next sub-block in a sub-block response (byte 2).
    pub const fn ack_block_size(&self) -> u8 {
        self.0[2]
    }

    /// The bytes of the frame.
    pub const fn as_bytes(&self) -> &'a [u8; FRAME_LEN] {
        self.0
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
                (command::expedited_bits(len), bytes)
            }
            InitiatePayload::ExpeditedUnsized { data } => (0b10, data),
            InitiatePayload::Sized(size) => (command::SIZE_INDICATED, size.to_le_bytes()),
            InitiatePayload::Unsized => (0b00, [0; 4]),
        }
    }

    fn decode(frame: Frame<'_>) -> Self {
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
    fn encode(&self, toggle: bool, last: bool) -> [u8; FRAME_LEN] {
        let unused = SEGMENT_DATA_LEN as u8 - self.len;
        frame(command::segment_bits(toggle, unused, last), self.bytes)
    }

    fn decode(frame: Frame<'_>) -> Self {
        let data = frame.segment_data();
        let mut bytes = [0u8; SEGMENT_DATA_LEN];
        bytes[..data.len()].copy_from_slice(data);
        SegmentData {
            bytes,
            len: data.len() as u8,
        }
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
        let frame = Frame::new_checked(bytes)?;
        let mux = frame.mux();
        Ok(match frame.specifier() {
            ccs::DOWNLOAD_SEGMENT => ClientRequest::DownloadSegment {
                toggle: frame.toggle(),
                data: SegmentData::decode(frame),
                last: frame.last(),
            },
            ccs::INITIATE_DOWNLOAD => ClientRequest::InitiateDownload {
                mux,
                payload: InitiatePayload::decode(frame),
            },
            ccs::INITIATE_UPLOAD => ClientRequest::InitiateUpload { mux },
            ccs::UPLOAD_SEGMENT => ClientRequest::UploadSegment {
                toggle: frame.toggle(),
            },
            ccs::ABORT => ClientRequest::Abort {
                mux,
                code: frame.value(),
            },
            ccs::BLOCK_UPLOAD => match frame.block_subcommand() {
                0 => ClientRequest::BlockUploadInitiate {
                    mux,
                    crc: frame.crc_supported(),
                    blksize: frame.initiate_block_size(),
                    pst: frame.protocol_switch_threshold(),
                },
                1 => ClientRequest::BlockUploadEnd,
                2 => ClientRequest::BlockUploadAck {
                    ackseq: frame.ackseq(),
                    blksize: frame.ack_block_size(),
                },
                _ => ClientRequest::BlockUploadStart,
            },
            ccs::BLOCK_DOWNLOAD => {
                if frame.block_subcommand() & 0b01 == 0 {
                    ClientRequest::BlockDownloadInitiate {
                        mux,
                        crc: frame.crc_supported(),
                        size: frame.block_size_indicated().then_some(frame.value()),
                    }
                } else {
                    ClientRequest::BlockDownloadEnd {
                        unused: frame.block_end_unused(),
                        crc: frame.block_crc(),
                    }
                }
            }
            _ => return Err(WireError::Command),
        })
    }

    /// The 8 bytes of this request.
    pub fn emit(&self) -> [u8; FRAME_LEN] {
        use command::{block_end_bits, crc_bit, of, toggle_bit};
        match *self {
            ClientRequest::InitiateDownload { mux, payload } => {
                let (bits, data) = payload.encode();
                let value = u32::from_le_bytes(data);
                mux_frame(of(ccs::INITIATE_DOWNLOAD) | bits, mux, value)
            }
            ClientRequest::DownloadSegment { toggle, data, last } => data.encode(toggle, last),
            ClientRequest::InitiateUpload { mux } => mux_frame(of(ccs::INITIATE_UPLOAD), mux, 0),
            ClientRequest::UploadSegment { toggle } => {
                frame(of(ccs::UPLOAD_SEGMENT) | toggle_bit(toggle), [0; 7])
            }
            ClientRequest::Abort { mux, code } => abort_frame(mux, code),
            ClientRequest::BlockUploadInitiate {
                mux,
                crc,
                blksize,
                pst,
            } => {
                let value = u32::from_le_bytes([blksize, pst, 0, 0]);
                mux_frame(of(ccs::BLOCK_UPLOAD) | crc_bit(crc), mux, value)
            }
            ClientRequest::BlockUploadStart => frame(of(ccs::BLOCK_UPLOAD) | 3, [0; 7]),
            ClientRequest::BlockUploadAck { ackseq, blksize } => {
                frame(of(ccs::BLOCK_UPLOAD) | 2, [ackseq, blksize, 0, 0, 0, 0, 0])
            }
            ClientRequest::BlockUploadEnd => frame(of(ccs::BLOCK_UPLOAD) | 1, [0; 7]),
            ClientRequest::BlockDownloadInitiate { mux, crc, size } => {
                let size_bit = if size.is_some() {
                    command::BLOCK_SIZE_INDICATED
                } else {
                    0
                };
                let command = of(ccs::BLOCK_DOWNLOAD) | crc_bit(crc) | size_bit;
                mux_frame(command, mux, size.unwrap_or(0))
            }
            ClientRequest::BlockDownloadEnd { unused, crc } => {
                let [lo, hi] = crc.to_le_bytes();
                let command = of(ccs::BLOCK_DOWNLOAD) | block_end_bits(unused) | 1;
                frame(command, [lo, hi, 0, 0, 0, 0, 0])
            }
        }
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
        let frame = Frame::new_checked(bytes)?;
        let mux = frame.mux();
        Ok(match frame.specifier() {
            scs::UPLOAD_SEGMENT => ServerResponse::UploadSegment {
                toggle: frame.toggle(),
                data: SegmentData::decode(frame),
                last: frame.last(),
            },
            scs::DOWNLOAD_SEGMENT => ServerResponse::DownloadSegment {
                toggle: frame.toggle(),
            },
            scs::INITIATE_UPLOAD => ServerResponse::InitiateUpload {
                mux,
                payload: InitiatePayload::decode(frame),
            },
            scs::INITIATE_DOWNLOAD => ServerResponse::InitiateDownload { mux },
            scs::ABORT => ServerResponse::Abort {
                mux,
                code: frame.value(),
            },
            scs::BLOCK_DOWNLOAD => match frame.block_subcommand() {
                0 => ServerResponse::BlockDownloadInitiate {
                    mux,
                    crc: frame.crc_supported(),
                    blksize: frame.initiate_block_size(),
                },
                1 => ServerResponse::BlockDownloadEnd,
                2 => ServerResponse::BlockDownloadAck {
                    ackseq: frame.ackseq(),
                    blksize: frame.ack_block_size(),
                },
                _ => return Err(WireError::Command),
            },
            scs::BLOCK_UPLOAD => {
                if frame.block_subcommand() & 0b01 == 0 {
                    ServerResponse::BlockUploadInitiate {
                        mux,
                        crc: frame.crc_supported(),
                        size: frame.block_size_indicated().then_some(frame.value()),
                    }
                } else {
                    ServerResponse::BlockUploadEnd {
                        unused: frame.block_end_unused(),
                        crc: frame.block_crc(),
                    }
                }
            }
            _ => return Err(WireError::Command),
        })
    }

    /// The 8 bytes of this response.
    pub fn emit(&self) -> [u8; FRAME_LEN] {
        use command::{block_end_bits, crc_bit, of, toggle_bit};
        match *self {
            ServerResponse::InitiateDownload { mux } => {
                mux_frame(of(scs::INITIATE_DOWNLOAD), mux, 0)
            }
            ServerResponse::DownloadSegment { toggle } => {
                frame(of(scs::DOWNLOAD_SEGMENT) | toggle_bit(toggle), [0; 7])
            }
            ServerResponse::InitiateUpload { mux, payload } => {
                let (bits, data) = payload.encode();
                let value = u32::from_le_bytes(data);
                mux_frame(of(scs::INITIATE_UPLOAD) | bits, mux, value)
            }
            ServerResponse::UploadSegment { toggle, data, last } => data.encode(toggle, last),
            ServerResponse::Abort { mux, code } => abort_frame(mux, code),
            ServerResponse::BlockDownloadInitiate { mux, crc, blksize } => {
                let command = of(scs::BLOCK_DOWNLOAD) | crc_bit(crc);
                mux_frame(command, mux, u32::from(blksize))
            }
            ServerResponse::BlockDownloadAck { ackseq, blksize } => frame(
                of(scs::BLOCK_DOWNLOAD) | 2,
                [ackseq, blksize, 0, 0, 0, 0, 0],
            ),
            ServerResponse::BlockDownloadEnd => frame(of(scs::BLOCK_DOWNLOAD) | 1, [0; 7]),
            ServerResponse::BlockUploadInitiate { mux, crc, size } => {
                let size_bit = if size.is_some() {
                    command::BLOCK_SIZE_INDICATED
                } else {
                    0
                };
                let command = of(scs::BLOCK_UPLOAD) | crc_bit(crc) | size_bit;
                mux_frame(command, mux, size.unwrap_or(0))
            }
            ServerResponse::BlockUploadEnd { unused, crc } => {
                let [lo, hi] = crc.to_le_bytes();
                let command = of(scs::BLOCK_UPLOAD) | block_end_bits(unused) | 1;
                frame(command, [lo, hi, 0, 0, 0, 0, 0])
            }
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

/// The abort frame for `mux` and `code` (the same layout in both directions).
pub const fn abort_frame(mux: Multiplexer, code: u32) -> [u8; FRAME_LEN] {
    mux_frame(command::of(ccs::ABORT), mux, code)
}

/// What an abort code means (CiA 301 table 22), or `None` for a code it does not define.
pub const fn abort_meaning(code: u32) -> Option<&'static str> {
    Some(match code {
        0x0503_0000 => "toggle bit not alternated",
        0x0504_0000 => "SDO protocol timed out",
        0x0504_0001 => "client/server command specifier not valid or unknown",
        0x0504_0002 => "invalid block size",
        0x0504_0003 => "invalid sequence number",
        0x0504_0004 => "CRC error",
        0x0504_0005 => "out of memory",
        0x0601_0000 => "unsupported access to an object",
        0x0601_0001 => "attempt to read a write-only object",
        0x0601_0002 => "attempt to write a read-only object",
        0x0602_0000 => "object does not exist in the object dictionary",
        0x0604_0041 => "object cannot be mapped to the PDO",
        0x0604_0042 => "the number and length of the objects to be mapped would exceed the PDO length",
        0x0604_0043 => "general parameter incompatibility",
        0x0604_0047 => "general internal incompatibility in the device",
        0x0606_0000 => "access failed due to a hardware error",
        0x0607_0010 => "data type does not match, length of service parameter does not match",
        0x0607_0012 => "data type does not match, length of service parameter too high",
        0x0607_0013 => "data type does not match, length of service parameter too low",
        0x0609_0011 => "sub-index does not exist",
        0x0609_0030 => "invalid value for parameter",
        0x0609_0031 => "value of parameter written too high",
        0x0609_0032 => "value of parameter written too low",
        0x0609_0036 => "maximum value is less than minimum value",
        0x060A_0023 => "resource not available: SDO connection",
        0x0800_0000 => "general error",
        0x0800_0020 => "data cannot be transferred or stored to the application",
        0x0800_0021 => "data cannot be transferred or stored to the application because of local control",
        0x0800_0022 => "data cannot be transferred or stored to the application because of the present device state",
        0x0800_0023 => "object dictionary dynamic generation fails or no object dictionary is present",
        0x0800_0024 => "no data available",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_view_reads_each_field_where_cia_301_puts_it() {
        // Initiate download, expedited, 2 bytes indicated, 1017h:00 = 1000.
        let bytes = [0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0x00, 0x00];
        let frame = Frame::new(&bytes);
        assert_eq!(frame.specifier(), ccs::INITIATE_DOWNLOAD);
        assert!(frame.expedited() && frame.size_indicated());
        assert_eq!(frame.expedited_len(), 2);
        assert_eq!(frame.mux(), Multiplexer::new(0x1017, 0));
        assert_eq!(frame.value(), 1000);
        // A download segment with toggle 1, 5 bytes unused, last.
        let bytes = [0x1B, b'a', b'b', 0, 0, 0, 0, 0];
        let frame = Frame::new(&bytes);
        assert!(frame.toggle() && frame.last());
        assert_eq!(frame.segment_data(), b"ab");
        // Initiate block upload: CRC, blksize 127, pst 20; an end block download: n = 5, CRC.
        let bytes = [0xA4, 0x50, 0x1F, 0x01, 0x7F, 0x14, 0, 0];
        let frame = Frame::new(&bytes);
        assert!(frame.crc_supported());
        assert_eq!(frame.block_subcommand(), 0);
        assert_eq!(
            (
                frame.initiate_block_size(),
                frame.protocol_switch_threshold()
            ),
            (127, 20)
        );
        let bytes = [0xD5, 0x1F, 0xE7, 0, 0, 0, 0, 0];
        let frame = Frame::new(&bytes);
        assert_eq!((frame.block_end_unused(), frame.block_crc()), (5, 0xE71F));
        // A sub-block acknowledgement: ackseq 92, next block size 127.
        let bytes = [0xA2, 0x5C, 0x7F, 0, 0, 0, 0, 0];
        let frame = Frame::new(&bytes);
        assert_eq!((frame.ackseq(), frame.ack_block_size()), (92, 127));
        assert_eq!(Frame::new_checked(&bytes[..7]), Err(WireError::Length));
    }

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
