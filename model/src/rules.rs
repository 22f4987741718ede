//! The rule catalogue: every diagnostic edsgen can emit, with its stable code and default severity.
//!
//! Codes never change meaning once published. Numbering by area: `EDS0xx` text and values (the
//! readers), `EDS1xx` `[FileInfo]`/`[DeviceInfo]`, `EDS2xx` object lists, `EDS3xx` objects and
//! sub-objects, `EDS4xx` PDOs, `EDS5xx` DCF, commissioning, modules and the rest, `EDS6xx` XML
//! (XDD/XDC), `EDS7xx` code generation, `EDS8xx` EtherCAT (ESI); `CIP0xx` ODVA EDS (EtherNet/IP,
//! listed first: the table sorts by code), `GSD0xx` PROFIBUS-DP (GSD), `PN0xx` PROFINET (GSDML);
//! and `CHKxxx`, a live device against its description (`edsgen check`; CHK006–CHK008 an EtherCAT
//! SubDevice, `edsgen ecat check`). `edsgen rules` prints
//! this table.

/// How serious a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// A dialect was normalised or something is worth knowing; never fails anything.
    Info,
    /// Suspicious, or the established tools disagree; fails only with `--deny warnings`.
    Warning,
    /// The file breaks the standard, or code generated from it would be wrong.
    Error,
}

impl Severity {
    /// The lowercase name used in output (`error`, `warning`, `info`).
    pub const fn as_str(self) -> &'static str {
        match self {
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Error => "error",
        }
    }
}

/// One validation rule.
#[derive(Debug, PartialEq, Eq)]
pub struct Rule {
    /// Stable code, e.g. `EDS301`.
    pub code: &'static str,
    /// Default severity.
    pub severity: Severity,
    /// What the rule checks, in one line.
    pub summary: &'static str,
}

mod catalogue;

pub use catalogue::*;

/// Looks a rule up by its code.
pub fn by_code(code: &str) -> Option<&'static Rule> {
    ALL.iter()
        .copied()
        .find(|r| r.code.eq_ignore_ascii_case(code))
}

/// The rule table as Markdown: the content of `docs/rules.md`, generated from [`ALL`].
pub fn markdown() -> String {
    let mut out = String::from(
        "# edsgen validation rules\n\n\
         Generated from `codegen/src/rules.rs` by the test `rules_doc_is_current`\n\
         (`EDSGEN_UPDATE_DOCS=1 cargo test -p edsgen-codegen --test rules` rewrites it). \
         Do not edit by hand.\n\n\
         Severities: **error** fails `edsgen validate` and the build; **warning** fails only with \
         `--deny warnings`; **info** never fails. Some rules report a secondary severity for some \
         instances; their summary says so. The `CHK` codes judge a live device against its \
         description (`edsgen check`), not the file.\n\n\
         | Code | Severity | What it checks |\n|---|---|---|\n",
    );
    for rule in ALL {
        out.push_str(&format!(
            "| {} | {} | {} |\n",
            rule.code,
            rule.severity.as_str(),
            rule.summary.replace('|', "\\|")
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unique_and_sorted() {
        for pair in ALL.windows(2) {
            assert!(
                pair[0].code < pair[1].code,
                "{} then {}",
                pair[0].code,
                pair[1].code
            );
        }
    }
}
