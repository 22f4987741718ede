//! Known keys: finding a section's CiA 306 keys whatever their case, and reading the plain
//! values (numbers, booleans, strings) of keys outside objects.

use super::Reader;
use crate::diag::Diagnostic;
use crate::model::*;
use crate::read::ini::{IniEntry, IniSection};
use crate::read::value::{octal_objection, parse_integer, split_inline_comment};
use crate::rules;

/// The position of `key` in `keys`, computed at compile time (a missing key fails the build).
pub(super) const fn key_index(keys: &[&str], key: &str) -> usize {
    let mut i = 0;
    while i < keys.len() {
        let (a, b) = (keys[i].as_bytes(), key.as_bytes());
        if a.len() == b.len() {
            let mut j = 0;
            while j < a.len() && a[j] == b[j] {
                j += 1;
            }
            if j == a.len() {
                return i;
            }
        }
        i += 1;
    }
    panic!("not a known key");
}

/// The most keys a known-key list (`OBJECT_KEYS`, ...) has; each list asserts it fits.
pub(super) const MAX_KNOWN_KEYS: usize = 16;

/// The entries of a section found for a list of known keys, by canonical key.
pub(super) struct KnownKeys<'s> {
    known: &'static [&'static str],
    /// The entry for `known[i]`, at `i`.
    found: [Option<&'s IniEntry<'s>>; MAX_KNOWN_KEYS],
}

impl<'s> KnownKeys<'s> {
    /// The entry for a canonical key.
    pub(super) fn get(&self, key: &str) -> Option<&&'s IniEntry<'s>> {
        let at = self.known.iter().position(|k| *k == key)?;
        self.found.get(at)?.as_ref()
    }

    /// The entry for `known[at]`.
    pub(super) fn at(&self, at: usize) -> Option<&'s IniEntry<'s>> {
        self.found.get(at).copied().flatten()
    }

    /// The found (canonical key, entry) pairs, sorted by key.
    pub(super) fn sorted(&self) -> Vec<(&'static str, &'s IniEntry<'s>)> {
        let mut pairs: Vec<_> = self
            .known
            .iter()
            .zip(self.found.iter())
            .filter_map(|(key, entry)| entry.map(|e| (*key, e)))
            .collect();
        pairs.sort_by_key(|(key, _)| *key);
        pairs
    }
}

/// Whether two keys are the same bytes: the length, then the first and the last eight bytes as
/// two words when the keys are that long (most are), without a call to `memcmp`.
#[inline]
fn same_bytes(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let word = |bytes: &[u8], at: usize| {
        bytes
            .get(at..at + 8)
            .and_then(|chunk| <[u8; 8]>::try_from(chunk).ok())
            .map(u64::from_le_bytes)
    };
    match a.len().checked_sub(8) {
        Some(last) if a.len() <= 16 => word(a, 0) == word(b, 0) && word(a, last) == word(b, last),
        _ => a == b,
    }
}

