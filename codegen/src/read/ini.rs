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

use crate::diag::Diagnostic;
use crate::model::Span;
use crate::rules;

/// The longest line CiA 306 allows, in characters.
pub const MAX_LINE_CHARS: usize = 255;

/// One `key=value` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IniEntry {
    /// The key as written (trimmed).
    pub key: String,
    /// Where the key is.
    pub key_span: Span,
    /// The value, trimmed (possibly empty).
    pub value: String,
    /// Where the value is (length 0 and just after `=` when empty).
    pub value_span: Span,
}

impl IniEntry {
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
pub struct IniSection {
    /// The name between the brackets, as first written (trimmed).
    pub name: String,
    /// Where the section header is (the whole `[name]`).
    pub span: Span,
    /// The entries, in file order; a key appears at most once (case-insensitively).
    pub entries: Vec<IniEntry>,
    /// The CANopenEditor comment extensions (`;StorageLocation=RAM`, `;TPDODetectCos=1`) found in
    /// the section, without the `;`. They are comments to CiA 306, and read back by CANopenEditor.
    pub commented: Vec<IniEntry>,
}

impl IniSection {
    /// The entry for `key`, compared case-insensitively.
    pub fn get(&self, key: &str) -> Option<&IniEntry> {
        self.entries
            .iter()
            .find(|e| e.key.eq_ignore_ascii_case(key))
    }
}

/// A lexed file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct IniFile {
    /// The sections in order of first appearance.
    pub sections: Vec<IniSection>,
}

/// The keys CANopenEditor writes as comments (`;StorageLocation=RAM`) and reads back.
pub const COMMENTED_KEYS: &[&str] = &["StorageLocation", "TPDODetectCos"];

/// Splits text into lines, accepting LF, CR LF and lone CR, and a last line without a newline.
pub fn lines(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut start = 0;
    let mut i = 0;
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

fn char_len(s: &str) -> u32 {
    u32::try_from(s.chars().count()).unwrap_or(u32::MAX)
}

/// The 1-based character column of byte offset `at` in `line`.
fn column_of(line: &str, at: usize) -> u32 {
    char_len(line.get(..at).unwrap_or(line)).saturating_add(1)
}

/// Whether a key is written only with `[A-Za-z0-9_]`.
pub fn is_plain_key(key: &str) -> bool {
    !key.is_empty() && key.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

/// A `;Key=value` comment line whose key is one of [`COMMENTED_KEYS`], as an entry.
fn commented_entry(line: &str, line_no: u32) -> Option<IniEntry> {
    let body = line.strip_prefix(';')?;
    let eq = body.find('=')?;
    let key = body[..eq].trim();
    if !COMMENTED_KEYS.iter().any(|k| k.eq_ignore_ascii_case(key)) {
        return None;
    }
    let value_raw = &body[eq + 1..];
    let value = value_raw.trim();
    let value_at = 1 + eq + 1 + (value_raw.len() - value_raw.trim_start().len());
    Some(IniEntry {
        key: key.to_owned(),
        key_span: Span::new(line_no, 2, char_len(key)),
        value: value.to_owned(),
        value_span: Span::new(line_no, column_of(line, value_at), char_len(value)),
    })
}

/// Lexes the text into sections, reporting EDS001, EDS003, EDS004, EDS005, EDS006 and EDS007.
pub fn parse(text: &str, diags: &mut Vec<Diagnostic>) -> IniFile {
    let mut file = IniFile::default();
    // Index into `file.sections` of the section that receives entries, and the lowercase keys
    // seen in the current occurrence of it.
    let mut current: Option<usize> = None;
    let mut keys_here: Vec<String> = Vec::new();
    // Lowercase section name -> position in `file.sections`.
    let mut section_at: HashMap<String, usize> = HashMap::new();
    for (number, line) in lines(text).into_iter().enumerate() {
        let line_no = u32::try_from(number + 1).unwrap_or(u32::MAX);
        let chars = line.chars().count();
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
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        let indent = line.len() - line.trim_start().len();
        let first_col = column_of(line, indent);
        if trimmed.starts_with(';') {
            if indent > 0 {
                diags.push(Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(Span::new(line_no, first_col, char_len(trimmed))),
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
            let Some(close) = trimmed.find(']') else {
                diags.push(
                    Diagnostic::new(
                        &rules::UNPARSEABLE_LINE,
                        Some(Span::new(line_no, first_col, char_len(trimmed))),
                        "section header without a closing `]`",
                    )
                    .with_label("the line is ignored"),
                );
                continue;
            };
            let inner = &trimmed[1..close];
            let name = inner.trim();
            let header_span = Span::new(line_no, first_col, char_len(&trimmed[..=close]));
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
            let rest = trimmed[close + 1..].trim();
            if rest.starts_with(';') {
                diags.push(Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(header_span),
                    "comment after a section header",
                ));
            } else if !rest.is_empty() {
                diags.push(Diagnostic::new(
                    &rules::UNPARSEABLE_LINE,
                    Some(Span::new(line_no, first_col, char_len(trimmed))),
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
            if let Some(&existing) = section_at.get(&name.to_ascii_lowercase()) {
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
                section_at.insert(name.to_ascii_lowercase(), file.sections.len());
                current = Some(file.sections.len());
                file.sections.push(IniSection {
                    name: name.to_owned(),
                    span: header_span,
                    entries: Vec::new(),
                    commented: Vec::new(),
                });
            }
            continue;
        }
        let Some(eq) = line.find('=') else {
            diags.push(
                Diagnostic::new(
                    &rules::UNPARSEABLE_LINE,
                    Some(Span::new(line_no, first_col, char_len(trimmed))),
                    "line is not a comment, a [section] or key=value",
                )
                .with_label("the line is ignored")
                .with_help("start the line with `;` if it is a comment, or remove it"),
            );
            continue;
        };
        let key_raw = &line[..eq];
        let key = key_raw.trim();
        let key_span = Span::new(line_no, first_col, char_len(key));
        let value_raw = &line[eq + 1..];
        let value = value_raw.trim();
        let value_at = eq + 1 + (value_raw.len() - value_raw.trim_start().len());
        let value_span = Span::new(line_no, column_of(line, value_at), char_len(value));
        if key.is_empty() {
            diags.push(Diagnostic::new(
                &rules::UNPARSEABLE_LINE,
                Some(Span::new(line_no, first_col, char_len(trimmed))),
                "entry without a key name is ignored",
            ));
            continue;
        }
        let Some(section) = current.and_then(|i| file.sections.get_mut(i)) else {
            diags.push(Diagnostic::new(
                &rules::UNPARSEABLE_LINE,
                Some(Span::new(line_no, first_col, char_len(trimmed))),
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
        let lower = key.to_ascii_lowercase();
        let entry = IniEntry {
            key: key.to_owned(),
            key_span,
            value: value.to_owned(),
            value_span,
        };
        if keys_here.contains(&lower) {
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
            keys_here.push(lower);
        }
        if let Some(existing) = section
            .entries
            .iter_mut()
            .find(|e| e.key.eq_ignore_ascii_case(key))
        {
            *existing = entry;
        } else {
            section.entries.push(entry);
        }
    }
    file
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Severity;

    fn lex(text: &str) -> (IniFile, Vec<(&'static str, Severity, u32)>) {
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
