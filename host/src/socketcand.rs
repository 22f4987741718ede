//! The socketcand protocol in the dialect python-can 4.6.1 speaks, and a client [`Transport`] over
//! TCP. [`MessageScanner`] cuts `< ... >` messages out of a byte stream however the reads split or
//! join them; [`Message`] parses and emits them (sans-IO); [`SocketcandClient`] does the handshake
//! and carries frames in rawmode.
//!
//! The dialect cannot carry a remote request: python-can sends one as `< send ID LEN  >` (a
//! length, no bytes), which [`Message::parse`] reads back as a remote request, but a `frame`
//! message has no place for the flag, so a receiver sees a data frame without data.

use std::fmt;
use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::{Duration as StdDuration, Instant as StdInstant};

use super::trace::parse_hex;
use super::Transport;
use edsgen_runtime::frame::{CanFrame, CanId};

/// The port socketcand listens on by default.
pub const DEFAULT_PORT: u16 = 29536;

/// The longest message body the scanner keeps: a `frame` with an extended identifier and 8 bytes
/// is under 50 bytes; anything much longer without a `>` is garbage and is dropped.
const MAX_MESSAGE: usize = 256;

/// Cuts `< ... >` messages out of a byte stream. Bytes outside a message are skipped, a `<` inside
/// an unfinished message starts a new one, and an unfinished message longer than 256 bytes is
/// dropped, so garbage costs bounded memory and never hides the messages after it.
#[derive(Debug, Default)]
pub struct MessageScanner {
    buffer: Vec<u8>,
    /// Where scanning resumes in `buffer`.
    start: usize,
}

impl MessageScanner {
    /// An empty scanner.
    pub fn new() -> Self {
        MessageScanner::default()
    }

    /// Appends bytes just read.
    pub fn push(&mut self, bytes: &[u8]) {
        if self.start > 0 && self.start == self.buffer.len() {
            self.buffer.clear();
            self.start = 0;
        }
        self.buffer.extend_from_slice(bytes);
    }

    /// The body of the next complete message (between `<` and `>`), if one has arrived.
    pub fn next_message(&mut self) -> Option<Vec<u8>> {
        loop {
            let rest = &self.buffer[self.start..];
            let Some(open) = rest.iter().position(|&b| b == b'<') else {
                self.start = self.buffer.len();
                return None;
            };
            let body_start = self.start + open + 1;
            let body = &self.buffer[body_start..];
            match body.iter().position(|&b| b == b'<' || b == b'>') {
                Some(end) if body[end] == b'>' => {
                    let message = body[..end].to_vec();
                    self.start = body_start + end + 1;
                    self.compact();
                    return Some(message);
                }
                // A new `<` before the `>`: the message so far was garbage.
                Some(end) => self.start = body_start + end,
                None => {
                    if body.len() > MAX_MESSAGE {
                        self.start = self.buffer.len();
                    }
                    self.compact();
                    return None;
                }
            }
        }
    }

    /// Whether part of a message is buffered (a peer that closes now closed mid-message).
    pub fn has_partial(&self) -> bool {
        self.buffer[self.start..].contains(&b'<')
    }

    fn compact(&mut self) {
        if self.start > 4096 || self.start == self.buffer.len() {
            self.buffer.drain(..self.start);
            self.start = 0;
        }
    }
}

/// One socketcand message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Message {
    /// `< hi >`: the server's greeting.
    Hi,
    /// `< ok >`: a command succeeded.
    Ok,
    /// `< open CHANNEL >`: the client picks a bus.
    Open(String),
    /// `< rawmode >`: the client asks for every frame of the bus.
    Rawmode,
    /// `< send ID LEN B0 B1 ... >`: a frame from a client to the bus. LEN > 0 with no bytes is
    /// read as a remote request (python-can drops the RTR flag and sends it so).
    Send(CanFrame),
    /// `< frame ID SECS.USECS HEX >`: a frame from the bus to a client, stamped with the wall
    /// clock (microseconds since the Unix epoch).
    Frame {
        /// The frame (a remote request is carried as its identifier with no data).
        frame: CanFrame,
        /// When it was seen.
        timestamp_us: u64,
    },
    /// `< error CLASS SECS.USECS >`: an error frame.
    Error {
        /// The error class.
        class: u32,
        /// When it was seen.
        timestamp_us: u64,
    },
    /// Any other message, as its words joined by one space (`echo`, `error could not open`, ...).
    Other(String),
}

