//! Frame traces in the `candump -L` log format, which `canplayer` replays and python-can reads:
//! `(1700000000.123456) can0 603#2B011803E8030000`, one frame a line.
//!
//! [`format_line`] and [`parse_log_line`] own the format (the one candump reader: `edsgen-decode`
//! reads candump logs through it); [`TraceWriter`] writes lines, [`TraceReader`] reads them with
//! line numbers in its errors, and [`Traced`] logs every frame a [`Transport`] sends or
//! receives. Beside them, the pieces other log formats share: hex bytes, decimal times, frames.

use std::fmt;
use std::io::{self, BufRead, Write};
use std::time::{Duration as StdDuration, SystemTime, UNIX_EPOCH};

use super::Transport;
use edsgen_runtime::frame::{CanFrame, CanId};

/// One line of a trace: when, on which interface, what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceRecord {
    /// Wall-clock time of the frame in microseconds since the Unix epoch.
    pub timestamp_us: u64,
    /// The interface name (`can0`).
    pub channel: String,
    /// The frame.
    pub frame: CanFrame,
}

/// Why a trace line could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceError {
    /// The 1-based line number (0 when parsing a line on its own).
    pub line: usize,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for TraceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "bad candump line: {}", self.message)
        } else {
            write!(f, "line {}: bad candump line: {}", self.line, self.message)
        }
    }
}

impl std::error::Error for TraceError {}

/// Microseconds since the Unix epoch of `time` (0 before the epoch).
pub fn epoch_micros(time: SystemTime) -> u64 {
    time.duration_since(UNIX_EPOCH)
        .map(|d| d.as_micros() as u64)
        .unwrap_or(0)
}

/// The `candump -L` line of `frame`, without a line break: 3 hex digits for a standard
/// identifier, 8 for an extended one, data in upper-case hex, `ID#R` (`ID#R<len>` when the
/// requested length is not 0) for a remote request, `ID#` for no data.
pub fn format_line(timestamp_us: u64, channel: &str, frame: &CanFrame) -> String {
    use fmt::Write as _;
    let mut line = format!(
        "({}.{:06}) {} ",
        timestamp_us / 1_000_000,
        timestamp_us % 1_000_000,
        channel
    );
    match frame.id() {
        CanId::Standard(id) => write!(line, "{id:03X}#"),
        CanId::Extended(id) => write!(line, "{id:08X}#"),
    }
    .ok();
    if frame.is_remote() {
        line.push('R');
        if frame.dlc() > 0 {
            write!(line, "{}", frame.dlc()).ok();
        }
    } else {
        for byte in frame.data() {
            write!(line, "{byte:02X}").ok();
        }
    }
    line
}

/// Reads one `candump -L` line (surrounding white space ignored) as a frame this crate carries:
/// a CAN FD or an error frame is an error here (see [`parse_log_line`] to tell them apart).
pub fn parse_line(line: &str) -> Result<TraceRecord, TraceError> {
    parse(line.trim()).map_err(|message| TraceError { line: 0, message })
}

fn parse(line: &str) -> Result<TraceRecord, String> {
    match parse_log_line(line)? {
        LogLine::Frame(record) => Ok(record),
        LogLine::Fd => Err(format!(
            "`{line}` is a CAN FD frame (`ID##FLAGSDATA`): not supported"
        )),
        LogLine::Error => Err(format!(
            "`{line}` is an error frame (CAN_ERR_FLAG set): not supported"
        )),
    }
}

/// What one `candump -L` line holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LogLine {
    /// A classic CAN frame.
    Frame(TraceRecord),
    /// A CAN FD frame (`ID##FLAGSDATA`).
    Fd,
    /// An error frame (the identifier has Linux's `CAN_ERR_FLAG`).
    Error,
}

/// The flag Linux sets in the identifier of an error frame, which candump logs as it is.
pub const CAN_ERR_FLAG: u32 = 0x2000_0000;

