//! The SDO server against a hand-written dictionary: every transfer type both ways, one test per
//! abort code the server sends (exact response bytes), the manuals' vectors, timeouts on a test
//! clock, and a property that arbitrary requests never panic.

mod support;

#[cfg(feature = "sdo-block")]
use edsgen_runtime::sdo::crc::crc16;
use edsgen_runtime::sdo::{SdoEvent, SdoServer};
#[cfg(feature = "sdo-block")]
use edsgen_runtime::wire::sdo::BlockSegment;
use edsgen_runtime::wire::sdo::{ClientRequest, SegmentData};
use edsgen_runtime::{Duration, Instant};
use proptest::prelude::*;
#[cfg(feature = "sdo-block")]
use support::domain_pattern;
use support::TestOd;

const TIMEOUT: Duration = Duration::from_millis(100);

/// A server, its dictionary and the test clock.
struct Rig {
    server: SdoServer,
    od: TestOd,
    now: Instant,
}

impl Rig {
    fn new() -> Self {
        Rig {
            server: SdoServer::new(TIMEOUT),
            od: TestOd::new(),
            now: Instant::from_millis(1_000),
        }
    }

    /// A server offering block downloads sub-blocks of `segments`.
    #[cfg(feature = "sdo-block")]
    fn with_block_size(segments: u8) -> Self {
        Rig {
            server: SdoServer::new(TIMEOUT).with_block_size(segments),
            ..Rig::new()
        }
    }

    /// Hands one request to the server and takes the one response it queued, if any.
    fn send(&mut self, request: &[u8]) -> (Option<[u8; 8]>, Option<SdoEvent>) {
        let event = self.server.handle(self.now, request, &mut self.od);
        let response = self.server.poll_transmit(self.now, &self.od);
        (response, event)
    }

    /// A request that must be answered.
    fn ask(&mut self, request: [u8; 8]) -> [u8; 8] {
        match self.send(&request) {
            (Some(response), _) => response,
            (None, _) => panic!("no response to {request:02X?}"),
        }
    }

    /// A request that must not be answered (a block-download segment within a sub-block, or a
    /// client's abort).
    fn tell(&mut self, request: [u8; 8]) {
        let (response, event) = self.send(&request);
        assert_eq!(response, None, "unexpected response to {request:02X?}");
        assert_eq!(event, None);
    }

    /// Hands one request over and takes every frame the server then has to send.
    #[cfg(feature = "sdo-block")]
    fn send_and_drain(&mut self, request: [u8; 8]) -> Vec<[u8; 8]> {
        assert_eq!(self.server.handle(self.now, &request, &mut self.od), None);
        let mut frames = Vec::new();
        while let Some(frame) = self.server.poll_transmit(self.now, &self.od) {
            frames.push(frame);
            assert!(frames.len() <= 200, "the server does not stop sending");
        }
        frames
    }

    fn advance(&mut self, millis: u64) {
        self.now = self.now + Duration::from_millis(millis);
    }
}

type Server512 = Rig;

fn written(index: u16, sub: u8) -> Option<SdoEvent> {
    Some(SdoEvent::Written { index, sub })
}

fn download_segment(toggle: bool, data: &[u8], last: bool) -> [u8; 8] {
    ClientRequest::DownloadSegment {
        toggle,
        data: SegmentData::new(data).unwrap(),
        last,
    }
    .emit()
}

#[cfg(feature = "sdo-block")]
fn block_segment(seqno: u8, last: bool, chunk: &[u8]) -> [u8; 8] {
    let mut data = [0u8; 7];
    data[..chunk.len()].copy_from_slice(chunk);
    BlockSegment { seqno, last, data }.emit()
}

/// Uploads (index, sub) segmented and returns the value; the initiate response must announce
/// `size` bytes.
fn segmented_upload(rig: &mut Rig, index: u16, sub: u8, size: u32) -> Vec<u8> {
    let [lo, hi] = index.to_le_bytes();
    let [s0, s1, s2, s3] = size.to_le_bytes();
    assert_eq!(
        rig.ask([0x40, lo, hi, sub, 0, 0, 0, 0]),
        [0x41, lo, hi, sub, s0, s1, s2, s3]
    );
    let mut value = Vec::new();
    let mut toggle = false;
    loop {
        let response = rig.ask([0x60 | if toggle { 0x10 } else { 0 }, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(
            response[0] & 0xF0,
            if toggle { 0x10 } else { 0 },
            "{response:02X?}"
        );
        let len = 7 - usize::from((response[0] >> 1) & 7);
        value.extend_from_slice(&response[1..1 + len]);
        if response[0] & 1 != 0 {
            return value;
        }
        toggle = !toggle;
    }
}

// ---------------------------------------------------------------------------------------------
// The manuals' vectors (node 3: requests on 0x603, responses on 0x583).

#[test]
fn manual_write_inhibit_time_then_read_it_back() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.send(&[0x2B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00]),
        (
            Some([0x60, 0x01, 0x18, 0x03, 0x00, 0x00, 0x00, 0x00]),
            written(0x1801, 3)
        )
    );
    assert_eq!(
        rig.ask([0x40, 0x01, 0x18, 0x03, 0x00, 0x00, 0x00, 0x00]),
        [0x4B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00]
    );
}

#[test]
fn manual_read_of_missing_object_aborts_0602_0000() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x40, 0x00, 0x60, 0x00, 0x00, 0x00, 0x00, 0x00]),
        [0x80, 0x00, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06]
    );
}

