//! `edsgen validate`: reads and judges each file, applies the command line's policy (`--allow`,
//! `--deny`, `--min-severity`/`--quiet`) and prints the diagnostics (rustc-style text or JSON) and
//! a summary that says what the policy did, so the exit code matches what is printed.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use edsgen_model::diag::{self, Diagnostic, Severity};
use edsgen_model::lint::{self, Verdict};
use edsgen_model::load::{self, LoadError};
use edsgen_model::{read, render, rules};

use super::{fail, parallel, rule_named, EXIT_USAGE};

/// What the command line asks of the diagnostics: the lint levels, and what to show.
pub struct Policy {
    /// `--allow` and `--deny` (codes or `warnings`).
    pub lint: lint::Policy,
    /// Diagnostics below this severity are counted but not shown.
    pub min_severity: Severity,
}

impl Policy {
    /// The policy from the raw `--allow` and `--deny` arguments (`--deny warnings` or a code).
    pub fn new(allow: &[String], deny: &[String], min_severity: Severity) -> Result<Self, String> {
        let mut lint = lint::Policy::new();
        for code in allow {
            lint.allow(rule_named("--allow", code)?);
        }
        for code in deny {
            if code.eq_ignore_ascii_case("warnings") {
                lint.deny_warnings();
                continue;
            }
            lint.deny(rule_named("--deny", code)?)?;
        }
        Ok(Policy { lint, min_severity })
    }
}

/// What was found over all files, for the summary line and the exit code.
#[derive(Default)]
struct Tally {
    checked: usize,
    unreadable: usize,
    errors: usize,
    denied: usize,
    warnings: usize,
    hidden: usize,
    allowed: usize,
}

impl Tally {
    fn add(&mut self, other: &Tally) {
        self.checked += other.checked;
        self.unreadable += other.unreadable;
        self.errors += other.errors;
        self.denied += other.denied;
        self.warnings += other.warnings;
        self.hidden += other.hidden;
        self.allowed += other.allowed;
    }
}

/// What one file gives: its counts and what to print for it (the JSON array's items, rendered,
/// or rustc-style text, and text for standard error).
#[derive(Default)]
struct Checked {
    tally: Tally,
    json: Vec<String>,
    text: String,
    error_text: String,
}

