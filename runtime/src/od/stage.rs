//! The staging room of a dictionary: where an SDO download of a string, octet string or domain
//! collects until the transfer completes, so that the value changes all at once or not at all
//! (the streaming steps of [`ObjectDictionary`](crate::ObjectDictionary): begin, write, commit,
//! abort). A generated dictionary holds one, sized at generation time to its largest writable
//! value.

use crate::od::SdoAbort;

/// Room for one download of up to `N` bytes, and which entry it is for.
///
/// Two stages compare equal whatever they hold: the bytes are scratch, not a value of the
/// dictionary, so a dictionary that derives `PartialEq` compares its values only.
#[derive(Debug, Clone)]
pub struct Stage<const N: usize> {
    bytes: [u8; N],
    /// The position of the entry whose download is open, if one is.
    open: Option<u16>,
}

impl<const N: usize> Stage<N> {
    /// An empty stage with no download open.
    pub const fn new() -> Self {
        Stage {
            bytes: [0; N],
            open: None,
        }
    }

    /// `ObjectDictionary::begin_write`: opens a download into the entry at `position`.
    /// `NoResource` (060A 0023) while another is open: one stage serves one SDO channel at a
    /// time.
    pub fn begin(&mut self, position: usize) -> Result<(), SdoAbort> {
        if self.open.is_some() {
            return Err(SdoAbort::NoResource);
        }
        self.open = Some(u16::try_from(position).map_err(|_| SdoAbort::NoObject)?);
        Ok(())
    }

    /// `ObjectDictionary::write_part`: keeps `data` at `offset` of the open download into the
    /// entry at `position`. `General` when no download into it is open, `OutOfMemory` past
    /// the stage's `N` bytes.
    pub fn write(&mut self, position: usize, offset: usize, data: &[u8]) -> Result<(), SdoAbort> {
        self.check(position)?;
        self.bytes
            .get_mut(offset..offset + data.len())
            .ok_or(SdoAbort::OutOfMemory)?
            .copy_from_slice(data);
        Ok(())
    }

    /// `ObjectDictionary::commit_write`: closes the download into the entry at `position` and
    /// returns its first `len` bytes, which the dictionary writes as the value.
    pub fn commit(&mut self, position: usize, len: usize) -> Result<&[u8], SdoAbort> {
        self.check(position)?;
        self.open = None;
        self.bytes.get(..len).ok_or(SdoAbort::OutOfMemory)
    }

    /// `ObjectDictionary::abort_write`: closes the download into the entry at `position`, its
    /// bytes discarded; nothing if no download into it is open.
    pub fn abort(&mut self, position: usize) {
        if self.check(position).is_ok() {
            self.open = None;
        }
    }

    /// Whether a download is open.
    pub const fn is_open(&self) -> bool {
        self.open.is_some()
    }

    fn check(&self, position: usize) -> Result<(), SdoAbort> {
        match self.open {
            Some(open) if usize::from(open) == position => Ok(()),
            _ => Err(SdoAbort::General),
        }
    }
}

impl<const N: usize> Default for Stage<N> {
    fn default() -> Self {
        Stage::new()
    }
}

impl<const N: usize> PartialEq for Stage<N> {
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_committed_download_hands_back_its_bytes_and_closes() {
        let mut stage = Stage::<8>::new();
        stage.begin(3).unwrap();
        stage.write(3, 0, b"abc").unwrap();
        stage.write(3, 3, b"de").unwrap();
        assert_eq!(stage.commit(3, 5).unwrap(), b"abcde");
        assert!(!stage.is_open());
    }

    #[test]
    fn one_download_at_a_time_the_second_refused_with_no_resource() {
        let mut stage = Stage::<8>::new();
        stage.begin(3).unwrap();
        assert_eq!(stage.begin(4), Err(SdoAbort::NoResource));
        // The second channel's pieces cannot reach the first's download.
        assert_eq!(stage.write(4, 0, b"x"), Err(SdoAbort::General));
        stage.abort(4);
        assert!(stage.is_open());
        stage.abort(3);
        assert!(!stage.is_open());
        stage.begin(4).unwrap();
    }

    #[test]
    fn pieces_past_the_room_are_out_of_memory() {
        let mut stage = Stage::<4>::new();
        stage.begin(0).unwrap();
        assert_eq!(stage.write(0, 2, b"abc"), Err(SdoAbort::OutOfMemory));
        assert_eq!(stage.commit(0, 5), Err(SdoAbort::OutOfMemory));
        assert!(!stage.is_open());
        assert_eq!(stage.commit(0, 0), Err(SdoAbort::General));
    }
}
