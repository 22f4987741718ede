//! PCAN TRC logs (PCAN-View, PCAN-Basic's tracer, python-can). Comment lines start with `;`;
//! 1.x files carry the start time as `;   Start time: 24.11.2026 16:00:00.000.0` (PCAN) or
//! `;    Start time: 2026-11-24 16:00:00.000100+00:00` (python-can), 2.x files as
//! `;$STARTTIME=46000.5` (days since 1899-12-30, UTC) and their columns as `;$COLUMNS=...`.
//! Message lines:
//! - 1.0 `1)  1841  0701  1  05`; 1.1 adds the direction (`1)  1841.0  Rx  0701  1  05`), 1.2 the
//!   bus before it, 1.3 a reserved `-` after the identifier; `RTR` in place of the data for a
//!   remote request; `Warng` and `Error` lines are bus status;
//! - 2.x `1  1841.000 DT 0701 Rx 1  05` in the order `$COLUMNS` gives (2.0's default: N, O, T,
//!   I, d, l, D), with the type `DT` data, `RR` remote request, `FD`/`FB`/`FE`/`BI` CAN FD,
//!   `ER` error frame, `ST`/`EC`/`EV` status and events.
//!
//! Offsets are milliseconds from the start; identifiers are hex, extended when longer than 4
//! digits.

use super::{date_time_micros, decimal_to_micros, hex_words, make_frame, Line};

/// The state of a TRC log between lines.
#[derive(Debug, Clone, Default)]
pub struct Trc {
    /// The major file version, once a `$FILEVERSION` said it (1 without one).
    version_2: bool,
    /// The 2.x columns (`$COLUMNS`), one letter each.
    columns: Option<Vec<char>>,
    /// When the trace started, in microseconds since the epoch.
    start_us: u64,
}

/// Whether `word` is a TRC 2.x message type.
pub fn is_message_type(word: &str) -> bool {
    matches!(
        word,
        "DT" | "RR" | "FD" | "FB" | "FE" | "BI" | "ER" | "ST" | "EC" | "EV"
    )
}

impl Trc {
    /// Reads one line.
    pub fn read(&mut self, text: &str) -> Result<Line, String> {
        if let Some(comment) = text.strip_prefix(';') {
            self.header(comment.trim())?;
            return Ok(Line::Nothing);
        }
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        match words.first() {
            Some(first) if first.ends_with(')') => self.version_1(&words[1..]),
            Some(_) => self.version_2(&words),
            None => Ok(Line::Nothing),
        }
    }

    fn header(&mut self, comment: &str) -> Result<(), String> {
        if let Some(version) = comment.strip_prefix("$FILEVERSION=") {
            self.version_2 = version.starts_with('2');
        } else if let Some(days) = comment.strip_prefix("$STARTTIME=") {
            self.start_us = ole_date_micros(days).ok_or_else(|| {
                format!("bad start time `{days}`: expected days since 1899-12-30")
            })?;
        } else if let Some(columns) = comment.strip_prefix("$COLUMNS=") {
            self.columns = Some(
                columns
                    .split(',')
                    .filter_map(|c| c.trim().chars().next())
                    .collect(),
            );
        } else if let Some(time) = comment.strip_prefix("Start time:") {
            if self.start_us == 0 {
                self.start_us = date_time_micros(time.trim())
                    .map_err(|_| format!("bad start time `{}`", time.trim()))?;
            }
        }
        Ok(())
    }

    /// `N)` already taken: `OFFSET [[BUS] DIR] ID [-] LEN DATA|RTR`.
    fn version_1(&self, words: &[&str]) -> Result<Line, String> {
        let expected = || "expected `N) OFFSET [BUS] [Rx|Tx] ID LEN DATA`".to_owned();
        let [offset, rest @ ..] = words else {
            return Err(expected());
        };
        let mut rest: &[&str] = rest;
        let time_us = self.time(offset)?;
        let is_direction = |w: &&str| matches!(*w, "Rx" | "Tx" | "Warng" | "Error");
        if let [bus, direction, ..] = rest {
            if bus.bytes().all(|b| b.is_ascii_digit()) && is_direction(direction) {
                rest = &rest[1..];
            }
        }
        if let [direction, more @ ..] = rest {
            if matches!(*direction, "Warng" | "Error") {
                return Ok(Line::Error);
            }
            if is_direction(direction) {
                rest = more;
            }
        }
        let [id, more @ ..] = rest else {
            return Err(expected());
        };
        rest = more;
        if let ["-", more @ ..] = rest {
            rest = more;
        }
        let [len, data @ ..] = rest else {
            return Err(expected());
        };
        frame(time_us, id, len, data, data.first() == Some(&"RTR"))
    }

