//! PROFIBUS FDL telegrams (EN 50170 layer 2) as a DP slave sees them: SD1 (no data), SD2
//! (variable data), SD3 (8 data bytes), SD4 (token), SC (short acknowledgement); the frame
//! check sequence (the sum of DA…data), the SAP extension bits of DA/SA, and the frame control
//! byte (request or response, FCB/FCV, function). Wire format only: a checked view
//! ([`Telegram`]) and its meaning ([`Repr`]), parsed from and emitted into the caller's bytes.

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
/// The longest telegram (SD2 with LE 249): 4 + 249 + 2 bytes.
pub const MAX_TELEGRAM_LEN: usize = 255;

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

/// Why bytes are no telegram (a slave stays silent on each), or why one cannot be emitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FdlError {
    /// More bytes are needed.
    Incomplete,
    /// Not a start delimiter.
    BadDelimiter(u8),
    /// SD2's two lengths differ, or are outside 4–249, or the second SD2 is missing; or the
    /// SAP bits are set with no room for the SAPs; or the data is too long to emit.
    BadLength,
    /// The frame check sequence is wrong.
    BadFcs,
    /// The end delimiter is not 16h.
    BadEnd,
    /// The caller's buffer is too small for the telegram.
    BufferTooSmall,
}

/// A checked view of one telegram at the start of a buffer (the buffer may go on after it).
#[derive(Debug, Clone, Copy)]
pub struct Telegram<T: AsRef<[u8]>> {
    buffer: T,
    /// Where DA…data starts and how long it is (`None` for SD4 and SC).
    body: Option<(usize, usize)>,
    len: usize,
}

impl<T: AsRef<[u8]>> Telegram<T> {
    /// Checks the telegram at the start of `buffer`: delimiter, lengths, FCS, end delimiter and
    /// room for the SAPs its address bits announce.
    pub fn new_checked(buffer: T) -> Result<Self, FdlError> {
        let bytes = buffer.as_ref();
        let Some(&sd) = bytes.first() else {
            return Err(FdlError::Incomplete);
        };
        let (body_start, body_len) = match sd {
            SC => {
                return Ok(Telegram {
                    buffer,
                    body: None,
                    len: 1,
                })
            }
            SD4 if bytes.len() < 3 => return Err(FdlError::Incomplete),
            SD4 => {
                return Ok(Telegram {
                    buffer,
                    body: None,
                    len: 3,
                })
            }
            SD1 => (1, 3),
            SD3 => (1, 11),
            SD2 => {
                let [_, le, le_repeated, sd2] = *bytes.get(..4).ok_or(FdlError::Incomplete)? else {
                    return Err(FdlError::Incomplete);
                };
                if le_repeated != le || sd2 != SD2 || !(4..=249).contains(&le) {
                    return Err(FdlError::BadLength);
                }
                (4, usize::from(le))
            }
            other => return Err(FdlError::BadDelimiter(other)),
        };
        let len = body_start + body_len + 2;
        let frame = bytes.get(..len).ok_or(FdlError::Incomplete)?;
        let body = &frame[body_start..body_start + body_len];
        if frame[len - 2] != checksum(body) {
            return Err(FdlError::BadFcs);
        }
        if frame[len - 1] != ED {
            return Err(FdlError::BadEnd);
        }
        let saps = usize::from(body[0] >> 7) + usize::from(body[1] >> 7);
        if body_len < 3 + saps {
            return Err(FdlError::BadLength);
        }
        Ok(Telegram {
            buffer,
            body: Some((body_start, body_len)),
            len,
        })
    }

    /// The telegram's length in bytes, delimiters included.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Never: a telegram has at least one byte.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The start delimiter.
    pub fn delimiter(&self) -> u8 {
        self.buffer.as_ref()[0]
    }

    /// DA…data of a data telegram (SD1, SD2, SD3).
    fn body(&self) -> Option<&[u8]> {
        let (start, len) = self.body?;
        self.buffer.as_ref().get(start..start + len)
    }

    /// The destination address byte as sent (with the SAP extension bit); the token's too.
    pub fn da_byte(&self) -> Option<u8> {
        match self.body() {
            Some(body) => Some(body[0]),
            None => (self.delimiter() == SD4).then(|| self.buffer.as_ref()[1]),
        }
    }

    /// The source address byte as sent (with the SAP extension bit); the token's too.
    pub fn sa_byte(&self) -> Option<u8> {
        match self.body() {
            Some(body) => Some(body[1]),
            None => (self.delimiter() == SD4).then(|| self.buffer.as_ref()[2]),
        }
    }

    /// The frame control byte of a data telegram.
    pub fn fc(&self) -> Option<u8> {
        Some(self.body()?[2])
    }

