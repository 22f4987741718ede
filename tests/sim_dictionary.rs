//! The run-time object dictionary (`edsgen_sim::canopen::RuntimeDictionary`): built from a model, it
//! answers every SDO request exactly as the `Od` generated from the same file, resolves
//! `$NODEID`, honours a DCF, checks lengths and limits, and serves a `Node` on the virtual bus
//! for every SDO transfer type and PDO mapping changes; a node serving each corpus device
//! answers an upload of every entry.

mod process_support;
#[path = "../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::path::Path;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::sdo::crc::crc16;
use edsgen_runtime::{CanFrame, DataType, Instant, Node, ObjectDictionary, ResetKind, SdoAbort};
use edsgen_sim::canopen::{commissioned_node_id, DictionaryHooks, RuntimeDictionary};
use process_support::corpus_dir;
use sim_support::{test_dcf, test_device};

fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// `605: 43 00 10 00 92 01 02 00` for a frame.
fn show(frame: &CanFrame) -> String {
    let bytes: Vec<String> = frame.data().iter().map(|b| format!("{b:02X}")).collect();
    format!("{:03X}: {}", frame.std_id().unwrap(), bytes.join(" "))
}

fn read_value(od: &impl ObjectDictionary, index: u16, sub: u8) -> Vec<u8> {
    let mut buf = vec![0u8; od.value_len(index, sub).unwrap()];
    let n = od.read(index, sub, 0, &mut buf).unwrap();
    buf.truncate(n);
    buf
}

/// Every SDO request of the equivalence test, against node 5: an upload of every entry, then
/// for every writable entry of up to 4 bytes a write of all-zero, all-ones, one byte too many
/// and one too few, then every upload again; plus an absent object and an absent sub-index.
fn requests(entries: &[edsgen_runtime::EntryDescriptor]) -> Vec<CanFrame> {
    let upload = |index: u16, sub: u8| {
        let [lo, hi] = index.to_le_bytes();
        frame(0x605, &[0x40, lo, hi, sub, 0, 0, 0, 0])
    };
    let download = |index: u16, sub: u8, data: &[u8]| {
        let [lo, hi] = index.to_le_bytes();
        let mut bytes = [
            0x23 | ((4 - data.len() as u8) << 2),
            lo,
            hi,
            sub,
            0,
            0,
            0,
            0,
        ];
        bytes[4..4 + data.len()].copy_from_slice(data);
        frame(0x605, &bytes)
    };
    let mut list: Vec<CanFrame> = entries.iter().map(|e| upload(e.index(), e.sub())).collect();
    for e in entries.iter().filter(|e| e.access().writable()) {
        let Some(size) = e.data_type().fixed_size().filter(|&s| s <= 4) else {
            continue;
        };
        list.push(download(e.index(), e.sub(), &vec![0x00; size]));
        list.push(download(e.index(), e.sub(), &vec![0xFF; size]));
        if size < 4 {
            list.push(download(e.index(), e.sub(), &vec![0x01; size + 1]));
        }
        if size > 1 {
            list.push(download(e.index(), e.sub(), &vec![0x01; size - 1]));
        }
    }
    list.extend(entries.iter().map(|e| upload(e.index(), e.sub())));
    list.push(upload(0x5FFF, 0));
    list.push(upload(0x1018, 0x7F));
    list
}