impl Reader {
    /// Looks up the known keys of a section, reporting case-only matches (EDS008), and returns the
    /// entries that are not in `known`.
    pub(super) fn split_keys<'s>(
        &mut self,
        section: &'s IniSection<'s>,
        known: &'static [&'static str],
    ) -> (KnownKeys<'s>, Vec<&'s IniEntry<'s>>) {
        let mut found = KnownKeys {
            known,
            found: [None; MAX_KNOWN_KEYS],
        };
        let mut rest = Vec::new();
        for entry in &section.entries {
            // Most files write the canonical spelling: try that before comparing case-blind,
            // and compare the first byte before the rest (lengths often agree, first letters
            // rarely do).
            let key = entry.key.as_bytes();
            let at = known
                .iter()
                .position(|k| same_bytes(k.as_bytes(), key))
                .or_else(|| {
                    known
                        .iter()
                        .position(|k| k.eq_ignore_ascii_case(&entry.key))
                });
            match at {
                Some(at) => {
                    let canonical = &known[at];
                    if *canonical != entry.key {
                        self.once(
                            Diagnostic::new(
                                &rules::CASE_ONLY_MATCH,
                                Some(entry.key_span),
                                format!("key `{}` is spelled `{canonical}` in CiA 306", entry.key),
                            ),
                            canonical,
                        );
                    }
                    if let Some(slot) = found.found.get_mut(at) {
                        *slot = Some(entry);
                    }
                }
                None => rest.push(entry),
            }
        }
        (found, rest)
    }

    pub(super) fn unknown_key(&mut self, entry: &IniEntry, section: &IniSection) {
        self.once(
            Diagnostic::new(
                &rules::UNKNOWN_ITEM,
                Some(entry.key_span),
                format!(
                    "key `{}` in [{}] is not a CiA 306 key; it is kept but not interpreted",
                    entry.key, section.name
                ),
            ),
            &entry.key,
        );
    }

    /// The value of a numeric or enumerated key, with an inline comment stripped (EDS004).
    /// `None` when empty.
    pub(super) fn plain_value<'e>(&mut self, entry: &'e IniEntry) -> Option<(&'e str, Span)> {
        let (value, comment) = split_inline_comment(&entry.value);
        if comment.is_some() {
            self.diags.push(
                Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(entry.value_span),
                    format!(
                        "inline comment after the value of `{}` is ignored",
                        entry.key
                    ),
                )
                .with_help("put the comment on its own line, starting with `;`"),
            );
        }
        if value.is_empty() {
            return None;
        }
        let chars = if value.is_ascii() {
            value.len()
        } else {
            value.chars().count()
        };
        let len = u32::try_from(chars).unwrap_or(u32::MAX);
        Some((
            value,
            Span::new(entry.value_span.line, entry.value_span.column, len),
        ))
    }

    /// A numeric key's value in `0..=max`; EDS011 when it is not one.
    pub(super) fn number(&mut self, entry: Option<&IniEntry>, max: u32) -> Option<Spanned<u32>> {
        let entry = entry?;
        let (text, span) = self.plain_value(entry)?;
        match parse_integer(text).and_then(|v| u32::try_from(v).ok()) {
            Some(v) if v <= max => Some(Spanned::new(v, span)),
            _ => {
                let diag = match octal_objection(text) {
                    Some((message, help)) => Diagnostic::new(
                        &rules::BAD_NUMBER,
                        Some(span),
                        format!("`{}` value {message}", entry.key),
                    )
                    .with_help(help),
                    None => Diagnostic::new(
                        &rules::BAD_NUMBER,
                        Some(span),
                        format!(
                            "`{}` value `{text}` is not a number in 0..={max}",
                            entry.key
                        ),
                    ),
                };
                self.diags.push(diag.with_label("ignored"));
                None
            }
        }
    }

    /// EDS028 for an empty number or boolean that python canopen reads with `int()` and no
    /// fallback (the `[DeviceInfo]` numbers and booleans, `[Comments]` `Lines`): CiA 306 reads it
    /// as absent, which edsgen does, but python cannot import the file.
    pub(super) fn empty_number(&mut self, entry: &IniEntry) {
        if !entry.value.as_str().trim().is_empty() {
            return;
        }
        self.diags.push(
            Diagnostic::new(
                &rules::EMPTY_NUMBER,
                Some(entry.key_span),
                format!("`{}` has an empty value", entry.key),
            )
            .with_label("read as absent, as CiA 306 says")
            .with_help(format!(
                "write the number, or remove the key: python canopen cannot import `{}=`",
                entry.key
            )),
        );
    }

    /// A boolean key: `0`/`1`; other spellings are read with EDS021. Missing or empty is false.
    pub(super) fn boolean(&mut self, entry: Option<&IniEntry>) -> bool {
        let Some(entry) = entry else { return false };
        let Some((text, span)) = self.plain_value(entry) else {
            return false;
        };
        // `0` and `1` as written nearly always: no number parsing for them.
        let number = match text {
            "0" => Some(0),
            "1" => Some(1),
            _ => parse_integer(text),
        };
        match number {
            Some(0) => false,
            Some(1) => true,
            _ => {
                let lower = text.to_ascii_lowercase();
                let value = match lower.as_str() {
                    "true" | "yes" => Some(true),
                    "false" | "no" => Some(false),
                    _ => parse_integer(text).map(|v| v != 0),
                };
                self.diags.push(
                    Diagnostic::new(
                        &rules::BAD_BOOLEAN,
                        Some(span),
                        format!(
                            "`{}` value `{text}` is not 0 or 1; read as {}",
                            entry.key,
                            u8::from(value.unwrap_or(false))
                        ),
                    )
                    .with_help("write 0 or 1"),
                );
                value.unwrap_or(false)
            }
        }
    }

    pub(super) fn string(entry: Option<&IniEntry>) -> Option<String> {
        entry
            .filter(|e| !e.value.is_empty())
            .map(|e| e.value.as_str().to_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::same_bytes;

    #[test]
    fn same_bytes_is_slice_equality() {
        let keys = [
            "",
            "a",
            "Lines",
            "DataType",
            "DataTypf",
            "EataType",
            "HighLimit",
            "ParameterName",
            "ParameterNamf",
            "ParameterValue",
            "ParameterVal_e",
            "AVeryLongKeyOverSixteen",
            "AVeryLongKeyOverSixteeN",
        ];
        for a in keys {
            for b in keys {
                assert_eq!(same_bytes(a.as_bytes(), b.as_bytes()), a == b, "{a} {b}");
            }
        }
    }
}
