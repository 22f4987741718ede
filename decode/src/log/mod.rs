//! CAN log files as `edsgen decode` reads them: candump `-L`, candump's default output (with or
//! without `-t a|d|z` timestamps), Vector ASC and PCAN TRC (1.x and 2.x), each recognised by
//! its content, not its file name. [`LogReader`] turns bytes into [`Entry`]s line by line: a
//! frame with its time, a line skipped on purpose (CAN FD, error frames), or a line it cannot
//! read (a warning); bytes that are not UTF-8 are read as U+FFFD and counted, never fatal.
//!
//! Times are microseconds: since the Unix epoch where the log says when it started (candump
//! `-L`, `-t a` and `-t A`, ASC's `Begin Triggerblock` or `date` line, TRC's start time; dates
//! without a time zone are read as UTC), else as the log prints them (`-t d` and `-t z`
//! offsets, candump without `-t`: 0).

pub mod asc;
pub mod candump;
pub mod trc;

use std::io::{self, BufRead};

use edsgen_runtime::CanFrame;

pub use edsgen_host::trace::seconds_to_micros;
use edsgen_host::trace::{decimal_to_micros, hex_words, make_frame, shorten};

/// What one line of a log holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Line {
    /// A classic CAN frame at `time_us`.
    Frame {
        /// The time (see the module comment for its origin).
        time_us: u64,
        /// The frame.
        frame: CanFrame,
    },
    /// A CAN FD frame: skipped (the decoder reads classic CAN).
    Fd,
    /// An error frame or a bus status line: skipped.
    Error,
    /// A header, comment or event line with no frame.
    Nothing,
}

/// The log formats read, as [`LogReader`] recognised them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `(1700000000.123456) can0 701#05`.
    CandumpLog,
    /// `  can0  701   [1]  05`, or `(1700000000.123456)  can0  701   [1]  05` with `-t`.
    Candump,
    /// Vector ASC.
    Asc,
    /// PCAN TRC.
    Trc,
}

impl Format {
    /// The name warnings give it (both candump formats are `candump`: the warning's text says
    /// which layout was expected).
    pub fn name(self) -> &'static str {
        match self {
            Format::CandumpLog | Format::Candump => "candump",
            Format::Asc => "ASC",
            Format::Trc => "TRC",
        }
    }
}

/// One line of the log, read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Entry {
    /// A frame.
    Frame {
        /// Its time in microseconds.
        time_us: u64,
        /// The frame.
        frame: CanFrame,
    },
    /// A line that cannot be read: its 1-based number and why.
    Warning(usize, String),
}

/// What a whole log held beside its frames, for the summary at the end.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Tally {
    /// Frames read.
    pub frames: u64,
    /// CAN FD frames skipped.
    pub fd: u64,
    /// Error frames and status lines skipped.
    pub errors: u64,
    /// Lines that could not be read.
    pub unreadable: u64,
    /// Lines that held bytes that are not UTF-8 (read with U+FFFD in their place).
    pub not_utf8: u64,
}

/// Reads a log line by line, recognising its format on the first line that shows it.
#[derive(Debug)]
pub struct LogReader<R> {
    input: R,
    line: usize,
    bytes: Vec<u8>,
    parser: Option<Parser>,
    tally: Tally,
}

/// The format found and its state.
#[derive(Debug)]
enum Parser {
    CandumpLog,
    Candump,
    Asc(asc::Asc),
    Trc(trc::Trc),
}

impl<R: BufRead> LogReader<R> {
    /// A reader of `input`.
    pub fn new(input: R) -> Self {
        LogReader {
            input,
            line: 0,
            bytes: Vec::new(),
            parser: None,
            tally: Tally::default(),
        }
    }

    /// The format found so far.
    pub fn format(&self) -> Option<Format> {
        self.parser.as_ref().map(|p| match p {
            Parser::CandumpLog => Format::CandumpLog,
            Parser::Candump => Format::Candump,
            Parser::Asc(_) => Format::Asc,
            Parser::Trc(_) => Format::Trc,
        })
    }

    /// What the log held so far beside its frames.
    pub fn tally(&self) -> &Tally {
        &self.tally
    }

