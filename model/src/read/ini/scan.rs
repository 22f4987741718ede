//! The lexer's byte searches: lines (LF, CR LF or lone CR) and a byte in a line, a word of
//! eight bytes at a time.

/// Splits text into lines, accepting LF, CR LF and lone CR, and a last line without a newline.
pub fn lines(text: &str) -> Vec<&str> {
    Lines::new(text).collect()
}

/// The lines of a text, as [`lines`] splits them, one at a time: the lexer walks them without
/// a list of them (which was as big as the text again, for a file of short lines).
pub struct Lines<'t> {
    text: &'t str,
    /// Where the next line starts.
    start: usize,
}

impl<'t> Lines<'t> {
    /// The lines of `text`.
    pub fn new(text: &'t str) -> Self {
        Lines { text, start: 0 }
    }
}

impl<'t> Iterator for Lines<'t> {
    type Item = &'t str;

    #[inline]
    fn next(&mut self) -> Option<&'t str> {
        let bytes = self.text.as_bytes();
        let start = self.start;
        if start >= bytes.len() {
            return None;
        }
        let end = line_end(bytes, start);
        self.start = end + 1;
        // The LF of a CR LF ends its line with the CR.
        if bytes.get(end) == Some(&b'\r') && bytes.get(end + 1) == Some(&b'\n') {
            self.start += 1;
        }
        Some(&self.text[start..end])
    }
}

/// Bytes read eight at a time, as one word, for the searches below: lines are about 20 bytes,
/// too short for a vector search to pay for its set-up.
const ONES: u64 = 0x0101_0101_0101_0101;
const HIGH: u64 = 0x8080_8080_8080_8080;

/// The eight bytes at `at` as one word (first byte lowest), if there are eight.
#[inline]
fn word_at(bytes: &[u8], at: usize) -> Option<u64> {
    let chunk = <[u8; 8]>::try_from(bytes.get(at..at.checked_add(8)?)?).ok()?;
    Some(u64::from_le_bytes(chunk))
}

/// The offset of the first CR or LF at or after `at`, or the text's length.
fn line_end(bytes: &[u8], mut at: usize) -> usize {
    // The lowest byte flagged is the first one below 0Eh exactly (LF is 0Ah, CR 0Dh); the
    // others may be false alarms, and so may the first (a tab): look at it, go on after it.
    while let Some(word) = word_at(bytes, at) {
        let below = word.wrapping_sub(ONES * 0x0E) & !word & HIGH;
        if below == 0 {
            at += 8;
            continue;
        }
        at += (below.trailing_zeros() / 8) as usize;
        if matches!(bytes.get(at), Some(b'\n' | b'\r')) {
            return at;
        }
        at += 1;
    }
    while at < bytes.len() && !matches!(bytes[at], b'\n' | b'\r') {
        at += 1;
    }
    at
}

/// The offset of the first `byte` in `bytes`.
pub(super) fn find_byte(bytes: &[u8], byte: u8) -> Option<usize> {
    let mut at = 0;
    // A byte equal to `byte` is a zero byte of `word ^ pattern`; the lowest byte flagged is the
    // first zero byte exactly.
    let pattern = ONES * u64::from(byte);
    while let Some(word) = word_at(bytes, at) {
        let zeros = word ^ pattern;
        let flagged = zeros.wrapping_sub(ONES) & !zeros & HIGH;
        if flagged != 0 {
            return Some(at + (flagged.trailing_zeros() / 8) as usize);
        }
        at += 8;
    }
    let rest = bytes.get(at..).unwrap_or_default();
    rest.iter().position(|b| *b == byte).map(|p| at + p)
}
