//! The ODVA EDS text: `[Section]` headers, `$` comments to the end of the line, and entries
//! `Key = field, field, ...;` that run over as many lines as they need until the `;`, with quoted
//! strings (commas and `$` inside are text; adjacent strings join) and empty fields.
//!
//! The CiA 306 reader (`read::ini`) is line-based (`key=value` on one line, `;` comments), so it
//! cannot serve: here an entry ends at its `;`, not at the line end. Every entry and field keeps
//! its span. Lexical problems are CIP001 diagnostics; nothing is dropped without one.

use crate::diag::Diagnostic;
use crate::model::{CipEntry, CipSection, Field, Span};
use crate::rules;

/// A position in the text: 1-based line and column (in characters).
#[derive(Debug, Clone, Copy)]
struct Pos {
    line: u32,
    column: u32,
}

/// Splits the text into sections of entries. Entries before the first section go into a section
/// with an empty name.
pub fn lex(text: &str, diags: &mut Vec<Diagnostic>) -> Vec<CipSection> {
    let lines: Vec<Vec<char>> = text
        .split('\n')
        .map(|l| l.strip_suffix('\r').unwrap_or(l).chars().collect())
        .collect();
    let mut lexer = Lexer {
        lines,
        line: 0,
        col: 0,
        sections: Vec::new(),
        diags,
    };
    lexer.run();
    lexer.sections
}

struct Lexer<'d> {
    lines: Vec<Vec<char>>,
    /// 0-based line and column of the next character.
    line: usize,
    col: usize,
    sections: Vec<CipSection>,
    diags: &'d mut Vec<Diagnostic>,
}

fn to_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

