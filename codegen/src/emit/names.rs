//! Rust names from ParameterNames: heck case conversion on an ASCII-only rendering of the name,
//! Rust keywords escaped, a leading digit prefixed, collisions made unique deterministically, and
//! the members of an ARRAY or RECORD named by what they add to their object's name.
//!
//! Rules (stable, documented in the generated code's contract):
//! - every character that is not an ASCII letter or digit separates words;
//! - words the field writes in mixed case keep together (`CANopen` is one word, not `CA_NOPEN`);
//! - an empty result takes the caller's fallback (built from the index and sub-index);
//! - a result starting with a digit gets `n_` (fields, modules) or `N_` (constants) in front;
//! - a keyword gets `_` appended (`type` becomes `type_`);
//! - in one namespace, the first name in (index, sub) order keeps its name, a later equal one
//!   gets the suffixes the caller gives (for a typed address: `SUBn` when the name is taken in
//!   the same object, the hex index when another object holds it), then `_2`, `_3`, ...

use std::collections::HashMap;
use std::rc::Rc;

use edsgen_model::read::hash::FastHash;

/// The case a name is rendered in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Case {
    /// `snake_case`: PDO struct fields and modules.
    Snake,
    /// `SHOUTY_SNAKE_CASE`: constants.
    Shouty,
}

const KEYWORDS: &[&str] = &[
    "abstract", "as", "async", "await", "become", "box", "break", "const", "continue", "crate",
    "do", "dyn", "else", "enum", "extern", "false", "final", "fn", "for", "gen", "if", "impl",
    "in", "let", "loop", "macro", "match", "mod", "move", "mut", "override", "priv", "pub", "ref",
    "return", "self", "Self", "static", "struct", "super", "trait", "true", "try", "type",
    "typeof", "unsafe", "unsized", "use", "virtual", "where", "while", "yield",
];

/// Words written in mixed case that case conversion would split at their inner capitals
/// (`CANopen` into `CA` and `Nopen`), and the spelling that keeps each one word.
const COMPOUND_WORDS: &[(&str, &str)] = &[
    ("CANopen", "Canopen"),
    ("DeviceNet", "Devicenet"),
    ("EtherCAT", "Ethercat"),
    ("PROFINET", "Profinet"),
];

/// Renders `text` as an identifier in `case`; `fallback` (already a valid identifier in that case)
/// when nothing of `text` survives.
pub fn ident(text: &str, case: Case, fallback: &str) -> String {
    let mut text = std::borrow::Cow::Borrowed(text);
    for (word, one_word) in COMPOUND_WORDS {
        if text.contains(word) {
            text = text.replace(word, one_word).into();
        }
    }
    let ascii: String = text
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { ' ' })
        .collect();
    let mut name = joined_words(&ascii, case);
    if name.is_empty() {
        name = fallback.to_owned();
    }
    if name.starts_with(|c: char| c.is_ascii_digit()) {
        name = match case {
            Case::Snake => format!("n_{name}"),
            Case::Shouty => format!("N_{name}"),
        };
    }
    if KEYWORDS.contains(&name.as_str()) {
        name.push('_');
    }
    name
}

/// Letters, digits and spaces (`ascii`) in `case`: its words, split as `heck` splits them,
/// joined by `_`. Written for this alphabet, without `heck`'s formatter: it was a tenth of
/// planning a dictionary (a test checks both agree).
fn joined_words(ascii: &str, case: Case) -> String {
    #[derive(Clone, Copy, PartialEq)]
    enum Mode {
        Boundary,
        Lowercase,
        Uppercase,
    }
    let mut out = String::with_capacity(ascii.len() + 8);
    let mut push_word = |word: &str| {
        if !out.is_empty() {
            out.push('_');
        }
        out.extend(word.chars().map(|c| match case {
            Case::Snake => c.to_ascii_lowercase(),
            Case::Shouty => c.to_ascii_uppercase(),
        }));
    };
    for word in ascii.split(' ').filter(|w| !w.is_empty()) {
        let bytes = word.as_bytes();
        let (mut start, mut mode) = (0, Mode::Boundary);
        for (at, &c) in bytes.iter().enumerate() {
            let Some(&next) = bytes.get(at + 1) else {
                push_word(&word[start..]);
                break;
            };
            let next_mode = if c.is_ascii_lowercase() {
                Mode::Lowercase
            } else if c.is_ascii_uppercase() {
                Mode::Uppercase
            } else {
                mode
            };
            if next_mode == Mode::Lowercase && next.is_ascii_uppercase() {
                // `fooBar`: a word ends after the lower-case letter.
                push_word(&word[start..=at]);
                (start, mode) = (at + 1, Mode::Boundary);
            } else if mode == Mode::Uppercase && c.is_ascii_uppercase() && next.is_ascii_lowercase()
            {
                // `HTTPServer`: a word ends before the capital that starts a lower-case run.
                push_word(&word[start..at]);
                (start, mode) = (at, Mode::Boundary);
            } else {
                mode = next_mode;
            }
        }
    }
    out
}

