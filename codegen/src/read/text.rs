//! Bytes to text: UTF-8 (with or without BOM), else Windows-1252, and which one it was.

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