/// One `candump -L` line, as can-utils and python-can write it: `(1700000000.123456) can0
/// 701#05`, any number of decimals (digits past the sixth are dropped), `ID#R` or `ID#R8` for a
/// remote request, an optional direction (`R`, `T`) after the frame as python-can writes it. CAN
/// FD and error frames are recognised, not read.
pub fn parse_log_line(text: &str) -> Result<LogLine, String> {
    let words: Vec<&str> = text.split_ascii_whitespace().collect();
    let (time, channel, frame) = match words.as_slice() {
        [time, channel, frame] | [time, channel, frame, "R" | "T"] => (*time, *channel, *frame),
        _ => {
            return Err(format!(
                "expected `(SECONDS) CHANNEL ID#DATA`, found `{}`",
                shorten(text)
            ))
        }
    };
    let timestamp_us = parenthesised_time(time)?;
    let (id, data) = frame
        .split_once('#')
        .ok_or_else(|| format!("bad frame `{frame}`: expected `ID#DATA`"))?;
    if data.starts_with('#') {
        return Ok(LogLine::Fd);
    }
    let (id, extended) = identifier(id)?;
    if extended && id & CAN_ERR_FLAG != 0 {
        return Ok(LogLine::Error);
    }
    let remote = match data.strip_prefix(['R', 'r']) {
        Some("") => Some(0),
        Some(len) if len.len() == 1 && len.as_bytes()[0].is_ascii_digit() => {
            Some(len.as_bytes()[0] - b'0')
        }
        Some(_) => {
            return Err(format!(
                "bad remote request `{frame}`: expected `ID#R` or `ID#R0`..`ID#R8`"
            ))
        }
        None => None,
    };
    let bytes = if remote.is_some() {
        Vec::new()
    } else {
        hex_pairs(data).ok_or_else(|| format!("bad data `{data}`: expected pairs of hex digits"))?
    };
    let frame = make_frame(id, extended, remote, &bytes)?;
    Ok(LogLine::Frame(TraceRecord {
        timestamp_us,
        channel: channel.to_owned(),
        frame,
    }))
}

/// `text` cut to its first 60 characters (and `...`) for an error message.
pub fn shorten(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((at, _)) => format!("{}...", &text[..at]),
        None => text.to_owned(),
    }
}

/// Bytes written as pairs of hex digits without separators (`057F`).
pub fn hex_pairs(text: &str) -> Option<Vec<u8>> {
    if !text.is_ascii() || text.len() % 2 != 0 {
        return None;
    }
    let pairs: Vec<&str> = (0..text.len() / 2)
        .map(|i| &text[2 * i..2 * i + 2])
        .collect();
    hex_words(&pairs)
}

/// `text` as at most 8 bytes written as pairs of hex digits. Only digits: a sign, which
/// `from_str_radix` would take (`+F`), is not one.
pub(crate) fn parse_hex(text: &str) -> Option<Vec<u8>> {
    hex_pairs(text).filter(|bytes| bytes.len() <= 8)
}

/// `(1700000000.123456)` (any decimals) as microseconds.
pub fn parenthesised_time(word: &str) -> Result<u64, String> {
    word.strip_prefix('(')
        .and_then(|w| w.strip_suffix(')'))
        .and_then(seconds_to_micros)
        .ok_or_else(|| {
            format!("bad timestamp `{word}`: expected `(SECONDS)`, such as `(1700000000.123456)`")
        })
}

/// An identifier in hex as candump writes it: 3 digits or fewer standard, 8 extended (flags
/// included); `(identifier, extended)`.
pub fn identifier(word: &str) -> Result<(u32, bool), String> {
    if word.is_empty() || word.len() > 8 || !word.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!(
            "bad identifier `{word}`: expected 3 or 8 hex digits"
        ));
    }
    let id = u32::from_str_radix(word, 16).map_err(|_| format!("bad identifier `{word}`"))?;
    Ok((id, word.len() == 8))
}

