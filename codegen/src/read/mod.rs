//! Readers: bytes of a description file into a [`Device`], never failing on content.
//!
//! Reading is lenient and lossless: every dialect seen in real vendor files is accepted and
//! reported as a diagnostic; nothing is dropped silently. Only I/O problems are errors.

use std::path::{Path, PathBuf};

use crate::diag::Diagnostic;
use crate::model::{Device, Format};

pub mod eds;
pub mod ini;
pub mod text;
pub mod value;
pub mod xdd;

/// What a reader produced: the model, the diagnostics about the text, and the decoded text (for
/// rendering diagnostics against it).
#[derive(Debug, Clone)]
pub struct Read {
    /// The device model.
    pub device: Device,
    /// Diagnostics found while reading (lexical problems, dialects, unparseable values).
    pub diagnostics: Vec<Diagnostic>,
    /// The decoded file text.
    pub text: String,
}

/// A file could not be read at all.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be opened or read.
    Io(PathBuf, std::io::Error),
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::Io(path, err) => write!(f, "cannot read `{}`: {err}", path.display()),
        }
    }
}

impl std::error::Error for ReadError {}

/// Reads a description file from disk; the format comes from the extension, or the content.
pub fn read_file(path: &Path) -> Result<Read, ReadError> {
    let bytes = std::fs::read(path).map_err(|e| ReadError::Io(path.to_path_buf(), e))?;
    Ok(read_bytes(path, &bytes))
}

/// Reads a description from bytes; `path` names it (and its extension picks the format).
pub fn read_bytes(path: &Path, bytes: &[u8]) -> Read {
    let mut read = match detect_format(path, bytes) {
        Format::Eds | Format::Dcf => eds::read(path, bytes),
        Format::Xdd | Format::Xdc => xdd::read(path, bytes),
    };
    value::aggregate_dialects(&mut read.diagnostics);
    read
}

/// The format of a file: by extension (case-insensitive), else XML if the first non-blank byte
/// (after a BOM) is `<`, else EDS.
pub fn detect_format(path: &Path, bytes: &[u8]) -> Format {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("eds") => Format::Eds,
        Some("dcf") => Format::Dcf,
        Some("xdd") => Format::Xdd,
        Some("xdc") => Format::Xdc,
        _ => {
            let body = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
            match body.iter().find(|b| !b.is_ascii_whitespace()) {
                Some(b'<') => Format::Xdd,
                _ => Format::Eds,
            }
        }
    }
}
