//! SYNC frame layout (CiA 301 §7.2.5.3): no data, or one byte with the counter (1..=240) when the
//! synchronous counter overflow value (1019h) is not zero.

/// The pre-defined SYNC COB-ID (1005h's default).
pub const SYNC_COB_ID: u16 = 0x080;

/// A SYNC message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SyncRepr {
    /// The counter, if the message carries one.
    pub counter: Option<u8>,
}

impl SyncRepr {
    /// Parses the data bytes. `None` unless there are zero bytes or one.
    #[inline]
    pub fn parse(data: &[u8]) -> Option<Self> {
        match *data {
            [] => Some(SyncRepr { counter: None }),
            [counter] => Some(SyncRepr {
                counter: Some(counter),
            }),
            _ => None,
        }
    }

    /// The data bytes and their number.
    #[inline]
    pub const fn emit(&self) -> ([u8; 1], usize) {
        match self.counter {
            Some(counter) => ([counter], 1),
            None => ([0], 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sync_with_and_without_counter() {
        assert_eq!(SyncRepr::parse(&[]), Some(SyncRepr { counter: None }));
        assert_eq!(SyncRepr::parse(&[7]), Some(SyncRepr { counter: Some(7) }));
        assert_eq!(SyncRepr { counter: Some(7) }.emit(), ([7], 1));
        assert_eq!(SyncRepr { counter: None }.emit().1, 0);
        assert_eq!(SyncRepr::parse(&[1, 2]), None);
    }
}
