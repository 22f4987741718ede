//! A small, span-keeping INI lexer for the CiA 306 dialect of EDS and DCF files.
//!
//! A generic INI crate is not used on purpose: none keeps line and column numbers (every
//! diagnostic must point at the vendor's line), none reports duplicate sections and keys (they
//! silently merge or overwrite), and none is lossless about the dialects vendors write (`key = value`
//! spacing, indented comments, lone CR line ends, junk lines), which this lexer accepts and reports.
//!
//! Policy for duplicates: a section that appears again (case-insensitively) is merged into the
//! first one, with an EDS005 error; a key that appears twice in one section (case-insensitively)
//! keeps the last value, with an EDS006 error. Keys repeated across the two parts of a merged
//! section also keep the last value (covered by the EDS005 error). Nothing is dropped silently.

use std::collections::HashMap;

use super::hash::{Caseless, FastHash};
use crate::diag::Diagnostic;
use crate::model::Span;
use crate::rules;
use scan::find_byte;
pub use scan::{lines, Lines};

mod scan;

/// The longest line CiA 306 allows, in characters.
pub const MAX_LINE_CHARS: usize = 255;

/// A piece of the lexed text, borrowed: the lexer copies no key or value (copies were most of
/// its cost). Reads like a `&str`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct IniText<'t>(&'t str);

impl<'t> IniText<'t> {
    /// The text.
    pub fn as_str(&self) -> &'t str {
        self.0
    }
}

impl std::ops::Deref for IniText<'_> {
    type Target = str;

    fn deref(&self) -> &str {
        self.0
    }
}

impl std::fmt::Debug for IniText<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Debug::fmt(self.0, f)
    }
}

impl std::fmt::Display for IniText<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(self.0, f)
    }
}

impl PartialEq<str> for IniText<'_> {
    fn eq(&self, other: &str) -> bool {
        self.0 == other
    }
}

impl PartialEq<&str> for IniText<'_> {
    fn eq(&self, other: &&str) -> bool {
        self.0 == *other
    }
}

impl PartialEq<IniText<'_>> for &str {
    fn eq(&self, other: &IniText<'_>) -> bool {
        *self == other.0
    }
}

/// One `key=value` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IniEntry<'t> {
    /// The key as written (trimmed).
    pub key: IniText<'t>,
    /// Where the key is.
    pub key_span: Span,
    /// The value, trimmed (possibly empty).
    pub value: IniText<'t>,
    /// Where the value is (length 0 and just after `=` when empty).
    pub value_span: Span,
}

impl IniEntry<'_> {
    /// The span of the whole `key=value` text.
    pub fn line_span(&self) -> Span {
        let end = if self.value.is_empty() {
            self.value_span.column
        } else {
            self.value_span.column + self.value_span.len
        };
        Span::new(
            self.key_span.line,
            self.key_span.column,
            end.saturating_sub(self.key_span.column),
        )
    }
}

/// One section: its name and its entries in file order (duplicates already resolved).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IniSection<'t> {
    /// The name between the brackets, as first written (trimmed).
    pub name: IniText<'t>,
    /// Where the section header is (the whole `[name]`).
    pub span: Span,
    /// The entries, in file order; a key appears at most once (case-insensitively).
    pub entries: Vec<IniEntry<'t>>,
    /// The CANopenEditor comment extensions (`;StorageLocation=RAM`, `;TPDODetectCos=1`) found in
    /// the section, without the `;`. They are comments to CiA 306, and read back by CANopenEditor.
    pub commented: Vec<IniEntry<'t>>,
}

impl<'t> IniSection<'t> {
    /// The entry for `key`, compared case-insensitively.
    pub fn get(&self, key: &str) -> Option<&IniEntry<'t>> {
        self.entries
            .iter()
            .find(|e| e.key.eq_ignore_ascii_case(key))
    }
}

/// A lexed file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct IniFile<'t> {
    /// The sections in order of first appearance.
    pub sections: Vec<IniSection<'t>>,
}

/// The keys CANopenEditor writes as comments (`;StorageLocation=RAM`) and reads back.
pub const COMMENTED_KEYS: &[&str] = &["StorageLocation", "TPDODetectCos"];

/// Whether an ASCII byte is white space to [`char::is_whitespace`].
#[inline]
fn is_ascii_space(b: u8) -> bool {
    // One comparison for the common case, a byte above the space.
    b <= b' ' && matches!(b, b'\t' | b'\n' | 0x0B | 0x0C | b'\r' | b' ')
}