/// Why a message could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MessageError(pub String);

impl fmt::Display for MessageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MessageError {}

impl Message {
    /// Parses the body of a message (what [`MessageScanner::next_message`] returns).
    pub fn parse(body: &[u8]) -> Result<Message, MessageError> {
        let text = std::str::from_utf8(body)
            .map_err(|_| MessageError("message is not ASCII text".to_owned()))?;
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        let bad = |what: &str| MessageError(format!("bad `{}` message: {what}", words.join(" ")));
        Ok(match words.as_slice() {
            ["hi"] => Message::Hi,
            ["ok"] => Message::Ok,
            ["open", channel] => Message::Open((*channel).to_owned()),
            ["rawmode"] => Message::Rawmode,
            ["send", id, len, bytes @ ..] => {
                let len = parse_id(len)
                    .filter(|&l| l <= 8)
                    .ok_or_else(|| bad("length is not 0 to 8"))? as u8;
                let data = bytes
                    .iter()
                    .map(|b| {
                        (b.len() <= 2)
                            .then(|| parse_id(b))
                            .flatten()
                            .map(|b| b as u8)
                    })
                    .collect::<Option<Vec<u8>>>()
                    .ok_or_else(|| bad("a data byte is not hex"))?;
                let frame = if data.is_empty() && len > 0 {
                    remote(id).map(|(id, extended)| remote_frame(id, extended, len))
                } else if data.len() != usize::from(len) {
                    return Err(bad("the length does not match the bytes"));
                } else {
                    remote(id).map(|(id, extended)| data_frame(id, extended, &data))
                };
                Message::Send(frame.flatten().ok_or_else(|| bad("bad identifier"))?)
            }
            ["frame", id, time, data @ ..] if data.len() <= 1 => {
                let timestamp_us = parse_time(time).ok_or_else(|| bad("bad timestamp"))?;
                let extended = match id.len() {
                    3 => false,
                    8 => true,
                    _ => return Err(bad("identifier is not 3 or 8 hex digits")),
                };
                let raw = parse_id(id).ok_or_else(|| bad("bad identifier"))?;
                let bytes = parse_hex(data.first().copied().unwrap_or(""))
                    .ok_or_else(|| bad("bad data"))?;
                let frame =
                    data_frame(raw, extended, &bytes).ok_or_else(|| bad("bad identifier"))?;
                Message::Frame {
                    frame,
                    timestamp_us,
                }
            }
            ["error", class, time] => match (parse_id(class), parse_time(time)) {
                (Some(class), Some(timestamp_us)) => Message::Error {
                    class,
                    timestamp_us,
                },
                _ => Message::Other(words.join(" ")),
            },
            [] => return Err(bad("empty message")),
            _ => Message::Other(words.join(" ")),
        })
    }

    /// Appends the message as python-can 4.6.1 writes and expects it: identifiers as 3 hex digits
    /// (standard) or 8 (extended); `send` bytes in lower-case hex without padding, separated by
    /// spaces; `frame` data in upper-case hex without separators; no data leaves two spaces
    /// before the `>`.
    pub fn emit(&self, out: &mut Vec<u8>) {
        use std::fmt::Write as _;
        let mut text = String::with_capacity(48);
        match self {
            Message::Hi => text.push_str("< hi >"),
            Message::Ok => text.push_str("< ok >"),
            Message::Open(channel) => write!(text, "< open {channel} >").unwrap_or(()),
            Message::Rawmode => text.push_str("< rawmode >"),
            Message::Send(frame) => {
                text.push_str("< send ");
                push_id(&mut text, frame);
                write!(text, " {:X} ", frame.dlc()).unwrap_or(());
                for (i, byte) in frame.data().iter().enumerate() {
                    if i > 0 {
                        text.push(' ');
                    }
                    write!(text, "{byte:x}").unwrap_or(());
                }
                text.push_str(" >");
            }
            Message::Frame {
                frame,
                timestamp_us,
            } => {
                text.push_str("< frame ");
                push_id(&mut text, frame);
                write!(
                    text,
                    " {}.{:06} ",
                    timestamp_us / 1_000_000,
                    timestamp_us % 1_000_000
                )
                .unwrap_or(());
                for byte in frame.data() {
                    write!(text, "{byte:02X}").unwrap_or(());
                }
                text.push_str(" >");
            }
            Message::Error {
                class,
                timestamp_us,
            } => write!(
                text,
                "< error {class:03X} {}.{:06} >",
                timestamp_us / 1_000_000,
                timestamp_us % 1_000_000
            )
            .unwrap_or(()),
            Message::Other(words) => write!(text, "< {words} >").unwrap_or(()),
        }
        out.extend_from_slice(text.as_bytes());
    }
}

