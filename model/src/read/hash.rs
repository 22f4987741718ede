//! Hashing for the readers' lookup tables: a fast non-cryptographic hasher (their keys are short
//! names) and names compared ignoring ASCII case.

use std::hash::{BuildHasherDefault, Hasher};

/// A small, fast, non-cryptographic hasher (the Fx scheme) for the reader's lookup tables, whose
/// keys are short names; the standard SipHash showed up in profiles.
#[derive(Debug, Default, Clone, Copy)]
pub struct FxHasher {
    hash: u64,
}

impl FxHasher {
    fn add(&mut self, word: u64) {
        const SEED: u64 = 0x51_7c_c1_b7_27_22_0a_95;
        self.hash = (self.hash.rotate_left(5) ^ word).wrapping_mul(SEED);
    }
}

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
        let tail = chunks.remainder();
        if !tail.is_empty() {
            let mut word = [0u8; 8];
            word[..tail.len()].copy_from_slice(tail);
            self.add(u64::from_le_bytes(word));
        }
    }

    fn write_u8(&mut self, n: u8) {
        self.add(u64::from(n));
    }

    fn write_u16(&mut self, n: u16) {
        self.add(u64::from(n));
    }

    fn write_u32(&mut self, n: u32) {
        self.add(u64::from(n));
    }

    fn write_u64(&mut self, n: u64) {
        self.add(n);
    }

    fn write_usize(&mut self, n: usize) {
        self.add(n as u64);
    }

    fn finish(&self) -> u64 {
        self.hash
    }
}

/// The [`std::hash::BuildHasher`] of [`FxHasher`].
pub type FastHash = BuildHasherDefault<FxHasher>;

/// A name hashed and compared ignoring ASCII case, borrowed from the text.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Caseless<'t>(pub(crate) &'t str);

impl PartialEq for Caseless<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.0.eq_ignore_ascii_case(other.0)
    }
}

impl Eq for Caseless<'_> {}

impl std::hash::Hash for Caseless<'_> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        // The length and the first and last eight bytes, lowercased, as two words: a word at a
        // time, not a byte. Names that agree in all three are rare, and are told apart by `eq`.
        let bytes = self.0.as_bytes();
        state.write_usize(bytes.len());
        state.write_u64(lowercase_word(bytes));
        if let Some(tail) = bytes.len().checked_sub(8).and_then(|at| bytes.get(at..)) {
            state.write_u64(lowercase_word(tail));
        }
    }
}

/// Up to the first eight bytes, ASCII-lowercased, as one word (first byte lowest).
fn lowercase_word(bytes: &[u8]) -> u64 {
    let mut word = [0u8; 8];
    let len = bytes.len().min(8);
    word[..len].copy_from_slice(&bytes[..len]);
    let word = u64::from_le_bytes(word);
    // All eight bytes at once: a byte gets 20h added when it is `A`..=`Z`. Each sum stays
    // within its byte (7Fh + 3Fh < 100h); its high bit says whether the byte's low seven bits
    // are at least 41h (`A`), or at least 5Bh (past `Z`). Bytes of 80h and above stay as they are.
    const ONES: u64 = 0x0101_0101_0101_0101;
    let low7 = word & (ONES * 0x7F);
    let from_a = low7 + ONES * (0x80 - 0x41);
    let past_z = low7 + ONES * (0x80 - 0x5B);
    let upper = from_a & !past_z & !word & (ONES * 0x80);
    word | (upper >> 2)
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::{Caseless, FastHash};

    #[test]
    fn names_that_differ_in_case_only_are_one_key() {
        let names = [
            "",
            "1",
            "a",
            "1000",
            "1000sub1",
            "1A00sub10",
            "DeviceInfo",
            "ParameterName",
            "ParameterNameX",
            "parameternamey",
        ];
        let mut at: HashMap<Caseless, usize, FastHash> = HashMap::default();
        for (i, name) in names.iter().enumerate() {
            assert_eq!(at.insert(Caseless(name), i), None, "{name}");
        }
        for (i, name) in names.iter().enumerate() {
            let upper = name.to_ascii_uppercase();
            assert_eq!(at.get(&Caseless(&upper)), Some(&i), "{upper}");
        }
        assert_eq!(at.get(&Caseless("ParameterNamey")), Some(&9));
        assert_eq!(at.get(&Caseless("1A00sub11")), None);
    }

    #[test]
    fn a_word_is_lowercased_as_its_bytes_are() {
        for byte in 0..=255u8 {
            let bytes = [byte, b'Z', byte, b'@', b'[', byte, b'a', byte];
            let expected = u64::from_le_bytes(bytes.map(|b| b.to_ascii_lowercase()));
            assert_eq!(super::lowercase_word(&bytes), expected, "{byte:#04x}");
        }
        assert_eq!(
            super::lowercase_word(b"AB"),
            u64::from_le_bytes(*b"ab\0\0\0\0\0\0")
        );
    }
}
