//! PROFIBUS FDL telegrams (EN 50170 layer 2) as a DP slave sees them: SD1 (no data), SD2
//! (variable data), SD3 (8 data bytes), SD4 (token), SC (short acknowledgement); the frame
//! check sequence (the sum of DA…data), the SAP extension bits of DA/SA, and the frame control
//! byte (request or response, FCB/FCV, function). Wire format only: no state.

/// Start delimiter of a telegram without data.
pub const SD1: u8 = 0x10;
/// Start delimiter of a telegram with variable data.
pub const SD2: u8 = 0x68;
/// Start delimiter of a telegram with 8 data bytes.
pub const SD3: u8 = 0xA2;
/// Start delimiter of the token.
pub const SD4: u8 = 0xDC;
/// The short acknowledgement.
pub const SC: u8 = 0xE5;
/// End delimiter.
pub const ED: u8 = 0x16;
/// The broadcast address.
pub const BROADCAST: u8 = 127;

/// Request functions (FC bits 0–3 with bit 6 set).
pub mod request {
    /// Send data with no acknowledge, high priority (Global_Control).
    pub const SDN_HIGH: u8 = 0x6;
    /// Send data with no acknowledge, low priority.
    pub const SDN_LOW: u8 = 0x4;
    /// Send data with acknowledge, low priority.
    pub const SDA_LOW: u8 = 0x3;
    /// Send data with acknowledge, high priority.
    pub const SDA_HIGH: u8 = 0x5;
    /// Request FDL status.
    pub const FDL_STATUS: u8 = 0x9;
    /// Send and request data, low priority (Data_Exchange, the DP services).
    pub const SRD_LOW: u8 = 0xC;
    /// Send and request data, high priority.
    pub const SRD_HIGH: u8 = 0xD;
}

/// Response functions (FC bits 0–3, bit 6 clear; bits 4–5 00: a slave).
pub mod response {
    /// Acknowledgement positive (OK).
    pub const OK: u8 = 0x0;
    /// The service or SAP is not activated (RS).
    pub const SAP_NOT_ACTIVATED: u8 = 0x3;
    /// Response data, low priority (DL).
    pub const DATA_LOW: u8 = 0x8;
    /// Response data, high priority (DH: diagnosis pending).
    pub const DATA_HIGH: u8 = 0xA;
}

/// A telegram's header and data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Telegram {
    /// SD1, SD2 or SD3.
    Data(DataTelegram),
    /// SD4: the token from `sa` to `da`.
    Token {
        /// Destination.
        da: u8,
        /// Source.
        sa: u8,
    },
    /// SC.
    ShortAck,
}

/// A data telegram: addresses, SAPs, frame control and data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DataTelegram {
    /// Destination address (without the SAP extension bit).
    pub da: u8,
    /// Source address (without the SAP extension bit).
    pub sa: u8,
    /// Destination SAP, if DA's extension bit was set.
    pub dsap: Option<u8>,
    /// Source SAP, if SA's extension bit was set.
    pub ssap: Option<u8>,
    /// The frame control byte.
    pub fc: u8,
    /// The data after the SAPs.
    pub data: Vec<u8>,
}

impl DataTelegram {
    /// Whether FC says a request (bit 6).
    pub fn is_request(&self) -> bool {
        self.fc & 0x40 != 0
    }

    /// FC bits 0–3.
    pub fn function(&self) -> u8 {
        self.fc & 0x0F
    }

    /// The frame count bit, if FCV (frame count valid) is set.
    pub fn fcb(&self) -> Option<bool> {
        (self.is_request() && self.fc & 0x10 != 0).then_some(self.fc & 0x20 != 0)
    }

    /// The telegram's bytes: SD1 without data or SAPs, SD3 with exactly 8 bytes of data and no
    /// SAPs, else SD2. `None` when the data does not fit (more than 246 bytes with the SAPs).
    pub fn emit(&self) -> Option<Vec<u8>> {
        let mut body = vec![
            self.da | if self.dsap.is_some() { 0x80 } else { 0 },
            self.sa | if self.ssap.is_some() { 0x80 } else { 0 },
            self.fc,
        ];
        body.extend(self.dsap);
        body.extend(self.ssap);
        body.extend_from_slice(&self.data);
        let fcs = body.iter().fold(0u8, |sum, b| sum.wrapping_add(*b));
        let extra = body.len() - 3;
        let mut out = match extra {
            0 => vec![SD1],
            8 if self.dsap.is_none() && self.ssap.is_none() => vec![SD3],
            _ => {
                let le = u8::try_from(body.len()).ok().filter(|le| *le <= 249)?;
                vec![SD2, le, le, SD2]
            }
        };
        out.extend(body);
        out.push(fcs);
        out.push(ED);
        Some(out)
    }
}

/// Why bytes are no telegram (a slave stays silent on each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FdlError {
    /// More bytes are needed.
    Incomplete,
    /// Not a start delimiter.
    BadDelimiter(u8),
    /// SD2's two lengths differ, or are outside 4–249, or the second SD2 is missing.
    BadLength,
    /// The frame check sequence is wrong.
    BadFcs,
    /// The end delimiter is not 16h.
    BadEnd,
}

