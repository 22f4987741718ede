//! The progress of a long `--file`/`--out` transfer: a bar (or, of a length not known, a byte
//! count) on standard error once the transfer has taken longer than a moment, only when
//! standard error is a terminal; cleared when it ends, so the summary line stands alone.

use std::io::{self, IsTerminal, Read, Write};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a transfer runs before its progress shows.
const MOMENT: Duration = Duration::from_millis(500);

/// A reader or writer whose bytes are counted onto a progress bar.
pub struct Counted<T> {
    inner: T,
    bar: ProgressBar,
    started: Instant,
    /// Whether the bar may draw at all (standard error is a terminal).
    shown: bool,
    visible: bool,
}

impl<T> Counted<T> {
    /// `inner`, counted against `length` bytes if it is known.
    pub fn new(inner: T, length: Option<u64>) -> Self {
        let bar = match length {
            Some(length) => {
                ProgressBar::with_draw_target(Some(length), ProgressDrawTarget::hidden())
                    .with_style(
                        ProgressStyle::with_template(
                            "{bar:40} {bytes}/{total_bytes} {bytes_per_sec} {eta}",
                        )
                        .unwrap_or_else(|_| ProgressStyle::default_bar()),
                    )
            }
            None => ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden()).with_style(
                ProgressStyle::with_template("{spinner} {bytes} {bytes_per_sec}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            ),
        };
        Counted {
            inner,
            bar,
            started: Instant::now(),
            shown: io::stderr().is_terminal(),
            visible: false,
        }
    }

    fn count(&mut self, n: usize) {
        self.bar.inc(n as u64);
        if self.shown && !self.visible && self.started.elapsed() >= MOMENT {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.visible = true;
        }
    }

    /// Clears the bar (the transfer is over).
    pub fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl<T: Read> Read for Counted<T> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.count(n);
        Ok(n)
    }
}

impl<T: Write> Write for Counted<T> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.count(n);
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

impl<T> Drop for Counted<T> {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counted_bytes_pass_unchanged_and_are_counted() {
        let data: Vec<u8> = (0..=255).collect();
        let mut reader = Counted::new(data.as_slice(), Some(256));
        let mut read = Vec::new();
        reader.read_to_end(&mut read).unwrap();
        assert_eq!((read.as_slice(), reader.bar.position()), (&data[..], 256));
        let mut writer = Counted::new(Vec::new(), None);
        writer.write_all(&data[..100]).unwrap();
        assert_eq!((writer.inner.len(), writer.bar.position()), (100, 100));
        // Tests run without a terminal on standard error: the bar never shows.
        assert!(!writer.visible);
    }
}
