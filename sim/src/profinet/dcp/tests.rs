//! The DCP machine against hand-built frames, byte for byte: Identify (all, by name, not me),
//! Get, Set of name, IP and signal, Hello, and frames it must ignore.

use super::*;

const DEVICE: Mac = [0x02, 0x00, 0x00, 0x00, 0x03, 0x50];
const CONTROLLER: Mac = [0x02, 0x00, 0x00, 0x00, 0x00, 0x01];

fn dcp() -> Dcp {
    Dcp::new(Station {
        mac: DEVICE,
        name_of_station: "goodrive350-pn".to_owned(),
        ip: [[0; 4]; 3],
        vendor_id: 0x0350,
        device_id: 0x0350,
        type_of_station: "GD350".to_owned(),
        instance: (0, 1),
    })
}

/// A request frame: Ethernet header, DCP header, blocks.
fn request(dst: Mac, frame_id: u16, service: u8, xid: u32, blocks: &[u8]) -> Vec<u8> {
    let mut f = Vec::new();
    append(&mut f, |b| Ethernet::emit(dst, CONTROLLER, b));
    f.extend_from_slice(&frame_id.to_be_bytes());
    f.extend_from_slice(&[service, 0]);
    f.extend_from_slice(&xid.to_be_bytes());
    f.extend_from_slice(&[0x00, 0x80]);
    f.extend_from_slice(&(blocks.len() as u16).to_be_bytes());
    f.extend_from_slice(blocks);
    f
}

#[test]
fn identify_all_is_answered_with_the_station_s_blocks() {
    let mut d = dcp();
    let req = request(MULTICAST_IDENTIFY, 0xFEFE, 5, 7, &[0xFF, 0xFF, 0, 0]);
    let resp = d.handle(&req).expect("an answer");
    let mut expected = Vec::new();
    expected.extend_from_slice(&CONTROLLER);
    expected.extend_from_slice(&DEVICE);
    expected.extend_from_slice(&[0x88, 0x92, 0xFE, 0xFF, 5, 1, 0, 0, 0, 7, 0, 0, 0, 0]);
    let blocks: &[u8] = &[
        // Device options: 10 pairs.
        2, 5, 0, 22, 0, 0, 1, 1, 1, 2, 2, 1, 2, 2, 2, 3, 2, 4, 2, 5, 2, 7, 5, 3, 5, 6,
        // Type of station "GD350" (odd: padded).
        2, 1, 0, 7, 0, 0, b'G', b'D', b'3', b'5', b'0', 0, // Name of station.
        2, 2, 0, 16, 0, 0, b'g', b'o', b'o', b'd', b'r', b'i', b'v', b'e', b'3', b'5', b'0', b'-',
        b'p', b'n', // VendorID, DeviceID.
        2, 3, 0, 6, 0, 0, 0x03, 0x50, 0x03, 0x50, // Role: IO device.
        2, 4, 0, 4, 0, 0, 1, 0, // Instance 0.1.
        2, 7, 0, 4, 0, 0, 0, 1, // IP parameter, not set.
        1, 2, 0, 14, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ];
    expected.extend_from_slice(blocks);
    let len = (blocks.len() as u16).to_be_bytes();
    expected[24] = len[0];
    expected[25] = len[1];
    assert_eq!(resp, expected);
}

#[test]
fn identify_by_name_answers_only_its_own_name() {
    let mut d = dcp();
    let mut by_name = vec![2, 2, 0, 14];
    by_name.extend_from_slice(b"goodrive350-pn");
    assert!(d
        .handle(&request(MULTICAST_IDENTIFY, 0xFEFE, 5, 1, &by_name))
        .is_some());
    let mut other = vec![2, 2, 0, 5];
    other.extend_from_slice(b"other\0");
    assert_eq!(
        d.handle(&request(MULTICAST_IDENTIFY, 0xFEFE, 5, 1, &other)),
        None
    );
}

#[test]
fn set_name_of_station_answers_with_a_control_response_and_an_event() {
    let mut d = dcp();
    // BlockQualifier 1 (permanent) and 7 characters: length 9, padded to even.
    let mut block = vec![2, 2, 0, 9, 0, 1];
    block.extend_from_slice(b"drive-7\0");
    let resp = d
        .handle(&request(DEVICE, 0xFEFD, 4, 9, &block))
        .expect("an answer");
    assert_eq!(
        resp[12..],
        [0x88, 0x92, 0xFE, 0xFD, 4, 1, 0, 0, 0, 9, 0, 0, 0, 8, 5, 4, 0, 3, 2, 2, 0, 0]
    );
    assert_eq!(d.station().name_of_station, "drive-7");
    assert_eq!(
        d.poll_event(),
        Some(DcpEvent::NameSet("drive-7".to_owned()))
    );
    assert_eq!(d.poll_event(), None);
    // An invalid name is refused with BlockError 3, "not set", as p-net refuses it.
    let mut bad = vec![2, 2, 0, 5, 0, 1];
    bad.extend_from_slice(b"Bad\0");
    let resp = d
        .handle(&request(DEVICE, 0xFEFD, 4, 10, &bad))
        .expect("an answer");
    assert_eq!(resp[30..34], [2, 2, 3, 0]);
    assert_eq!(d.station().name_of_station, "drive-7");
}

