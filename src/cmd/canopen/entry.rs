//! An entry of the object dictionary as the bench commands take it: by index as CANopen tools
//! spell it (`6041`, `6041:0`, `0x6041sub0`, `1018h:2`), or by name from an EDS (exact or
//! unique prefix, case- and space-insensitive), with suggestions when a name is ambiguous or
//! unknown.

use edsgen_model::model::Device;
use edsgen_runtime::wire::sdo::Multiplexer;

use super::sdo::describe;

/// The entry `text` names: an index (sub-index 0 when none is given), else a name of `device`.
pub fn resolve(text: &str, device: Option<&Device>) -> Result<Multiplexer, String> {
    if let Some(mux) = parse_index(text) {
        return Ok(mux);
    }
    match device {
        Some(device) => by_name(text, device),
        None => Err(format!(
            "`{text}` is not an entry: give INDEX[:SUB] in hex (6041, 6041:0, 0x6041sub0), or \
             a name with --eds FILE"
        )),
    }
}

/// `INDEX[:SUB]` or `INDEX[sub SUB]`, both hexadecimal with an optional `0x` or `h`.
pub fn parse_index(text: &str) -> Option<Multiplexer> {
    let text = text.trim();
    let lower = text.to_ascii_lowercase();
    let (index, sub) = match lower.split_once(':').or_else(|| lower.split_once("sub")) {
        Some((index, sub)) => (index.to_owned(), Some(sub.to_owned())),
        None => (lower, None),
    };
    let hex = |part: &str| {
        let part = part.trim();
        let part = part.strip_prefix("0x").unwrap_or(part);
        let part = part.strip_suffix('h').unwrap_or(part);
        if part.is_empty() || !part.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        u32::from_str_radix(part, 16).ok()
    };
    let index = u16::try_from(hex(&index)?).ok()?;
    let sub = match sub {
        Some(sub) => u8::try_from(hex(&sub)?).ok()?,
        None => 0,
    };
    Some(Multiplexer::new(index, sub))
}

/// Lower case without white space: how names compare.
fn key(name: &str) -> String {
    name.chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect()
}

/// Every entry of `device` with a name: its name as `describe` gives it ("Object / Sub" for
/// the sub-indices of records and arrays).
fn names(device: &Device) -> Vec<(String, Multiplexer)> {
    let mut names = Vec::new();
    for object in device.objects.values() {
        for sub in object.subs.values() {
            let mux = Multiplexer::new(object.index, sub.sub_index);
            if let Some((name, _)) = describe(device, mux) {
                names.push((name, mux));
            }
        }
    }
    names
}

/// The entry of `device` named `text`: exactly, else the one whose name starts with it.
fn by_name(text: &str, device: &Device) -> Result<Multiplexer, String> {
    let wanted = key(text);
    let names = names(device);
    if let Some((_, mux)) = names.iter().find(|(name, _)| key(name) == wanted) {
        return Ok(*mux);
    }
    let prefixed: Vec<_> = names
        .iter()
        .filter(|(name, _)| key(name).starts_with(&wanted))
        .collect();
    match prefixed.as_slice() {
        [(_, mux)] => Ok(*mux),
        [] => {
            let near: Vec<_> = names
                .iter()
                .filter(|(name, _)| key(name).contains(&wanted))
                .collect();
            let near = if near.is_empty() {
                closest(&wanted, &names)
            } else {
                near
            };
            Err(format!(
                "the description has no entry named `{text}`{}",
                suggestions(&near)
            ))
        }
        many => Err(format!(
            "`{text}` names {} entries{}",
            many.len(),
            suggestions(many)
        )),
    }
}

/// The names closest to `wanted` by edit distance, at most a third of its length away.
fn closest<'a>(wanted: &str, names: &'a [(String, Multiplexer)]) -> Vec<&'a (String, Multiplexer)> {
    let keyed = names.iter().map(|entry| (key(&entry.0), entry));
    crate::cmd::did_you_mean::closest(wanted, keyed, true)
}

/// `: did you mean ...?` with up to eight names and their indices, or nothing.
fn suggestions(names: &[&(String, Multiplexer)]) -> String {
    let lines: Vec<String> = names
        .iter()
        .map(|(name, mux)| format!("{:04X}:{:X}  {name}", mux.index, mux.sub))
        .collect();
    crate::cmd::did_you_mean::listing(&lines)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_in_the_usual_spellings() {
        let m = Multiplexer::new;
        assert_eq!(parse_index("6041"), Some(m(0x6041, 0)));
        assert_eq!(parse_index("6041:0"), Some(m(0x6041, 0)));
        assert_eq!(parse_index("0x6041sub0"), Some(m(0x6041, 0)));
        assert_eq!(parse_index("6041sub2"), Some(m(0x6041, 2)));
        assert_eq!(parse_index("0x1018:0x02"), Some(m(0x1018, 2)));
        assert_eq!(parse_index("1018h:1"), Some(m(0x1018, 1)));
        assert_eq!(parse_index("1018H:0AH"), Some(m(0x1018, 10)));
        assert_eq!(parse_index("10000:0"), None);
        assert_eq!(parse_index("6041:100"), None);
        assert_eq!(parse_index("Statusword"), None);
        assert_eq!(parse_index("Deadbeef"), None);
        assert_eq!(parse_index("6041:"), None);
        assert_eq!(parse_index(""), None);
    }

    proptest::proptest! {
        #[test]
        fn any_text_parses_or_is_refused_without_a_panic(text in "\\PC{0,16}") {
            let _ = parse_index(&text);
            let _ = resolve(&text, None);
        }

        #[test]
        fn every_index_reads_back_in_each_spelling(index: u16, sub: u8) {
            let want = Some(Multiplexer::new(index, sub));
            for text in [
                format!("{index:04X}:{sub:X}"),
                format!("0x{index:x}sub{sub:x}"),
                format!("{index:X}h:{sub:X}h"),
            ] {
                proptest::prop_assert_eq!(parse_index(&text), want, "{}", text);
            }
        }
    }
}
