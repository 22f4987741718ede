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

/// `00` to `99`: two digits copied at a time.
const DIGIT_PAIRS: &str = "\
    000102030405060708091011121314151617181920212223242526272829\
    303132333435363738394041424344454647484950515253545556575859\
    606162636465666768697071727374757677787980818283848586878889\
    90919293949596979899";

/// Appends `n` in decimal (`format!("{n}")` without the formatter: thousands of entries).
pub(crate) fn push_decimal(out: &mut String, n: u32) {
    let pair = |n: u32| {
        let at = 2 * n as usize;
        &DIGIT_PAIRS[at..at + 2]
    };
    match n {
        0..=9 => out.push_str(&pair(n)[1..]),
        10..=99 => out.push_str(pair(n)),
        _ => {
            push_decimal(out, n / 100);
            out.push_str(pair(n % 100));
        }
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

/// `00` to `FF`: a byte's two hex digits copied at once.
const HEX_PAIRS: &str = "\
    000102030405060708090A0B0C0D0E0F101112131415161718191A1B1C1D1E1F\
    202122232425262728292A2B2C2D2E2F303132333435363738393A3B3C3D3E3F\
    404142434445464748494A4B4C4D4E4F505152535455565758595A5B5C5D5E5F\
    606162636465666768696A6B6C6D6E6F707172737475767778797A7B7C7D7E7F\
    808182838485868788898A8B8C8D8E8F909192939495969798999A9B9C9D9E9F\
    A0A1A2A3A4A5A6A7A8A9AAABACADAEAFB0B1B2B3B4B5B6B7B8B9BABBBCBDBEBF\
    C0C1C2C3C4C5C6C7C8C9CACBCCCDCECFD0D1D2D3D4D5D6D7D8D9DADBDCDDDEDF\
    E0E1E2E3E4E5E6E7E8E9EAEBECEDEEEFF0F1F2F3F4F5F6F7F8F9FAFBFCFDFEFF";

/// Appends `n` as two upper-case hex digits (`{:02X}`).
pub(crate) fn push_hex2(out: &mut String, n: u8) {
    let at = 2 * usize::from(n);
    out.push_str(&HEX_PAIRS[at..at + 2]);
}

/// Appends `n` as four upper-case hex digits (`{:04X}`).
pub(crate) fn push_hex4(out: &mut String, n: u16) {
    let [high, low] = n.to_be_bytes();
    push_hex2(out, high);
    push_hex2(out, low);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_written_by_hand_read_as_formatted() {
        for n in [
            0u32,
            7,
            9,
            10,
            99,
            100,
            101,
            255,
            1_000,
            10_009,
            65_535,
            u32::MAX,
        ] {
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
        for n in 0..=u8::MAX {
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