fn push_id(text: &mut String, frame: &CanFrame) {
    use std::fmt::Write as _;
    match frame.id() {
        CanId::Standard(id) => write!(text, "{id:03X}"),
        CanId::Extended(id) => write!(text, "{id:08X}"),
    }
    .unwrap_or(())
}

/// Up to 8 hex digits (nothing else: no sign) as a number.
fn parse_id(text: &str) -> Option<u32> {
    (!text.is_empty() && text.len() <= 8 && text.bytes().all(|b| b.is_ascii_hexdigit()))
        .then(|| u32::from_str_radix(text, 16).ok())
        .flatten()
}

/// A `send` identifier: up to 3 digits is a standard one, more an extended one.
fn remote(text: &str) -> Option<(u32, bool)> {
    parse_id(text).map(|id| (id, text.len() > 3))
}

fn data_frame(id: u32, extended: bool, data: &[u8]) -> Option<CanFrame> {
    if extended {
        CanFrame::new_extended(id, data)
    } else {
        CanFrame::new(u16::try_from(id).ok()?, data)
    }
}

fn remote_frame(id: u32, extended: bool, len: u8) -> Option<CanFrame> {
    use embedded_can::{ExtendedId, Frame as _, Id, StandardId};
    let id = if extended {
        Id::Extended(ExtendedId::new(id)?)
    } else {
        Id::Standard(StandardId::new(u16::try_from(id).ok()?)?)
    };
    CanFrame::new_remote(id, usize::from(len))
}

/// `SECS.FRACTION` in microseconds (the fraction cut or padded to 6 digits).
fn parse_time(text: &str) -> Option<u64> {
    let (secs, fraction) = text.split_once('.').unwrap_or((text, ""));
    if secs.is_empty() || !(secs.bytes().chain(fraction.bytes())).all(|b| b.is_ascii_digit()) {
        return None;
    }
    let secs: u64 = secs.parse().ok()?;
    let mut micros = 0u64;
    for i in 0..6 {
        micros = micros * 10
            + fraction
                .as_bytes()
                .get(i)
                .map_or(0, |d| u64::from(d - b'0'));
    }
    secs.checked_mul(1_000_000)?.checked_add(micros)
}

/// Sets `TCP_NODELAY` on a socketcand connection so that each message leaves at once.
pub(crate) fn tune(stream: &TcpStream) -> io::Result<()> {
    stream.set_nodelay(true)?;
    rearm_quickack(stream);
    Ok(())
}

/// Re-arms `TCP_QUICKACK` (Linux clears it after a while), so that back-to-back messages are not
/// held up by a delayed ACK. Call after every read. Best effort: a failure only costs latency.
pub(crate) fn rearm_quickack(stream: &TcpStream) {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        let _ = socket2::SockRef::from(stream).set_tcp_quickack(true);
    }
    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    {
        let _ = stream;
    }
}

/// A socketcand client in rawmode: every frame sent on the bus by another client arrives here,
/// and what is sent here goes to all the others.
#[derive(Debug)]
pub struct SocketcandClient {
    stream: TcpStream,
    scanner: MessageScanner,
    /// The read mode last set on the socket, to save a system call per read.
    read_mode: Option<ReadMode>,
    out: Vec<u8>,
    peer: SocketAddr,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ReadMode {
    NonBlocking,
    /// Blocking, after [`crate::wait::readable`] said there is something to read.
    Waiting,
}

impl SocketcandClient {
    /// Connects to the server at `addr`, opens `channel` (`can0`) and enters rawmode, each step
    /// waiting at most `timeout`.
    pub fn connect(
        addr: impl ToSocketAddrs,
        channel: &str,
        timeout: StdDuration,
    ) -> io::Result<Self> {
        let mut last_error = None;
        for addr in addr.to_socket_addrs()? {
            match TcpStream::connect_timeout(&addr, timeout) {
                Ok(stream) => return SocketcandClient::handshake(stream, channel, timeout),
                Err(e) => last_error = Some(e),
            }
        }
        Err(last_error.unwrap_or_else(|| {
            io::Error::new(io::ErrorKind::InvalidInput, "no address to connect to")
        }))
    }

