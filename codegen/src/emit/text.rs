//! The module's big, regular items (the entry tables, the default image, the typed addresses)
//! written directly as text, formatted exactly as `prettyplease` formats them: re-parsing and
//! re-formatting thousands of table rows was most of a build script's time. Each such item
//! stands in the token stream as a placeholder item, replaced after formatting ([`Splices`]).

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

/// `prettyplease`'s line width, counting the indentation.
pub const MARGIN: usize = 89;

/// The indentation of the generated module's items (`pub mod NAME { ... }`).
pub const ITEM_INDENT: usize = 4;

/// Items written as text, each standing in the token stream as a placeholder item until
/// [`Splices::apply`] puts it in place of its placeholder in the formatted module.
#[derive(Debug, Default)]
pub struct Splices {
    texts: Vec<String>,
}

impl Splices {
    /// The placeholder item for `text`: one or more items, formatted at [`ITEM_INDENT`], each
    /// line ending in `\n`.
    pub fn item(&mut self, text: String) -> TokenStream {
        let placeholder = format_ident!("__EDSGEN_TEXT_{}", self.texts.len());
        self.texts.push(text);
        quote!(const #placeholder: () = ();)
    }

    /// Appends `formatted` to `out`, every placeholder line replaced by its text.
    pub fn apply(&self, formatted: &str, out: &mut String) {
        out.reserve(formatted.len() + self.texts.iter().map(String::len).sum::<usize>());
        for line in formatted.split_inclusive('\n') {
            match self.placeholder_text(line) {
                Some(text) => out.push_str(text),
                None => out.push_str(line),
            }
        }
    }

    fn placeholder_text(&self, line: &str) -> Option<&str> {
        let number = line
            .strip_prefix("    const __EDSGEN_TEXT_")?
            .strip_suffix(": () = ();\n")?;
        self.texts
            .get(number.parse::<usize>().ok()?)
            .map(String::as_str)
    }
}

/// Appends `indent` spaces.
pub fn indent(out: &mut String, indent: usize) {
    const SPACES: &str = "                                ";
    let mut left = indent;
    while left > 0 {
        let n = left.min(SPACES.len());
        out.push_str(&SPACES[..n]);
        left -= n;
    }
}

/// Appends rustdoc lines as `prettyplease` prints `#[doc = LINE]`: `///LINE`, trailing spaces
/// trimmed. Every line the emitter writes starts with a space or is empty, and holds no line
/// break (see `plan::doc_text`).
pub fn docs<S: AsRef<str>>(out: &mut String, at: usize, lines: &[S]) {
    for line in lines {
        debug_assert!(!line.as_ref().starts_with('/') && !line.as_ref().contains('\n'));
        indent(out, at);
        out.push_str("///");
        out.push_str(line.as_ref().trim_end_matches(' '));
        out.push('\n');
    }
}

/// Appends `HEAD[e0, e1, ...];` for an array of literals, the way `prettyplease` fills one:
/// on one line if it fits, else broken after `[`, as many elements per line as fit, a trailing
/// comma and `];` on a line of its own. `head` is the item up to the `[`.
pub fn literal_array<S: AsRef<str>>(out: &mut String, at: usize, head: &str, elems: &[S]) {
    indent(out, at);
    out.push_str(head);
    // `[a, b, c];`: each element and its separator, or `[` and `];` for the first.
    let one_line = elems.iter().map(|e| e.as_ref().len() + 2).sum::<usize>() + 1;
    if elems.is_empty() || at + head.len() + one_line <= MARGIN {
        out.push('[');
        for (i, elem) in elems.iter().enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            out.push_str(elem.as_ref());
        }
        out.push_str("];\n");
        return;
    }
    out.push_str("[\n");
    let inner = at + 4;
    let mut column = 0;
    for (i, elem) in elems.iter().enumerate() {
        let elem = elem.as_ref();
        // A break is taken unless the next element (with its comma, but for the last one)
        // still fits after a space.
        let last = i + 1 == elems.len();
        let width = elem.len() + usize::from(!last);
        if column == 0 {
            indent(out, inner);
            column = inner;
        } else if column + 1 + width <= MARGIN {
            out.push(' ');
            column += 1;
        } else {
            out.push('\n');
            indent(out, inner);
            column = inner;
        }
        out.push_str(elem);
        out.push(',');
        column += elem.len() + 1;
    }
    out.push('\n');
    indent(out, at);
    out.push_str("];\n");
}

/// The number of decimal digits of `n`.
pub(crate) fn decimal_digits(n: u32) -> usize {
    n.checked_ilog10().map_or(1, |log| log as usize + 1)
}

/// Appends `n` in decimal (`format!("{n}")` without the formatter: thousands of entries).
pub(crate) fn push_decimal(out: &mut String, n: u32) {
    let mut digits = [0u8; 10];
    let mut at = digits.len();
    let mut rest = n;
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            break;
        }
    }
    for &digit in &digits[at..] {
        out.push(char::from(digit));
    }
}

/// Numbers in decimal, written into one buffer and read back as one `&str` each: the cells of
/// a table of thousands of numbers (`OFFSETS`, `DEFAULTS`) without a `String` each.
pub(crate) struct Decimals {
    digits: String,
    ends: Vec<usize>,
}

impl Decimals {
    /// `values`, each written as `{n}` writes it.
    pub(crate) fn new(values: impl ExactSizeIterator<Item = u32>) -> Self {
        let mut digits = String::with_capacity(values.len() * 5);
        let mut ends = Vec::with_capacity(values.len());
        for n in values {
            push_decimal(&mut digits, n);
            ends.push(digits.len());
        }
        Decimals { digits, ends }
    }

    /// Each number's text, in order.
    pub(crate) fn cells(&self) -> Vec<&str> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts
            .zip(&self.ends)
            .map(|(start, &end)| &self.digits[start..end])
            .collect()
    }
}

const HEX: &[u8; 16] = b"0123456789ABCDEF";

/// Appends `n` as two upper-case hex digits (`{:02X}`).
pub(crate) fn push_hex2(out: &mut String, n: u8) {
    out.push(char::from(HEX[usize::from(n >> 4)]));
    out.push(char::from(HEX[usize::from(n & 0xF)]));
}

/// Appends `n` as four upper-case hex digits (`{:04X}`).
pub(crate) fn push_hex4(out: &mut String, n: u16) {
    for shift in [12, 8, 4, 0] {
        out.push(char::from(HEX[usize::from((n >> shift) & 0xF)]));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_written_by_hand_read_as_formatted() {
        for n in [0u32, 7, 9, 10, 99, 100, 255, 65_535, u32::MAX] {
            let mut out = String::new();
            push_decimal(&mut out, n);
            assert_eq!(out, n.to_string());
            assert_eq!(decimal_digits(n), n.to_string().len());
        }
        for n in [0u16, 0x1018, 0xABCD, 0xFFFF] {
            let mut out = String::new();
            push_hex4(&mut out, n);
            assert_eq!(out, format!("{n:04X}"));
        }
        for n in [0u8, 0x0A, 0x10, 0xFF] {
            let mut out = String::new();
            push_hex2(&mut out, n);
            assert_eq!(out, format!("{n:02X}"));
        }
        let numbers = [0u32, 5, 10, 65_535, 7];
        let decimals = Decimals::new(numbers.iter().copied());
        let expected: Vec<String> = numbers.iter().map(u32::to_string).collect();
        assert_eq!(decimals.cells(), expected);
        assert!(Decimals::new(std::iter::empty()).cells().is_empty());
    }
}
