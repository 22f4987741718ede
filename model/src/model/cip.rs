//! The CIP side of an ODVA EDS (EtherNet/IP, DeviceNet): identity, parameters and their
//! enumerations, assemblies with their members, the connections of `[Connection Manager]` with
//! their trigger/transport and connection-parameter words decoded, ports and capacity.
//!
//! Every entry keeps the span of its key and of each field, so a diagnostic can point at the exact
//! field of an entry that spans many lines.

use std::collections::BTreeMap;

use super::cip_path::{decode_path, PathSegment};
use super::{Span, Spanned};

/// What an ODVA EDS says about a CIP device.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cip {
    /// `[File]`.
    pub file: CipFile,
    /// `[Device]`: the Identity object's attributes.
    pub identity: CipIdentity,
    /// `[Device Classification]` `ClassN` values (`EtherNetIP`, `DeviceNet`, ...), in order.
    pub classifications: Vec<Spanned<String>>,
    /// `[Params]` `ParamN`, by N.
    pub params: BTreeMap<u32, CipParam>,
    /// `[Params]` (or `[EnumPar]`) `EnumN`: the named values of parameter N, by N.
    pub enums: BTreeMap<u32, CipEnum>,
    /// `[Assembly]` `AssemN`, by N (the Assembly object's instance number).
    pub assemblies: BTreeMap<u32, CipAssembly>,
    /// `[Connection Manager]` `ConnectionN`, by N.
    pub connections: BTreeMap<u32, CipConnection>,
    /// `[Port]` `PortN`, by N.
    pub ports: BTreeMap<u32, CipPort>,
    /// `[Capacity]` entries as written (`MaxIOConnections`, `TSpecN`, ...), in file order.
    pub capacity: Vec<CipEntry>,
    /// What an overlay says: the assemblies that carry the Goodrive350's PKW/PZD images.
    pub pkw_pzd: Option<PkwPzdImages>,
    /// The class sections (`[Identity Class]`, `[TCP/IP Interface Class]`, `[ClassN_VendorM]`, ...)
    /// and any other section, with their entries as written, in file order.
    pub other_sections: Vec<CipSection>,
}

/// The assemblies that carry the 16-word PKW/PZD images of `edsgen_runtime::pkw_pzd` (an
/// overlay's `[pkw_pzd]`: an EDS cannot say that words are a protocol of their own).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PkwPzdImages {
    /// `AssemN` of the scanner's image (PKW request, CW, PZD2-PZD12).
    pub output: u32,
    /// `AssemN` of the drive's image (PKW response, SW, PZD2-PZD12).
    pub input: u32,
    /// Whether words are little-endian (CIP's order), else big-endian.
    pub little_endian: bool,
}

/// One field of an entry, as written: the text without quotes (adjacent quoted strings joined).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Field {
    /// The text (trimmed; for a quoted string, its content).
    pub text: String,
    /// Whether it was a quoted string.
    pub quoted: bool,
    /// Where it is (its first line; the length on that line).
    pub span: Span,
}

impl Field {
    /// Whether nothing is written in the field.
    pub fn is_empty(&self) -> bool {
        self.text.is_empty() && !self.quoted
    }
}

/// An entry kept as written: `Key = field, field, ...;`.
#[derive(Debug, Clone, PartialEq)]
pub struct CipEntry {
    /// The key as written.
    pub key: String,
    /// Where the key is.
    pub span: Span,
    /// The fields.
    pub fields: Vec<Field>,
}

/// A section kept as written.
#[derive(Debug, Clone, PartialEq)]
pub struct CipSection {
    /// The name as written (without brackets).
    pub name: String,
    /// The header's span.
    pub span: Span,
    /// The entries in file order.
    pub entries: Vec<CipEntry>,
}

/// `[File]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CipFile {
    /// DescText.
    pub desc_text: Option<String>,
    /// CreateDate (`mm-dd-yyyy`).
    pub create_date: Option<String>,
    /// ModDate.
    pub mod_date: Option<String>,
    /// Revision (`major.minor`).
    pub revision: Option<String>,
    /// Where the section header is.
    pub span: Option<Span>,
}

