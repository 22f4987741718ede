//! can-utils' candump formats. `-L` (the log format, which canplayer replays):
//! `(1700000000.123456) can0 701#05`, any number of decimals, `ID#R` or `ID#R8` for a remote
//! request, an optional direction (`R`, `T`) after the frame as python-can writes it, CAN FD as
//! `ID##FLAGSDATA`. The default output: `  can0  701   [1]  05`, with `-t a|d|z` a
//! `(SECONDS)` first (`-t A`: `(YYYY-MM-DD HH:MM:SS.UUUUUU)`, read as UTC), with `-x` `TX - -` or `RX B E` before the identifier, `remote request`
//! for an RTR, a two-digit length (`[08]`) for CAN FD, and `-a`'s `'...'` or `ERRORFRAME` after
//! the data.

use edsgen_host::trace::{identifier, parenthesised_time, LogLine, CAN_ERR_FLAG};

use super::{hex_words, make_frame, Line};

/// One `candump -L` line, read by the host crate's trace codec.
pub fn parse_log_line(text: &str) -> Result<Line, String> {
    Ok(match edsgen_host::trace::parse_log_line(text)? {
        LogLine::Frame(record) => Line::Frame {
            time_us: record.timestamp_us,
            frame: record.frame,
        },
        LogLine::Fd => Line::Fd,
        LogLine::Error => Line::Error,
    })
}