#[test]
fn manual_rd11_parameter_read_and_write() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x40, 0x02, 0x20, 0x03, 0x00, 0x00, 0x00, 0x00]),
        [0x4B, 0x02, 0x20, 0x03, 0x02, 0x01, 0x00, 0x00]
    );
    // CiA 301 answers a download with 60h, whatever the manual prints.
    assert_eq!(
        rig.send(&[0x2B, 0x02, 0x20, 0x03, 0x03, 0x00, 0x00, 0x00]),
        (
            Some([0x60, 0x02, 0x20, 0x03, 0x00, 0x00, 0x00, 0x00]),
            written(0x2002, 3)
        )
    );
    assert_eq!(rig.od.value(0x2002, 3), &[0x03, 0x00]);
}

// ---------------------------------------------------------------------------------------------
// Expedited transfers.

#[test]
fn expedited_upload_indicates_the_size_of_each_width() {
    let mut rig = Server512::new();
    // 1 byte: n = 3.
    assert_eq!(
        rig.ask([0x40, 0x18, 0x10, 0x00, 0, 0, 0, 0]),
        [0x4F, 0x18, 0x10, 0x00, 0x01, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x40, 0x04, 0x20, 0x00, 0, 0, 0, 0]),
        [0x4F, 0x04, 0x20, 0x00, 0xFE, 0, 0, 0]
    );
    // 3 bytes: n = 1.
    assert_eq!(
        rig.ask([0x40, 0x08, 0x20, 0x00, 0, 0, 0, 0]),
        [0x47, 0x08, 0x20, 0x00, 0x01, 0x02, 0x03, 0]
    );
    // 4 bytes: n = 0.
    assert_eq!(
        rig.ask([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
    );
    assert_eq!(
        rig.ask([0x40, 0x09, 0x20, 0x00, 0, 0, 0, 0]),
        [0x43, 0x09, 0x20, 0x00, 0x00, 0x00, 0xC0, 0x3F]
    );
    // A string of 4 bytes or fewer is expedited too.
    rig.od.set_value(0x2005, 0, b"abc");
    assert_eq!(
        rig.ask([0x40, 0x05, 0x20, 0x00, 0, 0, 0, 0]),
        [0x47, 0x05, 0x20, 0x00, b'a', b'b', b'c', 0]
    );
    assert_eq!(rig.server.poll_timeout(), None);
}

#[test]
fn expedited_download_of_each_width() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.send(&[0x2F, 0x04, 0x20, 0x00, 0x80, 0xAA, 0xAA, 0xAA]),
        (
            Some([0x60, 0x04, 0x20, 0x00, 0, 0, 0, 0]),
            written(0x2004, 0)
        )
    );
    assert_eq!(rig.od.value(0x2004, 0), &[0x80]);
    assert_eq!(
        rig.send(&[0x27, 0x08, 0x20, 0x00, 0x0A, 0x0B, 0x0C, 0xAA]),
        (
            Some([0x60, 0x08, 0x20, 0x00, 0, 0, 0, 0]),
            written(0x2008, 0)
        )
    );
    assert_eq!(rig.od.value(0x2008, 0), &[0x0A, 0x0B, 0x0C]);
    assert_eq!(
        rig.send(&[0x23, 0x07, 0x20, 0x00, 0x01, 0x02, 0x03, 0x04]),
        (
            Some([0x60, 0x07, 0x20, 0x00, 0, 0, 0, 0]),
            written(0x2007, 0)
        )
    );
    assert_eq!(rig.od.value(0x2007, 0), &[1, 2, 3, 4]);
    // Write-only entries accept writes.
    assert_eq!(
        rig.send(&[0x23, 0x01, 0x20, 0x00, 0x11, 0x22, 0x33, 0x44]),
        (
            Some([0x60, 0x01, 0x20, 0x00, 0, 0, 0, 0]),
            written(0x2001, 0)
        )
    );
    assert_eq!(rig.od.value(0x2001, 0), &[0x11, 0x22, 0x33, 0x44]);
}

#[test]
fn expedited_download_without_size_writes_the_entry_size() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.send(&[0x22, 0x17, 0x10, 0x00, 0xE8, 0x03, 0xFF, 0xFF]),
        (
            Some([0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]),
            written(0x1017, 0)
        )
    );
    assert_eq!(rig.od.value(0x1017, 0), &[0xE8, 0x03]);
}

// ---------------------------------------------------------------------------------------------
// Segmented transfers.

#[test]
fn segmented_download_of_a_string() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x21, 0x05, 0x20, 0x00, 0x0E, 0x00, 0x00, 0x00]),
        [0x60, 0x05, 0x20, 0x00, 0, 0, 0, 0]
    );
    assert_eq!(
        rig.send(&[0x00, b'e', b'd', b's', b'g', b'e', b'n', b' ']),
        (Some([0x20, 0, 0, 0, 0, 0, 0, 0]), None)
    );
    // Staged: the entry keeps its value until the last segment arrives.
    assert_eq!(rig.od.value(0x2005, 0), b"hello");
    assert_eq!(
        rig.send(&[0x11, b'r', b'u', b'n', b't', b'i', b'm', b'e']),
        (Some([0x30, 0, 0, 0, 0, 0, 0, 0]), written(0x2005, 0))
    );
    assert_eq!(rig.od.value(0x2005, 0), b"edsgen runtime");
    assert_eq!(rig.server.poll_timeout(), None);
}

