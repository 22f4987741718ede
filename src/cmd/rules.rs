//! `edsgen rules` (the catalogue) and `edsgen explain CODE` (one rule, and how to act on it).

use std::process::ExitCode;

use edsgen_model::diag::Severity;
use edsgen_model::rules::{self, Rule};

use super::{fail, print_stdout};

/// Runs `edsgen rules [--format json]`.
pub fn list(json: bool) -> ExitCode {
    if json {
        let list: Vec<_> = rules::ALL
            .iter()
            .map(|r| {
                serde_json::json!({"code": r.code, "severity": r.severity.as_str(), "summary": r.summary})
            })
            .collect();
        print_stdout(&format!(
            "{}\n",
            serde_json::to_string_pretty(&list).unwrap_or_else(|_| "[]".into())
        ));
    } else {
        let table: String = rules::ALL
            .iter()
            .map(|rule| {
                format!(
                    "{}  {:<7}  {}\n",
                    rule.code,
                    rule.severity.as_str(),
                    rule.summary
                )
            })
            .collect();
        print_stdout(&table);
    }
    ExitCode::SUCCESS
}

/// Runs `edsgen explain CODE`.
pub fn explain(code: &str) -> ExitCode {
    match super::rule_named("explain", code) {
        Ok(rule) => {
            print_stdout(&explanation(rule));
            ExitCode::SUCCESS
        }
        Err(message) => fail(message),
    }
}

/// What the rule checks, which part of edsgen reports it, and what its severity does.
fn explanation(rule: &Rule) -> String {
    let code = rule.code;
    let area = match code.as_bytes().get(3) {
        _ if code.starts_with("CHK") => "a live device against its description (`edsgen check`)",
        Some(b'0') => "the text and its values (reported while reading)",
        Some(b'1') => "[FileInfo] and [DeviceInfo]",
        Some(b'2') => "the object lists",
        Some(b'3') => "objects and sub-objects",
        Some(b'4') => "PDOs",
        Some(b'5') => "DCF, commissioning, modules, comments, object links, dynamic channels",
        Some(b'6') => "XML descriptions (XDD, XDC)",
        _ => "code generation (reported by `edsgen generate` and build.rs)",
    };
    let effect = match rule.severity {
        _ if code.starts_with("CHK") => "`edsgen check` reports it where the device differs \
             from its description: an error fails the check (exit 1); a warning only under \
             `--deny-warnings`. It says nothing about the description file itself (`edsgen \
             validate` does)."
            .to_string(),
        Severity::Error => format!(
            "An error fails `edsgen validate` (exit 1) and the build: the file breaks the standard \
             or code generated from it would be wrong. `--allow {code}` and \
             `Builder::allow(\"{code}\")` do not silence errors."
        ),
        Severity::Warning => format!(
            "A warning fails `edsgen validate` only under `--deny warnings` or `--deny {code}`. \
             `--allow {code}` (in build.rs `Builder::allow(\"{code}\")`) silences it where the \
             description cannot avoid it without lying about the device."
        ),
        Severity::Info => format!(
            "An info never fails anything; `--quiet` hides it, `--allow {code}` silences it, \
             `--deny {code}` makes it an error."
        ),
    };
    format!(
        "{code} ({severity}): {summary}\n\nArea: {area}.\n{effect}\n",
        severity = rule.severity.as_str(),
        summary = rule.summary,
    )
}
