//! SDO downloads apply all or nothing (issue 21), on a node serving a dictionary built as a
//! generated `Od` is (a value image laid out by `image::Layout`, strings and domains staged in a
//! `Stage`): every way a download can end badly (toggle error, wrong CRC, sequence error,
//! timeout, abort from the client, new initiate, NMT reset or stop during the transfer), on both
//! SDO channels (1200h and 1201h), for expedited, segmented and block transfers, leaves the entry
//! with its old value and emits no `Written` event; afterwards the entry takes a complete
//! download on the other channel, so the broken one released the stage. Then a property test:
//! random interleavings of good and broken downloads on both channels, after which the
//! dictionary equals the result of applying only the completed ones.

mod node_support;

use edsgen_runtime::node::{Event, Node};
use edsgen_runtime::od::image::Layout;
use edsgen_runtime::od::stage::Stage;
use edsgen_runtime::{
    Access, CanFrame, DataType, Duration, EntryDescriptor, Instant, ObjectDictionary, SdoAbort,
};
use node_support::{frame, ms};

const NODE_ID: u8 = 3;

const ENTRIES: [EntryDescriptor; 8] = [
    EntryDescriptor::new(0x1000, 0, DataType::Unsigned32, Access::Ro, false),
    EntryDescriptor::new(0x1200, 0, DataType::Unsigned8, Access::Const, false),
    EntryDescriptor::new(0x1201, 0, DataType::Unsigned8, Access::Const, false),
    EntryDescriptor::new(0x1201, 1, DataType::Unsigned32, Access::Rw, false),
    EntryDescriptor::new(0x1201, 2, DataType::Unsigned32, Access::Rw, false),
    EntryDescriptor::new(0x2000, 0, DataType::Unsigned64, Access::Rw, false),
    EntryDescriptor::new(0x2001, 0, DataType::VisibleString, Access::Rw, false),
    EntryDescriptor::new(0x2002, 0, DataType::Domain, Access::Rw, false),
];
/// 1000h at 0, 1200h:00 at 4, 1201h at 5, 6 and 10, 2000h (8 bytes) at 14, 2001h (a 2-byte
/// length and 20 bytes) at 22, 2002h (a 2-byte length and 40 bytes) at 44.
const OFFSETS: [u16; 8] = [0, 4, 5, 6, 10, 14, 22, 44];
const IMAGE_SIZE: usize = 86;
static LAYOUT: Layout = Layout::new(&ENTRIES, &OFFSETS, &[], IMAGE_SIZE);
/// The largest writable string or domain, as a generated `Od`'s `STAGE_SIZE`.
const STAGE_SIZE: usize = 40;

/// The entries downloaded here: a fixed-size value (collected by the server), a string and a
/// domain (staged by the dictionary).
const TARGETS: [(u16, &[u8], &[u8]); 3] = [
    (0x2000, b"\x88\x77\x66\x55\x44\x33\x22\x11", b"ABCDEFGH"),
    (0x2001, b"abc", b"abcdefghijklmn"),
    (
        0x2002,
        b"\xD0\xD1\xD2\xD3\xD4\xD5\xD6\xD7\xD8",
        b"0123456789abcdefghijklmnopqrstuvwxyz",
    ),
];

/// The dictionary: the generated `Od`'s implementation, by hand.
#[derive(Debug, Clone, PartialEq)]
struct AtomicOd {
    values: [u8; IMAGE_SIZE],
    stage: Stage<STAGE_SIZE>,
    /// What `services` says of writable strings and domains (`Services::streamed_writes`).
    streamed_writes: bool,
}

impl AtomicOd {
    fn new() -> Self {
        let mut od = AtomicOd {
            values: [0; IMAGE_SIZE],
            stage: Stage::new(),
            streamed_writes: true,
        };
        let init: [(usize, &[u8]); 5] = [
            (1, &[2]),
            (2, &[2]),
            (3, &0x640u32.to_le_bytes()),
            (4, &0x5C0u32.to_le_bytes()),
            (0, &0x0000_0192u32.to_le_bytes()),
        ];
        for (position, value) in init {
            LAYOUT.write(&mut od.values, position, value).unwrap();
        }
        for (index, old, _) in TARGETS {
            let position = od.locate(index, 0).unwrap();
            LAYOUT.write(&mut od.values, position, old).unwrap();
        }
        od
    }