/// `[Device]`: the identity a scanner matches against the Identity object (class 1).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CipIdentity {
    /// VendCode (attribute 1).
    pub vendor_code: Option<Spanned<u16>>,
    /// VendName.
    pub vendor_name: Option<String>,
    /// ProdType (attribute 2, the device type).
    pub product_type: Option<Spanned<u16>>,
    /// ProdTypeStr.
    pub product_type_str: Option<String>,
    /// ProdCode (attribute 3).
    pub product_code: Option<Spanned<u16>>,
    /// MajRev (attribute 4, first byte).
    pub major_revision: Option<Spanned<u8>>,
    /// MinRev (attribute 4, second byte).
    pub minor_revision: Option<Spanned<u8>>,
    /// ProdName (attribute 7).
    pub product_name: Option<String>,
    /// Catalog.
    pub catalog: Option<String>,
    /// Where the section header is.
    pub span: Option<Span>,
}

/// A number or a reference, as fields of assemblies and connections hold them.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldRef {
    /// Nothing written.
    Empty,
    /// A number.
    Number(u64),
    /// `ParamN`.
    Param(u32),
    /// `AssemN`.
    Assem(u32),
    /// Anything else, as written.
    Other(String),
}

/// A numeric value of a parameter (limit or default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CipNumber {
    /// An integer.
    Int(i128),
    /// A real number.
    Real(f64),
}

impl CipNumber {
    /// The value as a real number, for comparisons across kinds.
    pub fn as_f64(self) -> f64 {
        match self {
            // Limits fit a 64-bit type: the precision lost above 2^53 does not change an order.
            CipNumber::Int(v) => v as f64,
            CipNumber::Real(v) => v,
        }
    }
}

/// `ParamN`.
#[derive(Debug, Clone, PartialEq)]
pub struct CipParam {
    /// N.
    pub number: u32,
    /// Where the key is.
    pub span: Span,
    /// The link path (hex bytes), when written.
    pub link_path: Option<Spanned<String>>,
    /// The descriptor word (bit 4: read only, ...).
    pub descriptor: Option<Spanned<u32>>,
    /// The CIP data type code (0xC1 BOOL .. 0xDA SHORT_STRING).
    pub data_type: Option<Spanned<u8>>,
    /// The data size in bytes.
    pub data_size: Option<Spanned<u32>>,
    /// The name.
    pub name: String,
    /// The units.
    pub units: String,
    /// The help text.
    pub help: String,
    /// The minimum.
    pub min: Option<Spanned<CipNumber>>,
    /// The maximum.
    pub max: Option<Spanned<CipNumber>>,
    /// The default.
    pub default: Option<Spanned<CipNumber>>,
    /// Scaling multiplier, divisor, base and offset (the engineering value is
    /// `(value + offset) * mult * base / div`), where written.
    pub scaling: [Option<i64>; 4],
    /// Decimal places to show.
    pub decimals: Option<u32>,
}

impl CipParam {
    /// Whether the descriptor marks the parameter read-only (bit 4).
    pub fn read_only(&self) -> bool {
        self.descriptor
            .as_ref()
            .is_some_and(|d| d.value & 0x10 != 0)
    }
}

/// `EnumN = value, "text", value, "text", ...;`.
#[derive(Debug, Clone, PartialEq)]
pub struct CipEnum {
    /// N: the parameter it names values of.
    pub number: u32,
    /// Where the key is.
    pub span: Span,
    /// (value, text) pairs in order.
    pub values: Vec<(i64, String)>,
}

/// One member of an assembly: a bit count and what fills the bits.
#[derive(Debug, Clone, PartialEq)]
pub struct AssemblyMember {
    /// The member's size in bits (empty: the size of what it names).
    pub bits: Option<u32>,
    /// `ParamN`, `AssemN`, or empty (padding).
    pub member: FieldRef,
    /// Where the bit count is written.
    pub span: Span,
}

/// `AssemN`.
#[derive(Debug, Clone, PartialEq)]
pub struct CipAssembly {
    /// N: the instance number.
    pub number: u32,
    /// Where the key is.
    pub span: Span,
    /// The name.
    pub name: String,
    /// The path, when written (else instance N of class 4).
    pub path: Option<Spanned<String>>,
    /// The size in bytes, when written (else the members' sum).
    pub size: Option<Spanned<u32>>,
    /// The descriptor word (bit 0: writable, ...).
    pub descriptor: Option<Spanned<u32>>,
    /// The members in order.
    pub members: Vec<AssemblyMember>,
}

impl CipAssembly {
    /// The Assembly object instance: the one its path names (class 4), else N.
    pub fn instance(&self) -> u32 {
        let from_path = self.path.as_ref().and_then(|p| {
            let segments = decode_path(&p.value).ok()?;
            let mut assembly = false;
            segments.iter().find_map(|s| match *s {
                PathSegment::Class(c) => {
                    assembly = c == 4;
                    None
                }
                PathSegment::Instance(i) if assembly => Some(i),
                _ => None,
            })
        });
        from_path.unwrap_or(self.number)
    }

