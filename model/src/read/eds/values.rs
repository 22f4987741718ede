//! Values: every kept value text parsed against its entry's data type once all sections are
//! read, and the limits vendors write past a type's range.

use std::collections::HashMap;
use std::ops::Bound::{Excluded, Included, Unbounded};

use super::Reader;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::read::hash::FastHash;
use crate::read::value::{parse_integer, parse_value, split_inline_comment, strips_inline_comment};
use crate::rules;

impl Reader {
    /// Parses every kept value text against its entry's data type, DEFTYPE objects first.
    pub(super) fn resolve_values(&mut self) {
        type Parsed = (String, Span, Option<Value>);
        let mut parsed: HashMap<(Span, String, Option<BasicType>), Parsed, FastHash> =
            HashMap::default();
        // Only a span written into several entries (CompactSubObj) can hit the cache: count them
        // first, so values with a span of their own skip the cache (and its copies).
        // Sized for the usual one or two values per entry, so the map does not grow as it fills.
        let entries: usize = self.device.objects.values().map(|o| o.subs.len()).sum();
        let mut span_uses: HashMap<Span, u32, FastHash> =
            HashMap::with_capacity_and_hasher(entries * 2, FastHash::default());
        for object in self.device.objects.values() {
            for entry in object.subs.values() {
                for source in [
                    &entry.default,
                    &entry.parameter_value,
                    &entry.low_limit,
                    &entry.high_limit,
                ]
                .into_iter()
                .flatten()
                {
                    *span_uses.entry(source.span).or_default() += 1;
                }
            }
        }
        // The DEFTYPE objects (below 1000h) first, then the others.
        for pass in [(Unbounded, Excluded(0x1000)), (Included(0x1000), Unbounded)] {
            // Every entry's basic type first (a DEFTYPE's is read from its values, resolved in
            // the first pass), then the entries again in the same order, to resolve their values.
            let basics: Vec<Option<BasicType>> = self
                .device
                .objects
                .range(pass)
                .flat_map(|(_, object)| object.subs.values())
                .map(|entry| entry.data_type.and_then(|t| self.device.basic_type(t)))
                .collect();
            let entries = self
                .device
                .objects
                .range_mut(pass)
                .flat_map(|(_, object)| object.subs.values_mut());
            for (entry, basic) in entries.zip(basics) {
                for (key, slot) in [
                    ("DefaultValue", &mut entry.default),
                    ("ParameterValue", &mut entry.parameter_value),
                    ("LowLimit", &mut entry.low_limit),
                    ("HighLimit", &mut entry.high_limit),
                ] {
                    let Some(source) = slot else { continue };
                    if span_uses.get(&source.span).copied().unwrap_or(0) < 2 {
                        resolve_value(source, key, basic, &mut self.diags);
                        continue;
                    }
                    // CompactSubObj copies one written value into many entries: parse it (and
                    // report it) once.
                    let cache_key = (source.span, source.raw.clone(), basic);
                    if let Some((raw, span, value)) = parsed.get(&cache_key) {
                        source.raw.clone_from(raw);
                        source.span = *span;
                        source.value.clone_from(value);
                        continue;
                    }
                    resolve_value(source, key, basic, &mut self.diags);
                    parsed.insert(
                        cache_key,
                        (source.raw.clone(), source.span, source.value.clone()),
                    );
                }
                if let Some(ty) = basic {
                    drop_inverting_hex_high_limit(entry, ty, &mut self.diags);
                }
            }
        }
    }
}