#[test]
fn segmented_upload_of_a_string() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0]),
        [0x41, 0x08, 0x10, 0x00, 0x06, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x03, b'e', b'd', b's', b'g', b'e', b'n', 0]
    );
    assert_eq!(rig.server.poll_timeout(), None);
}

#[test]
fn segmented_upload_of_a_u64_toggles() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x40, 0x03, 0x20, 0x00, 0, 0, 0, 0]),
        [0x41, 0x03, 0x20, 0x00, 0x08, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x00, 0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22]
    );
    assert_eq!(
        rig.ask([0x70, 0, 0, 0, 0, 0, 0, 0]),
        [0x1D, 0x11, 0, 0, 0, 0, 0, 0]
    );
}

#[test]
fn segmented_upload_of_an_empty_string() {
    let mut rig = Server512::new();
    rig.od.set_value(0x2005, 0, b"");
    assert_eq!(
        rig.ask([0x40, 0x05, 0x20, 0x00, 0, 0, 0, 0]),
        [0x41, 0x05, 0x20, 0x00, 0, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x0F, 0, 0, 0, 0, 0, 0, 0]
    );
}

#[test]
fn segmented_round_trip_of_a_300_byte_domain_without_size() {
    let mut rig = Server512::new();
    let value: Vec<u8> = (0..300u32).map(|i| (i * 13 + 5) as u8).collect();
    assert_eq!(
        rig.ask([0x20, 0x06, 0x20, 0x00, 0, 0, 0, 0]),
        [0x60, 0x06, 0x20, 0x00, 0, 0, 0, 0]
    );
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    for (i, chunk) in chunks.iter().enumerate() {
        let toggle = i % 2 == 1;
        let last = i + 1 == chunks.len();
        let (response, event) = rig.send(&download_segment(toggle, chunk, last));
        assert_eq!(
            response,
            Some([0x20 | if toggle { 0x10 } else { 0 }, 0, 0, 0, 0, 0, 0, 0])
        );
        assert_eq!(event, if last { written(0x2006, 0) } else { None });
    }
    assert_eq!(rig.od.value(0x2006, 0), &value[..]);
    assert_eq!(segmented_upload(&mut rig, 0x2006, 0, 300), value);
}

// ---------------------------------------------------------------------------------------------
// Block download.

