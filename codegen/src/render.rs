//! Rendering diagnostics: rustc-style text, and JSON. Placeholder until rendering lands.

use crate::diag::Diagnostic;

/// Renders diagnostics for one file as rustc-style text.
pub fn human(path: &str, _text: &str, diags: &[Diagnostic], _color: bool) -> String {
    let mut out = String::new();
    for d in diags {
        let line = d.span.map_or(0, |s| s.line);
        out.push_str(&format!(
            "{}[{}]: {}\n  --> {path}:{line}\n",
            d.severity.as_str(),
            d.code(),
            d.message
        ));
    }
    out
}

/// Renders diagnostics as JSON objects `{"file","line","column","severity","code","message"}`.
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
            })
        })
        .collect()
}
