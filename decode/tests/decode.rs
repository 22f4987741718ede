//! The bus decoder (`edsgen_decode::Decoder`): the exact line for every kind of frame, SDO
//! transfers of every type reassembled into one line, aborts with their meaning, PDOs decoded by
//! the mapping the SDO writes on the bus set, and raw lines for what it cannot attribute; and
//! EtherCAT process images decoded by an ESI file's default PDO assignment
//! (`edsgen_decode::image::ImageDecoder`).

#[path = "../../sim/tests/sim_support/mod.rs"]
mod sim_support;

use std::time::Duration;

use edsgen_decode::Decoder;
use edsgen_runtime::sdo::crc::crc16;
use edsgen_runtime::CanFrame;
use sim_support::test_device;

/// Feeds `frames` (COB-ID, data), one per millisecond from 1700000000 s, and returns the lines.
fn decode(decoder: &mut Decoder, frames: &[(u16, &[u8])]) -> Vec<String> {
    let start = Duration::from_secs(1_700_000_000);
    frames
        .iter()
        .enumerate()
        .flat_map(|(i, (id, data))| {
            let frame = CanFrame::new(*id, data).unwrap();
            decoder.decode(start + Duration::from_millis(i as u64), &frame)
        })
        .collect()
}

fn described() -> Decoder {
    let mut decoder = Decoder::new();
    decoder.describe(1, &test_device());
    decoder
}

#[test]
fn nmt_heartbeat_guarding_sync_and_emergency_lines() {
    let mut d = described();
    let mut lines = decode(
        &mut d,
        &[
            (0x701, &[0x00]),
            (0x000, &[0x01, 0x01]),
            (0x000, &[0x82, 0x00]),
            (0x701, &[0x7F]),
            (0x080, &[]),
            (0x080, &[3]),
            (0x081, &[0x30, 0x81, 0x11, 0, 0, 0, 0, 0]),
            (0x081, &[0x00, 0x00, 0x00, 1, 2, 3, 4, 5]),
            (0x000, &[0x81, 0x01]),
            (0x000, &[0x80, 0x00]),
        ],
    );
    lines.extend(d.decode(
        Duration::from_secs(1_700_000_001),
        &CanFrame::remote(0x701, 1),
    ));
    lines.extend(d.decode(
        Duration::from_secs(1_700_000_001),
        &CanFrame::new(0x701, &[0x85]).unwrap(),
    ));
    assert_eq!(
        lines,
        [
            "1700000000.000000  701  HEARTBEAT  node 1 boot-up",
            "1700000000.001000  000  NMT        start node 1",
            "1700000000.002000  000  NMT        reset communication, all nodes",
            "1700000000.003000  701  HEARTBEAT  node 1 pre-operational",
            "1700000000.004000  080  SYNC",
            "1700000000.005000  080  SYNC       counter 3",
            "1700000000.006000  081  EMCY       node 1 8130 life guard error or heartbeat error; register 11h (generic, communication); manufacturer 00 00 00 00 00",
            "1700000000.007000  081  EMCY       node 1 0000 error reset or no error; register 00h (none); manufacturer 01 02 03 04 05",
            "1700000000.008000  000  NMT        reset node 1",
            "1700000000.009000  000  NMT        enter pre-operational, all nodes",
            "1700000001.000000  701  GUARD      node 1 request",
            "1700000001.000000  701  GUARD      node 1 operational, toggle 1",
        ]
    );
}

