//! The rule catalogue: every diagnostic edsgen can emit, with its stable code and default severity.
//!
//! Codes never change meaning once published. Numbering by area: `EDS0xx` text and values (the
//! readers), `EDS1xx` `[FileInfo]`/`[DeviceInfo]`, `EDS2xx` object lists, `EDS3xx` objects and
//! sub-objects, `EDS4xx` PDOs, `EDS5xx` DCF, commissioning, modules and the rest, `EDS6xx` XML
//! (XDD/XDC), `EDS7xx` code generation, `EDS8xx` EtherCAT (ESI); `CIP0xx` ODVA EDS (EtherNet/IP,
//! listed first: the table sorts by code), `GSD0xx` PROFIBUS-DP (GSD), `PN0xx` PROFINET (GSDML);
//! and `CHKxxx`, a live device against its description (`edsgen check`; CHK006–CHK008 an EtherCAT
//! SubDevice, `edsgen ecat check`). Each rule says why it matters: what goes wrong on a bus or in
//! a tool when a file breaks it. `edsgen rules` prints this table, `edsgen explain` one rule.

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
    /// Why it matters, in a sentence: what goes wrong on a real bus or in a real tool when a file
    /// breaks the rule.
    pub why: &'static str,
}

impl Rule {
    /// The part of a description (or of edsgen) the rule judges, from its code's prefix and
    /// number; `None` for a code outside the numbering the module comment gives.
    pub fn area(&self) -> Option<&'static str> {
        let (prefix, number) = split_code(self.code)?;
        Some(match (prefix, number / 100, number / 10 % 10) {
            ("CHK", ..) => "a live device against its description (`edsgen check`)",
            ("CIP", 0, 0) => "ODVA EDS text, sections and identity (reported while reading)",
            ("CIP", 0, 1) => "ODVA EDS parameters and their value lists",
            ("CIP", 0, 2) => "ODVA EDS assemblies and their members",
            ("CIP", 0, 3) => "ODVA EDS connections and their paths",
            ("EDS", 0, _) => "the text and its values (reported while reading)",
            ("EDS", 1, _) => "[FileInfo] and [DeviceInfo]",
            ("EDS", 2, _) => "the object lists",
            ("EDS", 3, _) => "objects and sub-objects",
            ("EDS", 4, _) => "PDOs",
            ("EDS", 5, _) => {
                "DCF, commissioning, modules, comments, object links, dynamic channels"
            }
            ("EDS", 6, _) => "XML descriptions (XDD, XDC)",
            ("EDS", 7, _) => "code generation (reported by `edsgen generate` and build.rs)",
            ("EDS", 8, _) => "EtherCAT descriptions (ESI) and SII images",
            ("GSD", 0, 0) => "PROFIBUS-DP GSD text and keywords (reported while reading)",
            ("GSD", 0, 1) => "PROFIBUS-DP GSD modules, parameters and bus timing",
            ("PN", 0, _) => {
                "PROFINET GSDML: identity, access points, modules, records and diagnosis"
            }
            _ => return None,
        })
    }
}

/// A code's letters and number (`"EDS102"` is `("EDS", 102)`), the letters uppercased.
fn split_code(code: &str) -> Option<(&'static str, u32)> {
    let digits = code.find(|c: char| c.is_ascii_digit())?;
    let (letters, number) = code.split_at(digits);
    let prefix = ["CHK", "CIP", "EDS", "GSD", "PN"]
        .into_iter()
        .find(|p| p.eq_ignore_ascii_case(letters))?;
    Some((prefix, number.parse().ok()?))
}

mod catalogue;

pub use catalogue::*;

/// Looks a rule up by its code.
pub fn by_code(code: &str) -> Option<&'static Rule> {
    ALL.iter()
        .copied()
        .find(|r| r.code.eq_ignore_ascii_case(code))
}

/// The rule a mistyped code most likely means: of the same letters, the nearest number (the
/// lower on a tie); else the code a letter or two away
/// (a transposition counts as one). `None` when nothing is near.
pub fn nearest(code: &str) -> Option<&'static Rule> {
    if let Some((prefix, number)) = split_code(code) {
        return ALL
            .iter()
            .copied()
            .filter(|rule| split_code(rule.code).is_some_and(|(p, _)| p == prefix))
            .min_by_key(|rule| split_code(rule.code).map(|(_, n)| n.abs_diff(number)));
    }
    // A transposition (`CPI023`) is one edit here: codes are typed, not spelled.
    let wanted = code.to_ascii_uppercase();
    ALL.iter()
        .copied()
        .map(|rule| (strsim::osa_distance(&wanted, rule.code), rule))
        .filter(|(distance, _)| *distance <= 2)
        .min_by_key(|(distance, _)| *distance)
        .map(|(_, rule)| rule)
}

/// The rule table as Markdown: the content of `docs/rules.md`, generated from [`ALL`].
pub fn markdown() -> String {
    let mut out = String::from(
        "# edsgen validation rules\n\n\
         Generated from `model/src/rules/catalogue.rs` by the test `rules_doc_is_current`\n\
         (`EDSGEN_UPDATE_DOCS=1 cargo test -p edsgen-codegen --test rules` rewrites it). \
         Do not edit by hand.\n\n\
         Severities: **error** fails `edsgen validate` and the build; **warning** fails only with \
         `--deny warnings`; **info** never fails. Some rules report a secondary severity for some \
         instances; their summary says so. The `CHK` codes judge a live device against its \
         description (`edsgen check`), not the file.\n\n\
         | Code | Severity | What it checks | Why it matters |\n|---|---|---|---|\n",
    );
    for rule in ALL {
        out.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            rule.code,
            rule.severity.as_str(),
            rule.summary.replace('|', "\\|"),
            rule.why.replace('|', "\\|")
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_rule_says_why_it_matters_in_a_sentence_of_its_own() {
        for rule in ALL {
            let why = rule.why;
            assert!(
                why.len() > 40 && why.starts_with(char::is_uppercase) && why.ends_with('.'),
                "{}: `{why}` is not a sentence on why it matters",
                rule.code
            );
            assert_ne!(why, rule.summary, "{}", rule.code);
        }
    }

    #[test]
    fn every_rule_has_an_area() {
        for rule in ALL {
            assert!(rule.area().is_some(), "{} has no area", rule.code);
        }
    }

    #[test]
    fn the_nearest_code_is_the_nearest_number_of_the_same_letters_else_a_letter_away() {
        let nearest = |code| nearest(code).map(|rule| rule.code);
        assert_eq!(nearest("EDS999"), Some("EDS820"));
        assert_eq!(nearest("pn21"), Some("PN019"));
        assert_eq!(nearest("CIP024"), Some("CIP023"));
        assert_eq!(nearest("GSD008"), Some("GSD007"));
        assert_eq!(nearest("CPI023"), Some("CIP023"));
        assert_eq!(nearest("GSD16"), Some("GSD016"));
        assert_eq!(nearest("XYZ999"), None);
        assert_eq!(nearest("EDS"), None);
    }

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
