//! Diagnostics: what the readers and the validator say about a description file.
//!
//! A diagnostic has a stable rule code (see [`crate::rules`]), a severity, a one-line message, the
//! primary span in the file, an optional label for the underline and an optional `help:` line.
//! Rendering (rustc-style text and JSON) lives in [`crate::render`].

use crate::model::Span;
use crate::rules::Rule;
pub use crate::rules::Severity;

/// One finding about one file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// The rule that fired.
    pub rule: &'static Rule,
    /// The severity of this instance (usually `rule.severity`; rules with a secondary severity may
    /// use the other one).
    pub severity: Severity,
    /// A one-line message, specific to this instance.
    pub message: String,
    /// The primary span; `None` for findings about the file as a whole (no line to show).
    pub span: Option<Span>,
    /// The label printed under the underline.
    pub label: Option<String>,
    /// A `help:` line, where a fix is known.
    pub help: Option<String>,
}

impl Diagnostic {
    /// A diagnostic for `rule` at its default severity.
    pub fn new(rule: &'static Rule, span: Option<Span>, message: impl Into<String>) -> Self {
        Diagnostic {
            rule,
            severity: rule.severity,
            message: message.into(),
            span,
            label: None,
            help: None,
        }
    }

    /// Overrides the severity (for rules with a secondary severity).
    pub fn with_severity(mut self, severity: Severity) -> Self {
        self.severity = severity;
        self
    }

    /// Adds the label shown under the underlined span.
    pub fn with_label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }

    /// Adds a `help:` line.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// The rule code, e.g. `EDS301`.
    pub fn code(&self) -> &'static str {
        self.rule.code
    }
}

/// Sorts diagnostics into the order they are shown: by line, then column, then code.
pub fn sort(diags: &mut [Diagnostic]) {
    diags.sort_by(|a, b| {
        let key = |d: &Diagnostic| {
            (
                d.span.map_or(0, |s| s.line),
                d.span.map_or(0, |s| s.column),
                d.rule.code,
            )
        };
        key(a).cmp(&key(b))
    });
}

/// Folds repeated findings into the first one of their kind: diagnostics for which `kind` gives
/// the same key. The first keeps its span and gets `; {wording} N more line(s): a, b, ...` (the
/// first eight lines, then a count); the others are dropped. Diagnostics without a key stay.
pub fn fold<K: std::hash::Hash + Eq>(
    diags: &mut Vec<Diagnostic>,
    kind: impl Fn(&Diagnostic) -> Option<K>,
    wording: &str,
) {
    let mut first_of: std::collections::HashMap<K, usize> = std::collections::HashMap::new();
    let mut more: Vec<Vec<u32>> = vec![Vec::new(); diags.len()];
    let mut keep = vec![true; diags.len()];
    for (i, d) in diags.iter().enumerate() {
        let Some(key) = kind(d) else { continue };
        match first_of.get(&key) {
            Some(&first) => {
                more[first].push(d.span.map_or(0, |s| s.line));
                keep[i] = false;
            }
            None => {
                first_of.insert(key, i);
            }
        }
    }
    for (d, lines) in diags.iter_mut().zip(&more) {
        if lines.is_empty() {
            continue;
        }
        let shown: Vec<String> = lines.iter().take(8).map(u32::to_string).collect();
        let rest = if lines.len() > 8 {
            format!(" and {} more", lines.len() - 8)
        } else {
            String::new()
        };
        d.message = format!(
            "{}; {wording} {} more line(s): {}{rest}",
            d.message,
            lines.len(),
            shown.join(", ")
        );
    }
    let mut index = 0;
    diags.retain(|_| {
        index += 1;
        keep[index - 1]
    });
}

/// A short list of items for a message: the first few, then "and N more".
pub fn short_list(items: &[String]) -> String {
    const SHOWN: usize = 4;
    if items.len() <= SHOWN {
        items.join(", ")
    } else {
        format!(
            "{}, and {} more",
            items[..SHOWN].join(", "),
            items.len() - SHOWN
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_list_elides_after_four() {
        let items: Vec<String> = (1..=6).map(|i| i.to_string()).collect();
        assert_eq!(short_list(&items), "1, 2, 3, 4, and 2 more");
    }
}