/// Runs `edsgen validate`.
pub fn run(json: bool, policy: &Policy, files: &[PathBuf], device: Option<&str>) -> ExitCode {
    let color = std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    let mut tally = Tally::default();
    let mut all_json: Vec<String> = Vec::new();
    let mut out = std::io::stdout().lock();
    // Files are read and judged on every core, the biggest first, and printed in the order given.
    let size = |path: &PathBuf| std::fs::metadata(path).map_or(0, |m| m.len());
    let checked =
        parallel::map_in_order(files, size, |path| check(path, device, policy, json, color));
    for file in checked {
        tally.add(&file.tally);
        all_json.extend(file.json);
        eprint!("{}", file.error_text);
        let _ = out.write_all(file.text.as_bytes());
    }
    if json {
        // What `serde_json::to_string_pretty` prints for the array of all items, written at once.
        let text = if all_json.is_empty() {
            "[]".to_owned()
        } else {
            format!("[\n{}\n]", all_json.join(",\n"))
        };
        let _ = writeln!(out, "{text}");
    } else {
        let _ = writeln!(out, "{}", summary(&tally, policy));
    }
    if tally.unreadable > 0 {
        ExitCode::from(EXIT_USAGE)
    } else if tally.errors > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Reads and judges one file under the policy.
fn check(path: &Path, device: Option<&str>, policy: &Policy, json: bool, color: bool) -> Checked {
    let mut checked = Checked::default();
    let tally = &mut checked.tally;
    let name = path.display().to_string();
    let loaded = match load::load(path, device) {
        Ok(loaded) => loaded,
        Err(err) => {
            tally.unreadable += 1;
            let cause = match &err {
                LoadError::Read(read::ReadError::Io(_, io)) => io.to_string(),
                LoadError::Overlay(..) => err.to_string(),
            };
            let d = Diagnostic::new(
                &rules::UNREADABLE,
                None,
                format!("cannot read `{name}`: {cause}"),
            );
            if json {
                checked
                    .json
                    .extend(render::json(&name, &[d]).iter().map(array_item));
            } else {
                checked.error_text = render::human(&name, "", &[d], false);
            }
            return checked;
        }
    };
    tally.checked += 1;
    // The description's findings, then its overlay's under the overlay's own name, as
    // `edsgen generate` shows them.
    let mut parts = vec![(name, loaded.text.as_str(), loaded.diagnostics)];
    if let Some(overlay) = &loaded.overlay {
        let overlay_name = overlay.path.display().to_string();
        parts.push((
            overlay_name,
            overlay.text.as_str(),
            overlay.diagnostics.clone(),
        ));
    }
    for (name, text, mut diags) in parts {
        diag::sort(&mut diags);
        let mut shown = Vec::new();
        let mut denials = Vec::new();
        for mut d in diags {
            let denial = match policy.lint.verdict(&d) {
                Verdict::Allowed => {
                    tally.allowed += 1;
                    continue;
                }
                Verdict::Denied(by) => {
                    d.severity = Severity::Error;
                    tally.denied += 1;
                    Some(by)
                }
                Verdict::Kept => None,
            };
            match d.severity {
                Severity::Error => tally.errors += 1,
                Severity::Warning => tally.warnings += 1,
                Severity::Info => {}
            }
            if d.severity < policy.min_severity {
                tally.hidden += 1;
                continue;
            }
            shown.push(d);
            denials.push(denial);
        }
        if json {
            for (mut value, denial) in render::json(&name, &shown).into_iter().zip(&denials) {
                if let (Some(object), Some(by)) = (value.as_object_mut(), denial) {
                    object.insert("denied".into(), serde_json::json!(format!("--deny {by}")));
                }
                checked.json.push(array_item(&value));
            }
        } else {
            for (d, denial) in shown.iter_mut().zip(&denials) {
                if let Some(by) = denial {
                    d.message = format!("{} (denied by `--deny {by}`)", d.message);
                }
            }
            checked
                .text
                .push_str(&render::human(&name, text, &shown, color));
        }
    }
    checked
}

/// One item of the JSON array `validate` prints, as `serde_json::to_string_pretty` prints it
/// inside the array (one level in): rendered on the thread that read the file, not at the end.
fn array_item(value: &serde_json::Value) -> String {
    let text = serde_json::to_string_pretty(value).unwrap_or_default();
    // JSON strings hold no raw line break: each one is the printer's, and starts a line to indent.
    let mut item = String::with_capacity(text.len() + text.len() / 4);
    for (at, line) in text.split('\n').enumerate() {
        if at > 0 {
            item.push('\n');
        }
        item.push_str("  ");
        item.push_str(line);
    }
    item
}

/// `2 file(s) checked: 1 error(s) (1 of them denied by --deny warnings), 0 warning(s)`, with
/// what was not read, not shown or allowed.
fn summary(tally: &Tally, policy: &Policy) -> String {
    let mut line = format!("{} file(s) checked", tally.checked);
    if tally.unreadable > 0 {
        line.push_str(&format!(", {} not readable", tally.unreadable));
    }
    line.push_str(&format!(": {} error(s)", tally.errors));
    if tally.denied > 0 {
        let by = policy.lint.denials();
        line.push_str(&format!(
            " ({} of them denied by --deny {})",
            tally.denied,
            by.join(", ")
        ));
    }
    line.push_str(&format!(", {} warning(s)", tally.warnings));
    if tally.hidden > 0 {
        line.push_str(&format!(
            "; {} not shown (below {})",
            tally.hidden,
            policy.min_severity.as_str()
        ));
    }
    if tally.allowed > 0 {
        line.push_str(&format!(
            "; {} allowed by --allow {}",
            tally.allowed,
            policy.lint.allowed().join(", ")
        ));
    }
    line
}

/// The policy from the command line, or the usage error.
pub fn policy_or_exit(
    allow: &[String],
    deny: &[String],
    min_severity: Severity,
) -> Result<Policy, ExitCode> {
    Policy::new(allow, deny, min_severity).map_err(fail)
}