/// One line of candump's default output, with or without a `(SECONDS)` timestamp.
pub fn parse_line(text: &str) -> Result<Line, String> {
    let mut words: &[&str] = &text.split_ascii_whitespace().collect::<Vec<_>>();
    let expected = || {
        format!(
            "expected `[(SECONDS)] CHANNEL ID [LEN] DATA`, found `{}`",
            super::shorten(text.trim())
        )
    };
    let mut time_us = 0;
    match words {
        // -t A: `(2025-11-24 16:00:00.123456)`, local time, read as UTC.
        [date, time, rest @ ..] if date.starts_with('(') && !date.ends_with(')') => {
            let inner = format!("{} {}", &date[1..], time.strip_suffix(')').unwrap_or(time));
            time_us = super::date_time_micros(&inner).map_err(|_| {
                format!("bad timestamp `{date} {time}`: expected `(YYYY-MM-DD HH:MM:SS.UUUUUU)`")
            })?;
            words = rest;
        }
        [first, rest @ ..] if first.starts_with('(') => {
            time_us = parenthesised_time(first)?;
            words = rest;
        }
        _ => {}
    }
    // The channel, then -x's direction and flags.
    let [_channel, rest @ ..] = words else {
        return Err(expected());
    };
    words = rest;
    if let [direction, _, _, rest @ ..] = words {
        if matches!(*direction, "TX" | "RX") {
            words = rest;
        }
    }
    let [id, len, rest @ ..] = words else {
        return Err(expected());
    };
    let (id, extended) = identifier(id)?;
    let digits = len
        .strip_prefix('[')
        .and_then(|l| l.strip_suffix(']'))
        .filter(|l| !l.is_empty() && l.bytes().all(|b| b.is_ascii_digit()))
        .ok_or_else(|| format!("bad length `{len}`: expected `[0]`..`[8]`"))?;
    if digits.len() == 2 {
        return Ok(Line::Fd);
    }
    if extended && id & CAN_ERR_FLAG != 0 {
        return Ok(Line::Error);
    }
    let len: u8 = digits
        .parse()
        .ok()
        .filter(|&l| l <= 8)
        .ok_or_else(|| format!("bad length `[{digits}]`: a classic frame has 0 to 8 bytes"))?;
    if rest.starts_with(&["remote", "request"]) {
        return Ok(Line::Frame {
            time_us,
            frame: make_frame(id, extended, Some(len), &[])?,
        });
    }
    let data = rest
        .get(..usize::from(len))
        .ok_or_else(|| format!("[{len}] announces {len} bytes, the line has {}", rest.len()))?;
    let bytes = hex_words(data).ok_or_else(|| {
        format!(
            "bad data `{}`: expected pairs of hex digits",
            data.join(" ")
        )
    })?;
    // What may follow the data: -a's ASCII column, -e's ERRORFRAME.
    match rest.get(usize::from(len)..).unwrap_or(&[]) {
        [] => {}
        [ascii, ..] if ascii.starts_with('\'') => {}
        ["ERRORFRAME", ..] => return Ok(Line::Error),
        more => return Err(format!("unexpected `{}` after the data", more.join(" "))),
    }
    Ok(Line::Frame {
        time_us,
        frame: make_frame(id, extended, None, &bytes)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use edsgen_runtime::CanFrame;

    fn at(time_us: u64, frame: CanFrame) -> Result<Line, String> {
        Ok(Line::Frame { time_us, frame })
    }

    fn data(id: u16, bytes: &[u8]) -> CanFrame {
        CanFrame::new(id, bytes).unwrap()
    }

    #[test]
    fn log_lines_with_any_decimals_directions_and_remote_requests() {
        let cases = [
            (
                "(1700000000.123456) can0 603#2B011803E8030000",
                at(
                    1_700_000_000_123_456,
                    data(0x603, &[0x2B, 1, 0x18, 3, 0xE8, 3, 0, 0]),
                ),
            ),
            (
                "(1700000000.1) can0 080#",
                at(1_700_000_000_100_000, data(0x080, &[])),
            ),
            (
                "(1700000000.123456789) vcan1 701#05",
                at(1_700_000_000_123_456, data(0x701, &[5])),
            ),
            (
                "(1700000000.000100) can0 701#05 R",
                at(1_700_000_000_000_100, data(0x701, &[5])),
            ),
            (
                "(1.000000) can0 702#7f T",
                at(1_000_000, data(0x702, &[0x7F])),
            ),
            (
                "(1.000000) can0 705#R",
                at(1_000_000, CanFrame::remote(0x705, 0)),
            ),
            (
                "(1.000000) can0 705#R1 R",
                at(1_000_000, CanFrame::remote(0x705, 1)),
            ),
            (
                "(1.000000) can0 12345678#0102",
                at(
                    1_000_000,
                    CanFrame::new_extended(0x1234_5678, &[1, 2]).unwrap(),
                ),
            ),
            ("(1.000000) can0 123##1DEADBEEF", Ok(Line::Fd)),
            ("(1.000000) can0 20000004#0004000000000000", Ok(Line::Error)),
        ];
        for (line, expected) in cases {
            assert_eq!(parse_log_line(line), expected, "{line}");
        }
    }

    #[test]
    fn malformed_log_lines_say_why() {
        let cases = [
            (
                "can0 603#00",
                "expected `(SECONDS) CHANNEL ID#DATA`, found `can0 603#00`",
            ),
            (
                "(1.x) can0 603#00",
                "bad timestamp `(1.x)`: expected `(SECONDS)`, such as `(1700000000.123456)`",
            ),
            ("(1.0) can0 60300", "bad frame `60300`: expected `ID#DATA`"),
            (
                "(1.0) can0 G03#00",
                "bad identifier `G03`: expected 3 or 8 hex digits",
            ),
            ("(1.0) can0 803#00", "identifier 803 is not 11 bits"),
            (
                "(1.0) can0 603#0",
                "bad data `0`: expected pairs of hex digits",
            ),
            (
                "(1.0) can0 603#000102030405060708",
                "9 data bytes: a classic frame has at most 8",
            ),
            ("(1.0) can0 603#R9", "remote request of length 9: at most 8"),
            (
                "(1.0) can0 603#Rx",
                "bad remote request `603#Rx`: expected `ID#R` or `ID#R0`..`ID#R8`",
            ),
            (
                "(1.0) can0 603#é1",
                "bad data `é1`: expected pairs of hex digits",
            ),
        ];
        for (line, message) in cases {
            assert_eq!(parse_log_line(line), Err(message.to_owned()), "{line}");
        }
    }

    #[test]
    fn default_lines_with_timestamps_directions_rtr_and_fd() {
        let cases = [
            ("  can0  701   [1]  05", at(0, data(0x701, &[5]))),
            ("  can0  080   [0]", at(0, data(0x080, &[]))),
            (
                "(1700000000.123456)  can0  603   [8]  2B 01 18 03 E8 03 00 00",
                at(
                    1_700_000_000_123_456,
                    data(0x603, &[0x2B, 1, 0x18, 3, 0xE8, 3, 0, 0]),
                ),
            ),
            (
                "(000.000100)  can0  701   [1]  05",
                at(100, data(0x701, &[5])),
            ),
            (
                " (0.250000)  can0  TX - -  702   [1]  7F",
                at(250_000, data(0x702, &[0x7F])),
            ),
            (
                "  can0  RX - -  702   [1]  7F   '.'",
                at(0, data(0x702, &[0x7F])),
            ),
            (
                "  can0  705   [1]  remote request",
                at(0, CanFrame::remote(0x705, 1)),
            ),
            (
                "  can0  12345678   [2]  01 02",
                at(0, CanFrame::new_extended(0x1234_5678, &[1, 2]).unwrap()),
            ),
            (
                "  can0  123  [12]  00 11 22 33 44 55 66 77 88 99 AA BB",
                Ok(Line::Fd),
            ),
            ("  can0  123  [08]  00 11 22 33 44 55 66 77", Ok(Line::Fd)),
            (
                "  can0  20000004   [8]  00 04 00 00 00 00 00 00   ERRORFRAME",
                Ok(Line::Error),
            ),
        ];
        for (line, expected) in cases {
            assert_eq!(parse_line(line), expected, "{line}");
        }
    }

    #[test]
    fn malformed_default_lines_say_why() {
        let cases = [
            (
                "  can0",
                "expected `[(SECONDS)] CHANNEL ID [LEN] DATA`, found `can0`",
            ),
            (
                "  can0  701   1  05",
                "bad length `1`: expected `[0]`..`[8]`",
            ),
            (
                "  can0  701   [9]  05",
                "bad length `[9]`: a classic frame has 0 to 8 bytes",
            ),
            (
                "  can0  701   [2]  05",
                "[2] announces 2 bytes, the line has 1",
            ),
            (
                "  can0  701   [1]  5X",
                "bad data `5X`: expected pairs of hex digits",
            ),
            ("  can0  701   [1]  05 06", "unexpected `06` after the data"),
        ];
        for (line, message) in cases {
            assert_eq!(parse_line(line), Err(message.to_owned()), "{line}");
        }
    }
}