/// Parses one telegram at the start of `bytes`: the telegram and how many bytes it took.
pub fn parse(bytes: &[u8]) -> Result<(Telegram, usize), FdlError> {
    let Some(&sd) = bytes.first() else {
        return Err(FdlError::Incomplete);
    };
    let (body_start, body_len) = match sd {
        SC => return Ok((Telegram::ShortAck, 1)),
        SD4 => {
            let [_, da, sa] = *bytes.get(..3).ok_or(FdlError::Incomplete)? else {
                return Err(FdlError::Incomplete);
            };
            return Ok((Telegram::Token { da, sa }, 3));
        }
        SD1 => (1, 3),
        SD3 => (1, 11),
        SD2 => {
            let header = bytes.get(..4).ok_or(FdlError::Incomplete)?;
            let le = header[1];
            if header[2] != le || header[3] != SD2 || !(4..=249).contains(&le) {
                return Err(FdlError::BadLength);
            }
            (4, usize::from(le))
        }
        other => return Err(FdlError::BadDelimiter(other)),
    };
    let total = body_start + body_len + 2;
    let frame = bytes.get(..total).ok_or(FdlError::Incomplete)?;
    let body = &frame[body_start..body_start + body_len];
    let fcs = body.iter().fold(0u8, |sum, b| sum.wrapping_add(*b));
    if frame[total - 2] != fcs {
        return Err(FdlError::BadFcs);
    }
    if frame[total - 1] != ED {
        return Err(FdlError::BadEnd);
    }
    let (da, sa, fc) = (body[0], body[1], body[2]);
    let mut rest = &body[3..];
    let mut sap = |present: bool| -> Result<Option<u8>, FdlError> {
        if !present {
            return Ok(None);
        }
        let (&first, tail) = rest.split_first().ok_or(FdlError::BadLength)?;
        rest = tail;
        Ok(Some(first & 0x3F))
    };
    let dsap = sap(da & 0x80 != 0)?;
    let ssap = sap(sa & 0x80 != 0)?;
    Ok((
        Telegram::Data(DataTelegram {
            da: da & 0x7F,
            sa: sa & 0x7F,
            dsap,
            ssap,
            fc,
            data: rest.to_vec(),
        }),
        total,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sd1_fdl_status_request() {
        // FDL status request from master 2 to station 5: 10 05 02 49 50 16.
        let bytes = [0x10, 0x05, 0x02, 0x49, 0x50, 0x16];
        let (telegram, used) = parse(&bytes).unwrap();
        assert_eq!(used, 6);
        let Telegram::Data(t) = telegram else {
            panic!("{telegram:?}")
        };
        assert_eq!((t.da, t.sa, t.fc, t.function()), (5, 2, 0x49, 9));
        assert_eq!(t.emit().unwrap(), bytes);
    }

    #[test]
    fn sd2_with_saps() {
        // Slave_Diag request: DA 5 + ext, SA 2 + ext, FC 7D (SRD high, FCV, FCB 1), DSAP 60,
        // SSAP 62, no data.
        let t = DataTelegram {
            da: 5,
            sa: 2,
            dsap: Some(60),
            ssap: Some(62),
            fc: 0x7D,
            data: vec![],
        };
        let bytes = t.emit().unwrap();
        assert_eq!(
            bytes,
            [0x68, 0x05, 0x05, 0x68, 0x85, 0x82, 0x7D, 0x3C, 0x3E, 0xFE, 0x16]
        );
        assert_eq!(parse(&bytes), Ok((Telegram::Data(t.clone()), 11)));
        assert_eq!(t.fcb(), Some(true));
    }

    #[test]
    fn sd3_and_tokens() {
        let t = DataTelegram {
            da: 3,
            sa: 1,
            dsap: None,
            ssap: None,
            fc: 0x08,
            data: vec![1, 2, 3, 4, 5, 6, 7, 8],
        };
        let bytes = t.emit().unwrap();
        assert_eq!(bytes[0], SD3);
        assert_eq!(bytes.len(), 14);
        assert_eq!(parse(&bytes).unwrap().0, Telegram::Data(t));
        assert_eq!(
            parse(&[0xDC, 1, 2]),
            Ok((Telegram::Token { da: 1, sa: 2 }, 3))
        );
        assert_eq!(parse(&[0xE5, 0]), Ok((Telegram::ShortAck, 1)));
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
        assert_eq!(parse(&[0x68, 0x05, 0x06, 0x68]), Err(FdlError::BadLength));
        assert_eq!(parse(&[0x68, 0x02, 0x02, 0x68]), Err(FdlError::BadLength));
        assert_eq!(parse(&[0x42]), Err(FdlError::BadDelimiter(0x42)));
        // SAP bits set with no room for the SAP bytes.
        assert_eq!(
            parse(&[0x68, 3, 3, 0x68, 0x85, 0x02, 0x6D, 0xF4, 0x16]),
            Err(FdlError::BadLength)
        );
    }
}