/// What node 5 serving `od` answers to `requests`, one request per millisecond.
fn transcript(od: impl ObjectDictionary, requests: &[CanFrame]) -> Vec<String> {
    let mut node = Node::new(od, 5, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    for (i, request) in requests.iter().enumerate() {
        bus.run_until(ms(i as u64), &mut [&mut node]);
        bus.inject(*request, &mut [&mut node]);
    }
    bus.log()
        .iter()
        .filter(|(_, sender, _)| *sender == 0)
        .map(|(at, _, f)| format!("{} {}", at.as_micros() / 1000, show(f)))
        .collect()
}

/// Builds the run-time dictionary of `card` (in `eds/`) and checks it against the generated
/// `generated` through every request of [`requests`].
fn answers_as_generated(card: &str, generated: impl ObjectDictionary) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("eds").join(card);
    let device = edsgen_model::read::read_file(&path).unwrap().device;
    let runtime = RuntimeDictionary::new(&device, 5);
    let entries: Vec<_> = edsgen_runtime::od::descriptors(&generated)
        .map(|(_, e)| e)
        .collect();
    assert_eq!(entries.len(), generated.entry_count(), "{card}");
    assert_eq!(runtime.entries(), entries, "{card}");
    assert!(runtime.left_out().is_empty(), "{card}");
    for (position, entry) in entries.iter().enumerate() {
        assert_eq!(
            runtime.capacity(position),
            generated.capacity(position),
            "{card}"
        );
        // The generated dictionary answers from the position, the run-time one by the
        // trait's default (a search by the entry's index and sub-index): the same length.
        assert_eq!(
            generated.value_len_at(position),
            runtime.value_len(entry.index(), entry.sub()),
            "{card}"
        );
        assert_eq!(
            runtime.value_len_at(position),
            generated.value_len(entry.index(), entry.sub()),
            "{card}"
        );
    }
    let end = entries.len();
    assert_eq!(generated.value_len_at(end), Err(SdoAbort::NoObject));
    assert_eq!(runtime.value_len_at(end), Err(SdoAbort::NoObject));
    let requests = requests(&entries);
    let expected = transcript(generated, &requests);
    let got = transcript(runtime, &requests);
    // Every request is answered (the boot-up message first).
    assert_eq!(got.len(), requests.len() + 1, "{card}");
    assert_eq!(got, expected, "{card}");
}

#[test]
fn answers_every_sdo_request_exactly_as_the_generated_od_of_each_card() {
    use edsgen_sim::cards;
    answers_as_generated("cp301.eds", cards::cp301::Od::new(5));
    answers_as_generated("goodrive350.eds", cards::goodrive350::Od::new(5));
    answers_as_generated("hd1e.eds", cards::hd1e::Od::new(5));
    answers_as_generated("ms300.eds", cards::ms300::Od::new(5));
    answers_as_generated("rd11.eds", cards::rd11::Od::new(5));
}

#[test]
fn an_object_without_a_basic_data_type_is_left_out_and_listed() {
    let text = sim_support::DEVICE_EDS.replace(
        "[2005]\nParameterName=Enabled\nObjectType=0x7\nDataType=0x0001",
        "[2005]\nParameterName=Enabled\nObjectType=0x7\nDataType=0x0040",
    );
    let od = RuntimeDictionary::new(&sim_support::device("sim.eds", &text), 1);
    assert_eq!(od.left_out(), [(0x2005, "Enabled".to_owned())]);
    assert_eq!(od.locate(0x2005, 0), Err(SdoAbort::NoObject));
}

#[test]
fn node_id_defaults_are_resolved_for_the_given_node() {
    let od = RuntimeDictionary::new(&test_device(), 0x22);
    assert_eq!(read_value(&od, 0x1400, 1), 0x222u32.to_le_bytes());
    assert_eq!(read_value(&od, 0x1800, 1), 0x1A2u32.to_le_bytes());
    assert_eq!(read_value(&od, 0x1014, 0), 0xA2u32.to_le_bytes());
    assert_eq!(read_value(&od, 0x2003, 0), (-2i16).to_le_bytes());
    assert_eq!(read_value(&od, 0x2004, 0), 0.5f32.to_le_bytes());
}

#[test]
fn a_dcf_parameter_value_overrides_the_default_and_gives_the_node_id() {
    let dcf = test_dcf();
    assert_eq!(commissioned_node_id(&dcf), Some(0x0A));
    assert_eq!(commissioned_node_id(&test_device()), None);
    let od = RuntimeDictionary::new(&dcf, 0x0A);
    assert_eq!(read_value(&od, 0x2002, 0), 500u16.to_le_bytes());
    assert_eq!(read_value(&od, 0x1017, 0), 1000u16.to_le_bytes());
    assert_eq!(read_value(&od, 0x1400, 1), 0x20Au32.to_le_bytes());
}

#[test]
fn strings_and_domains_have_their_documented_capacity() {
    let od = RuntimeDictionary::new(&test_device(), 1);
    let label = od.locate(0x2000, 0).unwrap();
    let program = od.locate(0x2001, 0).unwrap();
    assert_eq!(od.entries()[label].data_type(), DataType::VisibleString);
    assert_eq!(
        od.capacity(label),
        Some(32),
        "at least 32 bytes when writable"
    );
    assert_eq!(
        od.capacity(program),
        Some(edsgen_sim::canopen::dictionary::DOMAIN_CAPACITY)
    );
    assert_eq!(od.value_len(0x2000, 0), Ok(3));
    assert_eq!(od.value_len(0x2001, 0), Ok(0), "no default: empty");
    assert_eq!(od.value_len_at(label), Ok(3));
    assert_eq!(od.value_len_at(program), Ok(0));
    assert_eq!(od.capacity(od.locate(0x2002, 0).unwrap()), Some(2));
}