/// [`str::trim_start`] for text known to be ASCII or not.
#[inline]
fn trim_start_in(s: &str, ascii: bool) -> &str {
    if ascii {
        let bytes = s.as_bytes();
        let mut start = 0;
        while start < bytes.len() && is_ascii_space(bytes[start]) {
            start += 1;
        }
        &s[start..]
    } else {
        s.trim_start()
    }
}

/// [`str::trim`] for text known to be ASCII or not.
#[inline]
fn trim_in(s: &str, ascii: bool) -> &str {
    if ascii {
        let s = trim_start_in(s, true);
        let bytes = s.as_bytes();
        let mut end = bytes.len();
        while end > 0 && is_ascii_space(bytes[end - 1]) {
            end -= 1;
        }
        &s[..end]
    } else {
        s.trim()
    }
}

fn char_len(s: &str) -> u32 {
    u32::try_from(s.chars().count()).unwrap_or(u32::MAX)
}

/// [`char_len`] for a piece of a line known to be ASCII or not.
fn char_len_in(s: &str, ascii: bool) -> u32 {
    if ascii {
        u32::try_from(s.len()).unwrap_or(u32::MAX)
    } else {
        char_len(s)
    }
}

/// The 1-based character column of byte offset `at` in `line`.
fn column_of(line: &str, at: usize) -> u32 {
    char_len(line.get(..at).unwrap_or(line)).saturating_add(1)
}

/// [`column_of`] for a line known to be ASCII or not.
fn column_in(line: &str, at: usize, ascii: bool) -> u32 {
    if ascii {
        u32::try_from(at.min(line.len()))
            .unwrap_or(u32::MAX)
            .saturating_add(1)
    } else {
        column_of(line, at)
    }
}

/// Whether a key is written only with `[A-Za-z0-9_]`.
pub fn is_plain_key(key: &str) -> bool {
    // Every byte looked up, without a branch per byte: keys are short, and nearly all plain.
    !key.is_empty()
        && key
            .bytes()
            .fold(true, |plain, b| plain & PLAIN_KEY_BYTES[usize::from(b)])
}

/// Whether a byte may appear in a plain key (`[A-Za-z0-9_]`), by byte: one load per byte.
const PLAIN_KEY_BYTES: [bool; 256] = {
    let mut table = [false; 256];
    let mut b = 0;
    while b < 256 {
        let byte = b as u8;
        table[b] = byte.is_ascii_alphanumeric() || byte == b'_';
        b += 1;
    }
    table
};

/// A `;Key=value` comment line whose key is one of [`COMMENTED_KEYS`], as an entry.
fn commented_entry(line: &str, line_no: u32) -> Option<IniEntry<'_>> {
    let body = line.strip_prefix(';')?;
    let eq = find_byte(body.as_bytes(), b'=')?;
    let key = body[..eq].trim();
    if !COMMENTED_KEYS.iter().any(|k| k.eq_ignore_ascii_case(key)) {
        return None;
    }
    let value_raw = &body[eq + 1..];
    let value = value_raw.trim();
    let value_at = 1 + eq + 1 + (value_raw.len() - value_raw.trim_start().len());
    Some(IniEntry {
        key: IniText(key),
        key_span: Span::new(line_no, 2, char_len(key)),
        value: IniText(value),
        value_span: Span::new(line_no, column_of(line, value_at), char_len(value)),
    })
}

/// One bit of 64 for a key, the same for keys equal ignoring ASCII case (from its length and its
/// first and last bytes, case folded): different bits are different keys.
fn key_mark(key: &str) -> u64 {
    let bytes = key.as_bytes();
    let fold = |b: Option<&u8>| usize::from(b.map_or(0, |b| b | 0x20));
    let bit = bytes.len() * 7 + fold(bytes.first()) * 3 + fold(bytes.last());
    1 << (bit % 64)
}

