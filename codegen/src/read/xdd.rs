//! XDD and XDC reader (CiA 311). Placeholder until the reader lands.

use std::path::Path;

use super::Read;
use crate::model::Format;

/// Reads an XDD or XDC file.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = super::text::decode(bytes);
    Read {
        device: super::eds::empty_device(path, Format::Xdd, encoding),
        diagnostics: Vec::new(),
        text,
    }
}