    /// The next frame or warning; `None` at the end; an error only when the input cannot be
    /// read at all.
    pub fn next_entry(&mut self) -> io::Result<Option<Entry>> {
        loop {
            self.bytes.clear();
            if self.input.read_until(b'\n', &mut self.bytes)? == 0 {
                return Ok(None);
            }
            self.line += 1;
            let text = String::from_utf8_lossy(&self.bytes);
            if matches!(text, std::borrow::Cow::Owned(_)) {
                self.tally.not_utf8 += 1;
            }
            let mut text = text.trim().to_owned();
            if self.parser.as_ref().is_none_or(Parser::is_candump) {
                text.truncate(without_comment(&text).len());
            }
            if text.is_empty() {
                continue;
            }
            let read = match &mut self.parser {
                Some(parser) => parser.read(&text),
                None => match recognise(&text) {
                    Some(mut parser) => {
                        let read = parser.read(&text);
                        self.parser = Some(parser);
                        read
                    }
                    None => Err(format!(
                        "not a line of a log format edsgen reads (candump, ASC, TRC): `{}`",
                        shorten(&text)
                    )),
                },
            };
            match read {
                Ok(Line::Frame { time_us, frame }) => {
                    self.tally.frames += 1;
                    return Ok(Some(Entry::Frame { time_us, frame }));
                }
                Ok(Line::Fd) => self.tally.fd += 1,
                Ok(Line::Error) => self.tally.errors += 1,
                Ok(Line::Nothing) => {}
                Err(message) => {
                    self.tally.unreadable += 1;
                    let format = self.format().map_or("log", Format::name);
                    return Ok(Some(Entry::Warning(
                        self.line,
                        format!("bad {format} line: {message}"),
                    )));
                }
            }
        }
    }
}

impl Parser {
    /// candump's own formats, where a `#` after white space starts a comment.
    fn is_candump(&self) -> bool {
        matches!(self, Parser::CandumpLog | Parser::Candump)
    }

    fn read(&mut self, text: &str) -> Result<Line, String> {
        match self {
            Parser::CandumpLog => candump::parse_log_line(text),
            Parser::Candump => candump::parse_line(text),
            Parser::Asc(asc) => asc.read(text),
            Parser::Trc(trc) => trc.read(text),
        }
    }
}

/// `text` without a trailing `# comment`, as logs pasted from documentation carry: a `#` at the
/// start or after white space (in `ID#DATA` the `#` follows the identifier directly).
fn without_comment(text: &str) -> &str {
    let mut previous_is_space = true;
    for (at, c) in text.char_indices() {
        if c == '#' && previous_is_space {
            return text[..at].trim_end();
        }
        previous_is_space = c.is_whitespace();
    }
    text
}

/// The format a line shows, if it shows one.
fn recognise(text: &str) -> Option<Parser> {
    let words: Vec<&str> = text.split_ascii_whitespace().collect();
    let first = *words.first()?;
    if text.starts_with(';') {
        return Some(Parser::Trc(trc::Trc::default()));
    }
    if asc::is_header(text) {
        return Some(Parser::Asc(asc::Asc::default()));
    }
    let bracketed = |w: &&str| w.starts_with('[') && w.ends_with(']');
    if first.starts_with('(') {
        return Some(if words.get(2).is_some_and(|w| w.contains('#')) {
            Parser::CandumpLog
        } else {
            Parser::Candump
        });
    }
    if words.iter().take(6).any(bracketed) {
        return Some(Parser::Candump);
    }
    if first.ends_with(')') && first[..first.len() - 1].bytes().all(|b| b.is_ascii_digit()) {
        return Some(Parser::Trc(trc::Trc::default()));
    }
    if words.get(2).is_some_and(|w| trc::is_message_type(w)) {
        return Some(Parser::Trc(trc::Trc::default()));
    }
    if first.contains('.') && first.parse::<f64>().is_ok() {
        return Some(Parser::Asc(asc::Asc::default()));
    }
    None
}

