//! Readers: bytes of a description file into a [`Device`], never failing on content.
//!
//! Reading is lenient and lossless: every dialect seen in real vendor files is accepted and
//! reported as a diagnostic; nothing is dropped silently. Only I/O problems are errors.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use crate::diag::Diagnostic;
use crate::model::{Device, Format, Span, TextEncoding};
use crate::rules;

pub mod eds;
pub mod esi;
pub mod gsd;
pub mod gsdml;
pub mod hash;
pub mod ini;
pub mod odva;
pub mod sii;
pub mod text;
pub mod value;
pub mod xdd;
mod xml;

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

impl Read {
    /// Whether nothing could be read: the file is empty, not text, or not well-formed XML, or an
    /// ESI file has no device (or none the choice names). The model is then empty, and showing
    /// it (`edsgen dump`) would say nothing true.
    pub fn nothing_read(&self) -> bool {
        self.diagnostics.iter().any(|d| {
            [
                &rules::EMPTY_FILE,
                &rules::NOT_TEXT,
                &rules::XML_MALFORMED,
                &rules::ESI_NO_DEVICE,
            ]
            .iter()
            .any(|rule| std::ptr::eq(d.rule, *rule))
                // An SII image too short to hold its header.
                || (std::ptr::eq(d.rule, &rules::SII_IMAGE) && self.device.ethercat().is_none())
        })
    }
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
    read_file_device(path, None)
}

/// Reads a description file, picking one device of an ESI file that describes several (by type
/// name or `#x` product code, see [`esi::DeviceChoice::parse`]); `None` reads the first. Other
/// formats describe one device and ignore the choice.
pub fn read_file_device(path: &Path, device: Option<&str>) -> Result<Read, ReadError> {
    let bytes = std::fs::read(path).map_err(|e| ReadError::Io(path.to_path_buf(), e))?;
    Ok(read_any(path, Cow::Owned(bytes), device))
}

/// Reads a description from bytes; `path` names it (and its extension picks the format).
pub fn read_bytes(path: &Path, bytes: &[u8]) -> Read {
    read_bytes_device(path, bytes, None)
}

/// [`read_bytes`] with a device choice, as [`read_file_device`].
pub fn read_bytes_device(path: &Path, bytes: &[u8], device: Option<&str>) -> Read {
    read_any(path, Cow::Borrowed(bytes), device)
}

/// [`read_bytes_device`] for bytes borrowed or owned: an EDS or DCF file read into owned bytes
/// that are UTF-8 (almost every one) becomes its text without a copy.
fn read_any(path: &Path, bytes: Cow<'_, [u8]>, device: Option<&str>) -> Read {
    if sii::is_sii_path(path) {
        return sii::read(path, &bytes);
    }
    if let Some(read) = not_a_description(path, &bytes) {
        return read;
    }
    let format = detect_format(path, &bytes);
    let bytes = match (format, bytes) {
        (Format::Eds | Format::Dcf, Cow::Owned(owned)) => match text::decode_owned(owned) {
            // UTF-8 text: no DOS code page to guess below, so no bytes are needed there.
            Ok((text, encoding)) => return finish(eds::read_text(path, text, encoding), &[]),
            Err(owned) => Cow::Owned(owned),
        },
        (_, bytes) => bytes,
    };
    let bytes: &[u8] = &bytes;
    let read = match format {
        Format::Eds | Format::Dcf => eds::read(path, bytes),
        Format::Xdd | Format::Xdc => xdd::read(path, bytes),
        Format::Esi => {
            let choice = device.map(esi::DeviceChoice::parse);
            esi::read_device(path, bytes, choice.as_ref())
        }
        Format::OdvaEds => odva::read(path, bytes),
        Format::Gsdml => gsdml::read(path, bytes),
        Format::Gsd => return gsd::read(path, bytes),
    };
    finish(read, bytes)
}

/// What every format but GSD gets after reading: the DOS code page guess for a Windows-1252
/// file (from its `bytes`), and the dialect diagnostics aggregated.
fn finish(mut read: Read, bytes: &[u8]) -> Read {
    if read.device.source.encoding == TextEncoding::Windows1252 {
        if let Some(guess) = dos_code_page_guess(bytes) {
            // The guess says more than "not ASCII" at the same byte: it replaces that one.
            read.diagnostics
                .retain(|d| !(std::ptr::eq(d.rule, &rules::NON_ASCII) && d.span == guess.span));
            read.diagnostics.push(guess);
            crate::diag::sort(&mut read.diagnostics);
        }
    }
    value::aggregate_dialects(&mut read.diagnostics);
    read
}

/// EDS029's help, for the format the file's name (or what little of it reads) says it is.
fn not_text_help(path: &Path, format: Format) -> String {
    let xml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"));
    let what = match format {
        Format::Esi => "an ESI is XML text (an SII image is a `.bin` or `.sii`)",
        Format::Gsdml => "a GSDML is XML text",
        _ if xml => {
            "an XML description (XDD, XDC, ESI or GSDML) is text (an EtherCAT SII image is a \
             `.bin` or `.sii`)"
        }
        Format::Eds | Format::Dcf => "an EDS or DCF is ASCII text",
        Format::OdvaEds => "an ODVA EDS is ASCII text",
        Format::Gsd => "a GSD is ASCII text",
        Format::Xdd | Format::Xdc => "an XDD or XDC is XML text",
    };
    format!("{what}; is this the right file?")
}

