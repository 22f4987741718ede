//! Vector ASC logs (as CANalyzer, CANoe and python-can write them): a header (`date ...`,
//! `base hex|dec  timestamps absolute|relative`, `internal events logged`), then
//! `Begin Triggerblock DATE`, one event a line (`   0.000100 1  701   Rx   d 1 05`: seconds, channel,
//! identifier with an `x` when extended, direction, `d` or `r`, length, data, and whatever the
//! logger adds after it), and `End TriggerBlock`. Times are offsets from the triggerblock's (or
//! else the header's) date, which carries no time zone: it is read as UTC.

use super::{epoch_micros, hex_words, make_frame, seconds_to_micros, Line};

/// The state of an ASC log between lines.
#[derive(Debug, Clone, Default)]
pub struct Asc {
    /// Identifiers in decimal (`base dec`) rather than hex.
    decimal: bool,
    /// Times relative to the previous event rather than to the start.
    relative: bool,
    /// When the measurement started (microseconds since the epoch), once a date was read.
    start_us: u64,
    /// The previous event's offset from the start, for relative times.
    elapsed_us: u64,
}

/// Whether `text` is one of the header lines that only an ASC log has.
pub fn is_header(text: &str) -> bool {
    [
        "date ",
        "base ",
        "Begin Triggerblock",
        "End TriggerBlock",
        "// ",
    ]
    .iter()
    .any(|start| text.starts_with(start))
        || text.ends_with("internal events logged")
}

impl Asc {
    /// Reads one line.
    pub fn read(&mut self, text: &str) -> Result<Line, String> {
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["date", date @ ..] => {
                if self.start_us == 0 {
                    self.start_us = date_micros(date)?;
                }
                return Ok(Line::Nothing);
            }
            ["Begin", "Triggerblock", date @ ..] => {
                if !date.is_empty() {
                    self.start_us = date_micros(date)?;
                }
                return Ok(Line::Nothing);
            }
            ["base", base, "timestamps", kind] => {
                self.decimal = match *base {
                    "hex" => false,
                    "dec" => true,
                    _ => return Err(format!("unknown base `{base}`: expected hex or dec")),
                };
                self.relative = match *kind {
                    "absolute" => false,
                    "relative" => true,
                    _ => {
                        return Err(format!(
                            "unknown timestamps `{kind}`: expected absolute or relative"
                        ))
                    }
                };
                return Ok(Line::Nothing);
            }
            _ if is_header(text) => return Ok(Line::Nothing),
            _ => {}
        }
        let [time, rest @ ..] = words.as_slice() else {
            return Ok(Line::Nothing);
        };
        let offset = seconds_to_micros(time)
            .ok_or_else(|| format!("bad time `{time}`: expected seconds such as 0.000100"))?;
        let time_us = if self.relative {
            self.elapsed_us = self.elapsed_us.saturating_add(offset);
            self.start_us.saturating_add(self.elapsed_us)
        } else {
            self.start_us.saturating_add(offset)
        };
        match rest {
            ["CANFD", ..] => Ok(Line::Fd),
            [_, "ErrorFrame", ..] => Ok(Line::Error),
            [_channel, id, "Rx" | "Tx" | "TxRq", kind, frame @ ..] => {
                let (id, extended) = self.identifier(id)?;
                let frame = match (*kind, frame) {
                    ("r", []) => make_frame(id, extended, Some(0), &[])?,
                    ("r", [len, ..]) => make_frame(id, extended, Some(length(len)?), &[])?,
                    ("d", [len, data @ ..]) => {
                        let len = usize::from(length(len)?);
                        let bytes = data.get(..len).and_then(hex_words).ok_or_else(|| {
                            format!("expected {len} data bytes in hex after the length")
                        })?;
                        make_frame(id, extended, None, &bytes)?
                    }
                    _ => {
                        return Err(format!(
                            "bad frame kind `{kind}`: expected `d LEN DATA` or `r [LEN]`"
                        ))
                    }
                };
                Ok(Line::Frame { time_us, frame })
            }
            // Other events (statistics, chip states, comments of the logger).
            _ => Ok(Line::Nothing),
        }
    }

    fn identifier(&self, word: &str) -> Result<(u32, bool), String> {
        let (digits, extended) = match word.strip_suffix(['x', 'X']) {
            Some(digits) => (digits, true),
            None => (word, false),
        };
        let radix = if self.decimal { 10 } else { 16 };
        let id = u32::from_str_radix(digits, radix)
            .ok()
            .filter(|_| !digits.starts_with(['+', '-']))
            .ok_or_else(|| format!("bad identifier `{word}`"))?;
        Ok((id, extended))
    }
}