    /// The members' total size in bits, when every member has a bit count.
    pub fn member_bits(&self) -> Option<u64> {
        self.members
            .iter()
            .map(|m| m.bits.map(u64::from))
            .sum::<Option<u64>>()
    }
}

/// The trigger and transport word of a connection (`0x84010002`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriggerTransport(pub u32);

impl TriggerTransport {
    /// The transport classes supported (bits 0-15: bit N is class N).
    pub fn classes(self) -> Vec<u8> {
        (0..16).filter(|b| self.0 & (1 << b) != 0).collect()
    }
    /// The triggers supported: `cyclic`, `change-of-state`, `application`.
    pub fn triggers(self) -> Vec<&'static str> {
        [(16, "cyclic"), (17, "change-of-state"), (18, "application")]
            .into_iter()
            .filter(|(b, _)| self.0 & (1 << b) != 0)
            .map(|(_, n)| n)
            .collect()
    }
    /// The connection's application type: `listen-only`, `input-only`, `exclusive-owner`,
    /// `redundant-owner` (bits 24-27), several when several are set.
    pub fn application_types(self) -> Vec<&'static str> {
        [
            (24, "listen-only"),
            (25, "input-only"),
            (26, "exclusive-owner"),
            (27, "redundant-owner"),
        ]
        .into_iter()
        .filter(|(b, _)| self.0 & (1 << b) != 0)
        .map(|(_, n)| n)
        .collect()
    }
    /// Bit 31: the device is the server (target) of the connection.
    pub fn server(self) -> bool {
        self.0 & (1 << 31) != 0
    }
}

/// The connection parameters word of a connection (`0x44640405`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConnectionParams(pub u32);

/// A real-time transfer format (connection parameters bits 8-10 and 12-14).
pub fn real_time_format_name(format: u8) -> &'static str {
    match format {
        0 => "modeless",
        1 => "zero-length idle",
        2 => "reserved (2)",
        3 => "heartbeat",
        4 => "32-bit run/idle header",
        5 => "safety",
        _ => "reserved",
    }
}

impl ConnectionParams {
    /// O→T fixed size supported (bit 0).
    pub fn o_t_fixed(self) -> bool {
        self.0 & 1 != 0
    }
    /// O→T variable size supported (bit 1).
    pub fn o_t_variable(self) -> bool {
        self.0 & 2 != 0
    }
    /// T→O fixed size supported (bit 2).
    pub fn t_o_fixed(self) -> bool {
        self.0 & 4 != 0
    }
    /// T→O variable size supported (bit 3).
    pub fn t_o_variable(self) -> bool {
        self.0 & 8 != 0
    }
    /// O→T real-time transfer format (bits 8-10; 4 is the 32-bit run/idle header).
    pub fn o_t_format(self) -> u8 {
        ((self.0 >> 8) & 7) as u8
    }
    /// T→O real-time transfer format (bits 12-14).
    pub fn t_o_format(self) -> u8 {
        ((self.0 >> 12) & 7) as u8
    }
    /// O→T connection types (bits 16-18): `null`, `multicast`, `point-to-point`.
    pub fn o_t_types(self) -> Vec<&'static str> {
        Self::types(self.0 >> 16)
    }
    /// T→O connection types (bits 20-22).
    pub fn t_o_types(self) -> Vec<&'static str> {
        Self::types(self.0 >> 20)
    }
    /// O→T priorities (bits 24-26): `low`, `high`, `scheduled`.
    pub fn o_t_priorities(self) -> Vec<&'static str> {
        Self::priorities(self.0 >> 24)
    }
    /// T→O priorities (bits 28-30).
    pub fn t_o_priorities(self) -> Vec<&'static str> {
        Self::priorities(self.0 >> 28)
    }
    fn types(nibble: u32) -> Vec<&'static str> {
        ["null", "multicast", "point-to-point"]
            .into_iter()
            .enumerate()
            .filter(|(b, _)| nibble & (1 << b) != 0)
            .map(|(_, n)| n)
            .collect()
    }
    fn priorities(nibble: u32) -> Vec<&'static str> {
        ["low", "high", "scheduled"]
            .into_iter()
            .enumerate()
            .filter(|(b, _)| nibble & (1 << b) != 0)
            .map(|(_, n)| n)
            .collect()
    }
}