#[cfg(feature = "sdo-block")]
/// Block-downloads `value` to 0x2006 through a server of `N` bytes, in sub-blocks of the
/// server's size, and returns the CRC the client sent.
fn block_download(rig: &mut Rig, value: &[u8]) -> u16 {
    let [s0, s1, s2, s3] = (value.len() as u32).to_le_bytes();
    let blksize = rig.server.block_size();
    assert_eq!(
        rig.ask([0xC6, 0x06, 0x20, 0x00, s0, s1, s2, s3]),
        [0xA4, 0x06, 0x20, 0x00, blksize, 0, 0, 0]
    );
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    for (i, chunk) in chunks.iter().enumerate() {
        let seqno = (i % usize::from(blksize)) as u8 + 1;
        let last = i + 1 == chunks.len();
        let (response, event) = rig.send(&block_segment(seqno, last, chunk));
        assert_eq!(event, None);
        if last || seqno == blksize {
            assert_eq!(response, Some([0xA2, seqno, blksize, 0, 0, 0, 0, 0]));
        } else {
            assert_eq!(response, None);
        }
    }
    crc16(value)
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_download_with_crc_in_two_sub_blocks() {
    let mut rig = Rig::with_block_size(42);
    let value: Vec<u8> = (0..300u32).map(|i| (i * 3 + 9) as u8).collect();
    let crc = block_download(&mut rig, &value);
    // 43 segments, the last holding 6 bytes: n = 1.
    let [c0, c1] = crc.to_le_bytes();
    assert_eq!(
        rig.send(&[0xC5, c0, c1, 0, 0, 0, 0, 0]),
        (Some([0xA1, 0, 0, 0, 0, 0, 0, 0]), written(0x2006, 0))
    );
    assert_eq!(rig.od.value(0x2006, 0), &value[..]);
    assert_eq!(rig.server.poll_timeout(), None);
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_download_of_a_short_string() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0xC6, 0x05, 0x20, 0x00, 0x03, 0, 0, 0]),
        [0xA4, 0x05, 0x20, 0x00, 127, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x81, b'x', b'y', b'z', 0, 0, 0, 0]),
        [0xA2, 0x01, 127, 0, 0, 0, 0, 0]
    );
    let [c0, c1] = crc16(b"xyz").to_le_bytes();
    // n = 4 unused bytes: 0xC1 | 4 << 2.
    assert_eq!(
        rig.send(&[0xD1, c0, c1, 0, 0, 0, 0, 0]),
        (Some([0xA1, 0, 0, 0, 0, 0, 0, 0]), written(0x2005, 0))
    );
    assert_eq!(rig.od.value(0x2005, 0), b"xyz");
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_download_without_client_crc_ignores_the_crc_field() {
    let mut rig = Server512::new();
    // cc = 0, size not indicated.
    assert_eq!(
        rig.ask([0xC0, 0x05, 0x20, 0x00, 0, 0, 0, 0]),
        [0xA4, 0x05, 0x20, 0x00, 127, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x81, b'a', b'b', 0, 0, 0, 0, 0]),
        [0xA2, 0x01, 127, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        rig.send(&[0xD5, 0xDE, 0xAD, 0, 0, 0, 0, 0]),
        (Some([0xA1, 0, 0, 0, 0, 0, 0, 0]), written(0x2005, 0))
    );
    assert_eq!(rig.od.value(0x2005, 0), b"ab");
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_download_lost_segment_is_repeated_after_the_acknowledgement() {
    let mut rig = Server512::new();
    let value = domain_pattern()
        .iter()
        .map(|b| b ^ 0x5A)
        .collect::<Vec<u8>>();
    assert_eq!(
        rig.ask([0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0]),
        [0xA4, 0x06, 0x20, 0x00, 127, 0, 0, 0]
    );
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    assert_eq!(chunks.len(), 43);
    rig.tell(block_segment(1, false, chunks[0]));
    rig.tell(block_segment(2, false, chunks[1]));
    // Segment 3 is lost; 4..=42 are ignored; the last ends the sub-block.
    for (i, chunk) in chunks.iter().enumerate().take(42).skip(3) {
        rig.tell(block_segment(i as u8 + 1, false, chunk));
    }
    assert_eq!(
        rig.ask(block_segment(43, true, chunks[42])),
        [0xA2, 0x02, 127, 0, 0, 0, 0, 0]
    );
    // The client repeats from the third segment, numbered from 1.
    for (i, chunk) in chunks.iter().enumerate().take(42).skip(2) {
        rig.tell(block_segment(i as u8 - 1, false, chunk));
    }
    assert_eq!(
        rig.ask(block_segment(41, true, chunks[42])),
        [0xA2, 41, 127, 0, 0, 0, 0, 0]
    );
    let [c0, c1] = crc16(&value).to_le_bytes();
    assert_eq!(
        rig.send(&[0xC5, c0, c1, 0, 0, 0, 0, 0]),
        (Some([0xA1, 0, 0, 0, 0, 0, 0, 0]), written(0x2006, 0))
    );
    assert_eq!(rig.od.value(0x2006, 0), &value[..]);
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_download_80_in_a_sub_block_is_sequence_number_0_aborted_with_0504_0003() {
    let mut rig = Server512::new();
    rig.ask([0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0]);
    rig.tell(block_segment(1, false, b"1234567"));
    // Within a sub-block every frame is a segment: `80` is sequence number 0 with the
    // last-segment bit (a client's abort there ends the transfer as well).
    assert_eq!(
        rig.send(&[0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x00, 0x08]),
        (Some([0x80, 0x06, 0x20, 0x00, 0x03, 0x00, 0x04, 0x05]), None)
    );
    assert_eq!(rig.server.poll_timeout(), None);
    assert_eq!(rig.od.value(0x2006, 0), &domain_pattern()[..]);
    // As `00` is.
    rig.ask([0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0]);
    assert_eq!(
        rig.send(&[0x00, 1, 2, 3, 4, 5, 6, 7]),
        (Some([0x80, 0x06, 0x20, 0x00, 0x03, 0x00, 0x04, 0x05]), None)
    );
    assert_eq!(rig.od.value(0x2006, 0), &domain_pattern()[..]);
}

// ---------------------------------------------------------------------------------------------
// Block upload.

#[cfg(feature = "sdo-block")]
/// Runs a block upload of (index, sub) whose initiate response announces `size`, acknowledging
/// each sub-block fully with `blksize`; returns the data and the end request's (n, CRC).
fn block_upload(
    rig: &mut Rig,
    index: u16,
    sub: u8,
    size: u32,
    blksize: u8,
    crc: bool,
) -> (Vec<u8>, u8, u16) {
    let [lo, hi] = index.to_le_bytes();
    let [s0, s1, s2, s3] = size.to_le_bytes();
    let cc = if crc { 0x04 } else { 0 };
    assert_eq!(
        rig.ask([0xA0 | cc, lo, hi, sub, blksize, 0, 0, 0]),
        [0xC6, lo, hi, sub, s0, s1, s2, s3]
    );
    let mut data = Vec::new();
    let mut request = [0xA3, 0, 0, 0, 0, 0, 0, 0];
    loop {
        let frames = rig.send_and_drain(request);
        if let [end] = frames[..] {
            if end[0] & 0xE3 == 0xC1 {
                assert_eq!(end[3..], [0; 5]);
                let unused = (end[0] >> 2) & 7;
                data.truncate(data.len() - usize::from(unused));
                assert_eq!(rig.send(&[0xA1, 0, 0, 0, 0, 0, 0, 0]), (None, None));
                assert_eq!(rig.server.poll_timeout(), None);
                return (data, unused, u16::from_le_bytes([end[1], end[2]]));
            }
        }
        assert!(!frames.is_empty() && frames.len() <= usize::from(blksize));
        for (i, frame) in frames.iter().enumerate() {
            let last = i + 1 == frames.len();
            assert_eq!(frame[0] & 0x7F, i as u8 + 1);
            assert!(last || frame[0] & 0x80 == 0);
            data.extend_from_slice(&frame[1..]);
        }
        request = [0xA2, frames.len() as u8, blksize, 0, 0, 0, 0, 0];
    }
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_of_the_domain_with_crc_in_sub_blocks_of_ten() {
    let mut rig = Server512::new();
    let (data, unused, crc) = block_upload(&mut rig, 0x2006, 0, 300, 10, true);
    assert_eq!(data, domain_pattern());
    assert_eq!(unused, 1);
    assert_eq!(crc, crc16(&domain_pattern()));
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_without_client_crc_sends_zero() {
    let mut rig = Server512::new();
    let (data, unused, crc) = block_upload(&mut rig, 0x2006, 0, 300, 127, false);
    assert_eq!(data, domain_pattern());
    assert_eq!(unused, 1);
    assert_eq!(crc, 0);
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_of_a_small_value_without_protocol_switch() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0xA4, 0x00, 0x10, 0x00, 0x7F, 0x00, 0, 0]),
        [0xC6, 0x00, 0x10, 0x00, 0x04, 0, 0, 0]
    );
    assert_eq!(
        rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]),
        vec![[0x81, 0x92, 0x01, 0x02, 0x00, 0, 0, 0]]
    );
    let [c0, c1] = crc16(&[0x92, 0x01, 0x02, 0x00]).to_le_bytes();
    // n = 3: 0xC1 | 3 << 2.
    assert_eq!(
        rig.ask([0xA2, 0x01, 0x7F, 0, 0, 0, 0, 0]),
        [0xCD, c0, c1, 0, 0, 0, 0, 0]
    );
    assert_eq!(rig.send(&[0xA1, 0, 0, 0, 0, 0, 0, 0]), (None, None));
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_of_an_empty_string_sends_one_empty_segment() {
    let mut rig = Server512::new();
    rig.od.set_value(0x2005, 0, b"");
    assert_eq!(
        rig.ask([0xA4, 0x05, 0x20, 0x00, 0x7F, 0x00, 0, 0]),
        [0xC6, 0x05, 0x20, 0x00, 0, 0, 0, 0]
    );
    assert_eq!(
        rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]),
        vec![[0x81, 0, 0, 0, 0, 0, 0, 0]]
    );
    // n = 7, CRC of nothing = 0.
    assert_eq!(
        rig.ask([0xA2, 0x01, 0x7F, 0, 0, 0, 0, 0]),
        [0xDD, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(rig.send(&[0xA1, 0, 0, 0, 0, 0, 0, 0]), (None, None));
    assert_eq!(rig.server.poll_timeout(), None);
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_switches_to_expedited_upload_below_the_threshold() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0xA4, 0x00, 0x10, 0x00, 0x7F, 0x04, 0, 0]),
        [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
    );
    assert_eq!(rig.server.poll_timeout(), None);
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_switches_to_segmented_upload_below_the_threshold() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0xA4, 0x05, 0x20, 0x00, 0x7F, 0x05, 0, 0]),
        [0x41, 0x05, 0x20, 0x00, 0x05, 0, 0, 0]
    );
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x05, b'h', b'e', b'l', b'l', b'o', 0, 0]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_above_the_threshold_stays_block() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0xA4, 0x05, 0x20, 0x00, 0x7F, 0x04, 0, 0]),
        [0xC6, 0x05, 0x20, 0x00, 0x05, 0, 0, 0]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn block_upload_repeats_unacknowledged_segments() {
    let mut rig = Server512::new();
    let value = domain_pattern();
    rig.ask([0xA4, 0x06, 0x20, 0x00, 10, 0, 0, 0]);
    let first = rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(first.len(), 10);
    // The client got only 4 segments in order and asks for 3 at a time from now on.
    let second = rig.send_and_drain([0xA2, 4, 3, 0, 0, 0, 0, 0]);
    assert_eq!(second.len(), 3);
    assert_eq!(second[0][0], 1);
    assert_eq!(second[0][1..], value[28..35]);
    assert_eq!(second[2][0], 3);
    assert_eq!(second[2][1..], value[42..49]);
}