/// Seconds with any number of decimals (`1700000000.123456`, `0.5`, `12`) as microseconds;
/// digits past the sixth decimal are dropped. `None` for anything else.
pub fn seconds_to_micros(text: &str) -> Option<u64> {
    decimal_to_micros(text, 1_000_000)
}

/// A decimal number of `unit`s (1,000,000 for seconds, 1,000 for milliseconds) as
/// microseconds, truncated.
pub fn decimal_to_micros(text: &str, unit: u64) -> Option<u64> {
    let (whole, fraction) = text.split_once('.').unwrap_or((text, ""));
    if whole.is_empty() || !whole.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    if !fraction.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let whole: u64 = whole.parse().ok()?;
    let mut micros = 0u64;
    let mut scale = unit;
    for digit in fraction.bytes() {
        scale /= 10;
        if scale == 0 {
            break;
        }
        micros += u64::from(digit - b'0') * scale;
    }
    whole.checked_mul(unit)?.checked_add(micros)
}

/// Bytes as pairs of hex digits, one pair a word (`05 7F`); `None` if a word is not one.
pub fn hex_words(words: &[&str]) -> Option<Vec<u8>> {
    words
        .iter()
        .map(|w| {
            (w.len() == 2 && w.bytes().all(|b| b.is_ascii_hexdigit()))
                .then(|| u8::from_str_radix(w, 16).ok())
                .flatten()
        })
        .collect()
}

/// A classic frame: standard when `extended` is false (11 bits), else 29 bits; a remote request
/// of `len` when `remote`.
pub fn make_frame(
    id: u32,
    extended: bool,
    remote: Option<u8>,
    data: &[u8],
) -> Result<CanFrame, String> {
    use embedded_can::{ExtendedId, Id, StandardId};
    if data.len() > 8 {
        return Err(format!(
            "{} data bytes: a classic frame has at most 8",
            data.len()
        ));
    }
    let bad_id = || {
        if extended {
            format!("identifier {id:X} is not 29 bits")
        } else {
            format!("identifier {id:X} is not 11 bits")
        }
    };
    match remote {
        Some(len) if len <= 8 => {
            let id = if extended {
                Id::Extended(ExtendedId::new(id).ok_or_else(bad_id)?)
            } else {
                let id = u16::try_from(id).ok().and_then(StandardId::new);
                Id::Standard(id.ok_or_else(bad_id)?)
            };
            <CanFrame as embedded_can::Frame>::new_remote(id, usize::from(len)).ok_or_else(bad_id)
        }
        Some(len) => Err(format!("remote request of length {len}: at most 8")),
        None if extended => CanFrame::new_extended(id, data).ok_or_else(bad_id),
        None => u16::try_from(id)
            .ok()
            .and_then(|id| CanFrame::new(id, data))
            .ok_or_else(bad_id),
    }
}

/// Reads a `candump -L` log line by line; blank lines are skipped.
#[derive(Debug)]
pub struct TraceReader<R> {
    input: R,
    line: usize,
    text: String,
}

impl<R: BufRead> TraceReader<R> {
    /// A reader of `input`.
    pub fn new(input: R) -> Self {
        TraceReader {
            input,
            line: 0,
            text: String::new(),
        }
    }
}

/// An error of [`TraceReader`]: the input could not be read, or a line is malformed.
#[derive(Debug)]
pub enum TraceReadError {
    /// Reading failed (the line number is the one being read).
    Io(usize, io::Error),
    /// A malformed line.
    Parse(TraceError),
}

impl fmt::Display for TraceReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TraceReadError::Io(line, e) => write!(f, "line {line}: cannot read: {e}"),
            TraceReadError::Parse(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for TraceReadError {}

impl<R: BufRead> Iterator for TraceReader<R> {
    type Item = Result<TraceRecord, TraceReadError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            self.text.clear();
            self.line += 1;
            match self.input.read_line(&mut self.text) {
                Ok(0) => return None,
                Ok(_) if self.text.trim().is_empty() => continue,
                Ok(_) => {
                    let line = self.line;
                    return Some(
                        parse(self.text.trim())
                            .map_err(|message| TraceReadError::Parse(TraceError { line, message })),
                    );
                }
                Err(e) => return Some(Err(TraceReadError::Io(self.line, e))),
            }
        }
    }
}

