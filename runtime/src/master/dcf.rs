//! The order in which a master downloads a node's configuration (a DCF's ParameterValues, a
//! concise DCF) so that no PDO runs half-configured: other entries first, then the PDOs disabled
//! (COB-ID bit 31), their communication parameters, each mapping cleared, filled and counted,
//! and the PDOs enabled with their final COB-IDs last (CiA 301 §7.5.2.35–38, CiA 302-2).

use crate::wire::sdo::Multiplexer;

use super::pdo::COB_ID_INVALID;

/// A value to write: the configuration's own bytes, or a word this order puts in between.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepValue<'a> {
    /// The configured value, as given.
    Bytes(&'a [u8]),
    /// A value of this order: a disabled COB-ID or a mapping count of 0, in `len` bytes.
    Word(u32, u8),
}

impl StepValue<'_> {
    /// Calls `f` with the value's bytes.
    pub fn with_bytes<R>(&self, f: impl FnOnce(&[u8]) -> R) -> R {
        match *self {
            StepValue::Bytes(bytes) => f(bytes),
            StepValue::Word(word, len) => {
                let bytes = word.to_le_bytes();
                f(&bytes[..usize::from(len).min(4)])
            }
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Area {
    Other,
    PdoCommunication,
    PdoMapping,
}

fn area(index: u16) -> Area {
    match index {
        0x1400..=0x15FF | 0x1800..=0x19FF => Area::PdoCommunication,
        0x1600..=0x17FF | 0x1A00..=0x1BFF => Area::PdoMapping,
        _ => Area::Other,
    }
}

/// What pass `pass` of the order writes for one configured entry, if anything.
fn step<'a>(pass: u8, mux: Multiplexer, value: &'a [u8]) -> Option<(Multiplexer, StepValue<'a>)> {
    let as_is = Some((mux, StepValue::Bytes(value)));
    let cob_id = || {
        let mut word = [0u8; 4];
        let n = value.len().min(4);
        word[..n].copy_from_slice(&value[..n]);
        u32::from_le_bytes(word)
    };
    match (pass, area(mux.index), mux.sub) {
        (0, Area::Other, _) => as_is,
        (1, Area::PdoCommunication, 1) => {
            Some((mux, StepValue::Word(cob_id() | COB_ID_INVALID, 4)))
        }
        (2, Area::PdoCommunication, sub) if sub > 1 => as_is,
        (3, Area::PdoMapping, 0) => Some((mux, StepValue::Word(0, 1))),
        (4, Area::PdoMapping, sub) if sub > 0 => as_is,
        (5, Area::PdoMapping, 0) | (6, Area::PdoCommunication, 1) => as_is,
        _ => None,
    }
}

/// The writes of a configuration in the safe order. `entries` are (entry, value bytes); a
/// PDO's COB-ID and mapping count appear twice (disabled or cleared first, final last).
pub fn download_order<'a, V: AsRef<[u8]>>(
    entries: &'a [(Multiplexer, V)],
) -> impl Iterator<Item = (Multiplexer, StepValue<'a>)> + 'a {
    (0..7u8).flat_map(move |pass| {
        entries
            .iter()
            .filter_map(move |(mux, value)| step(pass, *mux, value.as_ref()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pdos_are_disabled_cleared_mapped_counted_and_enabled_in_that_order() {
        let m = Multiplexer::new;
        let entries: [(Multiplexer, &[u8]); 6] = [
            (m(0x1017, 0), &[100, 0]),
            (m(0x1800, 1), &[0x93, 0x01, 0, 0]),
            (m(0x1800, 2), &[254]),
            (m(0x1A00, 0), &[1]),
            (m(0x1A00, 1), &[0x10, 0, 0x41, 0x60]),
            (m(0x6060, 0), &[2]),
        ];
        let mut order = [(m(0, 0), StepValue::Word(0, 0)); 9];
        let mut n = 0;
        for step in download_order(&entries) {
            order[n] = step;
            n += 1;
        }
        assert_eq!(
            order[..n],
            [
                (m(0x1017, 0), StepValue::Bytes(&[100, 0])),
                (m(0x6060, 0), StepValue::Bytes(&[2])),
                (m(0x1800, 1), StepValue::Word(0x8000_0193, 4)),
                (m(0x1800, 2), StepValue::Bytes(&[254])),
                (m(0x1A00, 0), StepValue::Word(0, 1)),
                (m(0x1A00, 1), StepValue::Bytes(&[0x10, 0, 0x41, 0x60])),
                (m(0x1A00, 0), StepValue::Bytes(&[1])),
                (m(0x1800, 1), StepValue::Bytes(&[0x93, 0x01, 0, 0])),
            ]
        );
    }
}