// ---------------------------------------------------------------------------------------------
// Transfer management.

#[test]
fn new_initiate_replaces_a_transfer_in_progress() {
    let mut rig = Server512::new();
    rig.ask([0x21, 0x05, 0x20, 0x00, 0x0E, 0x00, 0x00, 0x00]);
    assert_eq!(
        rig.ask([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
    );
    // The download is gone: its segment is now out of place.
    assert_eq!(
        rig.ask([0x00, b'e', b'd', b's', b'g', b'e', b'n', b' ']),
        [0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
}

#[test]
fn client_abort_ends_a_segmented_upload_without_response() {
    let mut rig = Server512::new();
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    rig.tell([0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x00, 0x08]);
    assert_eq!(rig.server.poll_timeout(), None);
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
}

#[test]
fn reset_drops_the_transfer_and_the_queued_response() {
    let mut rig = Server512::new();
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    assert!(rig.server.poll_timeout().is_some());
    assert_eq!(
        rig.server
            .handle(rig.now, &[0x60, 0, 0, 0, 0, 0, 0, 0], &mut rig.od),
        None
    );
    rig.server.reset(&mut rig.od);
    assert_eq!(rig.server.poll_transmit(rig.now, &rig.od), None);
    assert_eq!(rig.server.poll_timeout(), None);
    assert_eq!(
        rig.ask([0x70, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
}

#[test]
fn each_request_restarts_the_timeout() {
    let mut rig = Server512::new();
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    assert_eq!(rig.server.poll_timeout(), Some(Instant::from_millis(1_100)));
    rig.advance(90);
    rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(rig.server.poll_timeout(), Some(Instant::from_millis(1_190)));
    rig.server
        .handle_timeout(Instant::from_millis(1_150), &mut rig.od);
    assert_eq!(rig.server.poll_transmit(rig.now, &rig.od), None);
    assert_eq!(rig.ask([0x70, 0, 0, 0, 0, 0, 0, 0])[0], 0x10);
}

// ---------------------------------------------------------------------------------------------
// One test per abort code the server sends.

#[test]
fn abort_0503_0000_on_toggle_bit_not_alternated() {
    let mut rig = Server512::new();
    rig.ask([0x21, 0x05, 0x20, 0x00, 0x0A, 0x00, 0x00, 0x00]);
    assert_eq!(
        rig.send(&download_segment(true, b"1234567", false)),
        (Some([0x80, 0x05, 0x20, 0x00, 0x00, 0x00, 0x03, 0x05]), None)
    );
    // Upload too: the second segment request repeats toggle 0.
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x03, 0x05]
    );
    assert_eq!(rig.od.value(0x2005, 0), b"hello");
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0504_0000_on_timeout() {
    let mut rig = Server512::new();
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    let deadline = rig.server.poll_timeout().unwrap();
    assert_eq!(deadline, Instant::from_millis(1_100));
    rig.server
        .handle_timeout(Instant::from_micros(deadline.as_micros() - 1), &mut rig.od);
    assert_eq!(rig.server.poll_transmit(rig.now, &rig.od), None);
    rig.server.handle_timeout(deadline, &mut rig.od);
    assert_eq!(
        rig.server.poll_transmit(deadline, &rig.od),
        Some([0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x04, 0x05])
    );
    assert_eq!(rig.server.poll_timeout(), None);
    // The block upload's wait for an acknowledgement times out as well.
    rig.now = deadline;
    rig.ask([0xA4, 0x06, 0x20, 0x00, 0x05, 0x00, 0, 0]);
    assert_eq!(rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]).len(), 5);
    let deadline = rig.server.poll_timeout().unwrap();
    assert_eq!(deadline, rig.now + TIMEOUT);
    rig.server
        .handle_timeout(deadline + Duration::from_millis(5), &mut rig.od);
    assert_eq!(
        rig.server.poll_transmit(deadline, &rig.od),
        Some([0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x04, 0x05])
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0504_0000_on_timeout_of_downloads() {
    let mut rig = Server512::new();
    rig.ask([0x21, 0x05, 0x20, 0x00, 0x0E, 0x00, 0x00, 0x00]);
    rig.ask(download_segment(false, b"1234567", false));
    rig.advance(100);
    rig.server.handle_timeout(rig.now, &mut rig.od);
    assert_eq!(
        rig.server.poll_transmit(rig.now, &rig.od),
        Some([0x80, 0x05, 0x20, 0x00, 0x00, 0x00, 0x04, 0x05])
    );
    // A block download waiting for the rest of its sub-block.
    rig.ask([0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0]);
    rig.tell(block_segment(1, false, b"1234567"));
    rig.advance(100);
    rig.server.handle_timeout(rig.now, &mut rig.od);
    assert_eq!(
        rig.server.poll_transmit(rig.now, &rig.od),
        Some([0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x04, 0x05])
    );
    assert_eq!(rig.server.poll_timeout(), None);
    // Neither download changed its entry: a download applies all or nothing.
    assert_eq!(rig.od.value(0x2005, 0), b"hello");
    assert_eq!(rig.od.value(0x2006, 0), &domain_pattern()[..]);
    // The next transfer starts afresh.
    assert_eq!(
        rig.ask([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0504_0001_on_unknown_or_misplaced_command() {
    let mut rig = Server512::new();
    // ccs = 7 does not exist.
    assert_eq!(
        rig.ask([0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        [0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
    // A segment without a transfer.
    assert_eq!(
        rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
    // A download segment during an upload names the upload's entry.
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    assert_eq!(
        rig.ask(download_segment(false, b"abc", true)),
        [0x80, 0x06, 0x20, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
    // SDO frames are 8 bytes long.
    assert_eq!(
        rig.send(&[0x40, 0x00, 0x10, 0x00]),
        (Some([0x80, 0x00, 0x00, 0x00, 0x01, 0x00, 0x04, 0x05]), None)
    );
    // A second block upload start while the client should acknowledge.
    rig.ask([0xA4, 0x06, 0x20, 0x00, 0x05, 0x00, 0, 0]);
    assert_eq!(rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]).len(), 5);
    assert_eq!(
        rig.ask([0xA3, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x01, 0x00, 0x04, 0x05]
    );
    assert_eq!(rig.server.poll_timeout(), None);
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0504_0002_on_invalid_block_size() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0xA4, 0x06, 0x20, 0x00, 0x00, 0x00, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x02, 0x00, 0x04, 0x05]
    );
    assert_eq!(
        rig.ask([0xA4, 0x06, 0x20, 0x00, 0x80, 0x00, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x02, 0x00, 0x04, 0x05]
    );
    // In an acknowledgement.
    rig.ask([0xA4, 0x06, 0x20, 0x00, 0x05, 0x00, 0, 0]);
    rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        rig.ask([0xA2, 0x05, 0x00, 0, 0, 0, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x02, 0x00, 0x04, 0x05]
    );
    assert_eq!(rig.server.poll_timeout(), None);
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0504_0003_on_invalid_sequence_number() {
    let mut rig = Rig::with_block_size(73);
    rig.ask([0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0]);
    assert_eq!(
        rig.ask(block_segment(0, false, b"1234567")),
        [0x80, 0x06, 0x20, 0x00, 0x03, 0x00, 0x04, 0x05]
    );
    // Above the server's block size of 73.
    rig.ask([0xC6, 0x06, 0x20, 0x00, 0x2C, 0x01, 0, 0]);
    assert_eq!(
        rig.ask(block_segment(74, false, b"1234567")),
        [0x80, 0x06, 0x20, 0x00, 0x03, 0x00, 0x04, 0x05]
    );
    // A block upload acknowledgement of more segments than were sent.
    rig.ask([0xA4, 0x06, 0x20, 0x00, 0x05, 0x00, 0, 0]);
    rig.send_and_drain([0xA3, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        rig.ask([0xA2, 0x06, 0x05, 0, 0, 0, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x03, 0x00, 0x04, 0x05]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0504_0004_on_crc_error() {
    let mut rig = Rig::with_block_size(42);
    let value: Vec<u8> = (0..300u32).map(|i| (i * 5) as u8).collect();
    let crc = block_download(&mut rig, &value);
    let [c0, c1] = (crc ^ 0x0001).to_le_bytes();
    assert_eq!(
        rig.send(&[0xC5, c0, c1, 0, 0, 0, 0, 0]),
        (Some([0x80, 0x06, 0x20, 0x00, 0x04, 0x00, 0x04, 0x05]), None)
    );
    // The value whose CRC does not match was not applied.
    assert_eq!(rig.od.value(0x2006, 0), &domain_pattern()[..]);
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0601_0001_on_read_of_write_only() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x40, 0x01, 0x20, 0x00, 0, 0, 0, 0]),
        [0x80, 0x01, 0x20, 0x00, 0x01, 0x00, 0x01, 0x06]
    );
    assert_eq!(
        rig.ask([0xA4, 0x01, 0x20, 0x00, 0x7F, 0x00, 0, 0]),
        [0x80, 0x01, 0x20, 0x00, 0x01, 0x00, 0x01, 0x06]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0601_0002_on_write_to_read_only_or_const() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.send(&[0x23, 0x00, 0x10, 0x00, 1, 2, 3, 4]),
        (Some([0x80, 0x00, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06]), None)
    );
    assert_eq!(
        rig.ask([0x2F, 0x18, 0x10, 0x00, 0x05, 0, 0, 0]),
        [0x80, 0x18, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06]
    );
    assert_eq!(
        rig.ask([0x21, 0x08, 0x10, 0x00, 0x03, 0, 0, 0]),
        [0x80, 0x08, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06]
    );
    assert_eq!(
        rig.ask([0xC6, 0x08, 0x10, 0x00, 0x03, 0, 0, 0]),
        [0x80, 0x08, 0x10, 0x00, 0x02, 0x00, 0x01, 0x06]
    );
    assert_eq!(rig.od.value(0x1000, 0), &0x0002_0192u32.to_le_bytes());
    assert_eq!(rig.od.value(0x1018, 0), &[1]);
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0602_0000_on_missing_object() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x2B, 0x00, 0x60, 0x00, 1, 2, 0, 0]),
        [0x80, 0x00, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06]
    );
    assert_eq!(
        rig.ask([0xA4, 0x00, 0x30, 0x01, 0x7F, 0x00, 0, 0]),
        [0x80, 0x00, 0x30, 0x01, 0x00, 0x00, 0x02, 0x06]
    );
}

#[cfg(feature = "sdo-block")]
#[test]
fn abort_0607_0010_on_length_not_matching() {
    let mut rig = Server512::new();
    // Announced 10 bytes, sent 8.
    rig.ask([0x21, 0x05, 0x20, 0x00, 0x0A, 0x00, 0x00, 0x00]);
    rig.ask(download_segment(false, b"1234567", false));
    assert_eq!(
        rig.send(&download_segment(true, b"8", true)),
        (Some([0x80, 0x05, 0x20, 0x00, 0x10, 0x00, 0x07, 0x06]), None)
    );
    // Announced 5 bytes, sent 7 in the first segment.
    rig.ask([0x21, 0x05, 0x20, 0x00, 0x05, 0x00, 0x00, 0x00]);
    assert_eq!(
        rig.ask(download_segment(false, b"1234567", true)),
        [0x80, 0x05, 0x20, 0x00, 0x10, 0x00, 0x07, 0x06]
    );
    // Expedited without size to a 20-byte string: how many bytes are meant is unknown.
    assert_eq!(
        rig.ask([0x22, 0x05, 0x20, 0x00, b'a', b'b', b'c', b'd']),
        [0x80, 0x05, 0x20, 0x00, 0x10, 0x00, 0x07, 0x06]
    );
    // Block download: announced 3 bytes, the end says 2.
    rig.ask([0xC6, 0x05, 0x20, 0x00, 0x03, 0, 0, 0]);
    rig.ask([0x81, b'x', b'y', 0, 0, 0, 0, 0]);
    assert_eq!(
        rig.ask([0xD5, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x05, 0x20, 0x00, 0x10, 0x00, 0x07, 0x06]
    );
    // None of the refused transfers changed the entry.
    assert_eq!(rig.od.value(0x2005, 0), b"hello");
}

#[test]
fn abort_0607_0012_on_length_too_high() {
    let mut rig = Server512::new();
    // From the dictionary: 4 bytes for a UNSIGNED16.
    assert_eq!(
        rig.ask([0x23, 0x00, 0x20, 0x00, 0x64, 0x00, 0x00, 0x00]),
        [0x80, 0x00, 0x20, 0x00, 0x12, 0x00, 0x07, 0x06]
    );
    // From the server: 21 bytes announced for a 20-byte string.
    assert_eq!(
        rig.ask([0x21, 0x05, 0x20, 0x00, 0x15, 0x00, 0x00, 0x00]),
        [0x80, 0x05, 0x20, 0x00, 0x12, 0x00, 0x07, 0x06]
    );
    // Not announced: the third segment passes 20 bytes.
    rig.ask([0x20, 0x05, 0x20, 0x00, 0, 0, 0, 0]);
    rig.ask(download_segment(false, b"1234567", false));
    rig.ask(download_segment(true, b"1234567", false));
    assert_eq!(
        rig.ask(download_segment(false, b"1234567", true)),
        [0x80, 0x05, 0x20, 0x00, 0x12, 0x00, 0x07, 0x06]
    );
    assert_eq!(rig.od.value(0x2000, 0), &100u16.to_le_bytes());
    // The two segments that fitted were not applied.
    assert_eq!(rig.od.value(0x2005, 0), b"hello");
}

#[test]
fn abort_0607_0013_on_length_too_low() {
    let mut rig = Server512::new();
    // From the dictionary: 1 byte for a UNSIGNED16.
    assert_eq!(
        rig.ask([0x2F, 0x00, 0x20, 0x00, 0x64, 0x00, 0x00, 0x00]),
        [0x80, 0x00, 0x20, 0x00, 0x13, 0x00, 0x07, 0x06]
    );
    // From the server: 6 bytes announced for a UNSIGNED64.
    assert_eq!(
        rig.ask([0x21, 0x03, 0x20, 0x00, 0x06, 0x00, 0x00, 0x00]),
        [0x80, 0x03, 0x20, 0x00, 0x13, 0x00, 0x07, 0x06]
    );
}

#[test]
fn abort_0609_0011_on_missing_sub_index() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.ask([0x40, 0x18, 0x10, 0x05, 0, 0, 0, 0]),
        [0x80, 0x18, 0x10, 0x05, 0x11, 0x00, 0x09, 0x06]
    );
    assert_eq!(
        rig.ask([0x2B, 0x02, 0x20, 0x01, 1, 0, 0, 0]),
        [0x80, 0x02, 0x20, 0x01, 0x11, 0x00, 0x09, 0x06]
    );
}

#[test]
fn abort_0609_0031_on_value_too_high() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.send(&[0x2B, 0x00, 0x20, 0x00, 0xE9, 0x03, 0x00, 0x00]),
        (Some([0x80, 0x00, 0x20, 0x00, 0x31, 0x00, 0x09, 0x06]), None)
    );
    assert_eq!(rig.od.value(0x2000, 0), &100u16.to_le_bytes());
    // The limit itself is accepted.
    assert_eq!(
        rig.send(&[0x2B, 0x00, 0x20, 0x00, 0xE8, 0x03, 0x00, 0x00]),
        (
            Some([0x60, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
            written(0x2000, 0)
        )
    );
}

#[test]
fn abort_0609_0032_on_value_too_low() {
    let mut rig = Server512::new();
    assert_eq!(
        rig.send(&[0x2B, 0x00, 0x20, 0x00, 0x09, 0x00, 0x00, 0x00]),
        (Some([0x80, 0x00, 0x20, 0x00, 0x32, 0x00, 0x09, 0x06]), None)
    );
    assert_eq!(rig.od.value(0x2000, 0), &100u16.to_le_bytes());
}

#[test]
fn abort_0800_0000_when_the_value_shrinks_during_an_upload() {
    let mut rig = Server512::new();
    rig.ask([0x40, 0x06, 0x20, 0x00, 0, 0, 0, 0]);
    rig.ask([0x60, 0, 0, 0, 0, 0, 0, 0]);
    rig.od.set_value(0x2006, 0, &[1; 10]);
    assert_eq!(
        rig.ask([0x70, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0x06, 0x20, 0x00, 0x00, 0x00, 0x00, 0x08]
    );
}

// ---------------------------------------------------------------------------------------------
// Arbitrary input.

fn arbitrary_request() -> impl Strategy<Value = Vec<u8>> {
    // Mostly 8-byte frames whose first bytes hit the known commands and the test entries.
    let command = prop_oneof![
        any::<u8>(),
        Just(0x40u8),
        Just(0x60),
        Just(0x70),
        Just(0x21),
        Just(0x20),
        Just(0xA3),
        Just(0xA2),
        Just(0xA4),
        Just(0xC6),
        Just(0xC1),
        Just(0x81),
    ];
    let index = prop_oneof![any::<u16>(), Just(0x2006u16), Just(0x2005), Just(0x1000)];
    (
        command,
        index,
        any::<[u8; 5]>(),
        prop_oneof![Just(8usize), 0usize..=10],
    )
        .prop_map(|(command, index, rest, len)| {
            let [lo, hi] = index.to_le_bytes();
            let mut frame = vec![command, lo, hi, 0];
            frame.extend_from_slice(&rest[1..]);
            frame[3] = rest[0] % 4;
            frame.resize(len, 0x55);
            frame
        })
}

proptest! {
    #[test]
    fn arbitrary_requests_never_panic(
        requests in prop::collection::vec((arbitrary_request(), 0u64..150), 1..40)
    ) {
        let mut rig = Server512::new();
        for (request, millis) in requests {
            rig.advance(millis);
            rig.server.handle_timeout(rig.now, &mut rig.od);
            rig.server.handle(rig.now, &request, &mut rig.od);
            let mut sent = 0;
            while let Some(frame) = rig.server.poll_transmit(rig.now, &rig.od) {
                prop_assert_eq!(frame.len(), 8);
                sent += 1;
                prop_assert!(sent <= 128);
            }
        }
        rig.server.reset(&mut rig.od);
        prop_assert_eq!(rig.server.poll_timeout(), None);
        prop_assert_eq!(
            rig.ask([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
            [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
        );
    }
}