/// Lexes the text into sections, reporting EDS001, EDS003, EDS004, EDS005, EDS006, EDS007 and
/// EDS027.
pub fn parse<'t>(text: &'t str, diags: &mut Vec<Diagnostic>) -> IniFile<'t> {
    // Index into `file.sections` of the section that receives entries, and the keys seen in the
    // current occurrence of it (compared case-insensitively).
    let mut current: Option<usize> = None;
    let mut keys_here: Vec<&str> = Vec::new();
    // The sections and both maps are sized for the densest files of the corpus (about a section
    // per 190 bytes), so they do not grow while they fill.
    let expected = text.len() / 128;
    let mut file = IniFile {
        sections: Vec::with_capacity(expected),
    };
    // Section name (case-insensitively) -> position in `file.sections`.
    let mut section_at: HashMap<Caseless<'t>, usize, FastHash> =
        HashMap::with_capacity_and_hasher(expected, FastHash::default());
    // (section, key case-insensitively) -> position in its entries, for the sections with at
    // least INDEXED_FROM entries (long object lists, [xxxxValue]); smaller ones are scanned.
    const INDEXED_FROM: usize = 16;
    // For each section, the key marks of its entries (see `key_mark`): a key whose mark is not
    // among them is new, without a scan of the entries.
    let mut key_marks: Vec<u64> = Vec::with_capacity(expected);
    let mut entry_at: HashMap<(usize, Caseless<'t>), usize, FastHash> =
        HashMap::with_capacity_and_hasher(expected, FastHash::default());
    // The line of the comment that the previous line was or continued: a line without `;` or
    // `=` right after it continues that comment (a comment with a line break in it, EDS027).
    let mut comment_from: Option<u32> = None;
    // Most files are ASCII throughout: one test for the whole text, not one per line.
    let all_ascii = text.is_ascii();
    for (number, line) in Lines::new(text).enumerate() {
        let line_no = u32::try_from(number + 1).unwrap_or(u32::MAX);
        // A line of at most MAX_LINE_CHARS bytes has at most as many characters.
        let chars = if line.len() > MAX_LINE_CHARS {
            line.chars().count()
        } else {
            0
        };
        if chars > MAX_LINE_CHARS {
            diags.push(
                Diagnostic::new(
                    &rules::LONG_LINE,
                    Some(Span::new(line_no, 1, char_len(line))),
                    format!("line has {chars} characters; CiA 306 allows {MAX_LINE_CHARS}"),
                )
                .with_help("shorten the value; some tools truncate long lines"),
            );
        }
        let ascii = all_ascii || line.is_ascii();
        let trimmed = trim_in(line, ascii);
        let after_comment = comment_from.take();
        if trimmed.is_empty() {
            continue;
        }
        let indent = line.len() - trim_start_in(line, ascii).len();
        let first_col = column_in(line, indent, ascii);
        if trimmed.starts_with(';') {
            comment_from = Some(line_no);
            if indent > 0 {
                diags.push(Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                    "comment does not start in column 1",
                ));
            } else if let Some(section) = current.and_then(|i| file.sections.get_mut(i)) {
                if let Some(entry) = commented_entry(line, line_no) {
                    section.commented.push(entry);
                }
            }
            continue;
        }
        if trimmed.starts_with('[') {
            let Some(close) = trimmed.bytes().position(|b| b == b']') else {
                diags.push(
                    Diagnostic::new(
                        &rules::UNPARSEABLE_LINE,
                        Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                        "section header without a closing `]`",
                    )
                    .with_label("the line is ignored"),
                );
                continue;
            };
            let inner = &trimmed[1..close];
            let name = trim_in(inner, ascii);
            let header_span = Span::new(line_no, first_col, char_len_in(&trimmed[..=close], ascii));
            if indent > 0 || name.len() != inner.len() {
                diags.push(
                    Diagnostic::new(
                        &rules::KEY_SPELLING,
                        Some(header_span),
                        format!("whitespace around the section header `[{name}]`"),
                    )
                    .with_help(format!("write `[{name}]` starting in column 1")),
                );
            }
            let rest = trim_in(&trimmed[close + 1..], ascii);
            if rest.starts_with(';') {
                diags.push(Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(header_span),
                    "comment after a section header",
                ));
            } else if !rest.is_empty() {
                diags.push(Diagnostic::new(
                    &rules::UNPARSEABLE_LINE,
                    Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                    format!("text `{rest}` after the section header `[{name}]` is ignored"),
                ));
            }
            if name.is_empty() {
                diags.push(Diagnostic::new(
                    &rules::UNPARSEABLE_LINE,
                    Some(header_span),
                    "empty section name; its entries are ignored",
                ));
                current = None;
                keys_here.clear();
                continue;
            }
            keys_here.clear();
            if let Some(&existing) = section_at.get(&Caseless(name)) {
                let first_line = file.sections[existing].span.line;
                diags.push(
                    Diagnostic::new(
                        &rules::DUPLICATE_SECTION,
                        Some(header_span),
                        format!("section [{name}] already appeared on line {first_line}"),
                    )
                    .with_label(
                        "merged into the first one; repeated keys take this section's value",
                    ),
                );
                current = Some(existing);
            } else {
                section_at.insert(Caseless(name), file.sections.len());
                key_marks.push(0);
                current = Some(file.sections.len());
                file.sections.push(IniSection {
                    name: IniText(name),
                    span: header_span,
                    // Most object sections have up to eight keys: one allocation for them.
                    entries: Vec::with_capacity(8),
                    commented: Vec::new(),
                });
            }
            continue;
        }
        let Some(eq) = find_byte(line.as_bytes(), b'=') else {
            if let Some(comment_line) = after_comment {
                diags.push(
                    Diagnostic::new(
                        &rules::COMMENT_CONTINUATION,
                        Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                        format!("line continues the comment on line {comment_line}"),
                    )
                    .with_label("read as part of that comment")
                    .with_help("start the line with `;`, or join it to the comment"),
                );
                comment_from = Some(comment_line);
                continue;
            }
            diags.push(
                Diagnostic::new(
                    &rules::UNPARSEABLE_LINE,
                    Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                    "line is not a comment, a [section] or key=value",
                )
                .with_label("the line is ignored")
                .with_help("start the line with `;` if it is a comment, or remove it"),
            );
            continue;
        };
        let key_raw = &line[..eq];
        let key = trim_in(key_raw, ascii);
        let key_span = Span::new(line_no, first_col, char_len_in(key, ascii));
        let value_raw = &line[eq + 1..];
        let value = trim_in(value_raw, ascii);
        let value_at = eq + 1 + (value_raw.len() - trim_start_in(value_raw, ascii).len());
        let value_span = Span::new(
            line_no,
            column_in(line, value_at, ascii),
            char_len_in(value, ascii),
        );
        if key.is_empty() {
            diags.push(Diagnostic::new(
                &rules::UNPARSEABLE_LINE,
                Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                "entry without a key name is ignored",
            ));
            continue;
        }
        let Some((section_index, section)) =
            current.and_then(|i| Some((i, file.sections.get_mut(i)?)))
        else {
            diags.push(Diagnostic::new(
                &rules::UNPARSEABLE_LINE,
                Some(Span::new(line_no, first_col, char_len_in(trimmed, ascii))),
                format!("entry `{key}` before any section is ignored"),
            ));
            continue;
        };
        if indent > 0 || key.len() != key_raw.len() - indent {
            diags.push(
                Diagnostic::new(
                    &rules::KEY_SPELLING,
                    Some(key_span),
                    format!("whitespace around the key `{key}`"),
                )
                .with_help(format!("write `{key}=` starting in column 1")),
            );
        }
        if !is_plain_key(key) {
            let help = if key.starts_with('#') {
                "`#` does not start a comment in CiA 306: write `;` to comment the line out"
            } else {
                "CiA 306 keys are letters, digits and `_`; other tools may not find this key"
            };
            diags.push(
                Diagnostic::new(
                    &rules::KEY_SPELLING,
                    Some(key_span),
                    format!("key `{key}` has characters other than letters, digits and `_`"),
                )
                .with_help(help),
            );
        }
        let entry = IniEntry {
            key: IniText(key),
            key_span,
            value: IniText(value),
            value_span,
        };
        let marks = key_marks.get_mut(section_index);
        let mark = key_mark(key);
        let existing = if section.entries.len() >= INDEXED_FROM {
            entry_at.get(&(section_index, Caseless(key))).copied()
        } else if marks.as_ref().is_some_and(|m| **m & mark == 0) {
            None
        } else {
            section
                .entries
                .iter()
                .position(|e| e.key.eq_ignore_ascii_case(key))
        };
        // A key seen in this occurrence of the section is always among the entries.
        if existing.is_some() && keys_here.iter().any(|k| k.eq_ignore_ascii_case(key)) {
            let first = section.get(key).map_or(0, |e| e.key_span.line);
            diags.push(Diagnostic::new(
                &rules::DUPLICATE_KEY,
                Some(key_span),
                format!(
                    "key `{key}` already appeared in [{}] on line {first}; this value wins",
                    section.name
                ),
            ));
        } else {
            keys_here.push(key);
        }
        if let Some(marks) = marks {
            *marks |= mark;
        }
        match existing.and_then(|at| section.entries.get_mut(at)) {
            Some(existing) => *existing = entry,
            None => {
                section.entries.push(entry);
                let count = section.entries.len();
                if count == INDEXED_FROM {
                    for (at, e) in section.entries.iter().enumerate() {
                        entry_at.insert((section_index, Caseless(e.key.as_str())), at);
                    }
                } else if count > INDEXED_FROM {
                    entry_at.insert((section_index, Caseless(key)), count - 1);
                }
            }
        }
    }
    file
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Severity;

    fn lex(text: &str) -> (IniFile<'_>, Vec<(&'static str, Severity, u32)>) {
        let mut diags = Vec::new();
        let file = parse(text, &mut diags);
        let codes = diags
            .iter()
            .map(|d| (d.code(), d.severity, d.span.map_or(0, |s| s.line)))
            .collect();
        (file, codes)
    }

    #[test]
    fn line_endings_lf_crlf_cr_and_no_final_newline() {
        assert_eq!(lines("a\nb\r\nc\rd"), vec!["a", "b", "c", "d"]);
        assert_eq!(lines("a\n"), vec!["a"]);
        assert_eq!(lines("a\r\n\r\nb"), vec!["a", "", "b"]);
        assert_eq!(lines(""), Vec::<&str>::new());
    }

    /// The byte-at-a-time line splitter `lines` replaced, as the reference.
    fn reference_lines(text: &str) -> Vec<&str> {
        let mut out = Vec::new();
        let bytes = text.as_bytes();
        let (mut start, mut i) = (0, 0);
        while i < bytes.len() {
            match bytes[i] {
                b'\n' => {
                    out.push(&text[start..i]);
                    start = i + 1;
                }
                b'\r' => {
                    out.push(&text[start..i]);
                    if bytes.get(i + 1) == Some(&b'\n') {
                        i += 1;
                    }
                    start = i + 1;
                }
                _ => {}
            }
            i += 1;
        }
        if start < bytes.len() {
            out.push(&text[start..]);
        }
        out
    }

    #[test]
    fn lines_agree_with_the_bytewise_reference() {
        // Every text of up to 7 characters over {tab, CR, LF} (a tab is below 0Eh too: the
        // word search flags it and must go on), and the same padded past the eight-byte
        // stride with long runs before and after. `find_byte` against `position` on the same.
        let alphabet = ['\t', '\r', '\n'];
        let mut checked = 0;
        for len in 0..=7u32 {
            for mut code in 0..3usize.pow(len) {
                let mut text = String::new();
                for _ in 0..len {
                    text.push(alphabet[code % 3]);
                    code /= 3;
                }
                for padded in [
                    text.clone(),
                    format!("{}{text}", "x".repeat(13)),
                    format!("{text}{}", "é".repeat(9)),
                ] {
                    assert_eq!(lines(&padded), reference_lines(&padded), "{padded:?}");
                    assert_eq!(
                        find_byte(padded.as_bytes(), b'\r'),
                        padded.bytes().position(|b| b == b'\r'),
                        "{padded:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(
            checked,
            3 * (1..=7).map(|n| 3usize.pow(n)).sum::<usize>() + 3
        );
    }

    #[test]
    fn ascii_trims_match_the_unicode_ones() {
        for text in ["", " ", "\t a \x0B\x0C", "\r\n key \t", "k", " \x1F k\x1F "] {
            assert_eq!(trim_in(text, true), text.trim(), "{text:?}");
            assert_eq!(trim_start_in(text, true), text.trim_start(), "{text:?}");
        }
    }

    #[test]
    fn sections_and_entries_with_spans() {
        let (file, diags) = lex("[FileInfo]\r\nFileName=x.eds\r\nDescription=\r\n");
        assert!(diags.is_empty());
        let s = &file.sections[0];
        assert_eq!(s.name, "FileInfo");
        assert_eq!(s.span, Span::new(1, 1, 10));
        assert_eq!(s.entries[0].key, "FileName");
        assert_eq!(s.entries[0].key_span, Span::new(2, 1, 8));
        assert_eq!(s.entries[0].value, "x.eds");
        assert_eq!(s.entries[0].value_span, Span::new(2, 10, 5));
        assert_eq!(s.entries[1].value, "");
        assert_eq!(s.entries[1].value_span, Span::new(3, 13, 0));
        assert_eq!(s.get("filename").map(|e| e.value.as_str()), Some("x.eds"));
    }

    #[test]
    fn spacing_and_indentation_are_reported() {
        let (file, diags) = lex("[A]\nKey = value\n  ; indented\n [ B ]\nSupported Objects=1\n");
        assert_eq!(file.sections[0].entries[0].value, "value");
        assert_eq!(file.sections[0].entries[0].value_span, Span::new(2, 7, 5));
        assert_eq!(file.sections[1].name, "B");
        assert_eq!(
            diags,
            vec![
                ("EDS007", Severity::Warning, 2),
                ("EDS004", Severity::Warning, 3),
                ("EDS007", Severity::Warning, 4),
                ("EDS007", Severity::Warning, 5),
            ]
        );
    }

    #[test]
    fn junk_lines_are_errors() {
        let (file, diags) = lex("x=1\n[A]\njunk\n[B\n=3\n[C] tail\n");
        assert_eq!(file.sections.len(), 2);
        assert_eq!(
            diags,
            vec![
                ("EDS001", Severity::Error, 1),
                ("EDS001", Severity::Error, 3),
                ("EDS001", Severity::Error, 4),
                ("EDS001", Severity::Error, 5),
                ("EDS001", Severity::Error, 6),
            ]
        );
    }

    #[test]
    fn duplicates_merge_and_last_wins() {
        let (file, diags) = lex("[A]\nk=1\nK=2\n[b]\n[a]\nk=3\nz=4\n");
        assert_eq!(
            diags,
            vec![
                ("EDS006", Severity::Error, 3),
                ("EDS005", Severity::Error, 5)
            ]
        );
        assert_eq!(file.sections.len(), 2);
        let a = &file.sections[0];
        assert_eq!(a.entries.len(), 2);
        assert_eq!(
            a.get("k").map(|e| (e.value.as_str(), e.key_span.line)),
            Some(("3", 6))
        );
        assert_eq!(a.get("z").map(|e| e.value.as_str()), Some("4"));
    }

    #[test]
    fn duplicates_in_long_sections_merge_and_last_wins() {
        // Past INDEXED_FROM entries, keys are found through the index instead of a scan.
        let mut text = String::from("[A]\n");
        for n in 0..20 {
            text.push_str(&format!("k{n}={n}\n"));
        }
        text.push_str("K3=x\nk19=y\n[b]\n[a]\nk5=z\nk20=w\n");
        let (file, diags) = lex(&text);
        assert_eq!(
            diags,
            vec![
                ("EDS006", Severity::Error, 22),
                ("EDS006", Severity::Error, 23),
                ("EDS005", Severity::Error, 25)
            ]
        );
        let a = &file.sections[0];
        assert_eq!(a.entries.len(), 21);
        let value = |key: &str| a.get(key).map(|e| (e.value.as_str(), e.key_span.line));
        assert_eq!(value("k3"), Some(("x", 22)));
        assert_eq!(value("k19"), Some(("y", 23)));
        assert_eq!(value("k5"), Some(("z", 26)));
        assert_eq!(value("k20"), Some(("w", 27)));
        assert_eq!(value("k0"), Some(("0", 2)));
    }

    #[test]
    fn canopen_editor_comment_extensions_are_kept() {
        let (file, diags) = lex("[2000]\n;StorageLocation=RAM\n;Other=1\n;TPDODetectCos = 1\n");
        assert!(diags.is_empty());
        let kept: Vec<(&str, &str, Span)> = file.sections[0]
            .commented
            .iter()
            .map(|e| (e.key.as_str(), e.value.as_str(), e.value_span))
            .collect();
        assert_eq!(
            kept,
            vec![
                ("StorageLocation", "RAM", Span::new(2, 18, 3)),
                ("TPDODetectCos", "1", Span::new(4, 18, 1))
            ]
        );
        assert!(file.sections[0].entries.is_empty());
    }

    #[test]
    fn long_lines_warn() {
        let long = format!("[A]\nk={}\n", "x".repeat(254));
        let (_, diags) = lex(&long);
        assert_eq!(diags, vec![("EDS003", Severity::Warning, 2)]);
        let ok = format!("[A]\nk={}\n", "x".repeat(253));
        assert!(lex(&ok).1.is_empty());
    }

    #[test]
    fn columns_count_characters() {
        let (file, _) = lex("[A]\nName=é=ü\n");
        let e = &file.sections[0].entries[0];
        assert_eq!(e.value, "é=ü");
        assert_eq!(e.value_span, Span::new(2, 6, 3));
    }
}
