//! The telegram forms byte for byte, and the telegrams a slave must refuse.

use super::*;

fn emitted(t: &DataRepr<'_>) -> ([u8; MAX_TELEGRAM_LEN], usize) {
    let mut buf = [0; MAX_TELEGRAM_LEN];
    let n = t.emit(&mut buf).unwrap();
    (buf, n)
}

#[test]
fn sd1_fdl_status_request() {
    // FDL status request from master 2 to station 5: 10 05 02 49 50 16.
    let bytes = [0x10, 0x05, 0x02, 0x49, 0x50, 0x16];
    let (telegram, used) = parse(&bytes).unwrap();
    assert_eq!(used, 6);
    let Repr::Data(t) = telegram else {
        panic!("{telegram:?}")
    };
    assert_eq!((t.da, t.sa, t.fc, t.function()), (5, 2, 0x49, 9));
    let (buf, n) = emitted(&t);
    assert_eq!(buf[..n], bytes);
}

#[test]
fn sd2_with_saps() {
    // Slave_Diag request: DA 5 + ext, SA 2 + ext, FC 7D (SRD high, FCV, FCB 1), DSAP 60,
    // SSAP 62, no data.
    let t = DataRepr {
        da: 5,
        sa: 2,
        dsap: Some(60),
        ssap: Some(62),
        fc: 0x7D,
        data: &[],
    };
    let (buf, n) = emitted(&t);
    assert_eq!(
        buf[..n],
        [0x68, 0x05, 0x05, 0x68, 0x85, 0x82, 0x7D, 0x3C, 0x3E, 0xFE, 0x16]
    );
    assert_eq!(parse(&buf[..n]), Ok((Repr::Data(t), 11)));
    assert_eq!(t.fcb(), Some(true));
    let view = Telegram::new_checked(&buf[..]).unwrap();
    assert_eq!(
        (view.delimiter(), view.da_byte(), view.sa_byte(), view.fc()),
        (SD2, Some(0x85), Some(0x82), Some(0x7D))
    );
    assert_eq!(view.payload(), Some(&[0x3C, 0x3E][..]));
}

#[test]
fn sd3_and_tokens() {
    let t = DataRepr {
        da: 3,
        sa: 1,
        dsap: None,
        ssap: None,
        fc: 0x08,
        data: &[1, 2, 3, 4, 5, 6, 7, 8],
    };
    let (buf, n) = emitted(&t);
    assert_eq!(buf[0], SD3);
    assert_eq!(n, 14);
    assert_eq!(parse(&buf[..n]).unwrap().0, Repr::Data(t));
    assert_eq!(parse(&[0xDC, 1, 2]), Ok((Repr::Token { da: 1, sa: 2 }, 3)));
    assert_eq!(parse(&[0xE5, 0]), Ok((Repr::ShortAck, 1)));
}

#[test]
fn bad_telegrams() {
    assert_eq!(
        parse(&[0x10, 0x05, 0x02, 0x49, 0x51, 0x16]),
        Err(FdlError::BadFcs)
    );
    assert_eq!(
        parse(&[0x10, 0x05, 0x02, 0x49, 0x50, 0x17]),
        Err(FdlError::BadEnd)
    );
    assert_eq!(parse(&[0x10, 0x05]), Err(FdlError::Incomplete));
    assert_eq!(parse(&[0xDC, 0x05]), Err(FdlError::Incomplete));
    assert_eq!(parse(&[]), Err(FdlError::Incomplete));
    assert_eq!(parse(&[0x68, 0x05, 0x06, 0x68]), Err(FdlError::BadLength));
    assert_eq!(parse(&[0x68, 0x02, 0x02, 0x68]), Err(FdlError::BadLength));
    assert_eq!(parse(&[0x42]), Err(FdlError::BadDelimiter(0x42)));
    // SAP bits set with no room for the SAP bytes.
    assert_eq!(
        parse(&[0x68, 3, 3, 0x68, 0x85, 0x02, 0x6D, 0xF4, 0x16]),
        Err(FdlError::BadLength)
    );
}

#[test]
fn emit_refuses_what_does_not_fit() {
    let data = [0u8; 247];
    let long = DataRepr {
        da: 1,
        sa: 2,
        dsap: None,
        ssap: None,
        fc: 0x08,
        data: &data,
    };
    assert_eq!(long.buffer_len(), None);
    assert_eq!(long.emit(&mut [0; 300]), Err(FdlError::BadLength));
    let fits = DataRepr {
        data: &data[..246],
        ..long
    };
    assert_eq!(fits.buffer_len(), Some(255));
    assert_eq!(fits.emit(&mut [0; 254]), Err(FdlError::BufferTooSmall));
    assert_eq!(fits.emit(&mut [0; 255]), Ok(255));
}