    fn handshake(stream: TcpStream, channel: &str, timeout: StdDuration) -> io::Result<Self> {
        tune(&stream)?;
        let peer = stream.peer_addr()?;
        let mut client = SocketcandClient {
            stream,
            scanner: MessageScanner::new(),
            read_mode: None,
            out: Vec::new(),
            peer,
        };
        client.expect(Message::Hi, "the greeting", timeout)?;
        client.write(&Message::Open(channel.to_owned()))?;
        client.expect(Message::Ok, &format!("`< open {channel} >`"), timeout)?;
        client.write(&Message::Rawmode)?;
        client.expect(Message::Ok, "`< rawmode >`", timeout)?;
        Ok(client)
    }

    /// The server's address.
    pub fn peer_addr(&self) -> SocketAddr {
        self.peer
    }

    fn expect(&mut self, wanted: Message, after: &str, timeout: StdDuration) -> io::Result<()> {
        let deadline = StdInstant::now() + timeout;
        loop {
            if let Some(body) = self.scanner.next_message() {
                let got = Message::parse(&body);
                if got.as_ref() == Ok(&wanted) {
                    return Ok(());
                }
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "socketcand server {}: expected {wanted:?} after {after}, got `<{}>`",
                        self.peer,
                        String::from_utf8_lossy(&body)
                    ),
                ));
            }
            let left = deadline.saturating_duration_since(StdInstant::now());
            if left.is_zero() || !self.fill(left)? {
                return Err(io::Error::new(
                    io::ErrorKind::TimedOut,
                    format!(
                        "socketcand server {}: no answer after {after} within {timeout:?}",
                        self.peer
                    ),
                ));
            }
        }
    }

    fn write(&mut self, message: &Message) -> io::Result<()> {
        self.out.clear();
        message.emit(&mut self.out);
        self.stream.write_all(&self.out)
    }

    /// Reads what has arrived, waiting at most `timeout` (zero: only what is there). `Ok(false)`
    /// if nothing arrived in time; an error when the server closed the connection.
    fn fill(&mut self, timeout: StdDuration) -> io::Result<bool> {
        let mode = if timeout.is_zero() {
            ReadMode::NonBlocking
        } else {
            ReadMode::Waiting
        };
        if self.read_mode != Some(mode) {
            self.stream.set_nonblocking(mode == ReadMode::NonBlocking)?;
            self.read_mode = Some(mode);
        }
        if mode == ReadMode::Waiting && !crate::wait::readable(&self.stream, timeout)? {
            return Ok(false);
        }
        let mut chunk = [0u8; 4096];
        match self.stream.read(&mut chunk) {
            Ok(0) => Err(io::Error::new(
                io::ErrorKind::UnexpectedEof,
                format!("socketcand server {} closed the connection", self.peer),
            )),
            Ok(n) => {
                rearm_quickack(&self.stream);
                self.scanner.push(&chunk[..n]);
                Ok(true)
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock
                        | io::ErrorKind::TimedOut
                        | io::ErrorKind::Interrupted
                ) =>
            {
                Ok(false)
            }
            Err(e) => Err(e),
        }
    }
}

