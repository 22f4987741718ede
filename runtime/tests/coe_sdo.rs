//! CoE SDO through the runtime's SDO server (`ethercat::sdo`): the mailbox framing CoE adds to
//! CiA 301, byte for byte: normal transfers with data after the initiate and segments longer
//! than 7 bytes, answers as long as the mailbox allows, complete access, the caller's guard,
//! and aborts that name the request's index and sub-index.

use edsgen_runtime::ethercat::sdo::CoeSdoServer;
use edsgen_runtime::od::image::Layout;
use edsgen_runtime::{Access, DataType, EntryDescriptor, ObjectDictionary, SdoAbort};

const ENTRIES: [EntryDescriptor; 7] = [
    EntryDescriptor::new(0x1018, 0, DataType::Unsigned8, Access::Ro, false),
    EntryDescriptor::new(0x1018, 1, DataType::Unsigned32, Access::Ro, false),
    EntryDescriptor::new(0x1018, 2, DataType::Unsigned32, Access::Ro, false),
    EntryDescriptor::new(0x1C12, 0, DataType::Unsigned8, Access::Rw, false),
    EntryDescriptor::new(0x1C12, 1, DataType::Unsigned16, Access::Rw, false),
    EntryDescriptor::new(0x1C12, 2, DataType::Unsigned16, Access::Rw, false),
    EntryDescriptor::new(0x2000, 0, DataType::VisibleString, Access::Rw, false),
];
/// 1018h at 0, 1, 5; 1C12h at 9, 10, 12; 2000h at 14 (a 2-byte length and 30 bytes).
const OFFSETS: [u16; 7] = [0, 1, 5, 9, 10, 12, 14];
const IMAGE_SIZE: usize = 46;
static LAYOUT: Layout = Layout::new(&ENTRIES, &OFFSETS, &[], IMAGE_SIZE);

struct Od([u8; IMAGE_SIZE]);

impl Od {
    fn new() -> Self {
        let mut values = [0u8; IMAGE_SIZE];
        values[..9].copy_from_slice(&[2, 0xD8, 0x04, 0, 0, 0x52, 0x92, 0, 0]);
        Od(values)
    }
}

impl ObjectDictionary for Od {
    fn entry_count(&self) -> usize {
        ENTRIES.len()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        ENTRIES.get(position).copied()
    }
    fn capacity(&self, position: usize) -> Option<usize> {
        LAYOUT.capacity(position)
    }
    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        LAYOUT.value_len(&self.0, self.locate(index, sub)?)
    }
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        LAYOUT.read(&self.0, self.locate(index, sub)?, offset, buf)
    }
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let position = self.locate(index, sub)?;
        LAYOUT.write(&mut self.0, position, data)
    }
}

fn allow(_: u16, _: u8, _: &[u8]) -> Result<(), SdoAbort> {
    Ok(())
}

/// The answer to `request` with `room` bytes after the CoE header (the mailbox less 8).
fn ask(server: &mut CoeSdoServer, od: &mut Od, room: usize, request: &[u8]) -> Vec<u8> {
    let mut answer = vec![0xEE; room];
    let len = server
        .request(od, &allow, request, &mut answer)
        .expect("an answer");
    answer.truncate(len);
    answer
}

const STRING: &[u8; 30] = b"EtherCAT drive, 30 bytes long.";

#[test]
fn expedited_and_complete_access_uploads() {
    let (mut server, mut od) = (CoeSdoServer::new(), Od::new());
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]),
        [0x43, 0x18, 0x10, 1, 0xD8, 0x04, 0, 0]
    );
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]),
        [0x4F, 0x18, 0x10, 0, 2, 0, 0, 0]
    );
    // 1018h by complete access: sub 0, a padding byte, two UDINTs.
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x50, 0x18, 0x10, 0, 0, 0, 0, 0]),
        [0x51, 0x18, 0x10, 0, 10, 0, 0, 0, 2, 0, 0xD8, 0x04, 0, 0, 0x52, 0x92, 0, 0]
    );
    // From sub-index 1: the two UDINTs only.
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x50, 0x18, 0x10, 1, 0, 0, 0, 0]),
        [0x51, 0x18, 0x10, 1, 8, 0, 0, 0, 0xD8, 0x04, 0, 0, 0x52, 0x92, 0, 0]
    );
}