/// One namespace of generated names (the fields of a struct, the constants of a module, ...).
#[derive(Debug, Default)]
pub struct Namespace {
    /// Every name claimed, with the OD index of the object it was claimed for (hashed by the
    /// readers' Fx hasher: SipHash was most of a claim). A name is shared with its claimer, not
    /// copied.
    taken: HashMap<Rc<str>, u16, FastHash>,
}

impl Namespace {
    /// A namespace for about `names` names (an object's members): no growing while claiming.
    pub fn with_capacity(names: usize) -> Self {
        Namespace {
            taken: HashMap::with_capacity_and_hasher(names, FastHash::default()),
        }
    }

    /// The index of the object `name` was claimed for, if it was.
    pub fn owner(&self, name: &str) -> Option<u16> {
        self.taken.get(name).copied()
    }

    /// Claims `wanted` for the object at `index`, or the first free of `wanted` + each of
    /// `suffixes` (joined by `_`), then numbered variants. Returns the name and whether it had
    /// to change.
    pub fn claim(&mut self, wanted: &str, index: u16, suffixes: &[String]) -> (String, bool) {
        let (name, wanted) = self.claim_with(wanted, index, || suffixes.to_vec());
        (name.to_string(), wanted.is_some())
    }

    /// [`Self::claim`] making the suffixes only when `wanted` is taken, and giving the name as
    /// the namespace holds it: a free name (nearly every one) is stored once, shared by the
    /// namespace and the caller. Returns the name and, when it had to change, the name wanted.
    pub fn claim_with(
        &mut self,
        wanted: &str,
        index: u16,
        suffixes: impl FnOnce() -> Vec<String>,
    ) -> (Rc<str>, Option<String>) {
        let mut free = |name: &str| {
            if self.taken.contains_key(name) {
                return None;
            }
            let name: Rc<str> = Rc::from(name);
            self.taken.insert(Rc::clone(&name), index);
            Some(name)
        };
        if let Some(name) = free(wanted) {
            return (name, None);
        }
        let wanted = wanted.to_owned();
        let mut base = wanted.clone();
        for suffix in suffixes() {
            base = format!("{base}_{suffix}");
            if let Some(name) = free(&base) {
                return (name, Some(wanted));
            }
        }
        let mut n = 2u32;
        loop {
            let candidate = format!("{base}_{n}");
            if let Some(name) = free(&candidate) {
                return (name, Some(wanted));
            }
            n += 1;
        }
    }
}

/// The constant of a member of an ARRAY or RECORD in its object's module, from the object's
/// name `base` and the member's own name `own` (both SHOUTY): what the member's name adds to the
/// object's, since the module already says the object.
///
/// - a name that does not start with the object's whole words is kept (`VENDOR_ID` in
///   `identity_object`);
/// - a name that repeats the object's adds the rest (`Consumer heartbeat time 1` in
///   `Consumer heartbeat time`: `TIME_1`, the object's last word with the number, since a
///   number alone is no name); exactly the object's name is `SUBn`;
/// - a name that is only a number (`N_5`) gets the object's last word too (`TIME_5`).
pub fn member_name(base: &str, own: &str, sub_index: u8) -> String {
    // Only whole words: `SPEEDOMETER` does not repeat `SPEED`.
    let rest = own
        .strip_prefix(base)
        .filter(|rest| {
            rest.is_empty() || rest.starts_with(|c: char| c == '_' || c.is_ascii_digit())
        })
        .map(|rest| rest.trim_start_matches('_'));
    let rest = match rest {
        Some("") => return format!("SUB{sub_index}"),
        Some(rest) => rest,
        None => match own.strip_prefix("N_") {
            Some(number) if number.starts_with(|c: char| c.is_ascii_digit()) => number,
            _ => return own.to_owned(),
        },
    };
    if rest.starts_with(|c: char| c.is_ascii_digit()) {
        format!("{}_{rest}", last_word(base))
    } else {
        rest.to_owned()
    }
}