#[test]
fn writes_are_checked_for_length_boolean_and_limits_and_leave_the_value_on_error() {
    let mut od = RuntimeDictionary::new(&test_device(), 1);
    assert_eq!(od.write(0x2002, 0, &[9, 0]), Err(SdoAbort::ValueTooLow));
    assert_eq!(
        od.write(0x2002, 0, &[0xE9, 0x03]),
        Err(SdoAbort::ValueTooHigh)
    );
    assert_eq!(od.write(0x2002, 0, &[10]), Err(SdoAbort::LengthTooLow));
    assert_eq!(
        od.write(0x2002, 0, &[10, 0, 0]),
        Err(SdoAbort::LengthTooHigh)
    );
    assert_eq!(read_value(&od, 0x2002, 0), 100u16.to_le_bytes());
    assert_eq!(od.write(0x2002, 0, &[0xE8, 0x03]), Ok(()));
    assert_eq!(
        od.write(0x2004, 0, &(-1.75f32).to_le_bytes()),
        Err(SdoAbort::ValueTooLow)
    );
    assert_eq!(
        od.write(0x2004, 0, &2.75f32.to_le_bytes()),
        Err(SdoAbort::ValueTooHigh)
    );
    assert_eq!(od.write(0x2004, 0, &f32::NAN.to_le_bytes()), Ok(()));
    assert_eq!(od.write(0x2005, 0, &[2]), Err(SdoAbort::InvalidValue));
    assert_eq!(
        od.write(0x2000, 0, &[b'x'; 33]),
        Err(SdoAbort::LengthTooHigh)
    );
    assert_eq!(od.write(0x2000, 0, b"drive 7"), Ok(()));
    assert_eq!(read_value(&od, 0x2000, 0), b"drive 7");
    assert_eq!(od.write(0x2006, 0, &[0]), Err(SdoAbort::NoObject));
    assert_eq!(od.write(0x1018, 9, &[0]), Err(SdoAbort::NoSubIndex));
}

#[test]
fn resets_restore_their_area_and_save_keeps_values_across_them() {
    use edsgen_runtime::NodeHooks;
    let mut od = RuntimeDictionary::new(&test_device(), 1);
    od.write(0x1017, 0, &[0x64, 0]).unwrap();
    od.write(0x2002, 0, &[0x20, 0]).unwrap();
    od.reset(ResetKind::Communication);
    assert_eq!(read_value(&od, 0x1017, 0), [0, 0]);
    assert_eq!(read_value(&od, 0x2002, 0), [0x20, 0]);
    od.reset(ResetKind::Node);
    assert_eq!(read_value(&od, 0x2002, 0), [100, 0]);

    let mut hooks = DictionaryHooks::default();
    od.write(0x2002, 0, &[0x20, 0]).unwrap();
    hooks.save(1, &od).unwrap();
    od.write(0x2002, 0, &[0x30, 0]).unwrap();
    hooks.reset(ResetKind::Node, &mut od);
    assert_eq!(read_value(&od, 0x2002, 0), [0x20, 0]);
    hooks.restore_defaults(1).unwrap();
    hooks.reset(ResetKind::Node, &mut od);
    assert_eq!(read_value(&od, 0x2002, 0), [100, 0]);
}

/// Node 1 serving the test device on the virtual bus, booted, and what it sent.
struct Bench {
    node: Node<RuntimeDictionary, DictionaryHooks>,
    bus: VirtualBus,
}

impl Bench {
    fn new() -> Self {
        let od = RuntimeDictionary::new(&test_device(), 1);
        let mut node = Node::with_hooks(od, DictionaryHooks::default(), 1, ms(0)).unwrap();
        let mut bus = VirtualBus::new(ms(0));
        bus.run_until(ms(0), &mut [&mut node]);
        bus.take_log();
        Bench { node, bus }
    }

