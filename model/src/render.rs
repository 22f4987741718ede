//! Rendering diagnostics: rustc-style text (with `annotate-snippets`) and JSON.
//!
//! Text: `error[EDS301]: message`, ` --> file:line:col`, the source line with the span underlined
//! and the label, then `= help: ...`. Colours only when asked. A diagnostic without a span (about
//! the file as a whole) shows ` --> file` and no snippet. JSON: one object per diagnostic,
//! `{"file","line","column","severity","code","message","help"}` (line and column 0, help null
//! when there is none). Control characters from the file (an escape sequence in a value) are
//! shown as U+FFFD in text, so nothing a file holds can drive the terminal.

use annotate_snippets::{Level, Renderer, Snippet};

use crate::diag::{Diagnostic, Severity};
use crate::model::Span;

fn level(severity: Severity) -> Level {
    match severity {
        Severity::Error => Level::Error,
        Severity::Warning => Level::Warning,
        Severity::Info => Level::Info,
    }
}

/// The byte range in `line` of a span's characters; the whole trimmed line when the span has no
/// length or does not fit the line.
fn byte_range(line: &str, span: Span) -> std::ops::Range<usize> {
    let start_char = span.column.saturating_sub(1) as usize;
    let offsets: Vec<usize> = line
        .char_indices()
        .map(|(i, _)| i)
        .chain([line.len()])
        .collect();
    let chars = offsets.len() - 1;
    if span.len > 0 && start_char < chars {
        let end_char = (start_char + span.len as usize).min(chars);
        return offsets[start_char]..offsets[end_char];
    }
    if span.len == 0 && start_char > 0 && start_char == chars {
        // Just past the end of the line (an empty value after `=`): point there.
        return line.len()..line.len();
    }
    let trimmed_start = line.len() - line.trim_start().len();
    let trimmed_end = line.trim_end().len();
    if trimmed_start < trimmed_end {
        trimmed_start..trimmed_end
    } else {
        0..line.len()
    }
}

/// The text with every control character but the tab replaced by U+FFFD (one character for one,
/// so columns stay right).
fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if text.chars().any(|c| c.is_control() && c != '\t') {
        text.chars()
            .map(|c| {
                if c.is_control() && c != '\t' {
                    '\u{FFFD}'
                } else {
                    c
                }
            })
            .collect::<String>()
            .into()
    } else {
        text.into()
    }
}

/// Renders one diagnostic.
fn render_one(renderer: &Renderer, path: &str, lines: &[&str], d: &Diagnostic) -> String {
    let path = printable(path);
    let path = path.as_ref();
    let message = printable(&d.message);
    let title = level(d.severity).title(&message).id(d.code());
    let help_text = d.help.as_deref().map(printable);
    let help = help_text.as_deref().map(|h| Level::Help.title(h));
    let label = d.label.as_deref().map(printable);
    let source_line = d
        .span
        .and_then(|s| s.line.checked_sub(1))
        .and_then(|i| lines.get(i as usize));
    match (d.span, source_line) {
        // A blank line has nothing to underline (and annotate-snippets would misplace it).
        (Some(span), Some(line)) if !line.trim().is_empty() => {
            // Replacing a control character changes byte offsets: measure the printable line.
            let line = printable(line);
            let range = byte_range(&line, span);
            // annotate-snippets shows a tab as four spaces but neither moves the underline nor
            // counts the column with it: show each tab as one space, so the underline sits under
            // the span and the column stays the character column the readers report.
            let line = line.replace('\t', " ");
            let line = line.as_str();
            let mut annotation = level(d.severity).span(range);
            if let Some(label) = label.as_deref() {
                annotation = annotation.label(label);
            }
            let snippet = Snippet::source(line)
                .line_start(span.line as usize)
                .origin(path)
                .annotation(annotation);
            let mut message = title.snippet(snippet);
            if let Some(help) = help {
                message = message.footer(help);
            }
            format!("{}\n", renderer.render(message))
        }
        (span, _) => {
            let mut message = title;
            if let Some(help) = help {
                message = message.footer(help);
            }
            let rendered = renderer.render(message).to_string();
            let place = match span {
                Some(s) => format!("{path}:{}:{}", s.line, s.column),
                None => path.to_owned(),
            };
            // Title first, then where, then the footer (if any).
            let mut out = String::new();
            let mut parts = rendered.splitn(2, '\n');
            out.push_str(parts.next().unwrap_or_default());
            out.push_str(&format!("\n --> {place}\n"));
            if let Some(rest) = parts.next() {
                out.push_str(rest);
                out.push('\n');
            }
            out
        }
    }
}

