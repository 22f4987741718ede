//! Lint levels: which rules' warnings a caller silences (`allow`) or turns into errors (`deny`,
//! or every warning with `deny warnings`). One policy for `Builder` and `edsgen validate`;
//! errors are never silenced (the generated code would be wrong). A simulator asks
//! [`Policy::refusing`] instead: there `allow` is the user's word that a device with those
//! errors is worth serving.

use crate::diag::{Diagnostic, Severity};
use crate::rules::Rule;

/// The lint levels a caller sets, by rule code; every other rule keeps its own severity.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Policy {
    allowed: Vec<&'static str>,
    denied: Vec<&'static str>,
    deny_warnings: bool,
}

/// What a policy does to one diagnostic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// It stays as it is.
    Kept,
    /// An allowed warning or info: dropped.
    Allowed,
    /// A warning or info made an error, by `--deny` of this code or of `warnings`.
    Denied(&'static str),
}

impl Policy {
    /// A policy that changes nothing.
    pub fn new() -> Self {
        Self::default()
    }

    /// Silences the warnings and infos of `rule` (like `#[allow]`).
    pub fn allow(&mut self, rule: &'static Rule) {
        if !self.allowed.contains(&rule.code) {
            self.allowed.push(rule.code);
        }
    }

    /// Makes the warnings and infos of `rule` errors; refused for a rule already allowed (the
    /// message says so).
    pub fn deny(&mut self, rule: &'static Rule) -> Result<(), String> {
        if self.allowed.contains(&rule.code) {
            return Err(format!("{} is both allowed and denied", rule.code));
        }
        if !self.denied.contains(&rule.code) {
            self.denied.push(rule.code);
        }
        Ok(())
    }

    /// Makes every warning an error.
    pub fn deny_warnings(&mut self) {
        self.deny_warnings = true;
    }

    /// Whether the policy can make an info an error (it denies a code): when it cannot, a
    /// caller that shows no infos need not make them.
    pub fn raises_infos(&self) -> bool {
        !self.denied.is_empty()
    }

    /// The allowed codes, in the order given.
    pub fn allowed(&self) -> &[&'static str] {
        &self.allowed
    }

    /// What denies: `warnings` first if every warning is denied, then the denied codes in the
    /// order given.
    pub fn denials(&self) -> Vec<&'static str> {
        let mut by: Vec<&'static str> = self
            .deny_warnings
            .then_some("warnings")
            .into_iter()
            .collect();
        by.extend(&self.denied);
        by
    }

    /// What the policy does to `d` (errors are always kept).
    pub fn verdict(&self, d: &Diagnostic) -> Verdict {
        if d.severity == Severity::Error {
            Verdict::Kept
        } else if self.allowed.contains(&d.code()) {
            Verdict::Allowed
        } else if self.denied.contains(&d.code()) {
            Verdict::Denied(d.code())
        } else if self.deny_warnings && d.severity == Severity::Warning {
            Verdict::Denied("warnings")
        } else {
            Verdict::Kept
        }
    }

    /// The diagnostics that keep a simulator from serving a description: its errors, but those of
    /// a code the policy allows (`edsgen simulate --allow CODE`), in display order.
    pub fn refusing(&self, diagnostics: &[Diagnostic]) -> Vec<Diagnostic> {
        let mut refusing: Vec<Diagnostic> = diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error && !self.allowed.contains(&d.code()))
            .cloned()
            .collect();
        crate::diag::sort(&mut refusing);
        refusing
    }

    /// The diagnostics the policy keeps, denied ones made errors.
    pub fn apply(&self, diagnostics: Vec<Diagnostic>) -> Vec<Diagnostic> {
        diagnostics
            .into_iter()
            .filter_map(|mut d| match self.verdict(&d) {
                Verdict::Allowed => None,
                Verdict::Denied(_) => {
                    d.severity = Severity::Error;
                    Some(d)
                }
                Verdict::Kept => Some(d),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules;

    fn warning(rule: &'static Rule) -> Diagnostic {
        Diagnostic::new(rule, None, "m").with_severity(Severity::Warning)
    }

    #[test]
    fn allow_drops_warnings_deny_raises_them_errors_stay() {
        let mut policy = Policy::new();
        policy.allow(&rules::LONG_LINE);
        policy.deny(&rules::INLINE_COMMENT).expect("not allowed");
        assert_eq!(
            policy.verdict(&warning(&rules::LONG_LINE)),
            Verdict::Allowed
        );
        assert_eq!(
            policy.verdict(&warning(&rules::INLINE_COMMENT)),
            Verdict::Denied("EDS004")
        );
        assert_eq!(policy.verdict(&warning(&rules::NON_ASCII)), Verdict::Kept);
        let error = Diagnostic::new(&rules::LONG_LINE, None, "m").with_severity(Severity::Error);
        assert_eq!(policy.verdict(&error), Verdict::Kept);
        policy.deny_warnings();
        assert_eq!(
            policy.verdict(&warning(&rules::NON_ASCII)),
            Verdict::Denied("warnings")
        );
        assert_eq!(policy.denials(), ["warnings", "EDS004"]);
        let kept = policy.apply(vec![warning(&rules::LONG_LINE), warning(&rules::NON_ASCII)]);
        assert_eq!(kept.len(), 1);
        assert_eq!(
            (kept[0].code(), kept[0].severity),
            ("EDS002", Severity::Error)
        );
        assert_eq!(
            policy.deny(&rules::LONG_LINE),
            Err("EDS003 is both allowed and denied".to_owned())
        );
    }

    #[test]
    fn only_a_denied_code_can_raise_an_info() {
        let mut policy = Policy::new();
        assert!(!policy.raises_infos());
        policy.allow(&rules::LONG_LINE);
        policy.deny_warnings();
        assert!(!policy.raises_infos());
        policy.deny(&rules::NO_DEFAULT).expect("not allowed");
        assert!(policy.raises_infos());
        let info = Diagnostic::new(&rules::NO_DEFAULT, None, "m");
        assert_eq!(info.severity, Severity::Info);
        assert_eq!(policy.verdict(&info), Verdict::Denied("EDS705"));
    }

    #[test]
    fn refusing_keeps_the_errors_an_allow_does_not_name() {
        let error = |rule| Diagnostic::new(rule, None, "m").with_severity(Severity::Error);
        let found = [
            error(&rules::LONG_LINE),
            warning(&rules::NON_ASCII),
            error(&rules::INLINE_COMMENT),
        ];
        let mut policy = Policy::new();
        let codes = |ds: Vec<Diagnostic>| ds.iter().map(Diagnostic::code).collect::<Vec<_>>();
        assert_eq!(codes(policy.refusing(&found)), ["EDS003", "EDS004"]);
        policy.allow(&rules::LONG_LINE);
        assert_eq!(codes(policy.refusing(&found)), ["EDS004"]);
        policy.allow(&rules::INLINE_COMMENT);
        assert!(policy.refusing(&found).is_empty());
    }
}
