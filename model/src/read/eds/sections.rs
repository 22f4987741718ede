//! Section names: what a section's name says it is ([`SectionKind`]), with the hex numbers
//! written in it.

use crate::model::ObjectListKind;

/// What a section name says the section is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum SectionKind {
    FileInfo,
    DeviceInfo,
    DummyUsage,
    Comments,
    ObjectList(ObjectListKind),
    Commissioning,
    /// Kept in `other_sections` without a diagnostic (modules, dynamic channels, tools).
    Kept,
    Object(u16),
    Sub(u16, u8),
    /// `[xxxxsubN]` whose sub-index cannot exist: above FFh, or not hex (kept, an error).
    BadSub(u16),
    SubNames(u16),
    SubValues(u16),
    SubDenotations(u16),
    ObjectLinks(u16),
    Unknown,
}

/// Sections with a fixed name: canonical spelling and kind.
pub(super) const NAMED_SECTIONS: &[(&str, SectionKind)] = &[
    ("FileInfo", SectionKind::FileInfo),
    ("DeviceInfo", SectionKind::DeviceInfo),
    ("DummyUsage", SectionKind::DummyUsage),
    ("Comments", SectionKind::Comments),
    (
        "MandatoryObjects",
        SectionKind::ObjectList(ObjectListKind::Mandatory),
    ),
    (
        "OptionalObjects",
        SectionKind::ObjectList(ObjectListKind::Optional),
    ),
    (
        "ManufacturerObjects",
        SectionKind::ObjectList(ObjectListKind::Manufacturer),
    ),
    ("DeviceComissioning", SectionKind::Commissioning),
    ("DeviceCommissioning", SectionKind::Commissioning),
    ("SupportedModules", SectionKind::Kept),
    ("ConnectedModules", SectionKind::Kept),
    ("DynamicChannels", SectionKind::Kept),
    ("Tools", SectionKind::Kept),
];

/// Parses a hex number written without `0x` (as in section names and `DummyXXXX` keys), at most
/// eight digits and at most `max_value`.
pub(super) fn parse_hex_name(text: &str, max_value: u32) -> Option<u32> {
    if text.is_empty() || text.len() > 8 || !text.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(text, 16)
        .ok()
        .filter(|value| *value <= max_value)
}

/// Classifies a section name. Returns the kind, and whether an index/sub-index in it has extra
/// leading zeros (more than four index digits, or a sub-index with a leading 0), and whether `sub`
/// is spelled other than lowercase.
pub(super) fn classify(name: &str) -> (SectionKind, bool, bool) {
    if let Some(kind) = classify_plain(name) {
        return kind;
    }
    for (canonical, kind) in NAMED_SECTIONS {
        if name.eq_ignore_ascii_case(canonical) {
            return (*kind, false, false);
        }
    }
    // No lowercase copy of the name: every comparison below ignores ASCII case.
    // Module sections: [M<n>...] and tool sections: [Tool<n>].
    let bytes = name.as_bytes();
    if bytes.first().is_some_and(|b| b.eq_ignore_ascii_case(&b'm'))
        && bytes.get(1).is_some_and(u8::is_ascii_digit)
        && name[1..]
            .trim_start_matches(|c: char| c.is_ascii_digit())
            .starts_with(|c: char| c.is_ascii_alphabetic())
    {
        return (SectionKind::Kept, false, false);
    }
    if let Some(n) = strip_prefix_ignoring_case(name, "tool") {
        if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) {
            return (SectionKind::Kept, false, false);
        }
    }
    let index_of = |text: &str| -> Option<(u16, bool)> {
        let value = parse_hex_name(text, 0xFFFF)?;
        Some((u16::try_from(value).ok()?, text.len() > 4))
    };
    for (suffix, make) in [
        (
            "objectlinks",
            SectionKind::ObjectLinks as fn(u16) -> SectionKind,
        ),
        ("denotation", SectionKind::SubDenotations),
        ("value", SectionKind::SubValues),
        ("name", SectionKind::SubNames),
    ] {
        if let Some(prefix) = strip_suffix_ignoring_case(name, suffix) {
            if let Some((index, zeros)) = index_of(prefix) {
                return (make(index), zeros, false);
            }
        }
    }
    if let Some(at) = rfind_sub(name) {
        let (index_text, sub_text) = (&name[..at], &name[at + 3..]);
        if let (Some((index, index_zeros)), Some(sub)) =
            (index_of(index_text), parse_hex_name(sub_text, 0xFF))
        {
            let sub_zeros = sub_text.len() > 1 && sub_text.starts_with('0');
            let odd_spelling = &name[at..at + 3] != "sub";
            return (
                SectionKind::Sub(index, u8::try_from(sub).unwrap_or(0)),
                index_zeros || sub_zeros,
                odd_spelling,
            );
        }
        if let Some((index, _)) = index_of(index_text) {
            return (SectionKind::BadSub(index), false, false);
        }
    }
    if let Some((index, zeros)) = index_of(name) {
        return (SectionKind::Object(index), zeros, false);
    }
    (SectionKind::Unknown, false, false)
}

