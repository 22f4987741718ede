//! DCP headers and blocks byte for byte.

use super::*;

#[test]
fn blocks_are_padded_to_even_and_bounded() {
    let data = [2, 2, 0, 3, 0, 0, b'a', 0, 0xFF, 0xFF, 0, 0];
    let mut read = blocks(&data);
    assert_eq!(
        read.next(),
        Some(Ok(Block {
            option: (2, 2),
            data: &[0, 0, b'a'][..]
        }))
    );
    assert_eq!(
        read.next(),
        Some(Ok(Block {
            option: (0xFF, 0xFF),
            data: &[][..]
        }))
    );
    assert_eq!(read.next(), None);
    let mut short = blocks(&[2, 2, 0, 9, 1]);
    assert_eq!(
        (short.next(), short.next()),
        (Some(Err(TruncatedBlock)), None)
    );
    let mut short = blocks(&[2, 2]);
    assert_eq!(
        (short.next(), short.next()),
        (Some(Err(TruncatedBlock)), None)
    );
}

#[test]
fn header_round_trip_and_short_pdus() {
    let h = DcpHeader {
        frame_id: FRAME_IDENTIFY_REQUEST,
        service_id: SERVICE_IDENTIFY,
        service_type: TYPE_REQUEST,
        xid: 0x0102_0304,
        response_delay: 0x80,
        length: 4,
    };
    let mut out = [0u8; 16];
    assert_eq!(h.emit(&mut out), Ok(12));
    out[12..].copy_from_slice(&[0xFF, 0xFF, 0, 0]);
    assert_eq!(
        out,
        [0xFE, 0xFE, 5, 0, 1, 2, 3, 4, 0, 0x80, 0, 4, 0xFF, 0xFF, 0, 0]
    );
    assert_eq!(DcpHeader::parse(&out), Some((h, &out[12..])));
    assert_eq!(DcpHeader::parse(&out[..15]), None);
    assert_eq!(h.emit(&mut out[..11]), Err(BufferTooSmall));
}

#[test]
fn blocks_and_requests_written_into_the_buffer() {
    let mut buf = [0u8; 64];
    let n = emit_plain_block(&mut buf, NAME_OF_STATION, b"abc").unwrap();
    assert_eq!(buf[..n], [2, 2, 0, 3, b'a', b'b', b'c', 0]);
    let n = emit_block(&mut buf, DEVICE_ID, 0, &[0x00, 0x2A, 0x01, 0x02]).unwrap();
    assert_eq!(buf[..n], [2, 3, 0, 6, 0, 0, 0x00, 0x2A, 0x01, 0x02]);
    let n = emit_set_response(&mut buf, NAME_OF_STATION, ERROR_NONE).unwrap();
    assert_eq!(buf[..n], [5, 4, 0, 3, 2, 2, 0, 0]);
    assert_eq!(
        emit_set_response(&mut buf[..7], NAME_OF_STATION, 0),
        Err(BufferTooSmall)
    );
    let n = request(
        &mut buf,
        MULTICAST_IDENTIFY,
        [2; 6],
        FRAME_IDENTIFY_REQUEST,
        SERVICE_IDENTIFY,
        7,
        &[0xFF, 0xFF, 0, 0],
    )
    .unwrap();
    assert_eq!(n, 14 + 12 + 4);
    assert_eq!(
        buf[12..n],
        [0x88, 0x92, 0xFE, 0xFE, 5, 0, 0, 0, 0, 7, 0, 1, 0, 4, 0xFF, 0xFF, 0, 0]
    );
    let blocks: [((u8, u8), u16, &[u8]); 1] = [((2, 3), 0, &[0x00, 0x2A, 0x01, 0x02])];
    let mut read = response_blocks(&[2, 3, 0, 6, 0, 0, 0x00, 0x2A, 0x01, 0x02]);
    assert_eq!(read.next(), Some(blocks[0]));
    assert_eq!(read.next(), None);
}

#[test]
fn names_of_station_follow_iec_61158_6_10() {
    let long_label = "a".repeat(64);
    let longest_label = "a".repeat(63);
    let too_long = ["a"; 121].join(".");
    let longest = format!("{}a", ["a"; 120].join("."));
    for ok in [
        "",
        "a",
        "drive-7.line-2",
        "goodrive350-pn",
        "rt-labs-dev",
        "port-01",
        "port-0011",
        "port-abc",
        "port-001-0000",
        "a.port-001",
        "1.2.3",
        "1.2.3.4.5",
        "123",
        "xn--abc",
        &longest_label,
        &longest,
    ] {
        assert_eq!(name_problem(ok), None, "{ok}");
        assert!(valid_name(ok), "{ok}");
    }
    for (bad, problem) in [
        ("port-001", NameProblem::PortName),
        ("port-001-00000", NameProblem::PortName),
        ("port-001.line-2", NameProblem::PortName),
        ("1.2.3.4", NameProblem::IpAddress),
        ("192.168.0.1", NameProblem::IpAddress),
        ("Abc-dev", NameProblem::Uppercase),
        ("A", NameProblem::Uppercase),
        ("-ab", NameProblem::Hyphen),
        ("ab-", NameProblem::Hyphen),
        ("a..b", NameProblem::EmptyLabel),
        (".a", NameProblem::EmptyLabel),
        ("a_b", NameProblem::Character),
        ("drive 1", NameProblem::Character),
        (long_label.as_str(), NameProblem::LabelTooLong),
        (too_long.as_str(), NameProblem::TooLong),
    ] {
        assert_eq!(name_problem(bad), Some(problem), "{bad}");
        assert!(!valid_name(bad), "{bad}");
    }
    assert_eq!(longest.len(), 240);
    assert_eq!(too_long.len(), 241);
    assert_eq!(
        NameProblem::PortName.to_string(),
        "a first label of the form `port-xyz` or `port-xyz-abcde`, which names a port"
    );
}
