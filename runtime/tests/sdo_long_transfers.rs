//! SDO transfers of any length up to the entry's capacity, on the virtual bus with a scripted
//! client: a 64 KiB program domain (1F50h:01) whose bytes live outside the dictionary, by block
//! download and block upload, and a 100-byte VISIBLE_STRING held in a value image laid out by
//! `image::Layout` (as generated dictionaries hold theirs), by segmented download and upload.
//!
//! The dictionary is the contract's example of an application hook: it wraps a value image and
//! serves the domain's position itself (`read_at`, `value_len`, `capacity` and the streaming
//! steps `begin_write`, `write_part`, `commit_write`, `abort_write`), as a firmware would wrap
//! its generated `Od` to stream 1F50h to flash: the pieces go to a spare flash area, which
//! becomes the program on commit and is erased on abort. The string stages in a `Stage`, as a
//! generated `Od`'s do.

mod node_support;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::Node;
use edsgen_runtime::od::image::Layout;
use edsgen_runtime::od::stage::Stage;
use edsgen_runtime::{Access, DataType, EntryDescriptor, ObjectDictionary, SdoAbort};
use node_support::{frame, ms, show};

const ENTRIES: [EntryDescriptor; 4] = [
    EntryDescriptor::new(0x1000, 0, DataType::Unsigned32, Access::Ro, false),
    EntryDescriptor::new(0x1F50, 0, DataType::Unsigned8, Access::Ro, false),
    EntryDescriptor::new(0x1F50, 1, DataType::Domain, Access::Rw, false),
    EntryDescriptor::new(0x2000, 0, DataType::VisibleString, Access::Rw, false),
];
/// 1000h at 0 (4 bytes), 1F50h:00 at 4 (1 byte), 1F50h:01 at 5 (the image keeps only an empty
/// room: its bytes are the application's), 2000h at 7 (a 2-byte length and 120 bytes).
const OFFSETS: [u16; 4] = [0, 4, 5, 7];
const IMAGE_SIZE: usize = 129;
static LAYOUT: Layout = Layout::new(&ENTRIES, &OFFSETS, &[], IMAGE_SIZE);

/// Where 1F50h:01 is in `ENTRIES`.
const PROGRAM: usize = 2;
/// The most bytes the program domain takes.
const PROGRAM_CAPACITY: usize = 65_536;

struct DeviceOd {
    values: [u8; IMAGE_SIZE],
    /// The program's bytes ("flash").
    program: Vec<u8>,
    /// A program download in progress (the spare flash area), until it completes.
    incoming: Option<Vec<u8>>,
    /// A string download in progress.
    stage: Stage<120>,
}

impl DeviceOd {
    fn new() -> Self {
        let mut values = [0u8; IMAGE_SIZE];
        values[4] = 1;
        DeviceOd {
            values,
            program: Vec::new(),
            incoming: None,
            stage: Stage::new(),
        }
    }

    fn string(&self) -> Vec<u8> {
        let mut buf = vec![0u8; 200];
        let len = self.read_at(3, 0, &mut buf).unwrap();
        buf.truncate(len);
        buf
    }
}

impl ObjectDictionary for DeviceOd {
    fn entry_count(&self) -> usize {
        ENTRIES.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        ENTRIES.get(position).copied()
    }