#[test]
fn expedited_transfers_name_the_entry_and_type_the_value() {
    let mut d = described();
    let lines = decode(
        &mut d,
        &[
            (0x601, &[0x2B, 0x02, 0x20, 0x00, 0xE8, 0x03, 0, 0]),
            (0x581, &[0x60, 0x02, 0x20, 0x00, 0, 0, 0, 0]),
            (0x601, &[0x40, 0x03, 0x20, 0x00, 0, 0, 0, 0]),
            (0x581, &[0x4B, 0x03, 0x20, 0x00, 0xFE, 0xFF, 0, 0]),
            (0x601, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
            (0x581, &[0x43, 0x18, 0x10, 0x01, 0x34, 0x12, 0, 0]),
            (0x601, &[0x40, 0x04, 0x20, 0x00, 0, 0, 0, 0]),
            (0x581, &[0x43, 0x04, 0x20, 0x00, 0x00, 0x00, 0x00, 0x3F]),
            (0x601, &[0x2F, 0x05, 0x20, 0x00, 0x01, 0, 0, 0]),
            (0x581, &[0x60, 0x05, 0x20, 0x00, 0, 0, 0, 0]),
        ],
    );
    assert_eq!(
        lines,
        [
            "1700000000.001000  581  SDO        node 1 write 2002:00 Target speed = 1000 (0x03E8)",
            "1700000000.003000  581  SDO        node 1 read 2003:00 Actual speed = -2",
            "1700000000.005000  581  SDO        node 1 read 1018:01 Identity object: Vendor-ID = 4660 (0x00001234)",
            "1700000000.007000  581  SDO        node 1 read 2004:00 Gain = 0.5",
            "1700000000.009000  581  SDO        node 1 write 2005:00 Enabled = true",
        ]
    );
}

#[test]
fn aborts_give_their_code_and_meaning() {
    let mut d = described();
    let lines = decode(
        &mut d,
        &[
            (0x601, &[0x2B, 0x02, 0x20, 0x00, 0x05, 0x00, 0, 0]),
            (0x581, &[0x80, 0x02, 0x20, 0x00, 0x32, 0x00, 0x09, 0x06]),
            (0x601, &[0x40, 0x00, 0x60, 0x00, 0, 0, 0, 0]),
            (0x581, &[0x80, 0x00, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06]),
            (0x601, &[0x80, 0x00, 0x20, 0x00, 0x00, 0x00, 0x04, 0x05]),
        ],
    );
    assert_eq!(
        lines,
        [
            "1700000000.001000  581  SDO        node 1 write 2002:00 Target speed = 5: abort 0609 0032 value of parameter written too low",
            "1700000000.003000  581  SDO        node 1 read 6000:00 (not in the description): abort 0602 0000 object does not exist in the object dictionary",
            "1700000000.004000  601  SDO        node 1 read 2000:00 Device label: abort by the client 0504 0000 SDO protocol timed out",
        ]
    );
}

#[test]
fn a_segmented_upload_and_download_are_one_line_with_the_whole_value() {
    let mut d = described();
    let lines = decode(
        &mut d,
        &[
            (0x601, &[0x21, 0x00, 0x20, 0x00, 12, 0, 0, 0]),
            (0x581, &[0x60, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
            (0x601, &[0x00, b'd', b'r', b'i', b'v', b'e', b' ', b'7']),
            (0x581, &[0x20, 0, 0, 0, 0, 0, 0, 0]),
            (0x601, &[0x15, b' ', b'l', b'e', b'f', b't', 0, 0]),
            (0x581, &[0x30, 0, 0, 0, 0, 0, 0, 0]),
            (0x601, &[0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
            (0x581, &[0x41, 0x00, 0x20, 0x00, 0x0C, 0, 0, 0]),
            (0x601, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
            (0x581, &[0x00, 0x64, 0x72, 0x69, 0x76, 0x65, 0x20, 0x37]),
            (0x601, &[0x70, 0, 0, 0, 0, 0, 0, 0]),
            (0x581, &[0x15, 0x20, 0x6C, 0x65, 0x66, 0x74, 0x00, 0x00]),
        ],
    );
    assert_eq!(
        lines,
        [
            "1700000000.005000  581  SDO        node 1 write 2000:00 Device label = \"drive 7 left\" (segmented, 12 bytes)",
            "1700000000.011000  581  SDO        node 1 read 2000:00 Device label = \"drive 7 left\" (segmented, 12 bytes)",
        ]
    );
}

#[test]
fn block_transfers_are_reassembled_counting_a_repeated_segment_once() {
    let mut d = described();
    let program: Vec<u8> = (0u8..20).collect();
    let [lo, hi] = crc16(&program).to_le_bytes();
    let seg = |n: u8, last: bool, from: usize| {
        let mut data = [0u8; 8];
        data[0] = n | if last { 0x80 } else { 0 };
        let chunk = &program[from..(from + 7).min(20)];
        data[1..1 + chunk.len()].copy_from_slice(chunk);
        data
    };
    let (s1, s2, s3) = (seg(1, false, 0), seg(2, false, 7), seg(3, true, 14));
    // The download's first sub-block is acknowledged up to segment 1 only; 2 and 3 come again
    // as 1 and 2.
    let (r1, r2) = (seg(1, false, 7), seg(2, true, 14));
    let lines = decode(
        &mut d,
        &[
            (0x601, &[0xC6, 0x01, 0x20, 0x00, 20, 0, 0, 0]),
            (0x581, &[0xA4, 0x01, 0x20, 0x00, 4, 0, 0, 0]),
            (0x601, &s1),
            (0x601, &s2),
            (0x601, &s3),
            (0x581, &[0xA2, 1, 4, 0, 0, 0, 0, 0]),
            (0x601, &r1),
            (0x601, &r2),
            (0x581, &[0xA2, 2, 4, 0, 0, 0, 0, 0]),
            (0x601, &[0xC5, lo, hi, 0, 0, 0, 0, 0]),
            (0x581, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
            (0x601, &[0xA4, 0x01, 0x20, 0x00, 127, 0, 0, 0]),
            (0x581, &[0xC6, 0x01, 0x20, 0x00, 20, 0, 0, 0]),
            (0x601, &[0xA3, 0, 0, 0, 0, 0, 0, 0]),
            (0x581, &s1),
            (0x581, &s2),
            (0x581, &s3),
            (0x601, &[0xA2, 3, 127, 0, 0, 0, 0, 0]),
            (0x581, &[0xC5, lo, hi, 0, 0, 0, 0, 0]),
            (0x601, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
        ],
    );
    let value = "00 01 02 03 04 05 06 07 08 09 0A 0B 0C 0D 0E 0F 10 11 12 13";
    assert_eq!(
        lines,
        [
            format!("1700000000.010000  581  SDO        node 1 write 2001:00 Program = {value} (block, 20 bytes, CRC ACCCh)"),
            format!("1700000000.019000  601  SDO        node 1 read 2001:00 Program = {value} (block, 20 bytes, CRC ACCCh)"),
        ]
    );
}

#[test]
fn pdos_follow_the_mapping_and_cob_ids_written_on_the_bus() {
    let mut d = described();
    let lines = decode(
        &mut d,
        &[
            // The description's mapping: TPDO1 = 2003h, RPDO1 = 2002h.
            (0x181, &[0xFE, 0xFF]),
            (0x201, &[0x23, 0x01]),
            // TPDO1 remapped to 2005h (8 bits) and 2002h, and moved to 0x281.
            (0x601, &[0x23, 0x00, 0x18, 0x01, 0x81, 0x01, 0x00, 0x80]),
            (0x581, &[0x60, 0x00, 0x18, 0x01, 0, 0, 0, 0]),
            (0x601, &[0x2F, 0x00, 0x1A, 0x00, 0x00, 0, 0, 0]),
            (0x581, &[0x60, 0x00, 0x1A, 0x00, 0, 0, 0, 0]),
            (0x601, &[0x23, 0x00, 0x1A, 0x01, 0x08, 0x00, 0x05, 0x20]),
            (0x581, &[0x60, 0x00, 0x1A, 0x01, 0, 0, 0, 0]),
            (0x601, &[0x23, 0x00, 0x1A, 0x02, 0x10, 0x00, 0x02, 0x20]),
            (0x581, &[0x60, 0x00, 0x1A, 0x02, 0, 0, 0, 0]),
            (0x601, &[0x2F, 0x00, 0x1A, 0x00, 0x02, 0, 0, 0]),
            (0x581, &[0x60, 0x00, 0x1A, 0x00, 0, 0, 0, 0]),
            (0x601, &[0x23, 0x00, 0x18, 0x01, 0x81, 0x02, 0x00, 0x00]),
            (0x581, &[0x60, 0x00, 0x18, 0x01, 0, 0, 0, 0]),
            (0x281, &[0x01, 0x2C, 0x01]),
            (0x181, &[0x01, 0x2C, 0x01]),
            (0x281, &[0x01]),
            // Nothing mapped.
            (0x601, &[0x2F, 0x00, 0x16, 0x00, 0x00, 0, 0, 0]),
            (0x581, &[0x60, 0x00, 0x16, 0x00, 0, 0, 0, 0]),
            (0x201, &[]),
        ],
    );
    let sdo = |t: &str| format!("1700000000.{t}  581  SDO        node 1 write ");
    assert_eq!(
        lines,
        [
            "1700000000.000000  181  TPDO1      node 1 Actual speed = -2".to_owned(),
            "1700000000.001000  201  RPDO1      node 1 Target speed = 291 (0x0123)".to_owned(),
            sdo("003000") + "1800:01 TPDO1 communication parameter: COB-ID used by TPDO = 2147484033 (0x80000181)",
            sdo("005000") + "1A00:00 TPDO1 mapping parameter: Number of mapped objects = 0",
            sdo("007000") + "1A00:01 TPDO1 mapping parameter: Mapped object 1 = 537198600 (0x20050008)",
            sdo("009000") + "1A00:02 TPDO1 mapping parameter: Mapped object 2 = 537002000 (0x20020010)",
            sdo("011000") + "1A00:00 TPDO1 mapping parameter: Number of mapped objects = 2",
            sdo("013000") + "1800:01 TPDO1 communication parameter: COB-ID used by TPDO = 641 (0x00000281)",
            "1700000000.014000  281  TPDO1      node 1 Enabled = true, Target speed = 300 (0x012C)".to_owned(),
            "1700000000.015000  181  TPDO1      node 1 01 2C 01".to_owned(),
            "1700000000.016000  281  TPDO1      node 1 01 (the mapping needs 24 bits, the PDO has 8)".to_owned(),
            sdo("018000") + "1600:00 RPDO1 mapping parameter: Number of mapped objects = 0",
            "1700000000.019000  201  RPDO1      node 1 (nothing mapped)".to_owned(),
        ]
    );
}

#[test]
fn frames_it_cannot_attribute_are_printed_raw() {
    let mut d = Decoder::new();
    let mut lines = decode(
        &mut d,
        &[
            (0x7F0, &[0x12, 0x34]),
            (0x585, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
            (0x605, &[0xE0, 0x00, 0x10, 0x00]),
            (0x185, &[0xAA]),
            (0x605, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
            (0x605, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        ],
    );
    let ext = CanFrame::new_extended(0x1234567, &[1]).unwrap();
    lines.extend(d.decode(Duration::from_secs(1_700_000_001), &ext));
    lines.extend(d.finish(Duration::from_secs(1_700_000_002)));
    assert_eq!(
        lines,
        [
            "1700000000.000000  7F0  RAW        12 34",
            "1700000000.001000  585  SDO        node 5 00 01 02 03 04 05 06 07: an SDO response that fits no transfer seen",
            "1700000000.002000  605  SDO        node 5 E0 00 10 00: not an SDO request",
            "1700000000.003000  185  TPDO1      node 5 AA",
            "1700000000.005000  605  SDO        node 5 read 1018:01 (abandoned for a new request)",
            "1700000001.000000  01234567  RAW        01",
            "1700000002.000000  ---  SDO        node 5 read 1000:00 (unfinished)",
        ]
    );
}

#[test]
fn a_pdo_cob_id_on_a_restricted_identifier_does_not_hide_nmt() {
    // A TPDO COB-ID without a default reads as 0 (valid): NMT stays NMT.
    let text = sim_support::DEVICE_EDS.replace("DefaultValue=$NODEID+0x180", "DefaultValue=0");
    let mut d = Decoder::new();
    d.describe(1, &sim_support::device("sim.eds", &text));
    assert_eq!(
        decode(&mut d, &[(0x000, &[0x01, 0x01])]),
        ["1700000000.000000  000  NMT        start node 1"]
    );
}

proptest::proptest! {
    /// Any frames on any identifier, for a described node, give lines and never panic: every
    /// frame that is not a step of an unfinished transfer gives exactly one line.
    #[test]
    fn any_frames_decode_without_panicking(
        frames in proptest::collection::vec(
            (
                proptest::sample::select(vec![0x000u16, 0x080, 0x081, 0x181, 0x201, 0x581, 0x601, 0x701, 0x7E4, 0x7E5]),
                proptest::collection::vec(proptest::num::u8::ANY, 0..=8),
            ),
            0..64,
        )
    ) {
        let mut d = described();
        for (i, (id, data)) in frames.iter().enumerate() {
            let frame = CanFrame::new(*id, data).unwrap();
            let lines = d.decode(Duration::from_millis(i as u64), &frame);
            proptest::prop_assert!(lines.len() <= 1);
            if !matches!(id, 0x581 | 0x601) {
                proptest::prop_assert_eq!(lines.len(), 1);
            }
        }
        d.finish(Duration::ZERO);
    }
}

#[test]
fn a_second_sdo_channel_of_the_description_is_followed_apart() {
    let text = format!(
        "{}\n{}",
        sim_support::DEVICE_EDS,
        "[1201]\nParameterName=SDO server parameter 2\nObjectType=0x9\nSubNumber=3\n\n\
         [1201sub0]\nParameterName=Highest sub-index supported\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=2\n\n\
         [1201sub1]\nParameterName=COB-ID client to server\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x640\n\n\
         [1201sub2]\nParameterName=COB-ID server to client\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x5C0\n"
    );
    let mut d = Decoder::new();
    d.describe(1, &sim_support::device("sim.eds", &text));
    let lines = decode(
        &mut d,
        &[
            (0x641, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
            (0x601, &[0x40, 0x03, 0x20, 0x00, 0, 0, 0, 0]),
            (0x5C1, &[0x43, 0x18, 0x10, 0x01, 0x34, 0x12, 0, 0]),
            (0x581, &[0x4B, 0x03, 0x20, 0x00, 0xFE, 0xFF, 0, 0]),
        ],
    );
    assert_eq!(
        lines,
        [
            "1700000000.002000  5C1  SDO        node 1 (SDO channel 2) read 1018:01 Identity object: Vendor-ID = 4660 (0x00001234)",
            "1700000000.003000  581  SDO        node 1 read 2003:00 Actual speed = -2",
        ]
    );
}

#[test]
fn a_time_message_gives_the_date_and_time() {
    // 2026-11-24 15:04:05.123: 15,668 days after 1984-01-01, 54,245,123 ms after midnight.
    let ms = 54_245_123u32.to_le_bytes();
    let days = 15_668u16.to_le_bytes();
    let mut d = Decoder::new();
    let lines = decode(
        &mut d,
        &[
            (0x100, &[ms[0], ms[1], ms[2], ms[3], days[0], days[1]]),
            (0x100, &[0, 0, 0, 0, 0, 0]),
            (0x100, &[0, 0, 0, 0, 0x0F, 0x17]),
            (0x100, &[0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]),
            (0x100, &[1, 2]),
        ],
    );
    assert_eq!(
        lines,
        [
            "1700000000.000000  100  TIME       2026-11-24 15:04:05.123",
            "1700000000.001000  100  TIME       1984-01-01 00:00:00.000",
            "1700000000.002000  100  TIME       2000-02-29 00:00:00.000",
            "1700000000.003000  100  TIME       2163-06-06 74:33:55.455",
            "1700000000.004000  100  TIME       01 02",
        ]
    );
}

/// The EC-TX508's ESI model, for its process images.
fn ec_tx508_images() -> edsgen_decode::image::ImageDecoder {
    let path = std::path::Path::new(edsgen_sim::drives::ec_tx508::ESI_PATH);
    let model = edsgen_model::read::read_bytes(path, edsgen_sim::drives::ec_tx508::ESI).device;
    edsgen_decode::image::ImageDecoder::new(&model)
}

#[test]
fn ethercat_images_are_split_by_the_default_assignment_and_named_by_the_esi_file() {
    use edsgen_sim::cards::ec_tx508::ethercat::{Inputs, Outputs, RxPdo1600, TxPdo1A00};
    let images = ec_tx508_images();
    let outputs = Outputs {
        rx_pdo_1600: RxPdo1600 {
            control_word: 0x008F,
            target_speed: -300,
            operation_mode: -1,
            max_torque: 1000,
            ..RxPdo1600::default()
        },
    }
    .to_bytes();
    assert_eq!(
        images.outputs(&outputs),
        "Control word = 143, Target position = 0, Target speed = -300, Target torque = 0, \
         Max. torque = 1000 (0x03E8), Operation mode = -1, Speed in industrial regulations = 0, \
         Probe control = 0"
    );
    let inputs = Inputs {
        tx_pdo_1a00: TxPdo1A00 {
            status_word: 0x0637,
            position_actual_value: -2,
            operation_mode_display: 9,
            probe_position_rising_edge: 0x1234_5678,
            ..TxPdo1A00::default()
        },
    }
    .to_bytes();
    assert_eq!(
        images.inputs(&inputs),
        "Status word = 1591 (0x0637), Position actual value = -2, Actual speed = 0, \
         Actual torque = 0, Position deviation = 0, Operation mode display = 9, \
         Probe status = 0, Probe position rising edge = 305419896"
    );
}

#[test]
fn an_image_shorter_than_its_pdos_or_without_an_esi_mapping_is_printed_as_bytes() {
    let images = ec_tx508_images();
    assert_eq!(
        images.inputs(&[0x37, 0x06, 0x00]),
        "37 06 00 (the PDOs need 184 bits, the image has 24)"
    );
    assert_eq!(
        images.outputs(&[]),
        "(empty) (the PDOs need 168 bits, the image has 0)"
    );
    // A CANopen device has no SyncManagers.
    let eds = edsgen_model::read::read_bytes(
        std::path::Path::new("eds/cp301.eds"),
        edsgen_sim::drives::CARDS[0].eds,
    )
    .device;
    let images = edsgen_decode::image::ImageDecoder::new(&eds);
    assert_eq!(images.outputs(&[0x0F, 0x00]), "0F 00");
}

#[test]
fn sdo_frames_shorter_than_8_bytes_are_read_with_the_bytes_sent() {
    let mut d = described();
    let lines = decode(
        &mut d,
        &[
            // Expedited download of 2 bytes in a 6-byte frame, answered in 4 bytes.
            (0x601, &[0x2B, 0x02, 0x20, 0x00, 0xE8, 0x03]),
            (0x581, &[0x60, 0x02, 0x20, 0x00]),
            // Expedited upload answered in 6 bytes without the size (e=1, s=0).
            (0x601, &[0x40, 0x03, 0x20, 0x00]),
            (0x581, &[0x42, 0x03, 0x20, 0x00, 0xFE, 0xFF]),
            // Segmented upload whose segments carry fewer bytes than the frame could.
            (0x601, &[0x40, 0x00, 0x20, 0x00]),
            (0x581, &[0x41, 0x00, 0x20, 0x00, 0x05, 0x00, 0x00, 0x00]),
            (0x601, &[0x60]),
            (0x581, &[0x01, b'd', b'r', b'i', b'v', b'e']),
            // Too short for its header.
            (0x601, &[0x40, 0x00]),
            (0x581, &[]),
        ],
    );
    assert_eq!(
        lines,
        [
            "1700000000.001000  581  SDO        node 1 write 2002:00 Target speed = 1000 (0x03E8)",
            "1700000000.003000  581  SDO        node 1 read 2003:00 Actual speed = -2",
            "1700000000.007000  581  SDO        node 1 read 2000:00 Device label = \"drive\" (segmented, 5 bytes)",
            "1700000000.008000  601  SDO        node 1 40 00: an SDO initiate or abort shorter than its 4-byte header",
            "1700000000.009000  581  SDO        node 1 (empty): an empty SDO frame",
        ]
    );
}

#[test]
fn lss_requests_and_responses_are_decoded_by_name() {
    let mut d = Decoder::new();
    let lines = decode(
        &mut d,
        &[
            (0x7E5, &[0x04, 0x01, 0, 0, 0, 0, 0, 0]),
            (0x7E5, &[0x5A, 0, 0, 0, 0, 0, 0, 0]),
            (0x7E4, &[0x5A, 0x23, 0x01, 0, 0, 0, 0, 0]),
            (0x7E5, &[0x11, 0x05, 0, 0, 0, 0, 0, 0]),
            (0x7E4, &[0x11, 0x00, 0, 0, 0, 0, 0, 0]),
            (0x7E5, &[0x13, 0x00, 0x02, 0, 0, 0, 0, 0]),
            (0x7E4, &[0x13, 0x01, 0, 0, 0, 0, 0, 0]),
            (0x7E5, &[0x17, 0, 0, 0, 0, 0, 0, 0]),
            (0x7E4, &[0x17, 0x02, 0, 0, 0, 0, 0, 0]),
            (0x7E5, &[0x51, 0, 0, 0, 0, 0x80, 0, 0]),
            (0x7E4, &[0x4F, 0, 0, 0, 0, 0, 0, 0]),
        ],
    );
    let lss = |t: &str, id: &str, text: &str| format!("1700000000.{t}  {id}  LSS        {text}");
    assert_eq!(
        lines,
        [
            lss("000000", "7E5", "switch state global: configuration"),
            lss("001000", "7E5", "inquire vendor-ID"),
            lss("002000", "7E4", "vendor-ID = 0x00000123"),
            lss("003000", "7E5", "configure node-ID 5"),
            lss("004000", "7E4", "configure node-ID: success"),
            lss(
                "005000",
                "7E5",
                "configure bit timing: 500 kbit/s (table 0, index 2)"
            ),
            lss(
                "006000",
                "7E4",
                "configure bit timing: error 1, bit timing not supported"
            ),
            lss("007000", "7E5", "store configuration"),
            lss(
                "008000",
                "7E4",
                "store configuration: error 2, storage media access error"
            ),
            lss(
                "009000",
                "7E5",
                "fastscan: reset (are there non-configured slaves?)"
            ),
            lss("010000", "7E4", "identify slave: a slave matches"),
        ]
    );
}

/// A block download of `program` to 2001h (a DOMAIN) of node 1, in sub-blocks of 127
/// segments, all acknowledged; its end message carries `crc`.
fn block_download(program: &[u8], crc: u16) -> Vec<(u16, Vec<u8>)> {
    let mut frames = vec![
        (0x601, vec![0xC6, 0x01, 0x20, 0x00, 0, 0, 0, 0]),
        (0x581, vec![0xA4, 0x01, 0x20, 0x00, 127, 0, 0, 0]),
    ];
    let chunks: Vec<&[u8]> = program.chunks(7).collect();
    for (block, segments) in chunks.chunks(127).enumerate() {
        for (i, chunk) in segments.iter().enumerate() {
            let last = block * 127 + i + 1 == chunks.len();
            let mut data = vec![(i as u8 + 1) | if last { 0x80 } else { 0 }];
            data.extend_from_slice(chunk);
            data.resize(8, 0);
            frames.push((0x601, data));
        }
        frames.push((0x581, vec![0xA2, segments.len() as u8, 127, 0, 0, 0, 0, 0]));
    }
    let unused = (7 - program.len() % 7) % 7;
    let [lo, hi] = crc.to_le_bytes();
    frames.push((
        0x601,
        vec![0xC1 | (unused as u8) << 2, lo, hi, 0, 0, 0, 0, 0],
    ));
    frames.push((0x581, vec![0xA1, 0, 0, 0, 0, 0, 0, 0]));
    frames
}

#[test]
fn a_long_transfer_is_one_short_line_unless_the_full_value_is_asked_for() {
    let program: Vec<u8> = (0..65_536u32).map(|i| (i % 251) as u8).collect();
    let frames = block_download(&program, crc16(&program));
    let frames: Vec<(u16, &[u8])> = frames.iter().map(|(id, d)| (*id, d.as_slice())).collect();
    let lines = decode(&mut described(), &frames);
    assert_eq!(lines.len(), 1);
    let line = lines[0].split_once("  581  SDO        ").unwrap().1;
    assert_eq!(
        line,
        format!(
            "node 1 write 2001:00 Program = 00 01 02 03 04 05 06 07 08 09 0A 0B 0C 0D 0E 0F ... \
             (block, 65536 bytes, CRC {:04X}h; --full shows all)",
            crc16(&program)
        )
    );
    let mut full = described();
    full.show_full_values();
    let lines = decode(&mut full, &frames);
    let hex: Vec<String> = program.iter().map(|b| format!("{b:02X}")).collect();
    assert!(
        lines[0].ends_with(&format!(
            "Program = {} (block, 65536 bytes, CRC {:04X}h)",
            hex.join(" "),
            crc16(&program)
        )),
        "{}",
        &lines[0][..200]
    );
    // A CRC that does not match the data is said so.
    let frames = block_download(&program[..100], 0x1234);
    let frames: Vec<(u16, &[u8])> = frames.iter().map(|(id, d)| (*id, d.as_slice())).collect();
    let lines = decode(&mut described(), &frames);
    assert!(
        lines[0].ends_with(&format!(
            "(block, 100 bytes, CRC 1234h but the data's is {:04X}h; --full shows all)",
            crc16(&program[..100])
        )),
        "{}",
        lines[0]
    );
}
