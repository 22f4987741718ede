//! Overlays: what a device description cannot say, in a TOML file beside it (`eds/NAME.toml` for
//! `eds/NAME.eds`). Today that is the capacity of strings, octet strings and domains, for which
//! CiA 306 has no key; without one the generator uses the rule in `docs/generated-code.md`.
//!
//! ```toml
//! [capacity]
//! 1008 = 64        # 1008h sub 0, in bytes
//! 1F50sub1 = 4096  # 1F50h sub 1: keys are written as the EDS names sections
//! ```
//!
//! [`apply`] checks the overlay against the model and sets [`SubObject::capacity`]; its
//! diagnostics (EDS708) point into the TOML text and are rendered with it, not with the
//! description's. The builder and `edsgen generate` both find the overlay with [`path_for`].

use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use crate::diag::Diagnostic;
use crate::model::{BasicType, Device, SubObject};
use crate::read::text::LineIndex;
use crate::rules;

/// The largest capacity an entry can have: SDO sizes and the runtime's lengths are 16-bit.
const MAX_CAPACITY: u64 = 65_535;

/// Where the overlay of `description` lives: beside it, with the extension `toml`.
pub fn path_for(description: &Path) -> PathBuf {
    description.with_extension("toml")
}

/// Checks the overlay `text` against `device` and applies what is valid. Returns the overlay's
/// diagnostics (spans in `text`); an entry named with an error keeps its computed capacity.
pub fn apply(text: &str, device: &mut Device) -> Vec<Diagnostic> {
    let lines = LineIndex::new(text);
    let mut diags = Vec::new();
    let root = match DeTable::parse(text) {
        Ok(root) => root.into_inner(),
        Err(err) => {
            let span = err.span().map(|r| lines.span(text, r));
            diags.push(
                Diagnostic::new(
                    &rules::OVERLAY,
                    span,
                    format!("the overlay is not TOML: {}", err.message().trim()),
                )
                .with_label("the overlay is ignored"),
            );
            return diags;
        }
    };
    for (key, value) in &root {
        let key_span = lines.span(text, key.span());
        match (key.get_ref().as_ref(), value.get_ref()) {
            ("capacity", DeValue::Table(table)) => {
                for (entry, capacity) in table {
                    set_capacity(entry, capacity, device, text, &lines, &mut diags);
                }
            }
            ("capacity", _) => diags.push(Diagnostic::new(
                &rules::OVERLAY,
                Some(key_span),
                "`capacity` must be a table: `[capacity]`",
            )),
            (other, _) => diags.push(
                Diagnostic::new(
                    &rules::OVERLAY,
                    Some(key_span),
                    format!("unknown overlay table `{other}`"),
                )
                .with_label("ignored")
                .with_help("an overlay has one table: [capacity]"),
            ),
        }
    }
    // The TOML tables iterate by key; report in the order of the file.
    crate::diag::sort(&mut diags);
    diags
}

/// One `XXXXsubY = N` line of `[capacity]`.
fn set_capacity(
    key: &Spanned<std::borrow::Cow<'_, str>>,
    value: &Spanned<DeValue<'_>>,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let key_span = lines.span(text, key.span());
    let value_span = lines.span(text, value.span());
    let name = key.get_ref().as_ref();
    let Some((index, sub)) = entry_address(name) else {
        diags.push(
            Diagnostic::new(
                &rules::OVERLAY,
                Some(key_span),
                format!("`{name}` does not name an entry"),
            )
            .with_help("write the index in hex, with `subN` for a sub-index: `1008`, `1F50sub1`"),
        );
        return;
    };
    let capacity = match value.get_ref() {
        DeValue::Integer(n) => i64::from_str_radix(&n.as_str().replace('_', ""), n.radix())
            .ok()
            .and_then(|n| u64::try_from(n).ok())
            .filter(|n| (1..=MAX_CAPACITY).contains(n)),
        _ => None,
    };
    let Some(capacity) = capacity else {
        diags.push(Diagnostic::new(
            &rules::OVERLAY,
            Some(value_span),
            format!("the capacity of `{name}` must be a number of bytes in 1..={MAX_CAPACITY}"),
        ));
        return;
    };
    let place = format!("{index:04X}h sub {sub}");
    let basic = device
        .entry(index, sub)
        .and_then(|s| s.data_type)
        .and_then(|t| device.basic_type(t))
        .filter(|b| has_capacity(*b));
    let Some(entry) = device
        .objects
        .get_mut(&index)
        .and_then(|o| o.subs.get_mut(&sub))
    else {
        diags.push(Diagnostic::new(
            &rules::OVERLAY,
            Some(key_span),
            format!("{place} is not in the description"),
        ));
        return;
    };
    let Some(basic) = basic else {
        diags.push(
            Diagnostic::new(
                &rules::OVERLAY,
                Some(key_span),
                format!(
                    "{place} `{}` is not a string, octet string or domain",
                    entry.name
                ),
            )
            .with_label("only those have a capacity"),
        );
        return;
    };
    let needed = longest_value(basic, entry);
    // u64 -> usize: at most MAX_CAPACITY here.
    let capacity = usize::from(u16::try_from(capacity).unwrap_or(u16::MAX));
    if capacity < needed {
        diags.push(
            Diagnostic::new(
                &rules::OVERLAY,
                Some(value_span),
                format!(
                    "{place} `{}` holds {needed} bytes by default, more than the capacity {capacity}",
                    entry.name
                ),
            )
            .with_help(format!("give it at least {needed} bytes")),
        );
        return;
    }
    entry.capacity = Some(capacity);
}

/// `1008` → (0x1008, 0); `1F50sub1` → (0x1F50, 1), as EDS section names are written.
fn entry_address(name: &str) -> Option<(u16, u8)> {
    let lower = name.to_ascii_lowercase();
    let (index, sub) = match lower.split_once("sub") {
        Some((index, sub)) => (index, u8::from_str_radix(sub, 16).ok()?),
        None => (lower.as_str(), 0),
    };
    if index.is_empty() || index.len() > 4 {
        return None;
    }
    Some((u16::from_str_radix(index, 16).ok()?, sub))
}

fn has_capacity(basic: BasicType) -> bool {
    matches!(
        basic,
        BasicType::VisibleString
            | BasicType::OctetString
            | BasicType::UnicodeString
            | BasicType::Domain
    )
}

/// The bytes the entry's DefaultValue or ParameterValue needs (the larger).
fn longest_value(basic: BasicType, entry: &SubObject) -> usize {
    [&entry.default, &entry.parameter_value]
        .into_iter()
        .flatten()
        .filter_map(|v| v.value.as_ref())
        .filter_map(|v| crate::emit::types::value_bytes(basic, v))
        .map(|bytes| bytes.len())
        .max()
        .unwrap_or(0)
}