/// One direction (or configuration block) of a connection: RPI, size and format fields.
#[derive(Debug, Clone, PartialEq)]
pub struct ConnectionData {
    /// The RPI in microseconds, or the parameter holding it (absent for configuration blocks).
    pub rpi: Spanned<FieldRef>,
    /// The size in bytes, or the parameter holding it; empty means the format assembly's size.
    pub size: Spanned<FieldRef>,
    /// The format: `AssemN`, `ParamN` or empty.
    pub format: Spanned<FieldRef>,
}

/// `ConnectionN`.
#[derive(Debug, Clone, PartialEq)]
pub struct CipConnection {
    /// N.
    pub number: u32,
    /// Where the key is.
    pub span: Span,
    /// The trigger and transport word.
    pub trigger_transport: Option<Spanned<TriggerTransport>>,
    /// The connection parameters word.
    pub params: Option<Spanned<ConnectionParams>>,
    /// Originator to target (outputs of the scanner).
    pub o_t: ConnectionData,
    /// Target to originator (inputs of the scanner).
    pub t_o: ConnectionData,
    /// Configuration block 1 (size and format; its `rpi` is empty).
    pub config1: ConnectionData,
    /// Configuration block 2.
    pub config2: ConnectionData,
    /// The name.
    pub name: String,
    /// The help text.
    pub help: String,
    /// The connection path, as written (hex bytes, maybe with `[ParamN]` or symbolic parts).
    pub path: Option<Spanned<String>>,
}

/// `PortN = type, name, path, number;`.
#[derive(Debug, Clone, PartialEq)]
pub struct CipPort {
    /// N.
    pub number: u32,
    /// Where the key is.
    pub span: Span,
    /// The port type (`TCP`, `DeviceNet`, ...).
    pub port_type: String,
    /// The name.
    pub name: String,
    /// The path to the port's object (hex bytes).
    pub path: String,
    /// The port number.
    pub port_number: Option<u32>,
}

/// A CIP data type code: its name and size in bytes (`None` for variable-size types).
pub fn data_type_info(code: u8) -> Option<(&'static str, Option<u32>)> {
    Some(match code {
        0xC1 => ("BOOL", Some(1)),
        0xC2 => ("SINT", Some(1)),
        0xC3 => ("INT", Some(2)),
        0xC4 => ("DINT", Some(4)),
        0xC5 => ("LINT", Some(8)),
        0xC6 => ("USINT", Some(1)),
        0xC7 => ("UINT", Some(2)),
        0xC8 => ("UDINT", Some(4)),
        0xC9 => ("ULINT", Some(8)),
        0xCA => ("REAL", Some(4)),
        0xCB => ("LREAL", Some(8)),
        0xCC => ("STIME", Some(4)),
        0xCD => ("DATE", Some(2)),
        0xCE => ("TIME_OF_DAY", Some(4)),
        0xCF => ("DATE_AND_TIME", Some(6)),
        0xD0 => ("STRING", None),
        0xD1 => ("BYTE", Some(1)),
        0xD2 => ("WORD", Some(2)),
        0xD3 => ("DWORD", Some(4)),
        0xD4 => ("LWORD", Some(8)),
        0xD5 => ("STRING2", None),
        0xD6 => ("FTIME", Some(4)),
        0xD7 => ("LTIME", Some(8)),
        0xD8 => ("ITIME", Some(2)),
        0xD9 => ("STRINGN", None),
        0xDA => ("SHORT_STRING", None),
        0xDB => ("TIME", Some(4)),
        0xDC => ("EPATH", None),
        0xDD => ("ENGUNIT", Some(2)),
        0xDE => ("STRINGI", None),
        _ => return None,
    })
}

/// The range of an integer CIP data type, `None` for the others.
pub fn data_type_range(code: u8) -> Option<(i128, i128)> {
    Some(match code {
        0xC1 => (0, 1),
        0xC2 => (i8::MIN.into(), i8::MAX.into()),
        0xC3 => (i16::MIN.into(), i16::MAX.into()),
        0xC4 => (i32::MIN.into(), i32::MAX.into()),
        0xC5 => (i64::MIN.into(), i64::MAX.into()),
        0xC6 | 0xD1 => (0, u8::MAX.into()),
        0xC7 | 0xD2 | 0xCD | 0xD8 | 0xDD => (0, u16::MAX.into()),
        0xC8 | 0xD3 => (0, u32::MAX.into()),
        0xC9 | 0xD4 => (0, u64::MAX.into()),
        _ => return None,
    })
}
