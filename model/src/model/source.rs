//! Where the model came from: spans (line, column, length) into the source file, and the file's
//! format and text encoding.

use std::path::PathBuf;

/// A place in the source file: 1-based line and column (in characters), and a length in
/// characters (0 when only a position is known).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Span {
    /// 1-based line number.
    pub line: u32,
    /// 1-based column, counted in characters.
    pub column: u32,
    /// Length in characters of the spanned text on that line (0: a position only).
    pub len: u32,
}

impl Span {
    /// A span of `len` characters at `line`:`column`.
    pub const fn new(line: u32, column: u32, len: u32) -> Self {
        Span { line, column, len }
    }
}

/// A value together with where it was read.
#[derive(Debug, Clone, PartialEq)]
pub struct Spanned<T> {
    /// The value.
    pub value: T,
    /// Where it was read.
    pub span: Span,
}

impl<T> Spanned<T> {
    /// Pairs a value with its span.
    pub const fn new(value: T, span: Span) -> Self {
        Spanned { value, span }
    }
}

/// The kind of description file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Electronic data sheet (CiA 306).
    Eds,
    /// Device configuration file (CiA 306), an EDS with configured values.
    Dcf,
    /// XML device description (CiA 311).
    Xdd,
    /// XML device configuration (CiA 311).
    Xdc,
    /// EtherCAT Slave Information (ETG.2000): a CoE dictionary and the EtherCAT layout
    /// ([`Device::ethercat`](super::Device::ethercat)).
    Esi,
    /// ODVA EDS (EtherNet/IP, DeviceNet): a CIP device ([`Device::cip`](super::Device::cip)),
    /// told from a CiA 306 EDS by its `[File]`/`[Device]` sections.
    OdvaEds,
    /// PROFINET GSDML (`ISO15745Profile`): identity, access points, modules and records
    /// ([`Device::profinet`](super::Device::profinet)).
    Gsdml,
    /// PROFIBUS-DP device description (GSD, the PNO's specification): the DP part
    /// ([`Device::dp`](super::Device::dp)).
    Gsd,
}

// What a format's files are, each answered by an exhaustive match: a new format makes every
// rule that depends on these properties decide, instead of falling into a `!=` branch.
impl Format {
    /// Whether the dictionary is CANopen over EtherCAT (CoE, from an ESI): no COB-IDs, no NMT
    /// error control, no mandatory 1001h, and PDOs assigned through 1C1xh.
    pub fn is_coe(self) -> bool {
        match self {
            Format::Esi => true,
            Format::Eds | Format::Dcf | Format::Xdd | Format::Xdc => false,
            Format::OdvaEds | Format::Gsdml | Format::Gsd => false,
        }
    }

    /// Whether the file configures one device (DCF, XDC: values and commissioning) rather than
    /// describing a product.
    pub fn is_configuration(self) -> bool {
        match self {
            Format::Dcf | Format::Xdc => true,
            Format::Eds | Format::Xdd | Format::Esi => false,
            Format::OdvaEds | Format::Gsdml | Format::Gsd => false,
        }
    }
}

/// How the file's bytes were decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextEncoding {
    /// Only ASCII bytes.
    Ascii,
    /// Valid UTF-8 with non-ASCII characters.
    Utf8,
    /// UTF-8 with a byte-order mark.
    Utf8Bom,
    /// Not valid UTF-8; decoded as Windows-1252.
    Windows1252,
    /// ISO-8859-1, as the XML declaration says (an ESI file): each byte is one character.
    Latin1,
    /// UTF-16, little-endian (with a byte-order mark, or ASCII text with every second byte 0).
    Utf16Le,
    /// UTF-16, big-endian.
    Utf16Be,
}

/// Where the device came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Source {
    /// The path as given by the user.
    pub path: PathBuf,
    /// The file format.
    pub format: Format,
    /// The text encoding that was detected.
    pub encoding: TextEncoding,
}