    /// The SAP bytes and data after FC of a data telegram.
    pub fn payload(&self) -> Option<&[u8]> {
        Some(&self.body()?[3..])
    }
}

/// A data telegram's meaning: addresses, SAPs, frame control and data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataRepr<'a> {
    /// Destination address (without the SAP extension bit).
    pub da: u8,
    /// Source address (without the SAP extension bit).
    pub sa: u8,
    /// Destination SAP byte as sent, if DA's extension bit was set (0–63 for a SAP; bits 6–7,
    /// segment and address extension, are not DP-V0's).
    pub dsap: Option<u8>,
    /// Source SAP byte as sent, if SA's extension bit was set.
    pub ssap: Option<u8>,
    /// The frame control byte.
    pub fc: u8,
    /// The data after the SAPs.
    pub data: &'a [u8],
}

/// A telegram's meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Repr<'a> {
    /// SD1, SD2 or SD3.
    Data(DataRepr<'a>),
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

impl<'a> Repr<'a> {
    /// The meaning of a checked telegram.
    pub fn parse<T: AsRef<[u8]> + ?Sized>(telegram: &Telegram<&'a T>) -> Repr<'a> {
        let bytes: &'a [u8] = telegram.buffer.as_ref();
        let Some((start, len)) = telegram.body else {
            return match telegram.delimiter() {
                SD4 => Repr::Token {
                    da: bytes[1],
                    sa: bytes[2],
                },
                _ => Repr::ShortAck,
            };
        };
        let body = &bytes[start..start + len];
        let (da, sa, fc) = (body[0], body[1], body[2]);
        let mut rest = &body[3..];
        let mut sap = |present: bool| {
            let (&first, tail) = rest.split_first().filter(|_| present)?;
            rest = tail;
            Some(first)
        };
        let dsap = sap(da & 0x80 != 0);
        let ssap = sap(sa & 0x80 != 0);
        Repr::Data(DataRepr {
            da: da & 0x7F,
            sa: sa & 0x7F,
            dsap,
            ssap,
            fc,
            data: rest,
        })
    }
}

/// Parses one telegram at the start of `bytes`: its meaning and how many bytes it took.
pub fn parse(bytes: &[u8]) -> Result<(Repr<'_>, usize), FdlError> {
    let telegram = Telegram::new_checked(bytes)?;
    Ok((Repr::parse(&telegram), telegram.len()))
}

impl DataRepr<'_> {
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

    /// DA…data: the addresses, FC, the SAPs and the data.
    fn body_len(&self) -> usize {
        3 + usize::from(self.dsap.is_some()) + usize::from(self.ssap.is_some()) + self.data.len()
    }

    /// The telegram's length: SD1 without data or SAPs, SD3 with exactly 8 bytes of data and no
    /// SAPs, else SD2; `None` when the data does not fit (more than 246 bytes with the SAPs).
    pub fn buffer_len(&self) -> Option<usize> {
        let body = self.body_len();
        match self.delimiter() {
            SD1 | SD3 => Some(1 + body + 2),
            _ => (body <= 249).then_some(4 + body + 2),
        }
    }

    fn delimiter(&self) -> u8 {
        match self.body_len() {
            3 => SD1,
            11 if self.dsap.is_none() && self.ssap.is_none() => SD3,
            _ => SD2,
        }
    }

    /// Writes the telegram at the start of `buf`; its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, FdlError> {
        let len = self.buffer_len().ok_or(FdlError::BadLength)?;
        let out = buf.get_mut(..len).ok_or(FdlError::BufferTooSmall)?;
        let body_len = self.body_len();
        let sd = self.delimiter();
        let start = if sd == SD2 {
            // body_len <= 249: buffer_len said so.
            let le = body_len as u8;
            out[..4].copy_from_slice(&[SD2, le, le, SD2]);
            4
        } else {
            out[0] = sd;
            1
        };
        let body = &mut out[start..start + body_len];
        body[0] = self.da | if self.dsap.is_some() { 0x80 } else { 0 };
        body[1] = self.sa | if self.ssap.is_some() { 0x80 } else { 0 };
        body[2] = self.fc;
        let mut at = 3;
        for sap in [self.dsap, self.ssap].into_iter().flatten() {
            body[at] = sap;
            at += 1;
        }
        body[at..].copy_from_slice(self.data);
        let fcs = checksum(body);
        out[len - 2] = fcs;
        out[len - 1] = ED;
        Ok(len)
    }
}

/// The frame check sequence: the sum of DA…data, modulo 256.
fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(0u8, |sum, b| sum.wrapping_add(*b))
}

#[cfg(test)]
mod tests;
