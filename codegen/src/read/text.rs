//! Bytes to text: UTF-8 (with or without BOM), else Windows-1252, and which one it was, plus the
//! facts about the text that the EDS002 diagnostic needs.

use crate::model::TextEncoding;

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