/// [`classify`] for the names most sections have, `[1A00]` and `[1A00sub3]` (four hex digits,
/// `sub` in lowercase, one or two hex digits), without the other kinds' tests; `None` for the rest.
fn classify_plain(name: &str) -> Option<(SectionKind, bool, bool)> {
    let hex = |text: &[u8]| {
        text.iter().try_fold(0u16, |value, b| {
            let digit = char::from(*b).to_digit(16)?;
            Some(value << 4 | u16::try_from(digit).ok()?)
        })
    };
    let bytes = name.as_bytes();
    let index = hex(bytes.get(..4)?)?;
    match bytes.get(4..) {
        Some([]) => Some((SectionKind::Object(index), false, false)),
        Some([b's', b'u', b'b', sub @ ..]) if matches!(sub.len(), 1 | 2) => {
            let value = u8::try_from(hex(sub)?).ok()?;
            Some((
                SectionKind::Sub(index, value),
                sub.len() > 1 && sub[0] == b'0',
                false,
            ))
        }
        _ => None,
    }
}

/// The byte offset of the last `sub` in `name`, in any case: a byte scan, cheaper than
/// `str::rfind`'s substring searcher on names this short.
pub(super) fn rfind_sub(name: &str) -> Option<usize> {
    name.as_bytes()
        .windows(3)
        .rposition(|w| w.eq_ignore_ascii_case(b"sub"))
}

/// `name` without `prefix` (ASCII, compared ignoring case).
fn strip_prefix_ignoring_case<'n>(name: &'n str, prefix: &str) -> Option<&'n str> {
    let head = name.as_bytes().get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix.as_bytes())
        .then(|| name.get(prefix.len()..))
        .flatten()
}

/// `name` without `suffix` (ASCII, compared ignoring case).
fn strip_suffix_ignoring_case<'n>(name: &'n str, suffix: &str) -> Option<&'n str> {
    let at = name.len().checked_sub(suffix.len())?;
    let tail = name.as_bytes().get(at..)?;
    tail.eq_ignore_ascii_case(suffix.as_bytes())
        .then(|| name.get(..at))
        .flatten()
}

/// Why the sub-index written after `sub` in a section name (`100` in `[D000sub100]`) cannot exist,
/// and what to write instead: the sub-index as written, why it cannot exist, and the help.
pub(super) fn bad_sub_index(sub_text: &str) -> (String, &'static str, String) {
    let hex = parse_hex_name(sub_text, u32::MAX);
    match hex {
        Some(value) => {
            let decimal = sub_text
                .parse::<u32>()
                .ok()
                .filter(|d| *d <= 0xFF && sub_text.bytes().all(|b| b.is_ascii_digit()));
            let help = match decimal {
                Some(d) => format!(
                    "sub-index sections are hex: `sub{sub_text}` is 0x{value:X} = {value}, beyond 0xFF; \
                     if the file counts in decimal, write `sub{d:X}` (and its other sub-index \
                     sections in hex too: `sub10` is 0x10 = 16)"
                ),
                None => format!(
                    "sub-index sections are hex, 0..FF: `sub{sub_text}` is 0x{value:X} = {value}"
                ),
            };
            (format!("sub-index 0x{value:X}"), "beyond 0xFF", help)
        }
        None => (
            format!("sub-index `{sub_text}`"),
            "not a hex number",
            "CiA 306 writes sub-index sections as [<index>sub<sub-index>], the sub-index in hex, 0..FF"
                .to_owned(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{classify, SectionKind};

    #[test]
    fn object_and_entry_names_read_the_same_by_either_path() {
        let cases = [
            ("1A00", (SectionKind::Object(0x1A00), false, false)),
            ("1a00sub3", (SectionKind::Sub(0x1A00, 3), false, false)),
            ("1000sub1F", (SectionKind::Sub(0x1000, 0x1F), false, false)),
            ("1000sub01", (SectionKind::Sub(0x1000, 1), true, false)),
            ("1000SUB1", (SectionKind::Sub(0x1000, 1), false, true)),
            ("01000sub1", (SectionKind::Sub(0x1000, 1), true, false)),
            ("1000sub100", (SectionKind::BadSub(0x1000), false, false)),
            ("1000subG", (SectionKind::BadSub(0x1000), false, false)),
            ("01000", (SectionKind::Object(0x1000), true, false)),
            ("1G00", (SectionKind::Unknown, false, false)),
            ("1000Value", (SectionKind::SubValues(0x1000), false, false)),
            ("FileInfo", (SectionKind::FileInfo, false, false)),
        ];
        for (name, expected) in cases {
            assert_eq!(classify(name), expected, "{name}");
        }
    }
}