/// The lines of a text as the readers count them: LF, CR LF and a lone CR each end a line.
fn split_lines(text: &str) -> Vec<&str> {
    let mut lines = Vec::new();
    let mut start = 0;
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => {
                lines.push(&text[start..i]);
                start = i + 1;
            }
            b'\r' => {
                lines.push(&text[start..i]);
                if bytes.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                start = i + 1;
            }
            _ => {}
        }
        i += 1;
    }
    if start < text.len() {
        lines.push(&text[start..]);
    }
    lines
}

/// Renders diagnostics for one file as rustc-style text, one blank line between diagnostics.
pub fn human(path: &str, text: &str, diags: &[Diagnostic], color: bool) -> String {
    let renderer = if color {
        Renderer::styled()
    } else {
        Renderer::plain()
    };
    let lines = split_lines(text);
    let mut out = String::new();
    for d in diags {
        out.push_str(&render_one(&renderer, path, &lines, d));
        out.push('\n');
    }
    out
}

/// Renders diagnostics as JSON objects
/// `{"file","line","column","severity","code","message","help"}`.
pub fn json(path: &str, diags: &[Diagnostic]) -> Vec<serde_json::Value> {
    diags
        .iter()
        .map(|d| {
            serde_json::json!({
                "file": path,
                "line": d.span.map_or(0, |s| s.line),
                "column": d.span.map_or(0, |s| s.column),
                "severity": d.severity.as_str(),
                "code": d.code(),
                "message": d.message,
                "help": d.help,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules;

    const TEXT: &str = "[FileInfo]\nFileName=x.eds\n[2000]\nParameterName=Speed\nDataType=0x0099\n";

    #[test]
    fn renders_rustc_style_with_span_label_and_help() {
        let d = Diagnostic::new(
            &rules::UNKNOWN_DATA_TYPE,
            Some(Span::new(5, 10, 6)),
            "2000h has DataType 0099h",
        )
        .with_label("unknown data type")
        .with_help("use a basic type");
        let text = human("dev.eds", TEXT, &[d], false);
        assert_eq!(
            text,
            "error[EDS314]: 2000h has DataType 0099h\n \
             --> dev.eds:5:10\n  \
             |\n\
             5 | DataType=0x0099\n  \
             |          ^^^^^^ unknown data type\n  \
             |\n  \
             = help: use a basic type\n\n"
        );
    }

    #[test]
    fn zero_length_span_underlines_the_line_and_info_level_is_named() {
        let d = Diagnostic::new(&rules::SUB_INDEX_GAPS, Some(Span::new(3, 1, 0)), "gaps");
        let text = human("dev.eds", TEXT, &[d], false);
        assert_eq!(
            text,
            "info[EDS313]: gaps\n --> dev.eds:3:1\n  |\n3 | [2000]\n  | ------\n  |\n\n"
        );
    }

    #[test]
    fn spanless_diagnostic_has_no_snippet() {
        let d = Diagnostic::new(
            &rules::MANDATORY_LIST_MISSING,
            None,
            "[MandatoryObjects] is missing",
        )
        .with_help("add it");
        let text = human("dev.eds", TEXT, &[d], false);
        assert_eq!(
            text,
            "error[EDS201]: [MandatoryObjects] is missing\n --> dev.eds\n = help: add it\n\n"
        );
    }

    #[test]
    fn span_beyond_the_text_does_not_panic() {
        let d = Diagnostic::new(&rules::MISSING_NAME, Some(Span::new(99, 200, 5)), "x");
        let text = human("dev.eds", TEXT, &[d], false);
        assert_eq!(text, "error[EDS301]: x\n --> dev.eds:99:200\n\n");
    }

    #[test]
    fn tabs_keep_the_underline_and_the_column() {
        let text = "[2000]\r\n\tDefaultValue=\t300\r\n";
        let d = Diagnostic::new(&rules::OUT_OF_RANGE, Some(Span::new(2, 16, 3)), "too big")
            .with_label("out of range");
        assert_eq!(
            human("dev.eds", text, &[d], false),
            "error[EDS013]: too big\n --> dev.eds:2:16\n  |\n\
             2 |  DefaultValue= 300\n  |                ^^^ out of range\n  |\n\n"
        );
    }

    #[test]
    fn non_ascii_crlf_long_lines_and_the_last_line() {
        // Windows-1252 text arrives decoded; columns count characters, not bytes.
        let long = "x".repeat(300);
        let text = format!("[2000]\r\nParameterName={long}\r\nHighLimit=\u{e9}\u{e9}\u{e9}");
        let non_ascii = Diagnostic::new(&rules::BAD_VALUE, Some(Span::new(3, 11, 3)), "bad");
        let rendered = human("dev.eds", &text, &[non_ascii], false);
        assert_eq!(
            rendered,
            "error[EDS012]: bad\n --> dev.eds:3:11\n  |\n\
             3 | HighLimit=\u{e9}\u{e9}\u{e9}\n  |           ^^^\n  |\n\n"
        );
        let at_long = Diagnostic::new(&rules::LONG_LINE, Some(Span::new(2, 1, 0)), "long");
        let rendered = human("dev.eds", &text, &[at_long], false);
        assert_eq!(
            rendered,
            format!(
                "warning[EDS003]: long\n --> dev.eds:2:1\n  |\n2 | ParameterName={long}\n  | {}\n  |\n\n",
                "-".repeat(314)
            )
        );
    }

    #[test]
    fn empty_values_and_blank_lines_keep_their_place() {
        let after_equals = Diagnostic::new(&rules::BAD_VALUE, Some(Span::new(2, 14, 0)), "empty");
        assert_eq!(
            human("dev.eds", "[2000]\r\nDefaultValue=", &[after_equals], false),
            "error[EDS012]: empty\n --> dev.eds:2:14\n  |\n2 | DefaultValue=\n  |              ^\n  |\n\n"
        );
        let blank = Diagnostic::new(&rules::MISSING_NAME, Some(Span::new(2, 1, 0)), "blank");
        assert_eq!(
            human("dev.eds", "[2000]\n\t\n", &[blank], false),
            "error[EDS301]: blank\n --> dev.eds:2:1\n\n"
        );
    }

    #[test]
    fn control_characters_from_the_file_never_reach_the_terminal() {
        let text = "[2000]\nParameterName=\u{1b}[2J\u{7}Speed\n";
        let d = Diagnostic::new(
            &rules::LONG_NAME,
            Some(Span::new(2, 15, 10)),
            "name `\u{1b}[2J\u{7}Speed` is odd",
        )
        .with_label("\u{1b}]0;title\u{7}")
        .with_help("\u{9b}31m");
        assert_eq!(
            human("dev\u{1b}.eds", text, &[d], false),
            "warning[EDS302]: name `\u{fffd}[2J\u{fffd}Speed` is odd\n \
             --> dev\u{fffd}.eds:2:15\n  |\n\
             2 | ParameterName=\u{fffd}[2J\u{fffd}Speed\n  \
             |               ---------- \u{fffd}]0;title\u{fffd}\n  |\n  \
             = help: \u{fffd}31m\n\n"
        );
    }

    #[test]
    fn lines_end_at_lf_crlf_and_lone_cr() {
        assert_eq!(split_lines("a\nb\r\nc\rd"), vec!["a", "b", "c", "d"]);
        assert_eq!(split_lines("a\n"), vec!["a"]);
        assert_eq!(split_lines(""), Vec::<&str>::new());
    }

    #[test]
    fn json_has_the_contract_keys() {
        let d = Diagnostic::new(
            &rules::MISSING_NAME,
            Some(Span::new(3, 1, 6)),
            "2000h has no ParameterName",
        );
        let v = json("dev.eds", &[d]);
        assert_eq!(
            v[0],
            serde_json::json!({"file":"dev.eds","line":3,"column":1,"severity":"error","code":"EDS301","message":"2000h has no ParameterName","help":null})
        );
    }
}