impl Transport for SocketcandClient {
    fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
        self.write(&Message::Send(*frame))
    }

    /// Frames only: error frames and other messages are skipped, and so is a message that does
    /// not parse (the server is not ours to judge).
    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>> {
        let deadline = StdInstant::now() + timeout;
        loop {
            while let Some(body) = self.scanner.next_message() {
                if let Ok(Message::Frame { frame, .. }) = Message::parse(&body) {
                    return Ok(Some(frame));
                }
            }
            let left = deadline.saturating_duration_since(StdInstant::now());
            if !self.fill(left)? && left.is_zero() {
                return Ok(None);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn emitted(message: &Message) -> String {
        let mut out = Vec::new();
        message.emit(&mut out);
        String::from_utf8(out).unwrap()
    }

    fn frame(id: u16, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    #[test]
    fn send_is_emitted_with_lower_case_unpadded_bytes_and_two_spaces_for_no_data() {
        let sdo = frame(0x602, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]);
        assert_eq!(
            emitted(&Message::Send(sdo)),
            "< send 602 8 40 17 10 0 0 0 0 0 >"
        );
        assert_eq!(emitted(&Message::Send(frame(0, &[]))), "< send 000 0  >");
        assert_eq!(emitted(&Message::Send(frame(0x80, &[]))), "< send 080 0  >");
        assert_eq!(
            emitted(&Message::Send(
                CanFrame::new_extended(0x1AB, &[0xFF]).unwrap()
            )),
            "< send 000001AB 1 ff >"
        );
        assert_eq!(
            emitted(&Message::Send(CanFrame::remote(0x182, 8))),
            "< send 182 8  >"
        );
    }

    #[test]
    fn frame_is_emitted_with_three_or_eight_digit_id_and_upper_case_data() {
        let sdo = frame(0x583, &[0x4B, 0x01, 0x20, 0x00, 0x01, 0x01, 0x00, 0x00]);
        let message = Message::Frame {
            frame: sdo,
            timestamp_us: 1_700_000_000_123_456,
        };
        assert_eq!(
            emitted(&message),
            "< frame 583 1700000000.123456 4B01200001010000 >"
        );
        let empty = Message::Frame {
            frame: frame(0x123, &[]),
            timestamp_us: 1_000_000,
        };
        assert_eq!(emitted(&empty), "< frame 123 1.000000  >");
        let ext = Message::Frame {
            frame: CanFrame::new_extended(0x5, &[0xa]).unwrap(),
            timestamp_us: 7,
        };
        assert_eq!(emitted(&ext), "< frame 00000005 0.000007 0A >");
        let error = Message::Error {
            class: 4,
            timestamp_us: 2_000_001,
        };
        assert_eq!(emitted(&error), "< error 004 2.000001 >");
    }

    #[test]
    fn handshake_messages_are_emitted_exactly() {
        assert_eq!(emitted(&Message::Hi), "< hi >");
        assert_eq!(emitted(&Message::Ok), "< ok >");
        assert_eq!(emitted(&Message::Open("can0".into())), "< open can0 >");
        assert_eq!(emitted(&Message::Rawmode), "< rawmode >");
    }

    #[test]
    fn every_emitted_message_parses_back() {
        let messages = [
            Message::Hi,
            Message::Ok,
            Message::Open("vcan3".into()),
            Message::Rawmode,
            Message::Send(frame(0x602, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0])),
            Message::Send(frame(0x000, &[])),
            Message::Send(CanFrame::new_extended(0x1FFF_FFFF, &[1, 2, 3]).unwrap()),
            Message::Send(CanFrame::remote(0x705, 1)),
            Message::Frame {
                frame: frame(0x7FF, &[0xDE, 0xAD]),
                timestamp_us: 1_700_000_000_000_001,
            },
            Message::Frame {
                frame: frame(0x080, &[]),
                timestamp_us: 0,
            },
            Message::Frame {
                frame: CanFrame::new_extended(0x800, &[0; 8]).unwrap(),
                timestamp_us: 9,
            },
            Message::Error {
                class: 0x10,
                timestamp_us: 3,
            },
        ];
        for message in messages {
            let text = emitted(&message);
            let body = &text.as_bytes()[1..text.len() - 1];
            assert_eq!(Message::parse(body), Ok(message), "{text}");
        }
    }

    #[test]
    fn what_python_can_sends_is_understood() {
        let parse = |s: &str| Message::parse(s.as_bytes());
        assert_eq!(
            parse(" send 602 8 40 17 10 0 0 0 0 0 "),
            Ok(Message::Send(frame(
                0x602,
                &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]
            )))
        );
        assert_eq!(parse(" send 000 0  "), Ok(Message::Send(frame(0, &[]))));
        assert_eq!(
            parse(" send 182 8  "),
            Ok(Message::Send(CanFrame::remote(0x182, 8)))
        );
        assert_eq!(
            parse(" send 12345678 2 a b "),
            Ok(Message::Send(
                CanFrame::new_extended(0x1234_5678, &[0xA, 0xB]).unwrap()
            ))
        );
        assert_eq!(
            parse(" frame 123 23.424242 11223344 "),
            Ok(Message::Frame {
                frame: frame(0x123, &[0x11, 0x22, 0x33, 0x44]),
                timestamp_us: 23_424_242
            })
        );
        assert_eq!(
            parse(" frame 123 5.5  "),
            Ok(Message::Frame {
                frame: frame(0x123, &[]),
                timestamp_us: 5_500_000
            })
        );
        assert_eq!(parse(" echo "), Ok(Message::Other("echo".into())));
        assert_eq!(
            parse(" error could not open bus "),
            Ok(Message::Other("error could not open bus".into()))
        );
    }

    #[test]
    fn malformed_messages_are_errors_not_panics() {
        let cases = [
            (
                " send 602 9 1 2 3 4 5 6 7 8 9 ",
                "bad `send 602 9 1 2 3 4 5 6 7 8 9` message: length is not 0 to 8",
            ),
            (
                " send 602 2 1 ",
                "bad `send 602 2 1` message: the length does not match the bytes",
            ),
            (
                " send 602 1 1zz ",
                "bad `send 602 1 1zz` message: a data byte is not hex",
            ),
            (
                " send 602 +1 1 ",
                "bad `send 602 +1 1` message: length is not 0 to 8",
            ),
            (
                " send 602 1 +f ",
                "bad `send 602 1 +f` message: a data byte is not hex",
            ),
            (
                " frame 123 1.0 +F ",
                "bad `frame 123 1.0 +F` message: bad data",
            ),
            (
                " send 802 1 1 ",
                "bad `send 802 1 1` message: bad identifier",
            ),
            (
                " send 123456789 1 1 ",
                "bad `send 123456789 1 1` message: bad identifier",
            ),
            (
                " frame 12 1.0 00 ",
                "bad `frame 12 1.0 00` message: identifier is not 3 or 8 hex digits",
            ),
            (
                " frame 123 x 00 ",
                "bad `frame 123 x 00` message: bad timestamp",
            ),
            (
                " frame 123 1.0 0 ",
                "bad `frame 123 1.0 0` message: bad data",
            ),
            ("  ", "bad `` message: empty message"),
        ];
        for (body, message) in cases {
            assert_eq!(
                Message::parse(body.as_bytes()),
                Err(MessageError(message.to_owned())),
                "{body}"
            );
        }
        assert_eq!(
            Message::parse(&[0xFF, b' ']),
            Err(MessageError("message is not ASCII text".to_owned()))
        );
    }

    #[test]
    fn scanner_joins_split_reads_and_splits_joined_ones() {
        let mut scanner = MessageScanner::new();
        scanner.push(b"< h");
        assert_eq!(scanner.next_message(), None);
        assert!(scanner.has_partial());
        scanner.push(b"i >< ok >< fra");
        assert_eq!(scanner.next_message().as_deref(), Some(&b" hi "[..]));
        assert_eq!(scanner.next_message().as_deref(), Some(&b" ok "[..]));
        assert_eq!(scanner.next_message(), None);
        scanner.push(b"me 123 1.000000  >");
        assert_eq!(
            scanner.next_message().as_deref(),
            Some(&b" frame 123 1.000000  "[..])
        );
        assert!(!scanner.has_partial());
        for byte in b"< send 000 0  >" {
            scanner.push(&[*byte]);
        }
        assert_eq!(
            scanner.next_message().as_deref(),
            Some(&b" send 000 0  "[..])
        );
        assert_eq!(scanner.next_message(), None);
    }

    #[test]
    fn scanner_skips_garbage_and_recovers_at_the_next_message() {
        let mut scanner = MessageScanner::new();
        scanner.push(b"garbage > more < unfinished < ok >tail");
        assert_eq!(scanner.next_message().as_deref(), Some(&b" ok "[..]));
        assert_eq!(scanner.next_message(), None);
        assert!(!scanner.has_partial());
        scanner.push(b"<");
        scanner.push(&[b'x'; 300]);
        assert_eq!(scanner.next_message(), None);
        assert!(!scanner.has_partial(), "an overlong message is dropped");
        scanner.push(b"x>< hi >");
        assert_eq!(scanner.next_message().as_deref(), Some(&b" hi "[..]));
    }

    /// A one-connection server that plays `script`: `Ok(text)` is written, `Err(text)` is the
    /// exact message the client must send next.
    fn scripted_server(
        script: Vec<Result<&'static str, &'static str>>,
    ) -> (SocketAddr, std::thread::JoinHandle<()>) {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let thread = std::thread::spawn(move || {
            let (mut stream, _) = listener.accept().unwrap();
            stream
                .set_read_timeout(Some(StdDuration::from_secs(5)))
                .unwrap();
            for step in script {
                match step {
                    Ok(text) => stream.write_all(text.as_bytes()).unwrap(),
                    Err(wanted) => {
                        let mut got = Vec::new();
                        let mut byte = [0u8];
                        while got.last() != Some(&b'>') {
                            stream.read_exact(&mut byte).unwrap();
                            got.push(byte[0]);
                        }
                        assert_eq!(String::from_utf8(got).unwrap(), wanted);
                    }
                }
                stream.flush().unwrap();
            }
        });
        (addr, thread)
    }

    const SECOND: StdDuration = StdDuration::from_secs(1);

    #[test]
    fn client_handshakes_then_reads_joined_and_split_frames_and_sends() {
        let (addr, server) = scripted_server(vec![
            Ok("< hi >"),
            Err("< open can0 >"),
            Ok("< ok >"),
            Err("< rawmode >"),
            Ok("< ok >< frame 183 1.000000 0102 >< error 001 1.000000 >< fra"),
            Ok("me 080 2.000000  >"),
            Err("< send 603 4 40 0 10 0 >"),
        ]);
        let mut client = SocketcandClient::connect(addr, "can0", SECOND).unwrap();
        assert_eq!(
            client.recv_timeout(SECOND).unwrap(),
            Some(frame(0x183, &[1, 2]))
        );
        assert_eq!(
            client.recv_timeout(SECOND).unwrap(),
            Some(frame(0x080, &[]))
        );
        client.send(&frame(0x603, &[0x40, 0, 0x10, 0])).unwrap();
        server.join().unwrap();
        let error = client.recv_timeout(SECOND).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::UnexpectedEof);
        assert_eq!(
            error.to_string(),
            format!("socketcand server {addr} closed the connection")
        );
    }

    #[test]
    fn client_polls_without_waiting_and_times_out_when_nothing_arrives() {
        let (addr, server) = scripted_server(vec![
            Ok("< hi >"),
            Err("< open can1 >"),
            Ok("< ok >"),
            Err("< rawmode >"),
            Ok("< ok >"),
            Err("< send 000 2 1 0 >"),
        ]);
        let mut client = SocketcandClient::connect(addr, "can1", SECOND).unwrap();
        assert_eq!(client.recv_timeout(StdDuration::ZERO).unwrap(), None);
        let start = StdInstant::now();
        assert_eq!(
            client.recv_timeout(StdDuration::from_millis(30)).unwrap(),
            None
        );
        assert!(start.elapsed() >= StdDuration::from_millis(30));
        client.send(&frame(0, &[1, 0])).unwrap();
        server.join().unwrap();
    }

    #[test]
    fn client_reports_a_server_that_refuses_the_channel() {
        let (addr, server) = scripted_server(vec![
            Ok("< hi >"),
            Err("< open can9 >"),
            Ok("< error could not open bus >"),
        ]);
        let error = SocketcandClient::connect(addr, "can9", SECOND).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidData);
        assert_eq!(
            error.to_string(),
            format!("socketcand server {addr}: expected Ok after `< open can9 >`, got `< error could not open bus >`")
        );
        server.join().unwrap();
    }

    #[test]
    fn client_times_out_on_a_silent_server() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let error =
            SocketcandClient::connect(addr, "can0", StdDuration::from_millis(50)).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::TimedOut);
        assert_eq!(
            error.to_string(),
            format!("socketcand server {addr}: no answer after the greeting within 50ms")
        );
    }
}
