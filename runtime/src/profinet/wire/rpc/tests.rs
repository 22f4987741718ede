use super::*;

/// What `emit` writes into a buffer as large as a UDP datagram gets.
fn emitted(emit: impl FnOnce(&mut [u8]) -> Result<usize, BufferTooSmall>) -> Vec<u8> {
    let mut buf = vec![0; 1500];
    let n = emit(&mut buf).expect("it fits");
    buf.truncate(n);
    buf
}

/// The 80-byte header of a big-endian Connect request (as profinet-py sends it), body 4 bytes.
fn connect_header_be() -> Vec<u8> {
    let mut b = vec![4, REQUEST, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00];
    b.extend_from_slice(&Uuid::pnio_object(1, 0x0350, 0x0350).0);
    b.extend_from_slice(&Uuid::PNIO_DEVICE.0);
    b.extend_from_slice(&[0xA5; 16]);
    b.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 7]); // boot time, version 1, seq 7
    b.extend_from_slice(&[0, 0, 0xFF, 0xFF, 0xFF, 0xFF, 0, 4, 0, 0, 0, 0]); // opnum 0 .. serial
    b.extend_from_slice(&[1, 2, 3, 4]);
    b
}

#[test]
fn a_big_endian_request_reads_and_writes_back_the_same_bytes() {
    let pdu = connect_header_be();
    let (h, body) = RpcHeader::parse(&pdu).expect("a header");
    assert_eq!(
        (
            h.packet_type,
            h.little_endian,
            h.opnum,
            h.sequence,
            h.body_len,
            h.interface_version
        ),
        (REQUEST, false, OP_CONNECT, 7, 4, 1)
    );
    assert_eq!(h.interface, Uuid::PNIO_DEVICE);
    assert_eq!(
        h.object.0,
        [0xDE, 0xA0, 0, 0, 0x6C, 0x97, 0x11, 0xD1, 0x82, 0x71, 0, 1, 0x03, 0x50, 0x03, 0x50]
    );
    assert_eq!(body, [1, 2, 3, 4]);
    let out = emitted(|b| h.emit(4, b));
    assert_eq!(out, pdu[..80]);
    assert_eq!(h.emit(4, &mut [0; 79]), Err(BufferTooSmall));
}

#[test]
fn a_little_endian_header_swaps_the_integers_and_the_uuids_first_fields() {
    let be = connect_header_be();
    let (h, _) = RpcHeader::parse(&be).expect("a header");
    let le = RpcHeader {
        little_endian: true,
        ..h
    };
    let mut out = emitted(|b| le.emit(4, b));
    assert_eq!(out[4], 0x10);
    // DEA00001-6C97-11D1 with its first three fields little-endian.
    assert_eq!(
        out[24..32],
        [0x01, 0x00, 0xA0, 0xDE, 0x97, 0x6C, 0xD1, 0x11]
    );
    assert_eq!(out[32..40], be[32..40]);
    assert_eq!(out[64..68], [7, 0, 0, 0]);
    assert_eq!(out[74..76], [4, 0]);
    out.extend_from_slice(&[1, 2, 3, 4]);
    let (back, body) = RpcHeader::parse(&out).expect("a header");
    assert_eq!(back, le);
    assert_eq!(body, [1, 2, 3, 4]);
}

#[test]
fn short_pdus_other_versions_and_short_bodies_are_none() {
    let pdu = connect_header_be();
    assert_eq!(RpcHeader::parse(&pdu[..79]), None);
    assert_eq!(RpcHeader::parse(&pdu[..83]), None);
    let mut v5 = pdu.clone();
    v5[0] = 5;
    assert_eq!(RpcHeader::parse(&v5), None);
}

#[test]
fn the_ndr_header_and_the_pnio_status_in_both_byte_orders() {
    let status = PnioStatus::new(0xDB, 0x81, 0x40, 0x04);
    let be = emitted(|b| Ndr::response(status, 0, 4068, false).emit(b));
    assert_eq!(
        be,
        [0xDB, 0x81, 0x40, 0x04, 0, 0, 0, 0, 0, 0, 0x0F, 0xE4, 0, 0, 0, 0, 0, 0, 0, 0]
    );
    let le = emitted(|b| Ndr::response(status, 0, 4068, true).emit(b));
    assert_eq!(
        le,
        [0x04, 0x40, 0x81, 0xDB, 0, 0, 0, 0, 0xE4, 0x0F, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        Ndr::parse(&le, true).expect("an NDR header").0.status(),
        status
    );
    assert_eq!(
        Ndr::parse(&be, false).expect("an NDR header").0.status(),
        status
    );
    let mut req = emitted(|b| Ndr::request(4068, 2, false).emit(b));
    req.extend_from_slice(&[9, 9, 7]);
    let (ndr, args) = Ndr::parse(&req, false).expect("an NDR header");
    assert_eq!((ndr.args_maximum(), args), (4068, &[9, 9][..]));
    // ArgsLength past the body, or unlike ActualCount.
    assert_eq!(Ndr::parse(&req[..21], false), None);
    req[19] = 3;
    assert_eq!(Ndr::parse(&req, false), None);
}

#[test]
fn answers_keep_the_requests_uuids_and_sequence() {
    let (h, _) = RpcHeader::parse(&connect_header_be()).expect("a header");
    let pdu = emitted(|b| {
        emit_pdu(
            &h.answer(RESPONSE),
            &Ndr::response(PnioStatus::OK, 1, 4068, false),
            &[0xAB],
            b,
        )
    });
    assert_eq!(pdu.len(), 80 + 20 + 1);
    let (a, body) = RpcHeader::parse(&pdu).expect("a header");
    assert_eq!(
        (a.packet_type, a.flags1, a.sequence, a.activity, a.body_len),
        (RESPONSE, 0x0A, 7, Uuid([0xA5; 16]), 21)
    );
    assert_eq!(body[20], 0xAB);
    let reject = emitted(|b| emit_reject(&h, REJECT, NCA_UNKNOWN_INTERFACE, b));
    assert_eq!(reject.len(), 84);
    assert_eq!(reject[1], REJECT);
    assert_eq!(reject[80..], [0x1C, 0x01, 0x00, 0x03]);
}
