//! [`ServerResponse`]: every message from an SDO server to a client, parsed and emitted.

use super::command::{self, scs};
use super::{
    abort_frame, frame, mux_frame, Frame, InitiatePayload, Multiplexer, SegmentData, WireError,
    FRAME_LEN,
};

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
    /// with [`BlockSegment::parse`](super::BlockSegment::parse).
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
