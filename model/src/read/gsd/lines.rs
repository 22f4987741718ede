//! GSD text into logical lines: ISO 8859-1 decoding (UTF-8 recognised), `;` comments outside
//! quotes removed, `\` continuations joined; each logical line keeps the span of its first
//! physical line.

use crate::model::{Span, TextEncoding};

/// A logical line: its text (comment removed, continuations joined, trimmed) and where it
/// starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// The text.
    pub text: String,
    /// The first physical line's span (column 1, its length in characters).
    pub span: Span,
}

/// Decodes the bytes: UTF-8 when they are valid UTF-8 with non-ASCII characters (the caller
/// reports it), else ISO 8859-1 (each byte one character), ASCII when all bytes are.
pub fn decode(bytes: &[u8]) -> (String, TextEncoding) {
    let body = bytes.strip_prefix(b"\xEF\xBB\xBF");
    if let Some(body) = body {
        if let Ok(text) = std::str::from_utf8(body) {
            return (text.to_owned(), TextEncoding::Utf8Bom);
        }
    }
    if bytes.is_ascii() {
        return (
            bytes.iter().map(|&b| char::from(b)).collect(),
            TextEncoding::Ascii,
        );
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => (text.to_owned(), TextEncoding::Utf8),
        Err(_) => (
            bytes.iter().map(|&b| char::from(b)).collect(),
            TextEncoding::Latin1,
        ),
    }
}

/// The text without a `;` comment (a `;` inside double quotes is text).
fn strip_comment(line: &str) -> &str {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ';' if !quoted => return &line[..i],
            _ => {}
        }
    }
    line
}

/// The logical lines of a text.
pub fn logical_lines(text: &str) -> Vec<Line> {
    let mut out: Vec<Line> = Vec::new();
    let mut pending: Option<Line> = None;
    for (n, raw) in text.split('\n').enumerate() {
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let number = u32::try_from(n + 1).unwrap_or(u32::MAX);
        let content = strip_comment(raw).trim();
        let (content, continues) = match content.strip_suffix('\\') {
            Some(rest) => (rest.trim_end(), true),
            None => (content, false),
        };
        let mut line = match pending.take() {
            Some(mut line) => {
                if !content.is_empty() {
                    if !line.text.is_empty() {
                        line.text.push(' ');
                    }
                    line.text.push_str(content);
                }
                line
            }
            None => Line {
                text: content.to_owned(),
                span: Span::new(
                    number,
                    1,
                    u32::try_from(raw.chars().count()).unwrap_or(u32::MAX),
                ),
            },
        };
        if continues {
            line.text = line.text.trim_end().to_owned();
            pending = Some(line);
        } else if !line.text.is_empty() {
            out.push(line);
        }
    }
    if let Some(line) = pending {
        if !line.text.is_empty() {
            out.push(line);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_and_continuations() {
        let text = "; head\n#Profibus_DP\r\nA = 1 ; c\nB = \"x;y\"\nC = 1,\\\n 2,\\\n\n3\n";
        let lines = logical_lines(text);
        let texts: Vec<&str> = lines.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(
            texts,
            ["#Profibus_DP", "A = 1", "B = \"x;y\"", "C = 1, 2,", "3"]
        );
        assert_eq!(lines[3].span, Span::new(5, 1, 7));
    }

    #[test]
    fn encodings() {
        assert_eq!(decode(b"a").1, TextEncoding::Ascii);
        assert_eq!(decode(b"\xE4").0, "\u{e4}");
        assert_eq!(decode(b"\xE4").1, TextEncoding::Latin1);
        assert_eq!(decode("ä".as_bytes()).1, TextEncoding::Utf8);
    }
}