    fn value(&self, index: u16) -> Vec<u8> {
        let mut buf = [0u8; 64];
        let len = self.read(index, 0, 0, &mut buf).unwrap();
        buf[..len].to_vec()
    }
}

impl ObjectDictionary for AtomicOd {
    fn services(&self) -> edsgen_runtime::Services {
        edsgen_runtime::Services {
            streamed_writes: self.streamed_writes,
            ..edsgen_runtime::Services::ALL
        }
    }

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
        LAYOUT.value_len(&self.values, self.locate(index, sub)?)
    }
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.read_at(self.locate(index, sub)?, offset, buf)
    }
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        self.write_at(self.locate(index, sub)?, data)
    }
    fn read_at(&self, position: usize, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        LAYOUT.read(&self.values, position, offset, buf)
    }
    fn write_at(&mut self, position: usize, data: &[u8]) -> Result<(), SdoAbort> {
        LAYOUT.write(&mut self.values, position, data)
    }
    fn begin_write(&mut self, position: usize) -> Result<(), SdoAbort> {
        self.stage.begin(position)
    }
    fn write_part(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        self.stage.write(position, offset, data)
    }
    fn commit_write(&mut self, position: usize, len: usize) -> Result<(), SdoAbort> {
        let value = self.stage.commit(position, len)?;
        LAYOUT.write(&mut self.values, position, value)
    }
    fn abort_write(&mut self, position: usize) {
        self.stage.abort(position)
    }
}

/// The two SDO server channels: (name, request COB-ID, response COB-ID).
const CHANNELS: [(&str, u16, u16); 2] = [("1200h", 0x603, 0x583), ("1201h", 0x640, 0x5C0)];

struct Rig {
    node: Node<AtomicOd>,
    now: Instant,
}

impl Rig {
    fn new() -> Self {
        let mut rig = Rig {
            node: Node::new(AtomicOd::new(), NODE_ID, ms(0)).unwrap(),
            now: ms(0),
        };
        rig.drain();
        rig
    }

    /// Every frame the node has to send, and every `Written` event, since the last call.
    fn drain(&mut self) -> (Vec<CanFrame>, Vec<(u16, u8)>) {
        let mut frames = Vec::new();
        while let Some(frame) = self.node.poll_transmit(self.now) {
            frames.push(frame);
        }
        let mut written = Vec::new();
        while let Some(event) = self.node.poll_event() {
            if let Event::Written { index, sub } = event {
                written.push((index, sub));
            }
        }
        (frames, written)
    }

    /// Sends `data` to COB-ID `id`; returns the node's answers on `response` and the `Written`
    /// events.
    fn send(&mut self, id: u16, response: u16, data: &[u8]) -> (Vec<[u8; 8]>, Vec<(u16, u8)>) {
        self.node.handle_frame(self.now, &frame(id, data));
        let (frames, written) = self.drain();
        let answers = frames
            .iter()
            .filter(|f| f.std_id() == Some(response))
            .map(|f| f.data().try_into().unwrap())
            .collect();
        (answers, written)
    }

    /// Lets `millis` pass and runs the node's timers.
    fn wait(&mut self, millis: u64) {
        self.now = self.now + Duration::from_millis(millis);
        if self.node.poll_timeout().is_some_and(|at| at <= self.now) {
            self.node.handle_timeout(self.now);
        }
    }
}

fn mux(index: u16) -> [u8; 3] {
    let [lo, hi] = index.to_le_bytes();
    [lo, hi, 0]
}

fn with_mux(command: u8, index: u16, value: u32) -> [u8; 8] {
    let [a, b, c] = mux(index);
    let [v0, v1, v2, v3] = value.to_le_bytes();
    [command, a, b, c, v0, v1, v2, v3]
}

fn abort(index: u16, code: SdoAbort) -> [u8; 8] {
    with_mux(0x80, index, code.code())
}

