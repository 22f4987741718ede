//! Overlays: what a device description cannot say, in a TOML file beside it (`eds/NAME.toml` for
//! `eds/NAME.eds`): the capacity of strings, octet strings and domains, for which CiA 306 has no
//! key (without one the generator uses the rule in `docs/generated-code.md`), and generated names:
//! an object's or an entry's name, and how the device numbers an array's elements.
//!
//! ```toml
//! [capacity]
//! 1008 = 64        # 1008h sub 0, in bytes
//! 1F50sub1 = 4096  # 1F50h sub 1: keys are written as the EDS names sections
//!
//! [names]
//! 201C = "F28"                 # 201Ch's module is od::f28 (a VAR's constant F28)
//! 2030sub1 = "FREQUENCY_COMMAND"
//!
//! [numbering]
//! 2000-201F = 0    # sub-index 1 is element 0: 201Ch sub 86 is od::f28::F28_85
//!
//! [pdo_mapping]    # default mappings the description leaves empty (typed PDOs for them)
//! 1600 = ["6040", "6042"]
//!
//! [pkw_pzd]        # ODVA EDS: assemblies carrying the Goodrive350's PKW/PZD images
//! output = 150     # the scanner's image: PKW request, CW, PZD2-PZD12
//! input = 100      # the drive's image: PKW response, SW, PZD2-PZD12
//! byte_order = "little"
//! # (GSD: module = "4 PKW + 12 PZD", the module carrying them; GSDML: module = "MOD_1" (the
//! # ModuleItem's or DeviceAccessPointItem's ID or name) and subslot = 1, the submodule)
//!
//! [modules]        # a modular device's modules (GSD, GSDML, ESI), `NAME` or `SLOT=NAME`
//! slots = ["4 PKW, 2 PZD (PPO 1)", "3=8 DI"]
//! # (GSDML: access_point = "DAP 2", the DeviceAccessPointItem's ID or name; docs/modules.md)
//! ```
//!
//! [`apply`] checks the overlay against the model and sets [`SubObject::capacity`] and
//! [`Device::naming`]; its
//! diagnostics (EDS708) point into the TOML text and are rendered with it, not with the
//! description's. The builder and `edsgen generate` both find the overlay with [`path_for`].

use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use crate::diag::Diagnostic;
use crate::model::{BasicType, Device, ObjectType, SubObject, Value, ValueSource};
use crate::read::text::LineIndex;
use crate::rules;

