//! Frame traces in the `candump -L` log format, which `canplayer` replays and python-can reads:
//! `(1700000000.123456) can0 603#2B011803E8030000`, one frame a line.
//!
//! [`format_line`] and [`parse_line`] own the format; [`TraceWriter`] writes lines, [`TraceReader`]
//! reads them with line numbers in its errors, and [`Traced`] logs every frame a [`Transport`]
//! sends or receives.

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

/// Reads one `candump -L` line (surrounding white space ignored).
pub fn parse_line(line: &str) -> Result<TraceRecord, TraceError> {
    parse(line.trim()).map_err(|message| TraceError { line: 0, message })
}

fn parse(line: &str) -> Result<TraceRecord, String> {
    let mut fields = line.split_ascii_whitespace();
    let (Some(time), Some(channel), Some(frame), None) =
        (fields.next(), fields.next(), fields.next(), fields.next())
    else {
        return Err(format!(
            "expected `(SECS.USECS) CHANNEL ID#DATA`, found `{line}`"
        ));
    };
    let timestamp_us = parse_timestamp(time)?;
    let frame = parse_frame(frame)?;
    Ok(TraceRecord {
        timestamp_us,
        channel: channel.to_owned(),
        frame,
    })
}

fn parse_timestamp(field: &str) -> Result<u64, String> {
    let bad = || format!("bad timestamp `{field}`: expected `(SECS.USECS)` with 6 decimals");
    let inner = field
        .strip_prefix('(')
        .and_then(|f| f.strip_suffix(')'))
        .ok_or_else(bad)?;
    let (secs, micros) = inner.split_once('.').ok_or_else(bad)?;
    if secs.is_empty() || micros.len() != 6 || !all_digits(secs) || !all_digits(micros) {
        return Err(bad());
    }
    let secs: u64 = secs.parse().map_err(|_| bad())?;
    let micros: u64 = micros.parse().map_err(|_| bad())?;
    secs.checked_mul(1_000_000)
        .and_then(|s| s.checked_add(micros))
        .ok_or_else(bad)
}

fn all_digits(text: &str) -> bool {
    text.bytes().all(|b| b.is_ascii_digit())
}

fn parse_frame(field: &str) -> Result<CanFrame, String> {
    let (id, data) = field
        .split_once('#')
        .ok_or_else(|| format!("bad frame `{field}`: expected `ID#DATA`"))?;
    if data.starts_with('#') {
        return Err(format!(
            "`{field}` is a CAN FD frame (`ID##FLAGSDATA`): not supported"
        ));
    }
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!("bad identifier `{id}`: expected hex digits"));
    }
    let extended = match id.len() {
        3 => false,
        8 => true,
        n => {
            return Err(format!(
                "bad identifier `{id}`: {n} digits, expected 3 (standard) or 8 (extended)"
            ))
        }
    };
    let raw = u32::from_str_radix(id, 16).map_err(|_| format!("bad identifier `{id}`"))?;
    if extended && raw & CAN_ERR_FLAG != 0 {
        return Err(format!(
            "`{field}` is an error frame (CAN_ERR_FLAG set): not supported"
        ));
    }
    if let Some(len) = data.strip_prefix('R').or_else(|| data.strip_prefix('r')) {
        let len = match len {
            "" => 0,
            digit if digit.len() == 1 && all_digits(digit) && digit <= "8" => {
                digit.as_bytes()[0] - b'0'
            }
            _ => {
                return Err(format!(
                    "bad remote request `{field}`: expected `ID#R` or `ID#R0`..`ID#R8`"
                ))
            }
        };
        return remote_frame(raw, extended, len)
            .ok_or_else(|| format!("identifier {id} out of range"));
    }
    let bytes = parse_hex(data).ok_or_else(|| {
        format!("bad data `{data}`: expected 0 to 8 bytes as pairs of hex digits")
    })?;
    if extended {
        CanFrame::new_extended(raw, &bytes)
    } else {
        CanFrame::new(raw as u16, &bytes)
    }
    .ok_or_else(|| format!("identifier {id} out of range"))
}

/// The flag Linux sets in the identifier of an error frame, which candump logs as it is.
const CAN_ERR_FLAG: u32 = 0x2000_0000;

fn remote_frame(raw: u32, extended: bool, len: u8) -> Option<CanFrame> {
    use embedded_can::{ExtendedId, Frame as _, Id, StandardId};
    let id = if extended {
        Id::Extended(ExtendedId::new(raw)?)
    } else {
        Id::Standard(StandardId::new(u16::try_from(raw).ok()?)?)
    };
    CanFrame::new_remote(id, len as usize)
}

/// `text` as bytes written as pairs of hex digits (at most 8 of them). Only digits: a sign, which
/// `from_str_radix` would take (`+F`), is not one.
pub(crate) fn parse_hex(text: &str) -> Option<Vec<u8>> {
    if text.len() % 2 != 0 || text.len() > 16 || !text.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    (0..text.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&text[i..i + 2], 16).ok())
        .collect()
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
                "expected `(SECS.USECS) CHANNEL ID#DATA`, found `can0 603#00`",
            ),
            (
                "(1.5) can0 603#00",
                "bad timestamp `(1.5)`: expected `(SECS.USECS)` with 6 decimals",
            ),
            (
                "(x.000000) can0 603#00",
                "bad timestamp `(x.000000)`: expected `(SECS.USECS)` with 6 decimals",
            ),
            (
                "(1.000000) can0 60300",
                "bad frame `60300`: expected `ID#DATA`",
            ),
            (
                "(1.000000) can0 6030#00",
                "bad identifier `6030`: 4 digits, expected 3 (standard) or 8 (extended)",
            ),
            (
                "(1.000000) can0 G03#00",
                "bad identifier `G03`: expected hex digits",
            ),
            ("(1.000000) can0 803#00", "identifier 803 out of range"),
            (
                "(1.000000) can0 40000000#00",
                "identifier 40000000 out of range",
            ),
            (
                "(1.000000) can0 20000004#0004000000000000",
                "`20000004#0004000000000000` is an error frame (CAN_ERR_FLAG set): not supported",
            ),
            (
                "(1.000000) can0 123##1DEADBEEF",
                "`123##1DEADBEEF` is a CAN FD frame (`ID##FLAGSDATA`): not supported",
            ),
            (
                "(1.000000) can0 603#0",
                "bad data `0`: expected 0 to 8 bytes as pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#000102030405060708",
                "bad data `000102030405060708`: expected 0 to 8 bytes as pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#é1",
                "bad data `é1`: expected 0 to 8 bytes as pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#+F",
                "bad data `+F`: expected 0 to 8 bytes as pairs of hex digits",
            ),
            (
                "(1.000000) can0 603#R9",
                "bad remote request `603#R9`: expected `ID#R` or `ID#R0`..`ID#R8`",
            ),
            (
                "(1.000000) can0 603#00 extra",
                "expected `(SECS.USECS) CHANNEL ID#DATA`, found `(1.000000) can0 603#00 extra`",
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
            "line 4: bad candump line: expected `(SECS.USECS) CHANNEL ID#DATA`, found `nonsense`"
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