    /// A 2.x line, by its columns.
    fn version_2(&self, words: &[&str]) -> Result<Line, String> {
        let default = ['N', 'O', 'T', 'I', 'd', 'l', 'D'];
        let columns: &[char] = self.columns.as_deref().unwrap_or(&default);
        let field = |c: char| {
            columns
                .iter()
                .position(|&k| k == c)
                .and_then(|i| words.get(i).copied())
        };
        let kind = field('T').unwrap_or("DT");
        match kind {
            "DT" | "RR" => {}
            "FD" | "FB" | "FE" | "BI" => return Ok(Line::Fd),
            "ER" => return Ok(Line::Error),
            "ST" | "EC" | "EV" => return Ok(Line::Nothing),
            other => return Err(format!("unknown message type `{other}`")),
        }
        let missing = |what: &str| format!("no {what} column");
        let time_us = self.time(field('O').ok_or_else(|| missing("offset"))?)?;
        let id = field('I').ok_or_else(|| missing("identifier"))?;
        let len = field('l')
            .or_else(|| field('L'))
            .ok_or_else(|| missing("length"))?;
        let data_at = columns
            .iter()
            .position(|&c| c == 'D')
            .unwrap_or(columns.len());
        let data = words.get(data_at..).unwrap_or(&[]);
        frame(time_us, id, len, data, kind == "RR")
    }

    fn time(&self, offset: &str) -> Result<u64, String> {
        decimal_to_micros(offset, 1000)
            .map(|micros| self.start_us.saturating_add(micros))
            .ok_or_else(|| format!("bad offset `{offset}`: expected milliseconds such as 1841.5"))
    }
}

/// A frame from its identifier, length and data words.
fn frame(time_us: u64, id: &str, len: &str, data: &[&str], remote: bool) -> Result<Line, String> {
    if id.is_empty() || id.len() > 8 || !id.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!("bad identifier `{id}`: expected hex digits"));
    }
    let raw = u32::from_str_radix(id, 16).map_err(|_| format!("bad identifier `{id}`"))?;
    let len: u8 = len
        .parse()
        .ok()
        .filter(|&l| l <= 8)
        .ok_or_else(|| format!("bad length `{len}`: a classic frame has 0 to 8 bytes"))?;
    let frame = if remote {
        make_frame(raw, id.len() > 4, Some(len), &[])?
    } else {
        let bytes = data
            .get(..usize::from(len))
            .and_then(hex_words)
            .ok_or_else(|| format!("expected {len} data bytes in hex after the length"))?;
        make_frame(raw, id.len() > 4, None, &bytes)?
    };
    Ok(Line::Frame { time_us, frame })
}