    fn capacity(&self, position: usize) -> Option<usize> {
        match position {
            PROGRAM => Some(PROGRAM_CAPACITY),
            _ => LAYOUT.capacity(position),
        }
    }

    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        match self.locate(index, sub)? {
            PROGRAM => Ok(self.program.len()),
            position => LAYOUT.value_len(&self.values, position),
        }
    }

    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.read_at(self.locate(index, sub)?, offset, buf)
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        self.write_at(self.locate(index, sub)?, data)
    }

    fn read_at(&self, position: usize, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        match position {
            PROGRAM => {
                let rest = self.program.get(offset..).unwrap_or(&[]);
                let len = rest.len().min(buf.len());
                buf[..len].copy_from_slice(&rest[..len]);
                Ok(len)
            }
            _ => LAYOUT.read(&self.values, position, offset, buf),
        }
    }

    fn write_at(&mut self, position: usize, data: &[u8]) -> Result<(), SdoAbort> {
        match position {
            PROGRAM if data.len() > PROGRAM_CAPACITY => Err(SdoAbort::LengthTooHigh),
            PROGRAM => {
                self.program = data.to_vec();
                Ok(())
            }
            _ => LAYOUT.write(&mut self.values, position, data),
        }
    }

    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        match position {
            PROGRAM => {
                self.incoming = Some(Vec::new());
                Ok(())
            }
            _ => self.stage.begin(position),
        }
    }

    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        match (position, self.incoming.as_mut()) {
            (PROGRAM, _) if offset + data.len() > PROGRAM_CAPACITY => Err(SdoAbort::LengthTooHigh),
            (PROGRAM, Some(incoming)) => {
                incoming.truncate(offset);
                incoming.extend_from_slice(data);
                Ok(())
            }
            (PROGRAM, None) => Err(SdoAbort::General),
            _ => self.stage.write(position, offset, data),
        }
    }

    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        match position {
            PROGRAM => {
                let mut program = self.incoming.take().ok_or(SdoAbort::General)?;
                program.truncate(len);
                self.program = program;
                Ok(())
            }
            _ => {
                let value = self.stage.commit(position, len)?;
                LAYOUT.write(&mut self.values, position, value)
            }
        }
    }

    fn abort_write(&mut self, position: usize) {
        match position {
            // The spare area erased: the program stays the one before.
            PROGRAM => self.incoming = None,
            _ => self.stage.abort(position),
        }
    }
}

#[cfg(feature = "sdo-block")]
/// 64 KiB of program: byte i is i mod 251 (a period that does not divide the 7-byte segments).
fn program() -> Vec<u8> {
    (0..PROGRAM_CAPACITY).map(|i| (i % 251) as u8).collect()
}

#[cfg(feature = "sdo-block")]
/// Its CRC-16 (CCITT, initial 0), computed independently with Python's `binascii.crc_hqx`.
const PROGRAM_CRC: u16 = 0xE71F;

