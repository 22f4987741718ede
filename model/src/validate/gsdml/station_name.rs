//! PN018: an access point's default name of station (`DNS_CompatibleName`) against PROFINET's
//! name rules, the ones the DCP wire format checks
//! ([`edsgen_runtime::profinet::wire::dcp::valid_name`]), capitals aside.

use edsgen_runtime::profinet::wire::dcp::valid_name;

use crate::diag::Diagnostic;
use crate::model::AccessPoint;
use crate::rules;

pub(super) fn check(dap: &AccessPoint, out: &mut Vec<Diagnostic>) {
    let Some(name) = dap.dns_compatible_name.as_deref() else {
        return;
    };
    // DNS names are case-insensitive and controllers lowercase the default name (Siemens'
    // own files write capitals): only what no case makes valid is reported.
    if valid_name(&name.to_ascii_lowercase()) {
        return;
    }
    let mut diagnostic = Diagnostic::new(
        &rules::PN_STATION_NAME,
        Some(dap.span),
        format!(
            "access point `{}`'s DNS_CompatibleName `{name}` is not a name of station PROFINET allows",
            dap.id
        ),
    )
    .with_label("DNS_CompatibleName");
    let fixed = suggestion(name);
    diagnostic = if valid_name(&fixed) && !fixed.is_empty() {
        diagnostic.with_help(format!(
            "a name of station is DNS labels of lowercase letters, digits and `-`, joined by \
             `.`, at most 240 characters: `{fixed}` is one"
        ))
    } else {
        diagnostic.with_help(
            "a name of station is DNS labels of lowercase letters, digits and `-`, joined by \
             `.`, at most 240 characters",
        )
    };
    out.push(diagnostic);
}

/// The name lowercased, each other character a `-`, `-` trimmed off each label's ends.
fn suggestion(name: &str) -> String {
    let mapped: String = name
        .chars()
        .map(|c| match c.to_ascii_lowercase() {
            c @ ('a'..='z' | '0'..='9' | '-' | '.') => c,
            _ => '-',
        })
        .collect();
    let labels: Vec<&str> = mapped
        .split('.')
        .map(|l| l.trim_matches('-'))
        .filter(|l| !l.is_empty())
        .collect();
    labels.join(".")
}
