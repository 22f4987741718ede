//! A fixed-capacity byte queue: the window through which an SDO client streams a value between
//! the caller and the bus, so that a value of any length passes through a buffer of `N` bytes.

/// A ring buffer of `N` bytes.
#[derive(Debug, Clone)]
pub(crate) struct ByteFifo<const N: usize> {
    bytes: [u8; N],
    head: usize,
    len: usize,
}

impl<const N: usize> ByteFifo<N> {
    pub(crate) const fn new() -> Self {
        ByteFifo {
            bytes: [0; N],
            head: 0,
            len: 0,
        }
    }

    /// Bytes queued.
    pub(crate) const fn len(&self) -> usize {
        self.len
    }

    /// Room left.
    pub(crate) const fn free(&self) -> usize {
        N - self.len
    }

    pub(crate) fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }

    /// Appends as much of `data` as fits; returns how much did.
    pub(crate) fn push(&mut self, data: &[u8]) -> usize {
        let n = data.len().min(self.free());
        for (i, byte) in data[..n].iter().enumerate() {
            self.bytes[(self.head + self.len + i) % N] = *byte;
        }
        self.len += n;
        n
    }

    /// Copies queued bytes starting `offset` bytes in into `out`, without taking them.
    pub(crate) fn peek(&self, offset: usize, out: &mut [u8]) -> usize {
        let n = out.len().min(self.len.saturating_sub(offset));
        for (i, byte) in out[..n].iter_mut().enumerate() {
            *byte = self.bytes[(self.head + offset + i) % N];
        }
        n
    }

    /// Drops the first `n` queued bytes.
    pub(crate) fn discard(&mut self, n: usize) {
        let n = n.min(self.len);
        self.head = (self.head + n) % N.max(1);
        self.len -= n;
    }

    /// Fills the empty queue through `fill`, which gets the whole buffer and says how many
    /// bytes it wrote (`None`: none).
    pub(crate) fn fill_with(
        &mut self,
        fill: impl FnOnce(&mut [u8]) -> Option<usize>,
    ) -> Option<usize> {
        self.clear();
        let n = fill(&mut self.bytes)?.min(N);
        self.len = n;
        Some(n)
    }

    /// The queued bytes as one slice (rotating them to the front first).
    pub(crate) fn contiguous(&mut self) -> &[u8] {
        self.bytes.rotate_left(self.head);
        self.head = 0;
        &self.bytes[..self.len]
    }

    /// Takes queued bytes into `out`; returns how many.
    pub(crate) fn pop(&mut self, out: &mut [u8]) -> usize {
        let n = self.peek(0, out);
        self.discard(n);
        n
    }
}

#[cfg(test)]
mod tests {
    use super::ByteFifo;

    #[test]
    fn bytes_wrap_around_the_end_in_order() {
        let mut fifo = ByteFifo::<4>::new();
        assert_eq!(fifo.push(&[1, 2, 3]), 3);
        let mut out = [0; 2];
        assert_eq!(fifo.pop(&mut out), 2);
        assert_eq!(out, [1, 2]);
        assert_eq!(fifo.push(&[4, 5, 6, 7]), 3);
        let mut peeked = [0; 2];
        assert_eq!(fifo.peek(1, &mut peeked), 2);
        assert_eq!(peeked, [4, 5]);
        let mut all = [0; 8];
        assert_eq!(fifo.pop(&mut all), 4);
        assert_eq!(&all[..4], &[3, 4, 5, 6]);
        assert_eq!(fifo.len(), 0);
    }
}