fn booted() -> (Node<DeviceOd>, VirtualBus) {
    let mut node = Node::new(DeviceOd::new(), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    bus.take_log();
    (node, bus)
}

/// Sends one request to node 3 and returns what the node answered, as text.
fn request(bus: &mut VirtualBus, node: &mut Node<DeviceOd>, data: [u8; 8]) -> Vec<String> {
    bus.inject(frame(0x603, &data), &mut [node]);
    bus.take_log()
        .into_iter()
        .filter(|(_, sender, _)| *sender != usize::MAX)
        .map(|(_, _, f)| show(&f))
        .collect()
}

/// A block-transfer segment: sequence number, last flag, 7 bytes (zero-padded).
#[cfg(feature = "sdo-block")]
fn block_segment(seqno: u8, last: bool, chunk: &[u8]) -> [u8; 8] {
    let mut data = [0u8; 8];
    data[0] = seqno | if last { 0x80 } else { 0 };
    data[1..1 + chunk.len()].copy_from_slice(chunk);
    data
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_64_kib_domain_moves_by_block_download_and_block_upload() {
    let (mut node, mut bus) = booted();
    let value = program();
    // Initiate block download, CRC, size 65,536 (s): 127 segments per sub-block offered.
    assert_eq!(
        request(
            &mut bus,
            &mut node,
            [0xC6, 0x50, 0x1F, 0x01, 0x00, 0x00, 0x01, 0x00]
        ),
        ["583: A4 50 1F 01 7F 00 00 00"]
    );
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    assert_eq!(
        chunks.len(),
        9363,
        "73 full sub-blocks of 127 and one of 92"
    );
    let mut acks = Vec::new();
    for (i, chunk) in chunks.iter().enumerate() {
        let seqno = (i % 127) as u8 + 1;
        let last = i + 1 == chunks.len();
        acks.extend(request(
            &mut bus,
            &mut node,
            block_segment(seqno, last, chunk),
        ));
    }
    assert_eq!(acks.len(), 74);
    assert!(acks[..73]
        .iter()
        .all(|a| a == "583: A2 7F 7F 00 00 00 00 00"));
    assert_eq!(acks[73], "583: A2 5C 7F 00 00 00 00 00");
    // End: 5 bytes of the last segment unused (n = 5: C1 | 5 << 2), and the CRC.
    let [crc_lo, crc_hi] = PROGRAM_CRC.to_le_bytes();
    assert_eq!(
        request(&mut bus, &mut node, [0xD5, crc_lo, crc_hi, 0, 0, 0, 0, 0]),
        ["583: A1 00 00 00 00 00 00 00"]
    );
    assert_eq!(node.od().program, value);

    // Block upload back: client block size 127, no protocol switch.
    assert_eq!(
        request(
            &mut bus,
            &mut node,
            [0xA4, 0x50, 0x1F, 0x01, 0x7F, 0x00, 0, 0]
        ),
        ["583: C6 50 1F 01 00 00 01 00"]
    );
    let mut received = Vec::new();
    let mut next = [0xA3, 0, 0, 0, 0, 0, 0, 0];
    let mut last_sent = false;
    let end = loop {
        let frames = request(&mut bus, &mut node, next);
        if last_sent {
            // The acknowledgement of the last sub-block is answered by the end request.
            assert_eq!(frames.len(), 1);
            break frames[0].clone();
        }
        for segment in &frames {
            let bytes: Vec<u8> = segment[5..]
                .split(' ')
                .map(|b| u8::from_str_radix(b, 16).unwrap())
                .collect();
            received.extend_from_slice(&bytes[1..]);
            last_sent = bytes[0] & 0x80 != 0;
        }
        next = [0xA2, frames.len() as u8, 0x7F, 0, 0, 0, 0, 0];
    };
    // End block upload: n = 5 unused bytes, the CRC of the 65,536 bytes.
    assert_eq!(
        end,
        format!("583: D5 {crc_lo:02X} {crc_hi:02X} 00 00 00 00 00")
    );
    assert!(request(&mut bus, &mut node, [0xA1, 0, 0, 0, 0, 0, 0, 0]).is_empty());
    received.truncate(PROGRAM_CAPACITY);
    assert_eq!(received, value);
}

#[cfg(feature = "sdo-block")]
#[test]
fn a_program_download_that_fails_leaves_the_program_before_it_and_erases_the_spare_area() {
    let (mut node, mut bus) = booted();
    node.od_mut().program = b"firmware 1.0".to_vec();
    // A block download of 14 bytes whose CRC does not match: aborted, the program unchanged,
    // the spare area erased.
    assert_eq!(
        request(&mut bus, &mut node, [0xC6, 0x50, 0x1F, 0x01, 14, 0, 0, 0]),
        ["583: A4 50 1F 01 7F 00 00 00"]
    );
    assert!(request(&mut bus, &mut node, block_segment(1, false, b"firmwar")).is_empty());
    assert_eq!(
        request(&mut bus, &mut node, block_segment(2, true, b"e 2.0!!")),
        ["583: A2 02 7F 00 00 00 00 00"]
    );
    assert!(node.od().incoming.is_some());
    assert_eq!(
        request(&mut bus, &mut node, [0xC1, 0x12, 0x34, 0, 0, 0, 0, 0]),
        ["583: 80 50 1F 01 04 00 04 05"]
    );
    assert_eq!(node.od().program, b"firmware 1.0");
    assert!(node.od().incoming.is_none());
    // A segmented download the client aborts after its first segment: the same.
    assert_eq!(
        request(&mut bus, &mut node, [0x21, 0x50, 0x1F, 0x01, 14, 0, 0, 0]),
        ["583: 60 50 1F 01 00 00 00 00"]
    );
    assert_eq!(
        request(&mut bus, &mut node, *b"\x00firmwar"),
        ["583: 20 00 00 00 00 00 00 00"]
    );
    assert!(request(&mut bus, &mut node, [0x80, 0x50, 0x1F, 0x01, 0, 0, 0, 0x08]).is_empty());
    assert_eq!(node.od().program, b"firmware 1.0");
    assert!(node.od().incoming.is_none());
}

#[test]
fn a_100_byte_string_moves_by_segmented_download_and_upload() {
    let (mut node, mut bus) = booted();
    let value: Vec<u8> = (0..100u8).map(|i| b'A' + i % 26).collect();
    // Initiate segmented download, size 100 (s).
    assert_eq!(
        request(&mut bus, &mut node, [0x21, 0x00, 0x20, 0x00, 100, 0, 0, 0]),
        ["583: 60 00 20 00 00 00 00 00"]
    );
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    assert_eq!(chunks.len(), 15);
    let mut answers = Vec::new();
    for (i, chunk) in chunks.iter().enumerate() {
        let toggle = if i % 2 == 1 { 0x10 } else { 0 };
        let last = i + 1 == chunks.len();
        let unused = (7 - chunk.len()) as u8;
        let mut data = [0u8; 8];
        data[0] = toggle | unused << 1 | u8::from(last);
        data[1..1 + chunk.len()].copy_from_slice(chunk);
        answers.extend(request(&mut bus, &mut node, data));
    }
    assert_eq!(answers[0], "583: 20 00 00 00 00 00 00 00");
    assert_eq!(answers[1], "583: 30 00 00 00 00 00 00 00");
    // The 15th segment (toggle 0) carries 2 bytes: n = 5, c = 1.
    assert_eq!(answers[14], "583: 20 00 00 00 00 00 00 00");
    assert_eq!(node.od().string(), value);

    // Upload: the size indicated, then 15 segments, the last with n = 5 and c = 1.
    assert_eq!(
        request(&mut bus, &mut node, [0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        ["583: 41 00 20 00 64 00 00 00"]
    );
    let mut segments = Vec::new();
    for i in 0..15 {
        let toggle = if i % 2 == 1 { 0x10 } else { 0 };
        segments.extend(request(
            &mut bus,
            &mut node,
            [0x60 | toggle, 0, 0, 0, 0, 0, 0, 0],
        ));
    }
    assert_eq!(segments[0], "583: 00 41 42 43 44 45 46 47");
    assert_eq!(segments[1], "583: 10 48 49 4A 4B 4C 4D 4E");
    // Bytes 98 and 99: 'U' and 'V'.
    assert_eq!(segments[14], "583: 0B 55 56 00 00 00 00 00");
}

#[test]
fn a_download_beyond_the_capacity_is_refused_when_announced_and_when_exceeded() {
    let (mut node, mut bus) = booted();
    // 65,537 bytes announced for the 64 KiB domain: 0607 0012.
    assert_eq!(
        request(
            &mut bus,
            &mut node,
            [0x21, 0x50, 0x1F, 0x01, 0x01, 0x00, 0x01, 0x00]
        ),
        ["583: 80 50 1F 01 12 00 07 06"]
    );
    // A string of 120 bytes at most: the 18th segment (bytes 119..126) exceeds it.
    request(&mut bus, &mut node, [0x20, 0x00, 0x20, 0x00, 0, 0, 0, 0]);
    for i in 0..17 {
        let toggle = if i % 2 == 1 { 0x10 } else { 0 };
        let answer = request(&mut bus, &mut node, [toggle, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(answer.len(), 1);
        assert!(answer[0].starts_with("583: 20") || answer[0].starts_with("583: 30"));
    }
    assert_eq!(
        request(&mut bus, &mut node, [0x10, 1, 2, 3, 4, 5, 6, 7]),
        ["583: 80 00 20 00 12 00 07 06"]
    );
}