/// A segmented download's frames: the initiate request (size indicated) and the segments.
fn segmented(index: u16, value: &[u8]) -> Vec<[u8; 8]> {
    let mut frames = vec![with_mux(0x21, index, value.len() as u32)];
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    for (n, chunk) in chunks.iter().enumerate() {
        let last = n + 1 == chunks.len();
        let toggle = (n % 2) as u8;
        let mut segment = [0u8; 8];
        segment[0] = toggle << 4 | ((7 - chunk.len()) as u8) << 1 | u8::from(last);
        segment[1..=chunk.len()].copy_from_slice(chunk);
        frames.push(segment);
    }
    frames
}

/// A block download's frames: the initiate request (CRC, size indicated), one sub-block of
/// segments and the end request with `crc`.
#[cfg(feature = "sdo-block")]
fn block(index: u16, value: &[u8], crc: u16) -> Vec<[u8; 8]> {
    let mut frames = vec![with_mux(0xC6, index, value.len() as u32)];
    let chunks: Vec<&[u8]> = value.chunks(7).collect();
    for (n, chunk) in chunks.iter().enumerate() {
        let last = n + 1 == chunks.len();
        let mut segment = [0u8; 8];
        segment[0] = (n + 1) as u8 | if last { 0x80 } else { 0 };
        segment[1..=chunk.len()].copy_from_slice(chunk);
        frames.push(segment);
    }
    let unused = (7 - chunks.last().map_or(0, |c| c.len())) as u8;
    let [c0, c1] = crc.to_le_bytes();
    frames.push([0xC1 | unused << 2, c0, c1, 0, 0, 0, 0, 0]);
    frames
}

#[cfg(feature = "sdo-block")]
fn crc(value: &[u8]) -> u16 {
    let mut crc = edsgen_runtime::sdo::crc::Crc16::new();
    crc.update(value);
    crc.value()
}

/// Completes a segmented download of `value` into `index` on `channel`: the entry takes it and
/// one `Written` event says so (the stage is free again after whatever went before).
fn complete_download(rig: &mut Rig, channel: usize, index: u16, value: &[u8]) {
    let (_, rx, tx) = CHANNELS[channel];
    let mut written = Vec::new();
    for request in segmented(index, value) {
        let (answers, events) = rig.send(rx, tx, &request);
        assert_eq!(answers.len(), 1, "one answer to {request:02X?}");
        assert_ne!(answers[0][0], 0x80, "abort {:02X?}", answers[0]);
        written.extend(events);
    }
    assert_eq!(written, [(index, 0)]);
    assert_eq!(rig.node.od().value(index), value);
}

/// How a download ends badly, and what the node answers to the frame that ends it.
#[derive(Debug, Clone, Copy)]
#[cfg_attr(not(feature = "sdo-block"), allow(dead_code))]
enum Ending {
    /// A segment with the toggle bit of the one before: 0503 0000.
    ToggleError,
    /// The end request with a CRC that does not match: 0504 0004.
    WrongCrc,
    /// A sub-block segment with sequence number 0 (`00`): 0504 0003.
    SequenceZero,
    /// `80` within a sub-block (sequence number 0, last segment): 0504 0003.
    SequenceZeroLast,
    /// No request for longer than the SDO timeout: 0504 0000.
    Timeout,
    /// The client's abort request: no answer.
    ClientAbort,
    /// A new initiate (an upload of the same entry) replaces the download: the upload's answer,
    /// which carries the old value.
    NewInitiate,
    /// NMT reset communication: the boot-up message, no SDO answer.
    ResetCommunication,
    /// NMT reset node: the same, and the entry at its power-on value (its old one here).
    ResetNode,
    /// NMT stop: SDO is not served in stopped.
    Stop,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Segmented,
    #[cfg(feature = "sdo-block")]
    Block,
}