/// A length (a hex digit, as Vector writes it).
fn length(word: &str) -> Result<u8, String> {
    u8::from_str_radix(word, 16)
        .ok()
        .filter(|&l| l <= 8 && !word.starts_with(['+', '-']))
        .ok_or_else(|| format!("bad length `{word}`: a classic frame has 0 to 8 bytes"))
}

/// `Tue Nov 14 22:13:20.000 2023` (or with `am`/`pm` before the year) as microseconds since the
/// epoch, read as UTC.
fn date_micros(words: &[&str]) -> Result<u64, String> {
    let text = words.join(" ");
    let bad = || format!("bad date `{text}`: expected such as `Tue Nov 14 22:13:20.000 2023`");
    let (month, day, time, half, year) = match words {
        [_weekday, month, day, time, year] => (month, day, time, None, year),
        [_weekday, month, day, time, half, year] => (month, day, time, Some(*half), year),
        _ => return Err(bad()),
    };
    const MONTHS: [&str; 12] = [
        "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec",
    ];
    let month = MONTHS.iter().position(|m| m == month).ok_or_else(bad)? as u32 + 1;
    let day: u32 = day.parse().map_err(|_| bad())?;
    let year: i64 = year.parse().map_err(|_| bad())?;
    let mut parts = time.splitn(3, ':');
    let (Some(hour), Some(minute), Some(second)) = (parts.next(), parts.next(), parts.next())
    else {
        return Err(bad());
    };
    let mut hour: u32 = hour.parse().map_err(|_| bad())?;
    let minute: u32 = minute.parse().map_err(|_| bad())?;
    // Vector writes three decimals (milliseconds); python-can 4.6.1 writes the milliseconds
    // unpadded (`16:00:00.5` for 5 ms): up to three decimals are a count of milliseconds.
    let second = match second.split_once('.') {
        Some((whole, ms)) if (1..=3).contains(&ms.len()) => {
            let whole = seconds_to_micros(whole).ok_or_else(bad)?;
            let ms: u64 = ms
                .parse()
                .ok()
                .filter(|_| ms.bytes().all(|b| b.is_ascii_digit()))
                .ok_or_else(bad)?;
            whole + ms * 1000
        }
        _ => seconds_to_micros(second).ok_or_else(bad)?,
    };
    match half {
        None => {}
        Some("am") if hour == 12 => hour = 0,
        Some("am") => {}
        Some("pm") if hour < 12 => hour += 12,
        Some("pm") => {}
        Some(_) => return Err(bad()),
    }
    epoch_micros((year, month, day), (hour, minute), second).ok_or_else(bad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use edsgen_runtime::CanFrame;

    fn read_all(lines: &[&str]) -> Vec<Result<Line, String>> {
        let mut asc = Asc::default();
        lines.iter().map(|l| asc.read(l.trim())).collect()
    }

    fn at(time_us: u64, frame: CanFrame) -> Result<Line, String> {
        Ok(Line::Frame { time_us, frame })
    }

    const T0: u64 = 1_700_000_000_000_000;

    #[test]
    fn a_python_can_log_is_read_from_its_triggerblock_date() {
        let lines = read_all(&[
            "date Fri Nov 27 15:00:00.000 2026",
            "base hex  timestamps absolute",
            "internal events logged",
            "Begin Triggerblock Tue Nov 14 22:13:20.000 2023",
            " 0.000000 Start of measurement",
            " 0.000100 1  701             Rx   d 1 05",
            " 0.001000 1  12345678x       Tx   d 2 01 02",
            " 0.002500 1  705             Rx   r 1",
            " 0.003000 1  ErrorFrame",
            " 0.004000 CANFD   1 Rx      123                                   1 0 d 12 00 11 22 33 44 55 66 77 88 99 AA BB        0    0     3000        0        0        0        0        0",
            "End TriggerBlock",
        ]);
        assert_eq!(
            lines,
            [
                Ok(Line::Nothing),
                Ok(Line::Nothing),
                Ok(Line::Nothing),
                Ok(Line::Nothing),
                Ok(Line::Nothing),
                at(T0 + 100, CanFrame::new(0x701, &[5]).unwrap()),
                at(
                    T0 + 1000,
                    CanFrame::new_extended(0x1234_5678, &[1, 2]).unwrap()
                ),
                at(T0 + 2500, CanFrame::remote(0x705, 1)),
                Ok(Line::Error),
                Ok(Line::Fd),
                Ok(Line::Nothing),
            ]
        );
    }

    #[test]
    fn vector_logs_with_decimal_ids_relative_times_am_pm_dates_and_trailing_fields() {
        let lines = read_all(&[
            "date Tue Nov 14 10:13:20.500 pm 2023",
            "base dec  timestamps relative",
            "no internal events logged",
            "// version 9.0.0",
            "   1.000000 1  1793             Rx   d 1 05  Length = 0 BitCount = 0 ID = 1793",
            "   0.500000 2  1794             Tx   d 1 7F",
            "   0.100000 1  Statistic: D 0 R 0 XD 0 XR 0 E 0 O 0 B 0.00%",
            "   0.100000 1  705             Rx   r",
        ]);
        assert_eq!(
            &lines[4..],
            [
                at(
                    T0 + 500_000 + 1_000_000,
                    CanFrame::new(0x701, &[5]).unwrap()
                ),
                at(
                    T0 + 500_000 + 1_500_000,
                    CanFrame::new(0x702, &[0x7F]).unwrap()
                ),
                Ok(Line::Nothing),
                at(T0 + 500_000 + 1_700_000, CanFrame::remote(0x2C1, 0)),
            ]
        );
    }

    #[test]
    fn dates_with_unpadded_milliseconds_as_python_can_writes_them() {
        let lines = read_all(&[
            "Begin Triggerblock Tue Nov 14 22:13:20.5 2023",
            " 0.000100 1  701  Rx   d 1 05",
            "Begin Triggerblock Tue Nov 14 22:13:20.050 2023",
            " 0.000100 1  701  Rx   d 1 05",
            "Begin Triggerblock Tue Nov 14 22:13:20.000250 2023",
            " 0.000100 1  701  Rx   d 1 05",
        ]);
        let frame = CanFrame::new(0x701, &[5]).unwrap();
        assert_eq!(lines[1], at(T0 + 5_100, frame));
        assert_eq!(lines[3], at(T0 + 50_100, frame));
        assert_eq!(lines[5], at(T0 + 350, frame));
    }

    #[test]
    fn malformed_asc_lines_say_why() {
        let mut asc = Asc::default();
        let cases = [
            (
                "date Someday",
                "bad date `Someday`: expected such as `Tue Nov 14 22:13:20.000 2023`",
            ),
            (
                "base oct  timestamps absolute",
                "unknown base `oct`: expected hex or dec",
            ),
            (
                "x.5 1 701 Rx d 1 05",
                "bad time `x.5`: expected seconds such as 0.000100",
            ),
            ("0.5 1 7G1 Rx d 1 05", "bad identifier `7G1`"),
            (
                "0.5 1 701 Rx d 9 05",
                "bad length `9`: a classic frame has 0 to 8 bytes",
            ),
            (
                "0.5 1 701 Rx d 2 05",
                "expected 2 data bytes in hex after the length",
            ),
            (
                "0.5 1 701 Rx q 1 05",
                "bad frame kind `q`: expected `d LEN DATA` or `r [LEN]`",
            ),
            ("0.5 1 801 Rx d 1 05", "identifier 801 is not 11 bits"),
        ];
        for (line, message) in cases {
            assert_eq!(asc.read(line), Err(message.to_owned()), "{line}");
        }
    }
}