/// The last words of a SHOUTY name down to one that starts with a letter (`GROUP_01` of
/// `PARAMETER_GROUP_01`, `TIME` of `CONSUMER_HEARTBEAT_TIME`): what a number follows.
fn last_word(name: &str) -> &str {
    let starts: Vec<usize> = std::iter::once(0)
        .chain(name.match_indices('_').map(|(at, _)| at + 1))
        .collect();
    starts
        .iter()
        .rev()
        .map(|&start| &name[start..])
        .find(|tail| tail.starts_with(|c: char| c.is_ascii_alphabetic()))
        .unwrap_or(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_valid_identifiers() {
        assert_eq!(ident("Controlword", Case::Shouty, "X"), "CONTROLWORD");
        assert_eq!(ident("Vendor-ID", Case::Snake, "x"), "vendor_id");
        assert_eq!(ident("type", Case::Snake, "x"), "type_");
        assert_eq!(ident("1st axis", Case::Snake, "x"), "n_1st_axis");
        assert_eq!(ident("1st axis", Case::Shouty, "X"), "N_1ST_AXIS");
        assert_eq!(
            ident("Übertemperatur °C", Case::Snake, "x"),
            "bertemperatur_c"
        );
        assert_eq!(ident("°", Case::Snake, "entry_2000"), "entry_2000");
        assert_eq!(
            ident("CANopen node-ID", Case::Shouty, "X"),
            "CANOPEN_NODE_ID"
        );
        assert_eq!(
            ident("EtherCAT/CANopen gateway", Case::Snake, "x"),
            "ethercat_canopen_gateway"
        );
    }

    proptest::proptest! {
        /// The words are `heck`'s, for every text of letters, digits and spaces.
        #[test]
        fn words_are_split_and_cased_as_heck_does(ascii in "[a-zA-Z0-9 ]{0,24}") {
            use heck::{ToShoutySnakeCase, ToSnakeCase};
            proptest::prop_assert_eq!(joined_words(&ascii, Case::Snake), ascii.to_snake_case());
            proptest::prop_assert_eq!(
                joined_words(&ascii, Case::Shouty),
                ascii.to_shouty_snake_case()
            );
        }
    }

    #[test]
    fn members_are_named_by_what_they_add_to_their_object() {
        let member = |base, own| member_name(base, own, 3);
        assert_eq!(member("IDENTITY_OBJECT", "VENDOR_ID"), "VENDOR_ID");
        assert_eq!(
            member("CONSUMER_HEARTBEAT_TIME", "CONSUMER_HEARTBEAT_TIME_1"),
            "TIME_1"
        );
        assert_eq!(member("RPDO1_MAPPING", "RPDO1_MAPPING_ENTRY_2"), "ENTRY_2");
        assert_eq!(
            member("PARAMETER_GROUP_01", "PARAMETER_GROUP_01_5"),
            "GROUP_01_5"
        );
        assert_eq!(member("SPEED", "SPEEDOMETER"), "SPEEDOMETER");
        assert_eq!(member("SPEED", "SPEED"), "SUB3");
        assert_eq!(member("GAINS", "N_5"), "GAINS_5");
        assert_eq!(member("N_1ST", "N_2"), "N_1ST_2");
    }

    #[test]
    fn collisions_take_the_suffixes_in_order() {
        let mut ns = Namespace::default();
        let claim = |ns: &mut Namespace, index| ns.claim("speed", index, &[format!("{index:04X}")]);
        assert_eq!(claim(&mut ns, 0x2000), ("speed".into(), false));
        assert_eq!(ns.owner("speed"), Some(0x2000));
        assert_eq!(claim(&mut ns, 0x2001), ("speed_2001".into(), true));
        assert_eq!(claim(&mut ns, 0x2001), ("speed_2001_2".into(), true));
        assert_eq!(ns.owner("speed_2001_2"), Some(0x2001));
        assert_eq!(ns.owner("torque"), None);
    }
}