/// Runs a download of `new` into `index` on `channel` that ends with `ending` after the first
/// `sent` frames, and checks the node's answer to the ending frame.
fn broken_download(
    rig: &mut Rig,
    channel: usize,
    kind: Kind,
    index: u16,
    new: &[u8],
    sent: usize,
    ending: Ending,
) {
    let (name, rx, tx) = CHANNELS[channel];
    let frames = match kind {
        Kind::Segmented => segmented(index, new),
        #[cfg(feature = "sdo-block")]
        Kind::Block => block(index, new, crc(new)),
    };
    // `usize::MAX`: every frame but the end request.
    let sent = sent.min(frames.len() - 1);
    let context = format!("{name} {kind:?} {index:04X}h {ending:?} after {sent} frames");
    for request in &frames[..sent] {
        let (answers, written) = rig.send(rx, tx, request);
        assert!(
            answers.iter().all(|a| a[0] != 0x80),
            "{context}: {answers:02X?}"
        );
        assert_eq!(written, [], "{context}");
    }
    let (answers, written) = match ending {
        Ending::ToggleError => {
            let mut repeated = frames[sent - 1];
            repeated[0] &= !1;
            rig.send(rx, tx, &repeated)
        }
        Ending::WrongCrc => {
            for request in &frames[sent..frames.len() - 1] {
                rig.send(rx, tx, request);
            }
            let mut end = frames[frames.len() - 1];
            end[1] ^= 1;
            rig.send(rx, tx, &end)
        }
        Ending::SequenceZero => rig.send(rx, tx, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        Ending::SequenceZeroLast => rig.send(rx, tx, &[0x80, 1, 2, 3, 4, 5, 6, 7]),
        Ending::Timeout => {
            rig.wait(999);
            assert_eq!(
                rig.drain(),
                (vec![], vec![]),
                "{context}: before the timeout"
            );
            rig.wait(1);
            let (frames, written) = rig.drain();
            let answers = frames
                .iter()
                .filter(|f| f.std_id() == Some(tx))
                .map(|f| f.data().try_into().unwrap())
                .collect();
            (answers, written)
        }
        Ending::ClientAbort => rig.send(rx, tx, &abort(index, SdoAbort::General)),
        Ending::NewInitiate => rig.send(rx, tx, &with_mux(0x40, index, 0)),
        Ending::ResetCommunication => rig.send(0x000, tx, &[0x82, NODE_ID]),
        Ending::ResetNode => rig.send(0x000, tx, &[0x81, NODE_ID]),
        Ending::Stop => rig.send(0x000, tx, &[0x02, NODE_ID]),
    };
    let expected: Vec<[u8; 8]> = match ending {
        Ending::ToggleError => vec![abort(index, SdoAbort::ToggleBit)],
        Ending::WrongCrc => vec![abort(index, SdoAbort::CrcError)],
        Ending::SequenceZero | Ending::SequenceZeroLast => {
            vec![abort(index, SdoAbort::InvalidSequence)]
        }
        Ending::Timeout => vec![abort(index, SdoAbort::Timeout)],
        Ending::NewInitiate => {
            let old = rig.node.od().value(index);
            if old.len() <= 4 {
                // Expedited, the size indicated.
                let mut value = [0u8; 4];
                value[..old.len()].copy_from_slice(&old);
                let command = 0x43 | ((4 - old.len()) as u8) << 2;
                vec![with_mux(command, index, u32::from_le_bytes(value))]
            } else {
                vec![with_mux(0x41, index, old.len() as u32)]
            }
        }
        Ending::ClientAbort | Ending::ResetCommunication | Ending::ResetNode | Ending::Stop => {
            vec![]
        }
    };
    assert_eq!(answers, expected, "{context}");
    assert_eq!(written, [], "{context}");
    if let Ending::NewInitiate = ending {
        // End the upload, so that the next download starts on an idle channel.
        rig.send(rx, tx, &abort(index, SdoAbort::General));
    }
    if let Ending::Stop = ending {
        rig.send(0x000, tx, &[0x80, NODE_ID]);
    }
}

/// Which endings apply to which transfer, and after how many frames they strike.
fn cases() -> Vec<(Kind, Ending, usize)> {
    #[cfg_attr(not(feature = "sdo-block"), allow(unused_mut))]
    let mut cases = vec![
        (Kind::Segmented, Ending::ToggleError, 2),
        (Kind::Segmented, Ending::Timeout, 1),
        (Kind::Segmented, Ending::Timeout, 2),
        (Kind::Segmented, Ending::ClientAbort, 2),
        (Kind::Segmented, Ending::NewInitiate, 2),
        (Kind::Segmented, Ending::ResetCommunication, 2),
        (Kind::Segmented, Ending::ResetNode, 2),
        (Kind::Segmented, Ending::Stop, 2),
    ];
    #[cfg(feature = "sdo-block")]
    cases.extend([
        (Kind::Block, Ending::WrongCrc, 1),
        (Kind::Block, Ending::SequenceZero, 2),
        (Kind::Block, Ending::SequenceZeroLast, 2),
        (Kind::Block, Ending::Timeout, 2),
        // The client's abort and a new initiate after the sub-block (within one, every frame
        // is a segment).
        (Kind::Block, Ending::ClientAbort, usize::MAX),
        (Kind::Block, Ending::NewInitiate, usize::MAX),
        (Kind::Block, Ending::ResetCommunication, 2),
        (Kind::Block, Ending::ResetNode, 2),
        (Kind::Block, Ending::Stop, 2),
    ]);
    cases
}

#[test]
fn every_broken_download_leaves_the_entry_and_emits_no_written_event() {
    let mut checked = 0;
    for (channel, (name, _, _)) in CHANNELS.iter().enumerate() {
        for (kind, ending, sent) in cases() {
            for (index, old, new) in TARGETS {
                let mut rig = Rig::new();
                let before = rig.node.od().clone();
                broken_download(&mut rig, channel, kind, index, new, sent, ending);
                assert_eq!(
                    rig.node.od().value(index),
                    old,
                    "{name} {kind:?} {index:04X}h {ending:?}"
                );
                assert_eq!(rig.node.od(), &before);
                // Nothing was left open: the other channel completes a download.
                complete_download(&mut rig, 1 - channel, index, new);
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 2 * cases().len() * TARGETS.len());
}

/// A dictionary that says it has no writable string or domain (`streamed_writes: false`, as a
/// generated one without them does) gets no streaming code in its server: were it to have one
/// after all, the server collects a download of up to 8 bytes and writes it whole, refuses a
/// longer one with 0607 0012 at the segment that passes 8 bytes, and leaves the stage unused.
#[test]
fn without_streamed_writes_a_download_is_collected_and_written_whole() {
    let mut rig = Rig::new();
    rig.node.od_mut().streamed_writes = false;
    let (_, rx, tx) = CHANNELS[0];
    complete_download(&mut rig, 0, 0x2000, b"12345678");
    complete_download(&mut rig, 0, 0x2001, b"short");
    let old = rig.node.od().value(0x2002);
    let frames = segmented(0x2002, b"0123456789");
    let (answers, _) = rig.send(rx, tx, &frames[0]);
    assert_eq!(answers, [with_mux(0x60, 0x2002, 0)]);
    let (answers, _) = rig.send(rx, tx, &frames[1]);
    assert_eq!(answers, [[0x20, 0, 0, 0, 0, 0, 0, 0]]);
    let (answers, written) = rig.send(rx, tx, &frames[2]);
    assert_eq!(answers, [abort(0x2002, SdoAbort::LengthTooHigh)]);
    assert!(written.is_empty());
    assert_eq!(rig.node.od().value(0x2002), old);
    assert_eq!(rig.node.od().stage, Stage::new());
}

#[test]
fn refused_expedited_downloads_leave_the_entry_on_both_channels() {
    for (_, rx, tx) in CHANNELS {
        let mut rig = Rig::new();
        let before = rig.node.od().clone();
        // 4 bytes for an 8-byte value; no size for a string (how many bytes are meant?); an
        // entry that does not exist.
        for (request, code) in [
            (with_mux(0x23, 0x2000, 0x1234_5678), SdoAbort::LengthTooLow),
            (
                with_mux(0x22, 0x2001, 0x6463_6261),
                SdoAbort::LengthMismatch,
            ),
            (with_mux(0x23, 0x2003, 1), SdoAbort::NoObject),
        ] {
            let index = u16::from_le_bytes([request[1], request[2]]);
            assert_eq!(
                rig.send(rx, tx, &request),
                (vec![abort(index, code)], vec![])
            );
        }
        assert_eq!(rig.node.od(), &before);
        // An expedited download that completes is applied at once.
        assert_eq!(
            rig.send(rx, tx, &with_mux(0x27, 0x2001, 0x0078_7978)),
            (vec![with_mux(0x60, 0x2001, 0)], vec![(0x2001, 0)])
        );
        assert_eq!(rig.node.od().value(0x2001), b"xyx");
    }
}

#[test]
fn one_staged_download_at_a_time_the_other_channel_is_refused_with_060a_0023() {
    let mut rig = Rig::new();
    let (_, rx0, tx0) = CHANNELS[0];
    let (_, rx1, tx1) = CHANNELS[1];
    let first = segmented(0x2001, b"abcdefghijklmn");
    rig.send(rx0, tx0, &first[0]);
    rig.send(rx0, tx0, &first[1]);
    // The string's stage is taken: a download of the domain on 1201h is refused...
    assert_eq!(
        rig.send(rx1, tx1, &segmented(0x2002, b"01234567")[0]),
        (vec![abort(0x2002, SdoAbort::NoResource)], vec![])
    );
    // ... while a fixed-size value, collected by the server, goes through.
    complete_download(&mut rig, 1, 0x2000, b"ABCDEFGH");
    // The refusal did not end the first download.
    assert_eq!(
        rig.send(rx0, tx0, &first[2]),
        (vec![[0x30, 0, 0, 0, 0, 0, 0, 0]], vec![(0x2001, 0)])
    );
    assert_eq!(rig.node.od().value(0x2001), b"abcdefghijklmn");
    assert_eq!(rig.node.od().value(0x2002), TARGETS[2].1);
}

// ---------------------------------------------------------------------------------------------
// Random interleavings.

mod interleavings {
    use super::*;
    use proptest::prelude::*;

    /// One step of the script both channels follow.
    #[derive(Debug, Clone)]
    enum Step {
        /// A new download on `channel`: target `target`, `len` bytes of `fill`, block or not.
        Start {
            channel: usize,
            target: usize,
            len: usize,
            fill: u8,
            block: bool,
        },
        /// The next frame of `channel`'s download.
        Next { channel: usize },
        /// `channel`'s download broken by a frame: the client's abort, or a toggle error
        /// (segmented) or a wrong CRC (block, its remaining segments sent first).
        Break { channel: usize, client_abort: bool },
        /// The SDO timeout passes.
        Timeout,
        /// NMT reset communication.
        Reset,
    }

    fn step() -> impl Strategy<Value = Step> {
        prop_oneof![
            2 => (0..2usize, 0..3usize, 1..=6usize, any::<u8>(), any::<bool>()).prop_map(
                |(channel, target, len, fill, block)| Step::Start {
                    channel,
                    target,
                    len,
                    fill,
                    block,
                }
            ),
            6 => (0..2usize).prop_map(|channel| Step::Next { channel }),
            1 => (0..2usize, any::<bool>())
                .prop_map(|(channel, client_abort)| Step::Break { channel, client_abort }),
            1 => Just(Step::Timeout),
            1 => Just(Step::Reset),
        ]
    }

    /// A download in flight, as the script knows it.
    struct InFlight {
        index: u16,
        value: Vec<u8>,
        frames: Vec<[u8; 8]>,
        sent: usize,
        block: bool,
        /// Whether its value goes through the dictionary's stage (a string or domain).
        staged: bool,
    }

    /// The values of a target of each kind for `len` and `fill`: the fixed-size value's 8
    /// bytes, or a string or domain of `len * 3` bytes (up to 18: up to 3 segments).
    fn value(target: usize, len: usize, fill: u8) -> Vec<u8> {
        let len = if target == 0 { 8 } else { len * 3 };
        (0..len).map(|i| fill.wrapping_add(i as u8)).collect()
    }

    fn run(steps: &[Step]) -> Result<(), TestCaseError> {
        let mut rig = Rig::new();
        let mut model: Vec<Vec<u8>> = TARGETS.iter().map(|t| t.1.to_vec()).collect();
        let mut flight: [Option<InFlight>; 2] = [None, None];
        // The channel whose download holds the dictionary's stage.
        let mut stage: Option<usize> = None;
        for step in steps {
            match *step {
                Step::Start {
                    channel,
                    target,
                    len,
                    fill,
                    block,
                } => {
                    let (_, rx, tx) = CHANNELS[channel];
                    // The new initiate replaces the channel's download; within a block
                    // download's sub-block, where every frame is a segment, the client aborts
                    // first (`80`, aborted in turn with 0504 0003).
                    if let Some(download) = flight[channel].take() {
                        if download.block && download.sent < download.frames.len() - 1 {
                            let (answers, written) =
                                rig.send(rx, tx, &abort(download.index, SdoAbort::General));
                            prop_assert_eq!(
                                answers,
                                vec![abort(download.index, SdoAbort::InvalidSequence)]
                            );
                            prop_assert_eq!(written, vec![]);
                        }
                        if stage == Some(channel) {
                            stage = None;
                        }
                    }
                    let (index, _, _) = TARGETS[target];
                    let value = value(target, len, fill);
                    #[cfg(feature = "sdo-block")]
                    let frames = if block {
                        super::block(index, &value, crc(&value))
                    } else {
                        segmented(index, &value)
                    };
                    #[cfg(not(feature = "sdo-block"))]
                    let (frames, block) = {
                        let _ = block;
                        (segmented(index, &value), false)
                    };
                    let staged = target != 0;
                    let (answers, written) = rig.send(rx, tx, &frames[0]);
                    prop_assert_eq!(written, vec![]);
                    if staged && stage.is_some_and(|other| other != channel) {
                        prop_assert_eq!(answers, vec![abort(index, SdoAbort::NoResource)]);
                    } else {
                        prop_assert_eq!(answers.len(), 1);
                        prop_assert_ne!(answers[0][0], 0x80);
                        if staged {
                            stage = Some(channel);
                        }
                        flight[channel] = Some(InFlight {
                            index,
                            value,
                            frames,
                            sent: 1,
                            block,
                            staged,
                        });
                    }
                }
                Step::Next { channel } => {
                    let (_, rx, tx) = CHANNELS[channel];
                    let Some(download) = flight[channel].as_mut() else {
                        continue;
                    };
                    let request = download.frames[download.sent];
                    download.sent += 1;
                    let (answers, written) = rig.send(rx, tx, &request);
                    prop_assert!(answers.iter().all(|a| a[0] != 0x80), "{:02X?}", answers);
                    if download.sent == download.frames.len() {
                        prop_assert_eq!(written, vec![(download.index, 0)]);
                        let target = TARGETS.iter().position(|t| t.0 == download.index);
                        model[target.unwrap_or(0)] = download.value.clone();
                        if download.staged {
                            stage = None;
                        }
                        flight[channel] = None;
                    } else {
                        prop_assert_eq!(written, vec![]);
                    }
                }
                Step::Break {
                    channel,
                    client_abort,
                } => {
                    let (_, rx, tx) = CHANNELS[channel];
                    let Some(download) = flight[channel].take() else {
                        continue;
                    };
                    if download.staged {
                        stage = None;
                    }
                    let last = download.frames.len() - 1;
                    let request = if client_abort {
                        if download.block && download.sent < last {
                            // Within the sub-block: the rest of it first.
                            for request in &download.frames[download.sent..last] {
                                rig.send(rx, tx, request);
                            }
                        }
                        abort(download.index, SdoAbort::General)
                    } else if download.block {
                        for request in &download.frames[download.sent..last] {
                            rig.send(rx, tx, request);
                        }
                        let mut end = download.frames[last];
                        end[1] ^= 0x5A;
                        end
                    } else if download.sent >= 2 {
                        let mut repeated = download.frames[download.sent - 1];
                        repeated[0] &= !1;
                        repeated
                    } else {
                        // No segment yet: one with the wrong toggle bit.
                        let mut segment = download.frames[1];
                        segment[0] ^= 0x10;
                        segment
                    };
                    let (_, written) = rig.send(rx, tx, &request);
                    prop_assert_eq!(written, vec![]);
                }
                Step::Timeout => {
                    rig.wait(1_000);
                    flight = [None, None];
                    stage = None;
                    prop_assert_eq!(rig.drain().1, vec![]);
                }
                Step::Reset => {
                    let (_, written) = rig.send(0x000, 0x583, &[0x82, NODE_ID]);
                    prop_assert_eq!(written, vec![]);
                    flight = [None, None];
                    stage = None;
                }
            }
            for (target, (index, _, _)) in TARGETS.iter().enumerate() {
                prop_assert_eq!(
                    &rig.node.od().value(*index),
                    &model[target],
                    "{:04X}h",
                    index
                );
            }
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        #[test]
        fn the_dictionary_holds_exactly_the_completed_downloads(
            steps in proptest::collection::vec(step(), 1..60)
        ) {
            run(&steps)?;
        }
    }
}
