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

pub mod command;

mod abort;
mod client;
mod payload;
mod server;

pub use abort::{abort_frame, abort_meaning};
pub use client::ClientRequest;
pub use payload::{BlockSegment, InitiatePayload, SegmentData};
pub use server::ServerResponse;

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

#[cfg(test)]
mod tests {
    use super::command::ccs;
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