/// Writes frames as `candump -L` lines, each flushed at once so that a log stays whole when the
/// program is stopped.
#[derive(Debug)]
pub struct TraceWriter<W> {
    output: W,
    channel: String,
}

impl<W: Write> TraceWriter<W> {
    /// A writer to `output` that names the interface `channel` on every line.
    pub fn new(output: W, channel: &str) -> Self {
        TraceWriter {
            output,
            channel: channel.to_owned(),
        }
    }

    /// Writes `frame` at `timestamp_us` (microseconds since the Unix epoch).
    pub fn write_frame(&mut self, timestamp_us: u64, frame: &CanFrame) -> io::Result<()> {
        write_line(&mut self.output, timestamp_us, &self.channel, frame)
    }

    /// Writes `frame` at `timestamp_us` on the interface named `channel`.
    pub fn write_frame_on(
        &mut self,
        timestamp_us: u64,
        channel: &str,
        frame: &CanFrame,
    ) -> io::Result<()> {
        write_line(&mut self.output, timestamp_us, channel, frame)
    }

    /// Gives back the output.
    pub fn into_inner(self) -> W {
        self.output
    }
}

fn write_line(
    output: &mut impl Write,
    timestamp_us: u64,
    channel: &str,
    frame: &CanFrame,
) -> io::Result<()> {
    let mut line = format_line(timestamp_us, channel, frame);
    line.push('\n');
    output.write_all(line.as_bytes())?;
    output.flush()
}

/// A [`Transport`] that writes every frame it sends or receives to a [`TraceWriter`], stamped with
/// the wall clock. A frame is logged once it is sent (or received); a failing log does not fail
/// the transport, it only stops logging (see [`Traced::log_error`]).
#[derive(Debug)]
pub struct Traced<T, W> {
    inner: T,
    log: TraceWriter<W>,
    log_error: Option<io::Error>,
}

impl<T: Transport, W: Write> Traced<T, W> {
    /// Traces `inner` to `log`.
    pub fn new(inner: T, log: TraceWriter<W>) -> Self {
        Traced {
            inner,
            log,
            log_error: None,
        }
    }

    /// The error that stopped the logging, if any.
    pub fn log_error(&self) -> Option<&io::Error> {
        self.log_error.as_ref()
    }

    /// Gives back the transport and the log.
    pub fn into_parts(self) -> (T, TraceWriter<W>) {
        (self.inner, self.log)
    }

    fn record(&mut self, frame: &CanFrame) {
        if self.log_error.is_none() {
            if let Err(e) = self.log.write_frame(epoch_micros(SystemTime::now()), frame) {
                self.log_error = Some(e);
            }
        }
    }
}