    /// Sends each frame and returns the node's answers, as text.
    fn exchange(&mut self, frames: &[CanFrame]) -> Vec<String> {
        for f in frames {
            self.bus.inject(*f, &mut [&mut self.node]);
        }
        self.bus
            .take_log()
            .into_iter()
            .filter(|(_, sender, _)| *sender == 0)
            .map(|(_, _, f)| show(&f))
            .collect()
    }

    fn sdo(&mut self, data: [u8; 8]) -> String {
        let answers = self.exchange(&[frame(0x601, &data)]);
        assert_eq!(answers.len(), 1, "{answers:?}");
        answers[0].clone()
    }
}

#[test]
fn node_serves_a_segmented_download_and_upload_of_a_string() {
    let mut b = Bench::new();
    // "drive 7 left" (12 bytes): initiate with size, two segments.
    assert_eq!(
        b.sdo([0x21, 0x00, 0x20, 0x00, 12, 0, 0, 0]),
        "581: 60 00 20 00 00 00 00 00"
    );
    assert_eq!(
        b.sdo([0x00, b'd', b'r', b'i', b'v', b'e', b' ', b'7']),
        "581: 20 00 00 00 00 00 00 00"
    );
    assert_eq!(
        b.sdo([0x15, b' ', b'l', b'e', b'f', b't', 0, 0]),
        "581: 30 00 00 00 00 00 00 00"
    );
    assert_eq!(read_value(b.node.od(), 0x2000, 0), b"drive 7 left");
    assert_eq!(
        b.sdo([0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        "581: 41 00 20 00 0C 00 00 00"
    );
    assert_eq!(
        b.sdo([0x60, 0, 0, 0, 0, 0, 0, 0]),
        "581: 00 64 72 69 76 65 20 37"
    );
    assert_eq!(
        b.sdo([0x70, 0, 0, 0, 0, 0, 0, 0]),
        "581: 15 20 6C 65 66 74 00 00"
    );
    // 33 bytes announced: refused at once.
    assert_eq!(
        b.sdo([0x21, 0x00, 0x20, 0x00, 33, 0, 0, 0]),
        "581: 80 00 20 00 12 00 07 06"
    );
}

#[test]
fn node_serves_a_block_download_and_upload_of_a_domain() {
    let mut b = Bench::new();
    let program: Vec<u8> = (0u8..20).collect();
    // Block download, CRC, size 20 (the server streams into the dictionary, so it takes blocks
    // of the most segments, 127): three segments of 7, 7 and 6 bytes.
    assert_eq!(
        b.sdo([0xC6, 0x01, 0x20, 0x00, 20, 0, 0, 0]),
        "581: A4 01 20 00 7F 00 00 00"
    );
    let segments: Vec<CanFrame> = program
        .chunks(7)
        .enumerate()
        .map(|(i, chunk)| {
            let mut data = [0u8; 8];
            data[0] = (i as u8 + 1) | if i == 2 { 0x80 } else { 0 };
            data[1..1 + chunk.len()].copy_from_slice(chunk);
            frame(0x601, &data)
        })
        .collect();
    assert_eq!(b.exchange(&segments), ["581: A2 03 7F 00 00 00 00 00"]);
    let [lo, hi] = crc16(&program).to_le_bytes();
    assert_eq!(
        b.sdo([0xC5, lo, hi, 0, 0, 0, 0, 0]),
        "581: A1 00 00 00 00 00 00 00"
    );
    assert_eq!(read_value(b.node.od(), 0x2001, 0), program);
    // Block upload with CRC, block size 127.
    assert_eq!(
        b.sdo([0xA4, 0x01, 0x20, 0x00, 127, 0, 0, 0]),
        "581: C6 01 20 00 14 00 00 00"
    );
    assert_eq!(
        b.exchange(&[frame(0x601, &[0xA3, 0, 0, 0, 0, 0, 0, 0])]),
        [
            "581: 01 00 01 02 03 04 05 06",
            "581: 02 07 08 09 0A 0B 0C 0D",
            "581: 83 0E 0F 10 11 12 13 00",
        ]
    );
    let end = format!("581: C5 {lo:02X} {hi:02X} 00 00 00 00 00");
    assert_eq!(b.sdo([0xA2, 3, 127, 0, 0, 0, 0, 0]), end);
    assert_eq!(
        b.exchange(&[frame(0x601, &[0xA1, 0, 0, 0, 0, 0, 0, 0])]),
        Vec::<String>::new()
    );
}

#[test]
fn node_follows_a_pdo_mapping_change_and_exchanges_pdos_on_sync() {
    let mut b = Bench::new();
    let steps: [([u8; 8], &str); 8] = [
        // TPDO1: disable, clear the mapping, map 2003h (16 bits) and 2002h (16 bits), enable.
        (
            [0x23, 0x00, 0x18, 0x01, 0x81, 0x01, 0x00, 0x80],
            "581: 60 00 18 01 00 00 00 00",
        ),
        (
            [0x2F, 0x00, 0x1A, 0x00, 0x00, 0, 0, 0],
            "581: 60 00 1A 00 00 00 00 00",
        ),
        // The label (a string) cannot be mapped.
        (
            [0x23, 0x00, 0x1A, 0x01, 0x08, 0x00, 0x00, 0x20],
            "581: 80 00 1A 01 41 00 04 06",
        ),
        (
            [0x23, 0x00, 0x1A, 0x01, 0x10, 0x00, 0x03, 0x20],
            "581: 60 00 1A 01 00 00 00 00",
        ),
        (
            [0x23, 0x00, 0x1A, 0x02, 0x10, 0x00, 0x02, 0x20],
            "581: 60 00 1A 02 00 00 00 00",
        ),
        (
            [0x2F, 0x00, 0x1A, 0x00, 0x02, 0, 0, 0],
            "581: 60 00 1A 00 00 00 00 00",
        ),
        (
            [0x23, 0x00, 0x18, 0x01, 0x81, 0x01, 0x00, 0x00],
            "581: 60 00 18 01 00 00 00 00",
        ),
        // The RPDO is valid: its mapping cannot change.
        (
            [0x23, 0x00, 0x16, 0x02, 0x10, 0x00, 0x03, 0x20],
            "581: 80 00 16 02 22 00 00 08",
        ),
    ];
    for (request, answer) in steps {
        assert_eq!(b.sdo(request), answer);
    }
    // Operational, an RPDO sets 2002h to 0x0123, and the next SYNC sends TPDO1 with both.
    assert_eq!(
        b.exchange(&[frame(0x000, &[0x01, 0x01])]),
        Vec::<String>::new()
    );
    assert_eq!(
        b.exchange(&[frame(0x201, &[0x23, 0x01])]),
        Vec::<String>::new()
    );
    assert_eq!(read_value(b.node.od(), 0x2002, 0), [0x23, 0x01]);
    assert_eq!(b.exchange(&[frame(0x080, &[])]), ["181: FE FF 23 01"]);
}

#[test]
fn every_corpus_device_is_served_and_answers_an_upload_of_every_entry() {
    let Some(dir) = corpus_dir() else { return };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_dir())
        .flat_map(|e| std::fs::read_dir(e.path()).unwrap().flatten())
        .map(|e| e.path())
        .filter(|p| {
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
            matches!(
                ext.to_ascii_lowercase().as_str(),
                "eds" | "dcf" | "xdd" | "xdc"
            )
        })
        .collect();
    files.sort();
    assert!(files.len() >= 100, "{} files", files.len());
    for path in &files {
        let device = edsgen_model::read::read_file(path).unwrap().device;
        let od = RuntimeDictionary::new(&device, 1);
        // The default SDO server's COB-IDs are 601h/581h whatever 1200h stores (oresat's
        // battery card holds 8000 0000h there, to be set at run time).
        let (rx, tx) = (0x601, 0x581);
        let uploads: Vec<CanFrame> = od
            .entries()
            .iter()
            .map(|e| {
                let [lo, hi] = e.index().to_le_bytes();
                frame(rx, &[0x40, lo, hi, e.sub(), 0, 0, 0, 0])
            })
            .collect();
        let mut node = Node::with_hooks(od, DictionaryHooks::default(), 1, ms(0)).unwrap();
        let mut bus = VirtualBus::new(ms(0));
        bus.run_until(ms(0), &mut [&mut node]);
        bus.take_log();
        let mut answered = 0;
        for upload in &uploads {
            bus.inject(*upload, &mut [&mut node]);
            // Each upload is answered (expedited, a segmented initiate, or an abort for a
            // write-only entry); a segmented one is abandoned by the next request.
            answered += bus
                .take_log()
                .iter()
                .filter(|(_, sender, f)| *sender == 0 && f.std_id() == Some(tx))
                .count();
        }
        assert_eq!(answered, uploads.len(), "{}", path.display());
    }
}