#[test]
fn a_long_download_in_long_segments_and_an_upload_as_long_as_the_mailbox_allows() {
    let (mut server, mut od) = (CoeSdoServer::new(), Od::new());
    // 30 bytes announced, 10 in the initiate, 20 in one segment of CoE's length.
    let mut initiate = vec![0x21, 0x00, 0x20, 0, 30, 0, 0, 0];
    initiate.extend_from_slice(&STRING[..10]);
    assert_eq!(
        ask(&mut server, &mut od, 24, &initiate),
        [0x60, 0x00, 0x20, 0, 0, 0, 0, 0]
    );
    let mut segment = vec![0x01];
    segment.extend_from_slice(&STRING[10..]);
    assert_eq!(
        ask(&mut server, &mut od, 24, &segment),
        [0x20, 0, 0, 0, 0, 0, 0, 0]
    );
    let mut value = [0u8; 30];
    assert_eq!(od.read(0x2000, 0, 0, &mut value), Ok(30));
    assert_eq!(&value, STRING);

    // Up again with 16 bytes of room: 8 in the initiate's answer, 15 and 7 in segments.
    let first = ask(&mut server, &mut od, 16, &[0x40, 0x00, 0x20, 0, 0, 0, 0, 0]);
    assert_eq!(first[..8], [0x41, 0x00, 0x20, 0, 30, 0, 0, 0]);
    assert_eq!(first[8..], STRING[..8]);
    let second = ask(&mut server, &mut od, 16, &[0x60, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(second[0], 0x00);
    assert_eq!(second[1..], STRING[8..23]);
    let third = ask(&mut server, &mut od, 16, &[0x70, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(third[0], 0x11);
    assert_eq!(third[1..], STRING[23..]);
    // The transfer is over: another segment request is none.
    assert_eq!(
        ask(&mut server, &mut od, 16, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x80, 0, 0, 0, 0x01, 0x00, 0x04, 0x05]
    );
}

#[test]
fn a_download_of_whole_segments_ends_with_the_last_one() {
    let (mut server, mut od) = (CoeSdoServer::new(), Od::new());
    // 14 bytes: 7 in the initiate, 7 in a classic 8-byte last segment.
    let mut initiate = vec![0x21, 0x00, 0x20, 0, 14, 0, 0, 0];
    initiate.extend_from_slice(&STRING[..7]);
    ask(&mut server, &mut od, 24, &initiate);
    let mut segment = vec![0x01];
    segment.extend_from_slice(&STRING[7..14]);
    assert_eq!(
        ask(&mut server, &mut od, 24, &segment),
        [0x20, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(od.value_len(0x2000, 0), Ok(14));
    // A length that differs from the announced one is aborted (the value is the dictionary's
    // to keep: this one's default `write_part` is not all or nothing), naming the transfer's
    // entry 2000h:00 (CiA 301 §7.2.4.3.17), not the segment's data.
    ask(&mut server, &mut od, 24, &initiate);
    let short = [0x01 | (3 << 1), b'x', b'y', b'z', b'w', 0, 0, 0];
    assert_eq!(
        ask(&mut server, &mut od, 24, &short),
        [0x80, 0x00, 0x20, 0, 0x10, 0x00, 0x07, 0x06]
    );
}

#[test]
fn a_complete_access_download_writes_the_whole_object() {
    let (mut server, mut od) = (CoeSdoServer::new(), Od::new());
    let request = [
        0x31, 0x12, 0x1C, 0, 6, 0, 0, 0, 2, 0, 0x01, 0x16, 0x02, 0x16,
    ];
    assert_eq!(
        ask(&mut server, &mut od, 24, &request),
        [0x60, 0x12, 0x1C, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x50, 0x12, 0x1C, 0, 0, 0, 0, 0]),
        [0x51, 0x12, 0x1C, 0, 6, 0, 0, 0, 2, 0, 0x01, 0x16, 0x02, 0x16]
    );
    // The guard refuses: abort 0800 0022, naming the request's entry.
    let refuse = |_: u16, _: u8, _: &[u8]| Err(SdoAbort::DeviceState);
    let mut answer = [0u8; 24];
    let len = server.request(&mut od, &refuse, &request, &mut answer);
    assert_eq!(
        answer[..len.unwrap()],
        [0x80, 0x12, 0x1C, 0, 0x22, 0x00, 0x00, 0x08]
    );
    // Read-only entries stay read-only by complete access.
    assert_eq!(
        ask(
            &mut server,
            &mut od,
            24,
            &[0x31, 0x18, 0x10, 1, 4, 0, 0, 0, 1, 2, 3, 4]
        ),
        [0x80, 0x18, 0x10, 1, 0x02, 0x00, 0x01, 0x06]
    );
}

#[test]
fn an_upload_into_the_smallest_room_continues_in_segments() {
    let (mut server, mut od) = (CoeSdoServer::new(), Od::new());
    assert_eq!(
        ask(&mut server, &mut od, 8, &[0x50, 0x18, 0x10, 1, 0, 0, 0, 0]),
        [0x51, 0x18, 0x10, 1, 8, 0, 0, 0]
    );
    assert_eq!(
        ask(&mut server, &mut od, 8, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        [0x00, 0xD8, 0x04, 0, 0, 0x52, 0x92, 0]
    );
    assert_eq!(
        ask(&mut server, &mut od, 8, &[0x70, 0, 0, 0, 0, 0, 0, 0]),
        [0x1D, 0, 0, 0, 0, 0, 0, 0]
    );
}

#[test]
fn aborts_name_the_requests_entry() {
    let (mut server, mut od) = (CoeSdoServer::new(), Od::new());
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0xE0, 0x40, 0x60, 5, 0, 0, 0, 0]),
        [0x80, 0x40, 0x60, 5, 0x01, 0x00, 0x04, 0x05]
    );
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x40, 0x34, 0x12, 0, 0, 0, 0, 0]),
        [0x80, 0x34, 0x12, 0, 0x00, 0x00, 0x02, 0x06]
    );
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x23, 0x18, 0x10, 1, 1, 2, 3, 4]),
        [0x80, 0x18, 0x10, 1, 0x02, 0x00, 0x01, 0x06]
    );
    // A wrong toggle in an upload.
    ask(&mut server, &mut od, 16, &[0x40, 0x00, 0x20, 0, 0, 0, 0, 0]);
    let mut answer = [0u8; 16];
    assert_eq!(
        server.request(&mut od, &allow, &[0x80, 0, 0, 0, 0, 0, 0, 0], &mut answer),
        None
    );
    assert_eq!(
        ask(
            &mut server,
            &mut od,
            24,
            &[0x21, 0x00, 0x20, 0, 9, 0, 0, 0, 1]
        ),
        [0x60, 0x00, 0x20, 0, 0, 0, 0, 0]
    );
    // A segment with the wrong toggle: the abort names the transfer's entry, 2000h:00, not
    // the segment's data bytes.
    assert_eq!(
        ask(
            &mut server,
            &mut od,
            24,
            &[0x11, 0x33, 0x44, 0x55, 0, 0, 0, 0]
        ),
        [0x80, 0x00, 0x20, 0, 0x00, 0x00, 0x03, 0x05]
    );
    // A segment without a transfer names none.
    assert_eq!(
        ask(&mut server, &mut od, 24, &[0x60, 0x18, 0x10, 1, 0, 0, 0, 0]),
        [0x80, 0, 0, 0, 0x01, 0x00, 0x04, 0x05]
    );
}