/// `LowLimit=0` with `HighLimit=0xFFFF` on an INTEGER16 (Sevcon, Faulhaber): read as two's
/// complement the high limit is -1, below the low limit, and every value would be refused. The
/// vendor means the unsigned number, which is above the type's maximum and restricts nothing: the
/// high limit is dropped and the two's-complement info (EDS014) becomes an EDS013 warning.
fn drop_inverting_hex_high_limit(entry: &mut SubObject, ty: BasicType, diags: &mut [Diagnostic]) {
    let (Some(low), Some(high)) = (entry.low_limit.as_ref(), entry.high_limit.as_mut()) else {
        return;
    };
    let (Some(Value::Integer(lo)), Some(Value::Integer(hi))) = (&low.value, &high.value) else {
        return;
    };
    let is_hex = high.raw.trim().to_ascii_lowercase().starts_with("0x");
    if !(ty.is_signed_integer() && is_hex && *hi < 0 && lo > hi) {
        return;
    }
    let (hi, span) = (*hi, high.span);
    high.value = None;
    // CompactSubObj entries share one written limit: report it once.
    let Some(at) = diags
        .iter()
        .rposition(|d| d.rule.code == rules::TWOS_COMPLEMENT.code && d.span == Some(span))
    else {
        return;
    };
    let max = ty.integer_range().map_or(0, |(_, max)| max);
    diags[at] = Diagnostic::new(
        &rules::OUT_OF_RANGE,
        Some(span),
        format!(
            "HighLimit `{}` read as two's complement ({hi}) is below the LowLimit; as the unsigned number meant, it is above the maximum {max} of {}: it restricts nothing and is ignored",
            high.raw.trim(),
            ty.name()
        ),
    )
    .with_severity(Severity::Warning)
    .with_help(format!("remove the HighLimit, or write {max}"));
}

/// Strips an inline comment where the type allows it, then parses the value.
fn resolve_value(
    source: &mut ValueSource,
    key: &str,
    basic: Option<BasicType>,
    diags: &mut Vec<Diagnostic>,
) {
    if source.value.is_some() {
        return;
    }
    let (value, comment) = split_inline_comment(&source.raw);
    if comment.is_some() {
        if strips_inline_comment(basic) {
            diags.push(
                Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(source.span),
                    format!("inline comment after the {key} is ignored"),
                )
                .with_help("put the comment on its own line, starting with `;`"),
            );
            let value = value.to_owned();
            source.span.len = u32::try_from(value.chars().count()).unwrap_or(u32::MAX);
            source.raw = value;
        } else if basic.is_some() {
            diags.push(
                Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(source.span),
                    format!("the {key} contains `;`; it is kept as part of the string"),
                )
                .with_severity(Severity::Warning),
            );
        }
    }
    let mut found = Vec::new();
    source.value = parse_value(&source.raw, basic, source.span, &mut found);
    if let Some(ty) = basic {
        for diag in &mut found {
            soften_limit_beyond_type(diag, key, &source.raw, ty);
        }
    }
    diags.append(&mut found);
}

/// A LowLimit below the type's minimum or a HighLimit above its maximum restricts nothing: the
/// limit is dropped (the type's own range applies) and EDS013 becomes a warning. Vendors write
/// `HighLimit=65535` on INTEGER16 or `0xFFFFFFFF` on UNSIGNED16 to mean "no limit". A limit beyond
/// the other end (which would exclude every value) stays an error, except `HighLimit=-1` on an
/// unsigned type, which C and .NET tools read as all ones.
fn soften_limit_beyond_type(diag: &mut Diagnostic, key: &str, raw: &str, ty: BasicType) {
    if diag.rule.code != rules::OUT_OF_RANGE.code {
        return;
    }
    let (Some(value), Some((min, max))) = (parse_integer(raw), ty.integer_range()) else {
        return;
    };
    let (beyond, bound) = match key {
        "HighLimit" if value > max => ("above the maximum", max),
        "LowLimit" if value < min => ("below the minimum", min),
        // Sevcon writes HighLimit=-1 on unsigned entries: all ones, the maximum, as C and .NET
        // tools read it.
        "HighLimit" if value == -1 && min == 0 => ("all ones, the maximum", max),
        _ => return,
    };
    *diag = Diagnostic::new(
        &rules::OUT_OF_RANGE,
        diag.span,
        format!(
            "{key} `{}` is {beyond} {bound} of {}; it restricts nothing and is ignored",
            raw.trim(),
            ty.name()
        ),
    )
    .with_severity(Severity::Warning)
    .with_help(format!("remove the {key}, or write {bound}"));
}
