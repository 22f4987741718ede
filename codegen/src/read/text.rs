//! Bytes to text: UTF-8 (with or without BOM), else Windows-1252, and which one it was, plus the
//! facts about the text that the EDS002 diagnostic needs, and `LineIndex`, which turns the byte
//! ranges of the XML and TOML parsers into spans.

use crate::model::{Span, TextEncoding};

/// Decodes a file's bytes and says which encoding was used.
pub fn decode(bytes: &[u8]) -> (String, TextEncoding) {
    if let Some(rest) = bytes.strip_prefix(b"\xEF\xBB\xBF") {
        if let Ok(s) = std::str::from_utf8(rest) {
            return (s.to_owned(), TextEncoding::Utf8Bom);
        }
    }
    match std::str::from_utf8(bytes) {
        Ok(s) if s.is_ascii() => (s.to_owned(), TextEncoding::Ascii),
        Ok(s) => (s.to_owned(), TextEncoding::Utf8),
        Err(_) => {
            let (text, _, _) = encoding_rs::WINDOWS_1252.decode(bytes);
            (text.into_owned(), TextEncoding::Windows1252)
        }
    }
}

/// The 1-based line and character column of the first non-ASCII character, if any.
pub fn first_non_ascii(text: &str) -> Option<(u32, u32)> {
    super::ini::lines(text)
        .iter()
        .enumerate()
        .find_map(|(number, line)| {
            let column = line.chars().position(|c| !c.is_ascii())?;
            Some((
                u32::try_from(number + 1).unwrap_or(u32::MAX),
                u32::try_from(column + 1).unwrap_or(u32::MAX),
            ))
        })
}

/// A human name of an encoding, for messages.
pub const fn encoding_name(encoding: TextEncoding) -> &'static str {
    match encoding {
        TextEncoding::Ascii => "ASCII",
        TextEncoding::Utf8 => "UTF-8",
        TextEncoding::Utf8Bom => "UTF-8 (with a byte-order mark)",
        TextEncoding::Windows1252 => "Windows-1252",
    }
}

/// The byte offsets where the lines of a text start: byte ranges from a parser (roxmltree, toml)
/// to line/column spans.
pub(crate) struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    pub(crate) fn new(text: &str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { starts }
    }

    /// The span of `text[range]`, clipped to the line it starts on.
    pub(crate) fn span(&self, text: &str, range: std::ops::Range<usize>) -> Span {
        let start = range.start.min(text.len());
        let line = self.starts.partition_point(|&s| s <= start).max(1);
        let line_start = self.starts[line - 1];
        let column = text.get(line_start..start).map_or(0, |s| s.chars().count()) + 1;
        let end = range.end.clamp(start, text.len());
        let len = text
            .get(start..end)
            .map_or(0, |s| s.chars().take_while(|&c| c != '\n').count());
        let to_u32 = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        Span::new(to_u32(line), to_u32(column), to_u32(len))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detects_each_encoding() {
        assert_eq!(decode(b"[A]\n"), ("[A]\n".to_owned(), TextEncoding::Ascii));
        assert_eq!(decode("x\n\u{e9}".as_bytes()).1, TextEncoding::Utf8);
        assert_eq!(decode(b"\xEF\xBB\xBFx").1, TextEncoding::Utf8Bom);
        assert_eq!(decode(b"\xEF\xBB\xBFx").0, "x");
        assert_eq!(
            decode(b"a\xB5b"),
            ("a\u{b5}b".to_owned(), TextEncoding::Windows1252)
        );
    }

    #[test]
    fn finds_the_first_non_ascii_line() {
        assert_eq!(first_non_ascii("a\r\nb\r\nc\u{b0}"), Some((3, 2)));
        assert_eq!(first_non_ascii("a\nb"), None);
    }
}