impl<T: Transport, W: Write> Transport for Traced<T, W> {
    fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
        self.inner.send(frame)?;
        self.record(frame);
        Ok(())
    }

    fn recv_timeout(&mut self, timeout: StdDuration) -> io::Result<Option<CanFrame>> {
        let frame = self.inner.recv_timeout(timeout)?;
        if let Some(frame) = &frame {
            self.record(frame);
        }
        Ok(frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: u64 = 1_700_000_000_123_456;

    fn std_frame(id: u16, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    #[test]
    fn standard_frame_is_written_with_three_digit_id_and_upper_case_data() {
        let frame = std_frame(0x603, &[0x2B, 0x01, 0x18, 0x03, 0xE8, 0x03, 0x00, 0x00]);
        assert_eq!(
            format_line(T, "can0", &frame),
            "(1700000000.123456) can0 603#2B011803E8030000"
        );
        assert_eq!(
            format_line(5, "vcan1", &std_frame(0x00A, &[0xab])),
            "(0.000005) vcan1 00A#AB"
        );
    }

    #[test]
    fn extended_empty_and_remote_frames_are_written_as_candump_does() {
        let ext = CanFrame::new_extended(0x1234_5678, &[1, 2]).unwrap();
        assert_eq!(
            format_line(T, "can0", &ext),
            "(1700000000.123456) can0 12345678#0102"
        );
        assert_eq!(
            format_line(T, "can0", &std_frame(0x080, &[])),
            "(1700000000.123456) can0 080#"
        );
        assert_eq!(
            format_line(T, "can0", &CanFrame::remote(0x705, 0)),
            "(1700000000.123456) can0 705#R"
        );
        assert_eq!(
            format_line(T, "can0", &CanFrame::remote(0x705, 1)),
            "(1700000000.123456) can0 705#R1"
        );
    }

    #[test]
    fn lines_are_read_back_to_the_same_records() {
        let cases = [
            (
                "(1700000000.123456) can0 603#2B011803E8030000",
                std_frame(0x603, &[0x2B, 1, 0x18, 3, 0xE8, 3, 0, 0]),
            ),
            ("(0.000001) can1 080#", std_frame(0x80, &[])),
            (
                "(12.500000) can0 1FFFFFFF#ff",
                CanFrame::new_extended(0x1FFF_FFFF, &[0xFF]).unwrap(),
            ),
            ("(1.000000) can0 705#R", CanFrame::remote(0x705, 0)),
            ("(1.000000) can0 705#R8", CanFrame::remote(0x705, 8)),
        ];
        for (line, frame) in cases {
            let record = parse_line(line).unwrap();
            assert_eq!(record.frame, frame, "{line}");
            assert_eq!(
                format_line(record.timestamp_us, &record.channel, &frame).to_uppercase(),
                line.to_uppercase()
            );
        }
        let record = parse_line("  (1700000000.123456) can0 603#2B011803E8030000\r\n").unwrap();
        assert_eq!(record.timestamp_us, T);
        assert_eq!(record.channel, "can0");
    }

    #[test]
    fn malformed_lines_are_errors_with_the_reason() {
        let cases = [
            (
                "can0 603#00",
                "expected `(SECONDS) CHANNEL ID#DATA`, found `can0 603#00`",
            ),
            (
                "(1.x) can0 603#00",
                "bad timestamp `(1.x)`: expected `(SECONDS)`, such as `(1700000000.123456)`",
            ),
            (
                "(x.000000) can0 603#00",
                "bad timestamp `(x.000000)`: expected `(SECONDS)`, such as `(1700000000.123456)`",
            ),
            (
                "(1.000000) can0 60300",
                "bad frame `60300`: expected `ID#DATA`",
            ),
            (
                "(1.000000) can0 6030#00",
                "identifier 6030 is not 11 bits",
            ),
            (
                "(1.000000) can0 G03#00",
                "bad identifier `G03`: expected 3 or 8 hex digits",
            ),
            ("(1.000000) can0 803#00", "identifier 803 is not 11 bits"),
            (
                "(1.000000) can0 40000000#00",
                "identifier 40000000 is not 29 bits",
            ),
            (
                "(1.000000) can0 20000004#0004000000000000",
                "`(1.000000) can0 20000004#0004000000000000` is an error frame (CAN_ERR_FLAG set): not supported",
            ),
            (
                "(1.000000) can0 123##1DEADBEEF",
                "`(1.000000) can0 123##1DEADBEEF` is a CAN FD frame (`ID##FLAGSDATA`): not supported",
            ),
            (
                "(1.000000) can0 603#0",
                "bad data `0`: expected pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#000102030405060708",
                "9 data bytes: a classic frame has at most 8",
            ),
            (
                "(1.000000) can0 603#é1",
                "bad data `é1`: expected pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#+F",
                "bad data `+F`: expected pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#R9",
                "remote request of length 9: at most 8",
            ),
            (
                "(1.000000) can0 603#Rx",
                "bad remote request `603#Rx`: expected `ID#R` or `ID#R0`..`ID#R8`",
            ),
            (
                "(1.000000) can0 603#00 extra",
                "expected `(SECONDS) CHANNEL ID#DATA`, found `(1.000000) can0 603#00 extra`",
            ),
        ];
        for (line, message) in cases {
            assert_eq!(
                parse_line(line),
                Err(TraceError {
                    line: 0,
                    message: message.to_owned()
                }),
                "{line}"
            );
        }
    }

    #[test]
    fn reader_skips_blank_lines_and_names_the_line_of_an_error() {
        let log =
            "(1.000000) can0 080#\n\n(2.000000) can0 701#05\nnonsense\n(3.000000) can0 080#\n";
        let mut reader = TraceReader::new(log.as_bytes());
        assert_eq!(reader.next().unwrap().unwrap().frame, std_frame(0x80, &[]));
        let second = reader.next().unwrap().unwrap();
        assert_eq!(
            (second.timestamp_us, second.frame),
            (2_000_000, std_frame(0x701, &[5]))
        );
        let error = reader.next().unwrap().unwrap_err();
        assert_eq!(
            error.to_string(),
            "line 4: bad candump line: expected `(SECONDS) CHANNEL ID#DATA`, found `nonsense`"
        );
        assert_eq!(reader.next().unwrap().unwrap().timestamp_us, 3_000_000);
        assert!(reader.next().is_none());
    }

    #[test]
    fn writer_writes_one_line_per_frame() {
        let mut writer = TraceWriter::new(Vec::new(), "can0");
        writer
            .write_frame(T, &std_frame(0x183, &[1, 2, 3]))
            .unwrap();
        writer
            .write_frame_on(T + 1, "can1", &CanFrame::remote(0x703, 1))
            .unwrap();
        assert_eq!(
            String::from_utf8(writer.into_inner()).unwrap(),
            "(1700000000.123456) can0 183#010203\n(1700000000.123457) can1 703#R1\n"
        );
    }

    /// A transport that hands out scripted frames and keeps what it is given.
    #[derive(Default)]
    struct Script {
        incoming: Vec<CanFrame>,
        sent: Vec<CanFrame>,
    }

    impl Transport for Script {
        fn send(&mut self, frame: &CanFrame) -> io::Result<()> {
            self.sent.push(*frame);
            Ok(())
        }
        fn recv_timeout(&mut self, _: StdDuration) -> io::Result<Option<CanFrame>> {
            Ok((!self.incoming.is_empty()).then(|| self.incoming.remove(0)))
        }
    }

    #[test]
    fn traced_transport_logs_what_it_sends_and_receives_in_order() {
        let inner = Script {
            incoming: vec![std_frame(0x603, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0])],
            sent: Vec::new(),
        };
        let mut traced = Traced::new(inner, TraceWriter::new(Vec::new(), "can0"));
        let before = epoch_micros(SystemTime::now());
        traced.send(&std_frame(0x000, &[1, 5])).unwrap();
        let got = traced.recv_timeout(StdDuration::ZERO).unwrap();
        assert_eq!(
            got,
            Some(std_frame(0x603, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]))
        );
        assert_eq!(traced.recv_timeout(StdDuration::ZERO).unwrap(), None);
        let after = epoch_micros(SystemTime::now());
        let (inner, log) = traced.into_parts();
        assert_eq!(inner.sent, vec![std_frame(0x000, &[1, 5])]);
        let log = String::from_utf8(log.into_inner()).unwrap();
        let records: Vec<TraceRecord> = TraceReader::new(log.as_bytes())
            .map(Result::unwrap)
            .collect();
        assert_eq!(records.len(), 2, "{log}");
        for record in &records {
            assert!((before..=after).contains(&record.timestamp_us), "{log}");
        }
        let lines: Vec<&str> = log.lines().map(|l| l.split_once(") ").unwrap().1).collect();
        assert_eq!(lines, ["can0 000#0105", "can0 603#4017100000000000"]);
    }
}