mod modules;
mod pkw_pzd;

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
            ("names", DeValue::Table(table)) => {
                for (entry, name) in table {
                    set_name(entry, name, device, text, &lines, &mut diags);
                }
            }
            ("numbering", DeValue::Table(table)) => {
                for (range, first) in table {
                    set_numbering(range, first, device, text, &lines, &mut diags);
                }
            }
            ("pdo_mapping", DeValue::Table(table)) => {
                for (mapping, entries) in table {
                    set_mapping(mapping, entries, device, text, &lines, &mut diags);
                }
            }
            ("pkw_pzd", DeValue::Table(table)) => {
                pkw_pzd::apply(table, key_span, device, text, &lines, &mut diags);
            }
            ("modules", DeValue::Table(table)) => {
                modules::apply(table, key_span, device, text, &lines, &mut diags);
            }
            (
                table @ ("capacity" | "names" | "numbering" | "pdo_mapping" | "pkw_pzd" | "modules"),
                _,
            ) => {
                diags.push(Diagnostic::new(
                    &rules::OVERLAY,
                    Some(key_span),
                    format!("`{table}` must be a table: `[{table}]`"),
                ))
            }
            (other, _) => diags.push(
                Diagnostic::new(
                    &rules::OVERLAY,
                    Some(key_span),
                    format!("unknown overlay table `{other}`"),
                )
                .with_label("ignored")
                .with_help(
                    "an overlay has the tables [capacity], [names], [numbering], [pdo_mapping], [pkw_pzd] and [modules]",
                ),
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
    let capacity = integer(value.get_ref())
        .and_then(|n| u64::try_from(n).ok())
        .filter(|n| (1..=MAX_CAPACITY).contains(n));
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

/// One `XXXX = "NAME"` or `XXXXsubY = "NAME"` line of `[names]`: the object's name (a VAR's
/// constant, an ARRAY's or RECORD's module), or one entry's constant name.
fn set_name(
    key: &Spanned<std::borrow::Cow<'_, str>>,
    value: &Spanned<DeValue<'_>>,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let key_span = lines.span(text, key.span());
    let raw = key.get_ref().as_ref();
    let name = match value.get_ref() {
        DeValue::String(name) if name.chars().any(|c| c.is_ascii_alphanumeric()) => name,
        _ => {
            diags.push(Diagnostic::new(
                &rules::OVERLAY,
                Some(lines.span(text, value.span())),
                format!("the name of `{raw}` must be a string with a letter or digit in it"),
            ));
            return;
        }
    };
    let whole_object = !raw.to_ascii_lowercase().contains("sub");
    match entry_address(raw) {
        Some((index, _)) if whole_object && device.objects.contains_key(&index) => {
            device.naming.objects.insert(index, name.to_string());
        }
        Some((index, sub)) if device.entry(index, sub).is_some() => {
            device.naming.entries.insert((index, sub), name.to_string());
        }
        _ => diags.push(
            Diagnostic::new(
                &rules::OVERLAY,
                Some(key_span),
                format!("`{raw}` names no object or entry of the description"),
            )
            .with_help("write the index in hex, with `subN` for a sub-index: `2030`, `2030sub1`"),
        ),
    }
}

/// One `XXXX = N` or `XXXX-YYYY = N` line of `[numbering]`: each ARRAY in the range numbers its
/// elements from N at sub-index 1.
fn set_numbering(
    key: &Spanned<std::borrow::Cow<'_, str>>,
    value: &Spanned<DeValue<'_>>,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let key_span = lines.span(text, key.span());
    let raw = key.get_ref().as_ref();
    let range = match raw.split_once('-') {
        Some((first, last)) => u16::from_str_radix(first.trim(), 16)
            .ok()
            .zip(u16::from_str_radix(last.trim(), 16).ok()),
        None => u16::from_str_radix(raw.trim(), 16).ok().map(|i| (i, i)),
    };
    let Some((first, last)) = range.filter(|(first, last)| first <= last) else {
        diags.push(
            Diagnostic::new(
                &rules::OVERLAY,
                Some(key_span),
                format!("`{raw}` is not an index or a range of indices"),
            )
            .with_help("write `2000` or `2000-201F` (hex)"),
        );
        return;
    };
    let number = integer(value.get_ref()).and_then(|n| u32::try_from(n).ok());
    let Some(number) = number else {
        diags.push(Diagnostic::new(
            &rules::OVERLAY,
            Some(lines.span(text, value.span())),
            format!("the numbering of `{raw}` must be the number of sub-index 1 (0 or more)"),
        ));
        return;
    };
    let arrays: Vec<u16> = device
        .objects
        .range(first..=last)
        .filter(|(_, o)| o.object_type == ObjectType::Array)
        .map(|(index, _)| *index)
        .collect();
    if arrays.is_empty() {
        diags.push(Diagnostic::new(
            &rules::OVERLAY,
            Some(key_span),
            format!("`{raw}` holds no ARRAY of the description"),
        ));
    }
    for index in arrays {
        device.naming.first_number.insert(index, number);
    }
}

/// One `1600 = ["6040", "6042sub0"]` line of `[pdo_mapping]`: the default mapping of a PDO
/// whose description maps nothing, written into the mapping object's defaults (sub 0 the count,
/// subs 1..n index << 16 | sub << 8 | bits), as a device configured that way would hold them.
fn set_mapping(
    key: &Spanned<std::borrow::Cow<'_, str>>,
    value: &Spanned<DeValue<'_>>,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let key_span = lines.span(text, key.span());
    let value_span = lines.span(text, value.span());
    let raw = key.get_ref().as_ref();
    let mut refuse = |span, message: String| {
        diags.push(Diagnostic::new(&rules::OVERLAY, Some(span), message));
    };
    let mapping = u16::from_str_radix(raw, 16)
        .ok()
        .filter(|i| matches!(i, 0x1600..=0x17FF | 0x1A00..=0x1BFF))
        .filter(|i| device.objects.contains_key(i));
    let Some(mapping) = mapping else {
        return refuse(
            key_span,
            format!(
                "`{raw}` is not a PDO mapping object of the description (1600h-17FFh, 1A00h-1BFFh)"
            ),
        );
    };
    let DeValue::Array(items) = value.get_ref() else {
        return refuse(
            value_span,
            format!("the mapping of `{raw}` must be a list of entries: [\"6040\", \"2000sub1\"]"),
        );
    };
    let mut words = Vec::new();
    for item in items.iter() {
        let span = lines.span(text, item.span());
        let DeValue::String(name) = item.get_ref() else {
            return refuse(
                span,
                "a mapped entry is written as a string: \"6040\", \"2000sub1\"".into(),
            );
        };
        let bits = entry_address(name).and_then(|(index, sub)| {
            let entry = device.entry(index, sub)?;
            let bits = device.basic_type(entry.data_type?)?.bits()?;
            Some(u32::from(index) << 16 | u32::from(sub) << 8 | bits)
        });
        let Some(word) = bits else {
            return refuse(
                span,
                format!("`{name}` is not an entry of the description with a fixed-size type"),
            );
        };
        words.push(word);
    }
    let object = device.objects.get_mut(&mapping).expect("checked above");
    if words.len() > object.subs.len().saturating_sub(1) {
        return refuse(
            value_span,
            format!(
                "{mapping:04X}h has {} mapping entries, fewer than the {} listed",
                object.subs.len().saturating_sub(1),
                words.len()
            ),
        );
    }
    let set = |sub: &mut SubObject, value: u32| {
        sub.default = Some(ValueSource {
            value: Some(Value::Integer(i128::from(value))),
            raw: format!("{value:#X}"),
            span: value_span,
        });
    };
    // Sub-indices 1..n in order, as CiA 301 numbers a mapping's entries.
    for (n, word) in (1u8..).zip(&words) {
        let Some(sub) = object.subs.get_mut(&n) else {
            return refuse(value_span, format!("{mapping:04X}h has no sub-index {n}"));
        };
        set(sub, *word);
    }
    if let Some(count) = object.subs.get_mut(&0) {
        set(count, words.len() as u32);
    }
}

/// A TOML integer (decimal, hex, octal or binary, with `_` separators), or `None` for another
/// kind of value or one that does not fit 64 bits.
fn integer(value: &DeValue) -> Option<i64> {
    match value {
        DeValue::Integer(n) => i64::from_str_radix(&n.as_str().replace('_', ""), n.radix()).ok(),
        _ => None,
    }
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
        .filter_map(|v| crate::model::layout::value_bytes(basic, v))
        .map(|bytes| bytes.len())
        .max()
        .unwrap_or(0)
}