/// Days since 1970-01-01 of a civil date (the proleptic Gregorian calendar).
pub(crate) fn days_from_civil(year: i64, month: u32, day: u32) -> i64 {
    let year = if month <= 2 { year - 1 } else { year };
    let era = year.div_euclid(400);
    let yoe = year - era * 400;
    let month = i64::from(month);
    let doy = (153 * (if month > 2 { month - 3 } else { month + 9 }) + 2) / 5 + i64::from(day) - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Microseconds since the epoch of a UTC date and time; `None` outside 1970 to 9999 or for a
/// field out of its range.
pub(crate) fn epoch_micros(
    (year, month, day): (i64, u32, u32),
    (hour, minute): (u32, u32),
    second_micros: u64,
) -> Option<u64> {
    let valid = (1970..=9999).contains(&year)
        && (1..=12).contains(&month)
        && (1..=31).contains(&day)
        && hour <= 23
        && minute <= 59
        && second_micros < 61_000_000;
    if !valid {
        return None;
    }
    let days = u64::try_from(days_from_civil(year, month, day)).ok()?;
    let seconds = days * 86_400 + u64::from(hour) * 3600 + u64::from(minute) * 60;
    Some(seconds * 1_000_000 + second_micros)
}

/// `24.11.2026 16:00:00.000.0` (PCAN: milliseconds, then tenths of them) or
/// `2026-11-24 16:00:00.000100+00:00` (python-can, candump `-t A` without the zone) as
/// microseconds since the epoch.
pub(crate) fn date_time_micros(text: &str) -> Result<u64, String> {
    let bad = || format!("bad date `{text}`");
    let (date, time) = text.split_once(' ').ok_or_else(bad)?;
    let numbers = |part: &str, separator: char| -> Option<Vec<i64>> {
        part.split(separator).map(|n| n.parse().ok()).collect()
    };
    let (year, month, day) = match (numbers(date, '.'), numbers(date, '-')) {
        (Some(d), _) if d.len() == 3 => (d[2], d[1], d[0]),
        (_, Some(d)) if d.len() == 3 => (d[0], d[1], d[2]),
        _ => return Err(bad()),
    };
    // A python-can time zone (`+00:00`) is subtracted; PCAN's local time is read as UTC.
    let (time, zone_us) = match time.find(['+', '-']) {
        Some(at) => {
            let zone = &time[at + 1..];
            let (h, m) = zone.split_once(':').ok_or_else(bad)?;
            let minutes = i64::from(h.parse::<u8>().map_err(|_| bad())?) * 60
                + i64::from(m.parse::<u8>().map_err(|_| bad())?);
            let sign = if time.as_bytes()[at] == b'+' { 1 } else { -1 };
            (&time[..at], sign * minutes * 60_000_000)
        }
        None => (time, 0),
    };
    let mut parts = time.splitn(3, ':');
    let (Some(hour), Some(minute), Some(second)) = (parts.next(), parts.next(), parts.next())
    else {
        return Err(bad());
    };
    let hour: u32 = hour.parse().map_err(|_| bad())?;
    let minute: u32 = minute.parse().map_err(|_| bad())?;
    let second_us = match second.split('.').collect::<Vec<_>>().as_slice() {
        // PCAN: seconds, milliseconds, tenths of a millisecond.
        [s, ms, tenth] => {
            let s: u64 = s.parse().map_err(|_| bad())?;
            let ms: u64 = ms.parse().map_err(|_| bad())?;
            let tenth: u64 = tenth.parse().map_err(|_| bad())?;
            s * 1_000_000 + ms * 1000 + tenth * 100
        }
        _ => seconds_to_micros(second).ok_or_else(bad)?,
    };
    let month = u32::try_from(month).map_err(|_| bad())?;
    let day = u32::try_from(day).map_err(|_| bad())?;
    let micros = epoch_micros((year, month, day), (hour, minute), second_us).ok_or_else(bad)?;
    u64::try_from(micros as i64 - zone_us).map_err(|_| bad())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn entries(log: &[u8]) -> (Vec<Entry>, Tally, Option<Format>) {
        let mut reader = LogReader::new(log);
        let mut entries = Vec::new();
        while let Some(entry) = reader.next_entry().unwrap() {
            entries.push(entry);
        }
        (entries, reader.tally().clone(), reader.format())
    }

    fn frame(time_us: u64, id: u16, data: &[u8]) -> Entry {
        Entry::Frame {
            time_us,
            frame: CanFrame::new(id, data).unwrap(),
        }
    }

    #[test]
    fn seconds_with_any_number_of_decimals() {
        assert_eq!(
            seconds_to_micros("1700000000.123456"),
            Some(1_700_000_000_123_456)
        );
        assert_eq!(seconds_to_micros("1.5"), Some(1_500_000));
        assert_eq!(seconds_to_micros("12"), Some(12_000_000));
        assert_eq!(seconds_to_micros("0.123456789"), Some(123_456));
        assert_eq!(seconds_to_micros("000.000100"), Some(100));
        assert_eq!(decimal_to_micros("1059.9", 1000), Some(1_059_900));
        for bad in ["", ".5", "1.x", "-1.0", "1.2.3", "+1"] {
            assert_eq!(seconds_to_micros(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_trailing_comment_after_a_candump_frame_is_ignored() {
        let log = b"# a session pasted from a manual\n\
            (1700000000.000000) can0 703#00 # boot-up\n\
            (1700000000.000100) can0 603#4018100100000000   # read 1018h:01\n";
        let (read, tally, format) = entries(log);
        assert_eq!(format, Some(Format::CandumpLog));
        assert_eq!(tally.unreadable, 0);
        let request = [0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0];
        assert_eq!(
            read,
            [
                frame(1_700_000_000_000_000, 0x703, &[0x00]),
                frame(1_700_000_000_000_100, 0x603, &request),
            ]
        );
        let log = b"  can0  583   [8]  43 18 10 01 D8 04 00 00  # the vendor-ID\n";
        let (read, tally, format) = entries(log);
        assert_eq!(format, Some(Format::Candump));
        assert_eq!(tally.unreadable, 0);
        let vendor = [0x43, 0x18, 0x10, 0x01, 0xD8, 0x04, 0, 0];
        assert_eq!(read.len(), 1);
        assert!(matches!(&read[0], Entry::Frame { frame, .. } if frame.data() == vendor));
        assert_eq!(without_comment("can0 123#11 # note"), "can0 123#11");
        assert_eq!(without_comment("can0 123#11"), "can0 123#11");
        assert_eq!(without_comment("# only a comment"), "");
    }

    #[test]
    fn civil_dates_count_days_from_the_epoch() {
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
        assert_eq!(days_from_civil(2025, 11, 24), 20_416);
        assert_eq!(
            epoch_micros((2023, 11, 14), (22, 13), 20_000_000),
            Some(1_700_000_000_000_000)
        );
    }

    #[test]
    fn each_format_is_recognised_by_its_first_telling_line() {
        let cases: [(&[u8], Format); 6] = [
            (b"(1700000000.000100) can0 701#05\n", Format::CandumpLog),
            (b"  can0  701   [1]  05\n", Format::Candump),
            (b"(000.000100)  can0  701   [1]  05\n", Format::Candump),
            (
                b"date Tue Nov 14 22:13:20.000 2023\n   0.000100 1  701  Rx   d 1 05\n",
                Format::Asc,
            ),
            (b";$FILEVERSION=2.1\n", Format::Trc),
            (b"     1)         0  0701  1  05\n", Format::Trc),
        ];
        for (log, format) in cases {
            assert_eq!(
                entries(log).2,
                Some(format),
                "{}",
                String::from_utf8_lossy(log)
            );
        }
    }

    #[test]
    fn bad_lines_and_bytes_that_are_not_utf8_are_counted_and_reading_goes_on() {
        let log =
            b"(1.000000) can0 701#05\n\xFF\xFEgarbage\n\n(2.5) can0 702#7F\n(3.0) can0 123##1AA\n";
        let (entries, tally, _) = entries(log);
        assert_eq!(
            entries,
            [
                frame(1_000_000, 0x701, &[5]),
                Entry::Warning(
                    2,
                    "bad candump line: expected `(SECONDS) CHANNEL ID#DATA`, found `\u{FFFD}\u{FFFD}garbage`".into()
                ),
                frame(2_500_000, 0x702, &[0x7F]),
            ]
        );
        assert_eq!(
            tally,
            Tally {
                frames: 2,
                fd: 1,
                errors: 0,
                unreadable: 1,
                not_utf8: 1
            }
        );
    }

    #[test]
    fn a_first_line_of_no_known_format_is_a_warning() {
        let (entries, tally, format) = entries(b"hello world\n  can0  701   [1]  05\n");
        assert_eq!(
            entries,
            [
                Entry::Warning(
                    1,
                    "bad log line: not a line of a log format edsgen reads (candump, ASC, TRC): `hello world`".into()
                ),
                frame(0, 0x701, &[5]),
            ]
        );
        assert_eq!((tally.frames, tally.unreadable), (1, 1));
        assert_eq!(format, Some(Format::Candump));
    }

    /// Words of every format, for lines that get past the first checks.
    const WORDS: [&str; 32] = [
        "(1700000000.1)",
        "(2023-11-14",
        "22:13:20.5)",
        "can0",
        "701#05",
        "123##1AA",
        "705#R8",
        "20000004#",
        "[1]",
        "[08]",
        "05",
        "7F",
        "remote",
        "request",
        "TX",
        "-",
        "Rx",
        "d",
        "r",
        "1)",
        "0.000100",
        "1841.5",
        "DT",
        "FD",
        ";$FILEVERSION=2.1",
        ";$COLUMNS=N,O,T,I,d,l,D",
        ";$STARTTIME=45244.9",
        "date",
        "Tue Nov 14 22:13:20.000 2023",
        "base dec  timestamps relative",
        "Begin Triggerblock",
        "\u{FFFD}",
    ];

    proptest! {
        #[test]
        fn any_bytes_are_read_to_the_end_without_panicking(
            lines in prop::collection::vec(
                prop::collection::vec(
                    prop_oneof![
                        (0..WORDS.len()).prop_map(|i| WORDS[i].as_bytes().to_vec()),
                        prop::collection::vec(any::<u8>(), 0..6),
                    ],
                    0..8,
                ),
                0..12,
            )
        ) {
            let log: Vec<u8> = lines
                .iter()
                .flat_map(|words| words.join(&b' ').into_iter().chain([b'\n']))
                .collect();
            let (entries, tally, _) = entries(&log);
            let frames = entries.iter().filter(|e| matches!(e, Entry::Frame { .. })).count();
            prop_assert_eq!(tally.frames, frames as u64);
            prop_assert_eq!(tally.unreadable, (entries.len() - frames) as u64);
        }
    }
}