/// The names p-net's device refuses (BlockError 3) are refused the same, byte for byte: the
/// answer p-net sent to each of them on a veth pair, and the name kept.
#[test]
fn names_a_real_device_refuses_are_refused_with_block_error_3() {
    let long_label = "a".repeat(64);
    for name in [
        "port-001",
        "port-001-00000",
        "1.2.3.4",
        "Abc-dev",
        "-ab",
        "ab-",
        long_label.as_str(),
    ] {
        let mut d = dcp();
        let mut value = vec![0, 1];
        value.extend_from_slice(name.as_bytes());
        let mut block = vec![2, 2];
        block.extend_from_slice(&(value.len() as u16).to_be_bytes());
        block.extend_from_slice(&value);
        if value.len() % 2 == 1 {
            block.push(0);
        }
        let resp = d
            .handle(&request(DEVICE, 0xFEFD, 4, 0x1234, &block))
            .expect("an answer");
        assert_eq!(
            resp[14..],
            [0xFE, 0xFD, 4, 1, 0, 0, 0x12, 0x34, 0, 0, 0, 8, 5, 4, 0, 3, 2, 2, 3, 0],
            "{name}"
        );
        assert_eq!(d.station().name_of_station, "goodrive350-pn", "{name}");
        assert_eq!(d.poll_event(), None, "{name}");
    }
}

#[test]
fn set_ip_and_signal_then_get_reads_them_back() {
    let mut d = dcp();
    let block = [
        1, 2, 0, 14, 0, 1, 192, 168, 0, 1, 255, 255, 255, 0, 0, 0, 0, 0, 5, 3, 0, 4, 0, 0, 1, 0,
    ];
    let resp = d
        .handle(&request(DEVICE, 0xFEFD, 4, 3, &block))
        .expect("an answer");
    assert_eq!(resp[26..], [5, 4, 0, 3, 1, 2, 0, 0, 5, 4, 0, 3, 5, 3, 0, 0]);
    assert_eq!(
        d.poll_event(),
        Some(DcpEvent::IpSet([
            [192, 168, 0, 1],
            [255, 255, 255, 0],
            [0; 4]
        ]))
    );
    assert_eq!(d.poll_event(), Some(DcpEvent::Signal));
    let resp = d
        .handle(&request(DEVICE, 0xFEFD, 3, 4, &[1, 2, 9, 9]))
        .expect("an answer");
    assert_eq!(
        resp[26..],
        [
            1, 2, 0, 14, 0, 1, 192, 168, 0, 1, 255, 255, 255, 0, 0, 0, 0, 0, // IP, "set"
            5, 4, 0, 3, 9, 9, 1, 0 // option 9 unknown
        ]
    );
}

#[test]
fn hello_announces_name_ip_and_ids() {
    let mut d = dcp();
    let hello = d.hello();
    assert_eq!(hello[..6], MULTICAST_HELLO);
    assert_eq!(hello[14..20], [0xFE, 0xFC, 6, 0, 0, 0]);
    assert_eq!(hello[26..32], [2, 2, 0, 16, 0, 0]);
}

#[test]
fn frames_not_for_the_device_or_malformed_are_ignored() {
    let mut d = dcp();
    let other_mac = [2, 0, 0, 0, 0, 9];
    for frame in [
        request(other_mac, 0xFEFD, 3, 1, &[2, 2]),
        request(DEVICE, 0xFEFD, 4, 1, &[2, 2, 0, 40, 0]),
        request(MULTICAST_IDENTIFY, 0xFEFE, 5, 1, &[0xFF]),
        request(DEVICE, 0x8000, 5, 1, &[]),
        vec![0; 10],
        request(DEVICE, 0xFEFE, 5, 1, &[])[..20].to_vec(),
    ] {
        assert_eq!(d.handle(&frame), None, "{frame:02x?}");
    }
    // An unknown service on the Get/Set FrameID: "not supported".
    let resp = d
        .handle(&request(DEVICE, 0xFEFD, 9, 2, &[]))
        .expect("an answer");
    assert_eq!(resp[16..18], [9, 5]);
}

#[test]
fn names_follow_the_dns_rules() {
    for ok in ["", "a", "drive-7.line-2", "goodrive350-pn"] {
        assert!(valid_name(ok), "{ok}");
    }
    for bad in ["A", "-a", "a-", "a..b", "a_b", &"x".repeat(64)] {
        assert!(!valid_name(bad), "{bad}");
    }
}
