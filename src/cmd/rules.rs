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
                serde_json::json!({
                    "code": r.code,
                    "severity": r.severity.as_str(),
                    "summary": r.summary,
                    "why": r.why,
                })
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
                    "{:<6}  {:<7}  {}\n{:17}why: {}\n",
                    rule.code,
                    rule.severity.as_str(),
                    rule.summary,
                    "",
                    rule.why
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

/// What the rule checks, why it matters, which part of a description it judges, and what its
/// severity does.
fn explanation(rule: &Rule) -> String {
    let code = rule.code;
    let area = rule.area().unwrap_or("not numbered by area");
    let effect = match rule.severity {
        _ if code.starts_with("CHK") => {
            let command = if rule.summary.starts_with("(`edsgen ecat check`)") {
                "edsgen ecat check"
            } else {
                "edsgen check"
            };
            format!(
                "`{command}` reports it where the device differs from its description: an \
                 error fails the check (exit 1); a warning only under `--deny-warnings`. It says \
                 nothing about the description file itself (`edsgen validate` does)."
            )
        }
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
        "{code} ({severity}): {summary}\n\nWhy it matters: {why}\nArea: {area}.\n{effect}\n",
        severity = rule.severity.as_str(),
        summary = rule.summary,
        why = rule.why,
    )
}
