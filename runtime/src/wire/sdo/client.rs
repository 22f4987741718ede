//! [`ClientRequest`]: every message from an SDO client to a server, parsed and emitted.

use super::command::{self, ccs};
use super::{
    abort_frame, frame, mux_frame, Frame, InitiatePayload, Multiplexer, SegmentData, WireError,
    FRAME_LEN,
};

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
    /// with [`BlockSegment::parse`](super::BlockSegment::parse).
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