/// Days since 1899-12-30 (an OLE date, as `$STARTTIME` gives it) as microseconds since the
/// epoch, to the nearest microsecond.
fn ole_date_micros(days: &str) -> Option<u64> {
    let days: f64 = days.trim().parse().ok()?;
    let micros = ((days - 25_569.0) * 86_400_000_000.0).round();
    (0.0..1e19).contains(&micros).then_some(micros as u64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use edsgen_runtime::CanFrame;

    fn read_all(lines: &[&str]) -> Vec<Result<Line, String>> {
        let mut trc = Trc::default();
        lines.iter().map(|l| trc.read(l.trim())).collect()
    }

    fn at(time_us: u64, frame: CanFrame) -> Result<Line, String> {
        Ok(Line::Frame { time_us, frame })
    }

    const T0: u64 = 1_700_000_000_000_000;

    #[test]
    fn version_1_0_as_python_can_writes_it() {
        let lines = read_all(&[
            ";##########################################################################",
            ";    Start time: 2023-11-14 22:13:20+00:00",
            ";----+- ---+--- ----+--- + -+ -- -- ...",
            "     0)       0     0701 1 05",
            "     1)       2  1234567 2 01 02",
        ]);
        assert_eq!(
            &lines[3..],
            [
                at(T0, CanFrame::new(0x701, &[5]).unwrap()),
                at(
                    T0 + 2000,
                    CanFrame::new_extended(0x123_4567, &[1, 2]).unwrap()
                ),
            ]
        );
    }

    #[test]
    fn versions_1_1_to_1_3_as_pcan_writes_them() {
        let lines = read_all(&[
            ";$FILEVERSION=1.3",
            ";   Start time: 14.11.2023 22:13:20.000.5",
            "     1)      1841.0  1  Rx         0701 -  1  05",
            "     2)      1842.3  1  Tx         0702 -  1  7F",
            "     3)      1843.0  1  Rx         0705 -  1  RTR",
            "     4)      1848.0  1  Warng  FFFFFFFF -  4  00 00 00 08  BUSHEAVY",
            "     5)      1849.7  Rx         0703  1  05",
        ]);
        let t = T0 + 500;
        assert_eq!(
            &lines[2..],
            [
                at(t + 1_841_000, CanFrame::new(0x701, &[5]).unwrap()),
                at(t + 1_842_300, CanFrame::new(0x702, &[0x7F]).unwrap()),
                at(t + 1_843_000, CanFrame::remote(0x705, 1)),
                Ok(Line::Error),
                at(t + 1_849_700, CanFrame::new(0x703, &[5]).unwrap()),
            ]
        );
    }

    #[test]
    fn version_2_by_its_columns() {
        let lines = read_all(&[
            ";$FILEVERSION=2.1",
            ";$STARTTIME=45244.92592592593",
            ";$COLUMNS=N,O,T,B,I,d,R,L,D",
            "      1         0.100 DT  1     0701 Rx -  1    05",
            "      2         1.000 DT  1 12345678 Tx -  2    01 02",
            "      3         2.000 RR  1     0705 Rx -  1",
            "      4         3.000 FD  1     0123 Rx -  9    00 11 22 33 44 55 66 77 88 99 AA BB",
            "      5         4.000 ER  1          Rx -  5    00 01 02 03 04",
            "      6         5.000 ST  1          Rx    00 00 00 08",
        ]);
        assert_eq!(
            &lines[3..],
            [
                at(T0 + 100, CanFrame::new(0x701, &[5]).unwrap()),
                at(
                    T0 + 1000,
                    CanFrame::new_extended(0x1234_5678, &[1, 2]).unwrap()
                ),
                at(T0 + 2000, CanFrame::remote(0x705, 1)),
                Ok(Line::Fd),
                Ok(Line::Error),
                Ok(Line::Nothing),
            ]
        );
        let v20 = read_all(&[";$FILEVERSION=2.0", "  1  1841.500 DT 0701 Rx 1  05"]);
        assert_eq!(v20[1], at(1_841_500, CanFrame::new(0x701, &[5]).unwrap()));
    }

    #[test]
    fn malformed_trc_lines_say_why() {
        let mut trc = Trc::default();
        let cases = [
            (
                ";$STARTTIME=soon",
                "bad start time `soon`: expected days since 1899-12-30",
            ),
            (";   Start time: yesterday", "bad start time `yesterday`"),
            ("1)", "expected `N) OFFSET [BUS] [Rx|Tx] ID LEN DATA`"),
            (
                "1) 5x 0701 1 05",
                "bad offset `5x`: expected milliseconds such as 1841.5",
            ),
            (
                "1) 5 07G1 1 05",
                "bad identifier `07G1`: expected hex digits",
            ),
            (
                "1) 5 0701 9 05",
                "bad length `9`: a classic frame has 0 to 8 bytes",
            ),
            (
                "1) 5 0701 2 05",
                "expected 2 data bytes in hex after the length",
            ),
            ("1) 5 0801 1 05", "identifier 801 is not 11 bits"),
            ("1 5.0 XX 0701 Rx 1 05", "unknown message type `XX`"),
        ];
        for (line, message) in cases {
            assert_eq!(trc.read(line), Err(message.to_owned()), "{line}");
        }
    }
}