/// One diagnostic instead of a reading, for a file that is empty (or only whitespace) or is not
/// text at all: a binary file would otherwise give a diagnostic per "line" of noise, and its bytes
/// would reach the terminal.
fn not_a_description(path: &Path, bytes: &[u8]) -> Option<Read> {
    let diag = if bytes.iter().all(u8::is_ascii_whitespace) {
        let message = if bytes.is_empty() {
            "the file is empty".to_owned()
        } else {
            format!("the file holds only whitespace ({} bytes)", bytes.len())
        };
        Diagnostic::new(&rules::EMPTY_FILE, None, message)
    } else {
        let offset = text::first_nul(bytes)?;
        Diagnostic::new(
            &rules::NOT_TEXT,
            None,
            format!("not a text file: NUL byte at offset {offset}"),
        )
        .with_help(not_text_help(path, detect_format(path, bytes)))
    };
    Some(Read {
        device: eds::empty_device(path, detect_format(path, bytes), TextEncoding::Ascii),
        diagnostics: vec![diag],
        text: String::new(),
    })
}

/// The EDS002 guess that a file read as Windows-1252 was written in a DOS code page.
fn dos_code_page_guess(bytes: &[u8]) -> Option<Diagnostic> {
    let (offset, byte, windows, dos) = text::dos_code_page_guess(bytes)?;
    // Windows-1252 maps each byte to one character: the column counts bytes since the line start.
    let before = &bytes[..offset];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n' || b == b'\r')
        .map_or(0, |i| i + 1);
    let crlf = before.windows(2).filter(|w| w == b"\r\n").count();
    let ends = before.iter().filter(|&&b| b == b'\n' || b == b'\r').count() - crlf;
    let to_u32 = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    Some(
        Diagnostic::new(
            &rules::NON_ASCII,
            Some(Span::new(to_u32(ends + 1), to_u32(offset - line_start + 1), 1)),
            format!(
                "byte {byte:#04X} between two letters reads `{windows}` in Windows-1252 but `{dos}` \
                 in DOS code page 437/850: the file may be in a DOS code page (a guess)"
            ),
        )
        .with_label(format!("shown as Windows-1252 `{windows}`"))
        .with_help("save the file as ASCII or UTF-8"),
    )
}

/// The format of a file: by extension (case-insensitive; `.esi` is ESI; `.gsd` and the GSD
/// language variants `.gse .gsg .gsf .gsi .gss` are GSD), else GSD if the first line that is
/// not blank or a comment is `#Profibus_DP`, else XML if the first
/// non-blank byte (after a BOM) is `<` (ESI when the root element is `EtherCATInfo` or
/// `EtherCATModule`; GSDML when it is `ISO15745Profile` with a `DeviceIdentity`; else XDD),
/// else EDS. An EDS (by extension or content) with a `[File]` or `[Device]` section is ODVA's
/// (CIP), not CiA 306's (`[FileInfo]`, `[DeviceInfo]`).
pub fn detect_format(path: &Path, bytes: &[u8]) -> Format {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("eds") if odva::is_odva(bytes) => Format::OdvaEds,
        Some("eds") => Format::Eds,
        Some("dcf") => Format::Dcf,
        Some("xdd") => Format::Xdd,
        Some("xdc") => Format::Xdc,
        Some("esi") => Format::Esi,
        Some("gsd" | "gse" | "gsg" | "gsf" | "gsi" | "gss") => Format::Gsd,
        _ => {
            let body = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
            if is_gsd_text(body) {
                return Format::Gsd;
            }
            match body.iter().find(|b| !b.is_ascii_whitespace()) {
                Some(b'<') if matches!(root_name(body), "EtherCATInfo" | "EtherCATModule") => {
                    Format::Esi
                }
                Some(b'<') if gsdml::looks_like_gsdml(root_name(body), body) => Format::Gsdml,
                Some(b'<') => Format::Xdd,
                _ if odva::is_odva(bytes) => Format::OdvaEds,
                _ => Format::Eds,
            }
        }
    }
}

/// Whether the first line that is not blank or a `;` comment is `#Profibus_DP`
/// (case-insensitive): a GSD file under another name.
fn is_gsd_text(bytes: &[u8]) -> bool {
    bytes
        .split(|&b| b == b'\n')
        .map(|line| line.trim_ascii())
        .find(|line| !line.is_empty() && !line.starts_with(b";"))
        .is_some_and(|line| line.eq_ignore_ascii_case(b"#Profibus_DP"))
}

/// The local name of an XML file's root element, found by skipping the declaration, processing
/// instructions, comments and a DOCTYPE; empty when there is none.
fn root_name(bytes: &[u8]) -> &str {
    let mut rest = bytes;
    loop {
        let Some(at) = rest.iter().position(|&b| b == b'<') else {
            return "";
        };
        rest = &rest[at..];
        let skip_to: &[u8] = if rest.starts_with(b"<?") {
            b"?>"
        } else if rest.starts_with(b"<!--") {
            b"-->"
        } else if rest.starts_with(b"<!") {
            b">"
        } else {
            let name = &rest[1..];
            let end = name
                .iter()
                .position(|b| b.is_ascii_whitespace() || matches!(b, b'>' | b'/'))
                .unwrap_or(name.len());
            let name = std::str::from_utf8(&name[..end]).unwrap_or("");
            return name.rsplit(':').next().unwrap_or(name);
        };
        match rest.windows(skip_to.len()).position(|w| w == skip_to) {
            Some(end) => rest = &rest[end + skip_to.len()..],
            None => return "",
        }
    }
}
