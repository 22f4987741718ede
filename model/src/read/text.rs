//! Bytes to text: UTF-16 (by its byte-order mark or its zero bytes), UTF-8 (with or without BOM),
//! else Windows-1252, and which one it was, plus the facts about the bytes that the EDS002 and
//! EDS022 diagnostics need (a NUL byte, a byte a DOS code page reads better), and `LineIndex`,
//! which turns the byte ranges of the XML and TOML parsers into spans.

use crate::model::{Span, TextEncoding};

/// Decodes a file's bytes and says which encoding was used.
pub fn decode(bytes: &[u8]) -> (String, TextEncoding) {
    if let Some(encoding) = utf16(bytes) {
        let codec = match encoding {
            TextEncoding::Utf16Be => encoding_rs::UTF_16BE,
            _ => encoding_rs::UTF_16LE,
        };
        let body = bytes
            .strip_prefix(b"\xFF\xFE")
            .or_else(|| bytes.strip_prefix(b"\xFE\xFF"))
            .unwrap_or(bytes);
        let (text, _) = codec.decode_without_bom_handling(body);
        return (text.into_owned(), encoding);
    }
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

/// [`decode`] for bytes the caller owns: the text without a copy when it is ASCII or UTF-8
/// without a byte-order mark (almost every file), else the bytes back, for [`decode`].
pub fn decode_owned(bytes: Vec<u8>) -> Result<(String, TextEncoding), Vec<u8>> {
    if utf16(&bytes).is_some() || bytes.starts_with(b"\xEF\xBB\xBF") {
        return Err(bytes);
    }
    match String::from_utf8(bytes) {
        Ok(text) if text.is_ascii() => Ok((text, TextEncoding::Ascii)),
        Ok(text) => Ok((text, TextEncoding::Utf8)),
        Err(err) => Err(err.into_bytes()),
    }
}

/// Whether the bytes are UTF-16: a byte-order mark, or (without one) text whose first two
/// characters are ASCII with a zero byte each, as Windows "Unicode" editors write it.
pub fn utf16(bytes: &[u8]) -> Option<TextEncoding> {
    match bytes {
        [0xFF, 0xFE, ..] => Some(TextEncoding::Utf16Le),
        [0xFE, 0xFF, ..] => Some(TextEncoding::Utf16Be),
        [a, 0, c, 0, ..] if a.is_ascii() && *a != 0 && c.is_ascii() && *c != 0 => {
            Some(TextEncoding::Utf16Le)
        }
        [0, b, 0, d, ..] if b.is_ascii() && *b != 0 && d.is_ascii() && *d != 0 => {
            Some(TextEncoding::Utf16Be)
        }
        _ => None,
    }
}

/// The offset of the first NUL byte of a file that is not UTF-16: no text file has one.
pub fn first_nul(bytes: &[u8]) -> Option<usize> {
    if utf16(bytes).is_some() {
        return None;
    }
    memchr::memchr(0, bytes)
}

/// DOS code page 437 (and 850, which agrees here) for the bytes 80h..9Ah, all letters.
const DOS_LETTERS: [char; 27] = [
    'Ç', 'ü', 'é', 'â', 'ä', 'à', 'å', 'ç', 'ê', 'ë', 'è', 'ï', 'î', 'ì', 'Ä', 'Å', 'É', 'æ', 'Æ',
    'ô', 'ö', 'ò', 'û', 'ù', 'ÿ', 'Ö', 'Ü',
];

/// A byte that Windows-1252 reads as punctuation (a quote, a dash, a dagger) but that sits between
/// two letters, where DOS code page 437/850 reads a letter: the file was more likely written in
/// a DOS code page. The byte's offset, the byte, and the two readings.
pub fn dos_code_page_guess(bytes: &[u8]) -> Option<(usize, u8, char, char)> {
    (1..bytes.len().saturating_sub(1)).find_map(|i| {
        let byte = bytes[i];
        let dos = *DOS_LETTERS.get(usize::from(byte.checked_sub(0x80)?))?;
        let windows = encoding_rs::WINDOWS_1252
            .decode_without_bom_handling(&bytes[i..=i])
            .0
            .chars()
            .next()?;
        (bytes[i - 1].is_ascii_alphabetic()
            && bytes[i + 1].is_ascii_alphabetic()
            && !windows.is_alphabetic())
        .then_some((i, byte, windows, dos))
    })
}

/// The 1-based line and character column of the first non-ASCII character, if any.
pub fn first_non_ascii(text: &str) -> Option<(u32, u32)> {
    super::ini::Lines::new(text)
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
        TextEncoding::Latin1 => "ISO-8859-1",
        TextEncoding::Utf16Le => "UTF-16 (little-endian)",
        TextEncoding::Utf16Be => "UTF-16 (big-endian)",
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
    fn utf16_is_decoded_and_labelled_with_or_without_a_byte_order_mark() {
        let le: Vec<u8> = "[A]\n".encode_utf16().flat_map(u16::to_le_bytes).collect();
        let be: Vec<u8> = "[A]\n".encode_utf16().flat_map(u16::to_be_bytes).collect();
        assert_eq!(
            decode(&[&[0xFF, 0xFE][..], &le].concat()),
            ("[A]\n".to_owned(), TextEncoding::Utf16Le)
        );
        assert_eq!(decode(&le), ("[A]\n".to_owned(), TextEncoding::Utf16Le));
        assert_eq!(decode(&be), ("[A]\n".to_owned(), TextEncoding::Utf16Be));
        assert_eq!(first_nul(&le), None);
        assert_eq!(first_nul(b"[A]\n\x7fELF\0\0"), Some(8));
    }

    #[test]
    fn a_quote_between_letters_is_guessed_to_be_a_dos_letter() {
        assert_eq!(
            dos_code_page_guess(b"Line3=71101 Sch\x94naich\r\n"),
            Some((15, 0x94, '\u{201d}', '\u{f6}'))
        );
        // A real quote after a letter, and a Windows-1252 letter between letters, are not guesses.
        assert_eq!(dos_code_page_guess(b"say \x93hi\x94 now"), None);
        assert_eq!(dos_code_page_guess(b"Stra\x9Ae"), None);
    }

    #[test]
    fn finds_the_first_non_ascii_line() {
        assert_eq!(first_non_ascii("a\r\nb\r\nc\u{b0}"), Some((3, 2)));
        assert_eq!(first_non_ascii("a\nb"), None);
    }
}