impl Lexer<'_> {
    fn pos(&self) -> Pos {
        Pos {
            line: to_u32(self.line + 1),
            column: to_u32(self.col + 1),
        }
    }

    fn peek(&self) -> Option<char> {
        self.lines.get(self.line)?.get(self.col).copied()
    }

    /// The rest of the current line.
    fn rest(&self) -> &[char] {
        self.lines
            .get(self.line)
            .map_or(&[], |l| l.get(self.col..).unwrap_or(&[]))
    }

    fn next_line(&mut self) {
        self.line += 1;
        self.col = 0;
    }

    fn eof(&self) -> bool {
        self.line >= self.lines.len()
    }

    fn skip_blank(&mut self) {
        while let Some(c) = self.peek() {
            if !c.is_whitespace() {
                break;
            }
            self.col += 1;
        }
    }

    fn error(&mut self, span: Span, message: String, help: &str) {
        self.diags.push(
            Diagnostic::new(&rules::CIP_SYNTAX, Some(span), message).with_help(help.to_owned()),
        );
    }

    fn run(&mut self) {
        while !self.eof() {
            self.skip_blank();
            match self.peek() {
                None => self.next_line(),
                Some('$') => self.next_line(),
                Some('[') => self.section(),
                Some(_) => self.entry_or_junk(),
            }
        }
    }

    fn section(&mut self) {
        let start = self.pos();
        let rest: String = self.rest().iter().collect();
        let Some(close) = rest.find(']') else {
            let len = to_u32(rest.trim_end().chars().count());
            self.error(
                Span::new(start.line, start.column, len),
                "a section header without `]`".to_owned(),
                "write the header as `[Section Name]`",
            );
            self.next_line();
            return;
        };
        let name = rest[1..close].trim().to_owned();
        let len = to_u32(rest[..=close].chars().count());
        self.sections.push(CipSection {
            name,
            span: Span::new(start.line, start.column, len),
            entries: Vec::new(),
        });
        self.col += rest[..=close].chars().count();
        self.skip_blank();
        if !matches!(self.peek(), None | Some('$')) {
            let at = self.pos();
            self.error(
                Span::new(at.line, at.column, to_u32(self.rest().len())),
                "text after a section header".to_owned(),
                "put entries on lines of their own, comments after `$`",
            );
        }
        self.next_line();
    }

    /// The key of an entry starting at the current position: its text and length in characters
    /// up to the `=`, if the line has the form `Key =`.
    fn key_here(&self) -> Option<(String, usize)> {
        let rest = self.rest();
        let eq = rest.iter().position(|&c| c == '=')?;
        let key: String = rest[..eq].iter().collect();
        let key = key.trim_end();
        let ok = !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | ' ' | '.' | '-'));
        ok.then(|| (key.to_owned(), eq))
    }

    fn entry_or_junk(&mut self) {
        let start = self.pos();
        let Some((key, eq)) = self.key_here() else {
            let len = to_u32(self.rest().len());
            self.error(
                Span::new(start.line, start.column, len),
                "a line that is neither a `[section]`, an entry `Key = ...;` nor a `$` comment"
                    .to_owned(),
                "entries are `Key = value;`; comments start with `$`",
            );
            self.next_line();
            return;
        };
        self.col += eq + 1;
        let key_span = Span::new(start.line, start.column, to_u32(key.chars().count()));
        let fields = self.fields(&key, key_span);
        let entry = CipEntry {
            key,
            span: key_span,
            fields,
        };
        match self.sections.last_mut() {
            Some(section) => section.entries.push(entry),
            None => self.sections.push(CipSection {
                name: String::new(),
                span: key_span,
                entries: vec![entry],
            }),
        }
    }

    /// The fields of an entry, up to and past its `;`.
    fn fields(&mut self, key: &str, key_span: Span) -> Vec<Field> {
        let mut fields = Vec::new();
        let mut field = FieldBuilder::default();
        let mut at_line_start = false;
        loop {
            if self.eof() {
                self.missing_semicolon(key, key_span, "the end of the file");
                fields.push(field.finish());
                return fields;
            }
            if at_line_start {
                self.skip_blank();
                let starts_section = self.peek() == Some('[') && self.rest().contains(&']');
                if starts_section || self.key_here().is_some() {
                    let what = if starts_section {
                        "the next section"
                    } else {
                        "the next entry"
                    };
                    self.missing_semicolon(key, key_span, what);
                    fields.push(field.finish());
                    return fields;
                }
                at_line_start = false;
            }
            let Some(c) = self.peek() else {
                self.next_line();
                at_line_start = true;
                continue;
            };
            match c {
                '$' => {
                    self.next_line();
                    at_line_start = true;
                }
                ',' => {
                    fields.push(std::mem::take(&mut field).finish());
                    self.col += 1;
                }
                ';' => {
                    fields.push(field.finish());
                    self.col += 1;
                    self.after_entry();
                    return fields;
                }
                '"' => self.string(&mut field),
                c if c.is_whitespace() => {
                    field.space();
                    self.col += 1;
                }
                c => {
                    let pos = self.pos();
                    field.push(c, pos);
                    self.col += 1;
                }
            }
        }
    }

    fn missing_semicolon(&mut self, key: &str, key_span: Span, before: &str) {
        self.error(
            key_span,
            format!("the entry `{key}` has no `;` before {before}"),
            "end every entry with `;`",
        );
    }

    /// After an entry's `;`: only a comment may follow on the line.
    fn after_entry(&mut self) {
        self.skip_blank();
        match self.peek() {
            None | Some('$') => self.next_line(),
            Some(_) => {}
        }
    }

    fn string(&mut self, field: &mut FieldBuilder) {
        let start = self.pos();
        self.col += 1;
        field.open_quote(start);
        loop {
            match self.peek() {
                None => {
                    self.error(
                        Span::new(
                            start.line,
                            start.column,
                            to_u32(self.col) - start.column + 1,
                        ),
                        "a string without its closing `\"` on the line".to_owned(),
                        "close the string on the line it starts; join long strings as \"a\" \"b\"",
                    );
                    return;
                }
                Some('"') => {
                    let end = self.pos();
                    self.col += 1;
                    field.mark(end);
                    return;
                }
                Some('\\') => {
                    self.col += 1;
                    if let Some(c) = self.peek() {
                        field.text.push(c);
                        self.col += 1;
                    }
                }
                Some(c) => {
                    field.text.push(c);
                    self.col += 1;
                }
            }
        }
    }
}

/// A field while it is read.
#[derive(Default)]
struct FieldBuilder {
    text: String,
    quoted: bool,
    /// Whitespace seen after text, written out only if more text follows.
    pending_space: bool,
    start: Option<Pos>,
    /// The column after the last character on the field's first line.
    end_col: usize,
}

impl FieldBuilder {
    fn mark(&mut self, pos: Pos) {
        if self.start.is_none() {
            self.start = Some(pos);
        }
        if self.start.is_some_and(|s| s.line == pos.line) {
            self.end_col = pos.column as usize;
        }
    }

    fn space(&mut self) {
        if !self.text.is_empty() && !self.quoted {
            self.pending_space = true;
        }
    }

    fn push(&mut self, c: char, pos: Pos) {
        if self.pending_space {
            self.text.push(' ');
            self.pending_space = false;
        }
        self.text.push(c);
        self.mark(pos);
    }

    fn open_quote(&mut self, pos: Pos) {
        self.pending_space = false;
        self.quoted = true;
        self.mark(pos);
    }

    fn finish(self) -> Field {
        let span = match self.start {
            Some(s) => Span::new(
                s.line,
                s.column,
                to_u32((self.end_col + 1).saturating_sub(s.column as usize)),
            ),
            None => Span::default(),
        };
        Field {
            text: self.text,
            quoted: self.quoted,
            span,
        }
    }
}
