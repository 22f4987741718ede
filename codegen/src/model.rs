//! The resolved device model: one intermediate representation for EDS, DCF, XDD and XDC.
//!
//! Readers (`read::eds`, `read::xdd`) build it, the validator judges it, the emitter turns it into
//! Rust. Every object, sub-object and value keeps the [`Span`] it was read from, so a diagnostic can
//! point at the exact line of the vendor file. Nothing here evaluates `$NODEID`: node-relative
//! values stay symbolic ([`Value::NodeRelative`]) until a DCF or the generated `new(node_id)` fixes
//! the node-ID.

use std::collections::BTreeMap;
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
    /// ([`Device::ethercat`]).
    Esi,
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

/// An object dictionary access type as written in CiA 306.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum AccessType {
    /// Read only.
    Ro,
    /// Write only.
    Wo,
    /// Read and write.
    Rw,
    /// Read and write, mapped into TPDOs (read on process input).
    Rwr,
    /// Read and write, mapped into RPDOs (write on process output).
    Rww,
    /// Read only, constant value.
    Const,
}

impl AccessType {
    /// The lowercase CiA 306 spelling.
    pub const fn as_str(self) -> &'static str {
        match self {
            AccessType::Ro => "ro",
            AccessType::Wo => "wo",
            AccessType::Rw => "rw",
            AccessType::Rwr => "rwr",
            AccessType::Rww => "rww",
            AccessType::Const => "const",
        }
    }

    /// Parses the CiA 306 spelling, case-insensitively.
    pub fn parse(text: &str) -> Option<Self> {
        Some(match text.trim().to_ascii_lowercase().as_str() {
            "ro" => AccessType::Ro,
            "wo" => AccessType::Wo,
            "rw" => AccessType::Rw,
            "rwr" => AccessType::Rwr,
            "rww" => AccessType::Rww,
            "const" => AccessType::Const,
            _ => return None,
        })
    }

    /// Whether an SDO client may read this entry.
    pub const fn readable(self) -> bool {
        !matches!(self, AccessType::Wo)
    }

    /// Whether an SDO client may write this entry.
    pub const fn writable(self) -> bool {
        matches!(
            self,
            AccessType::Wo | AccessType::Rw | AccessType::Rwr | AccessType::Rww
        )
    }
}

/// The object code of an object (CiA 301 table 42).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ObjectType {
    /// 0x0: no data fields.
    Null,
    /// 0x2: large variable amount of data.
    Domain,
    /// 0x5: a type definition (BOOLEAN, UNSIGNED8, ...).
    DefType,
    /// 0x6: a record type definition.
    DefStruct,
    /// 0x7: a single value.
    Var,
    /// 0x8: several values of one type, sub-index 0 is the count.
    Array,
    /// 0x9: several values of possibly different types.
    Record,
}

impl ObjectType {
    /// The object code as a number.
    pub const fn code(self) -> u8 {
        match self {
            ObjectType::Null => 0x0,
            ObjectType::Domain => 0x2,
            ObjectType::DefType => 0x5,
            ObjectType::DefStruct => 0x6,
            ObjectType::Var => 0x7,
            ObjectType::Array => 0x8,
            ObjectType::Record => 0x9,
        }
    }

    /// The object type for an object code, if it is one CiA 301 defines.
    pub const fn from_code(code: u32) -> Option<Self> {
        Some(match code {
            0x0 => ObjectType::Null,
            0x2 => ObjectType::Domain,
            0x5 => ObjectType::DefType,
            0x6 => ObjectType::DefStruct,
            0x7 => ObjectType::Var,
            0x8 => ObjectType::Array,
            0x9 => ObjectType::Record,
            _ => return None,
        })
    }

    /// Whether objects of this type hold sub-indices 0..n (ARRAY, RECORD, DEFSTRUCT).
    pub const fn has_subs(self) -> bool {
        matches!(
            self,
            ObjectType::Array | ObjectType::Record | ObjectType::DefStruct
        )
    }
}

/// The CiA 301 basic data types (OD indices 0x0001-0x001B).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BasicType {
    /// 0x0001
    Boolean,
    /// 0x0002
    Integer8,
    /// 0x0003
    Integer16,
    /// 0x0004
    Integer32,
    /// 0x0005
    Unsigned8,
    /// 0x0006
    Unsigned16,
    /// 0x0007
    Unsigned32,
    /// 0x0008
    Real32,
    /// 0x0009
    VisibleString,
    /// 0x000A
    OctetString,
    /// 0x000B
    UnicodeString,
    /// 0x000C
    TimeOfDay,
    /// 0x000D
    TimeDifference,
    /// 0x000F
    Domain,
    /// 0x0010
    Integer24,
    /// 0x0011
    Real64,
    /// 0x0012
    Integer40,
    /// 0x0013
    Integer48,
    /// 0x0014
    Integer56,
    /// 0x0015
    Integer64,
    /// 0x0016
    Unsigned24,
    /// 0x0018
    Unsigned40,
    /// 0x0019
    Unsigned48,
    /// 0x001A
    Unsigned56,
    /// 0x001B
    Unsigned64,
}

impl BasicType {
    /// The basic type that an OD data type index names, if any.
    pub const fn from_index(index: u16) -> Option<Self> {
        Some(match index {
            0x01 => BasicType::Boolean,
            0x02 => BasicType::Integer8,
            0x03 => BasicType::Integer16,
            0x04 => BasicType::Integer32,
            0x05 => BasicType::Unsigned8,
            0x06 => BasicType::Unsigned16,
            0x07 => BasicType::Unsigned32,
            0x08 => BasicType::Real32,
            0x09 => BasicType::VisibleString,
            0x0A => BasicType::OctetString,
            0x0B => BasicType::UnicodeString,
            0x0C => BasicType::TimeOfDay,
            0x0D => BasicType::TimeDifference,
            0x0F => BasicType::Domain,
            0x10 => BasicType::Integer24,
            0x11 => BasicType::Real64,
            0x12 => BasicType::Integer40,
            0x13 => BasicType::Integer48,
            0x14 => BasicType::Integer56,
            0x15 => BasicType::Integer64,
            0x16 => BasicType::Unsigned24,
            0x18 => BasicType::Unsigned40,
            0x19 => BasicType::Unsigned48,
            0x1A => BasicType::Unsigned56,
            0x1B => BasicType::Unsigned64,
            _ => return None,
        })
    }

    /// The OD index of this data type.
    pub const fn index(self) -> u16 {
        match self {
            BasicType::Boolean => 0x01,
            BasicType::Integer8 => 0x02,
            BasicType::Integer16 => 0x03,
            BasicType::Integer32 => 0x04,
            BasicType::Unsigned8 => 0x05,
            BasicType::Unsigned16 => 0x06,
            BasicType::Unsigned32 => 0x07,
            BasicType::Real32 => 0x08,
            BasicType::VisibleString => 0x09,
            BasicType::OctetString => 0x0A,
            BasicType::UnicodeString => 0x0B,
            BasicType::TimeOfDay => 0x0C,
            BasicType::TimeDifference => 0x0D,
            BasicType::Domain => 0x0F,
            BasicType::Integer24 => 0x10,
            BasicType::Real64 => 0x11,
            BasicType::Integer40 => 0x12,
            BasicType::Integer48 => 0x13,
            BasicType::Integer56 => 0x14,
            BasicType::Integer64 => 0x15,
            BasicType::Unsigned24 => 0x16,
            BasicType::Unsigned40 => 0x18,
            BasicType::Unsigned48 => 0x19,
            BasicType::Unsigned56 => 0x1A,
            BasicType::Unsigned64 => 0x1B,
        }
    }

    /// The CiA 301 name, e.g. `UNSIGNED16`.
    pub const fn name(self) -> &'static str {
        match self {
            BasicType::Boolean => "BOOLEAN",
            BasicType::Integer8 => "INTEGER8",
            BasicType::Integer16 => "INTEGER16",
            BasicType::Integer32 => "INTEGER32",
            BasicType::Unsigned8 => "UNSIGNED8",
            BasicType::Unsigned16 => "UNSIGNED16",
            BasicType::Unsigned32 => "UNSIGNED32",
            BasicType::Real32 => "REAL32",
            BasicType::VisibleString => "VISIBLE_STRING",
            BasicType::OctetString => "OCTET_STRING",
            BasicType::UnicodeString => "UNICODE_STRING",
            BasicType::TimeOfDay => "TIME_OF_DAY",
            BasicType::TimeDifference => "TIME_DIFFERENCE",
            BasicType::Domain => "DOMAIN",
            BasicType::Integer24 => "INTEGER24",
            BasicType::Real64 => "REAL64",
            BasicType::Integer40 => "INTEGER40",
            BasicType::Integer48 => "INTEGER48",
            BasicType::Integer56 => "INTEGER56",
            BasicType::Integer64 => "INTEGER64",
            BasicType::Unsigned24 => "UNSIGNED24",
            BasicType::Unsigned40 => "UNSIGNED40",
            BasicType::Unsigned48 => "UNSIGNED48",
            BasicType::Unsigned56 => "UNSIGNED56",
            BasicType::Unsigned64 => "UNSIGNED64",
        }
    }

    /// Width in bits of a fixed-size type; `None` for strings and DOMAIN.
    pub const fn bits(self) -> Option<u32> {
        Some(match self {
            BasicType::Boolean => 1,
            BasicType::Integer8 | BasicType::Unsigned8 => 8,
            BasicType::Integer16 | BasicType::Unsigned16 => 16,
            BasicType::Integer24 | BasicType::Unsigned24 => 24,
            BasicType::Integer32 | BasicType::Unsigned32 | BasicType::Real32 => 32,
            BasicType::Integer40 | BasicType::Unsigned40 => 40,
            BasicType::Integer48
            | BasicType::Unsigned48
            | BasicType::TimeOfDay
            | BasicType::TimeDifference => 48,
            BasicType::Integer56 | BasicType::Unsigned56 => 56,
            BasicType::Integer64 | BasicType::Unsigned64 | BasicType::Real64 => 64,
            BasicType::VisibleString
            | BasicType::OctetString
            | BasicType::UnicodeString
            | BasicType::Domain => return None,
        })
    }

    /// Whether this is a signed integer type.
    pub const fn is_signed_integer(self) -> bool {
        matches!(
            self,
            BasicType::Integer8
                | BasicType::Integer16
                | BasicType::Integer24
                | BasicType::Integer32
                | BasicType::Integer40
                | BasicType::Integer48
                | BasicType::Integer56
                | BasicType::Integer64
        )
    }

    /// Whether this is an unsigned integer type (BOOLEAN excluded).
    pub const fn is_unsigned_integer(self) -> bool {
        matches!(
            self,
            BasicType::Unsigned8
                | BasicType::Unsigned16
                | BasicType::Unsigned24
                | BasicType::Unsigned32
                | BasicType::Unsigned40
                | BasicType::Unsigned48
                | BasicType::Unsigned56
                | BasicType::Unsigned64
        )
    }

    /// Whether this is an integer type (BOOLEAN excluded).
    pub const fn is_integer(self) -> bool {
        self.is_signed_integer() || self.is_unsigned_integer()
    }

    /// Whether this is REAL32 or REAL64.
    pub const fn is_real(self) -> bool {
        matches!(self, BasicType::Real32 | BasicType::Real64)
    }

    /// The inclusive integer range of an integer or BOOLEAN type.
    pub const fn integer_range(self) -> Option<(i128, i128)> {
        if matches!(self, BasicType::Boolean) {
            return Some((0, 1));
        }
        let bits = match self.bits() {
            Some(b) => b,
            None => return None,
        };
        if self.is_signed_integer() {
            Some((-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1))
        } else if self.is_unsigned_integer() {
            Some((0, (1i128 << bits) - 1))
        } else {
            None
        }
    }
}

/// A value read from the file, typed by the entry's data type.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// An integer (any integer type or BOOLEAN), already range-checked by the reader where the type
    /// is known. Signed types written as unsigned hex are stored as their two's-complement value.
    Integer(i128),
    /// `$NODEID + offset`, kept symbolic; resolved with the node-ID at run time or by a DCF.
    NodeRelative(i64),
    /// A REAL32/REAL64 value.
    Real(f64),
    /// A VISIBLE_STRING or UNICODE_STRING value, as written (quotes kept, per the spec).
    Text(String),
    /// An OCTET_STRING or DOMAIN value.
    Bytes(Vec<u8>),
}

/// One value as written in the file, and what it was understood as.
#[derive(Debug, Clone, PartialEq)]
pub struct ValueSource {
    /// The parsed value; `None` if the text could not be parsed for the data type (a diagnostic
    /// was emitted) or the data type is unknown.
    pub value: Option<Value>,
    /// The text exactly as written, after trimming (and after stripping an inline comment).
    pub raw: String,
    /// Where the value text is.
    pub span: Span,
}

/// One entry of the object dictionary: a VAR or DOMAIN object (sub-index 0) or one sub-object of
/// an ARRAY, RECORD or DEFSTRUCT.
#[derive(Debug, Clone, PartialEq)]
pub struct SubObject {
    /// Sub-index (0 for a VAR or DOMAIN object).
    pub sub_index: u8,
    /// ParameterName (or the name derived by CompactSubObj rules, or the XML `name`).
    pub name: String,
    /// The data type index (a basic type 0x0001-0x001B, or a DEFTYPE/DEFSTRUCT index). `None` if
    /// the file does not give one (a diagnostic says so).
    pub data_type: Option<u16>,
    /// The access type; `None` if missing or unparseable (a diagnostic says so).
    pub access: Option<AccessType>,
    /// Whether the entry may be mapped into a PDO.
    pub pdo_mapping: bool,
    /// DefaultValue.
    pub default: Option<ValueSource>,
    /// DCF ParameterValue (or XDC actualValue): the configured value, overriding the default.
    pub parameter_value: Option<ValueSource>,
    /// LowLimit.
    pub low_limit: Option<ValueSource>,
    /// HighLimit.
    pub high_limit: Option<ValueSource>,
    /// ObjFlags (bit 0 refuse write on download, bit 1 refuse read on scan).
    pub obj_flags: u32,
    /// DCF Denotation: a display name chosen by the integrator.
    pub denotation: Option<String>,
    /// DCF UploadFile (DOMAIN).
    pub upload_file: Option<String>,
    /// DCF DownloadFile (DOMAIN).
    pub download_file: Option<String>,
    /// Where the sub-object is described: its section header (EDS), or its element (XML). For
    /// sub-objects synthesised from CompactSubObj or CompactPDO, the span of what implied them.
    pub span: Span,
    /// Keys the reader does not interpret (`Unit`, `Factor`, `StorageLocation`, ...), in file
    /// order, with their original spelling.
    pub custom: Vec<(String, String)>,
    /// Set when this entry was not written out in the file but implied (CompactSubObj,
    /// CompactPDO); the emitter treats it exactly like a written one.
    pub implicit: bool,
    /// Where the DataType, AccessType and PDOMapping values are written, so that diagnostics
    /// about them point at the key rather than the section. Empty when not known.
    pub key_spans: KeySpans,
    /// The capacity in bytes of a string, octet string or domain, set by the overlay beside the
    /// description (see [`crate::overlay`]); `None` for the generator's rule.
    pub capacity: Option<usize>,
}

/// Where some keys of an entry are written (the value text), when the reader knows it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KeySpans {
    /// The DataType value.
    pub data_type: Option<Span>,
    /// The AccessType value.
    pub access: Option<Span>,
    /// The PDOMapping value.
    pub pdo_mapping: Option<Span>,
    /// The DCF UploadFile value.
    pub upload_file: Option<Span>,
    /// The DCF DownloadFile value.
    pub download_file: Option<Span>,
}

/// One object (one OD index).
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// The OD index.
    pub index: u16,
    /// ParameterName.
    pub name: String,
    /// The object code.
    pub object_type: ObjectType,
    /// The entries: for VAR and DOMAIN exactly sub-index 0; for ARRAY, RECORD and DEFSTRUCT every
    /// implemented sub-index, sparse allowed.
    pub subs: BTreeMap<u8, SubObject>,
    /// SubNumber as written (ARRAY/RECORD), for the validator to compare.
    pub sub_number: Option<Spanned<u32>>,
    /// CompactSubObj as written, if non-zero.
    pub compact_sub_obj: Option<Spanned<u32>>,
    /// ObjFlags of the object itself.
    pub obj_flags: u32,
    /// Where the object is described (its `[xxxx]` section header or XML element).
    pub span: Span,
    /// Keys of the main section the reader does not interpret, in file order.
    pub custom: Vec<(String, String)>,
    /// Indices listed in `[xxxxObjectLinks]`.
    pub object_links: Vec<u16>,
    /// Set when the object was not written out but implied (CompactPDO).
    pub implicit: bool,
}

/// `[FileInfo]` (EDS/DCF) or the XML ProfileBody attributes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FileInfo {
    /// FileName.
    pub file_name: Option<String>,
    /// FileVersion.
    pub file_version: Option<String>,
    /// FileRevision.
    pub file_revision: Option<String>,
    /// EDSVersion (missing means 3.0).
    pub eds_version: Option<Spanned<String>>,
    /// Description.
    pub description: Option<String>,
    /// CreationTime.
    pub creation_time: Option<String>,
    /// CreationDate.
    pub creation_date: Option<String>,
    /// CreatedBy.
    pub created_by: Option<String>,
    /// ModificationTime.
    pub modification_time: Option<String>,
    /// ModificationDate.
    pub modification_date: Option<String>,
    /// ModifiedBy.
    pub modified_by: Option<String>,
    /// DCF LastEDS.
    pub last_eds: Option<String>,
    /// Where the section is (its header), if present.
    pub span: Option<Span>,
    /// Where each key's value is written, by canonical key name (`FileVersion`, ...), when the
    /// reader knows it; diagnostics about one key point there.
    pub key_spans: BTreeMap<String, Span>,
}

/// `[DeviceInfo]` (EDS/DCF) or DeviceIdentity and the general features (XML).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeviceInfo {
    /// VendorName.
    pub vendor_name: Option<String>,
    /// VendorNumber (1018h sub 1).
    pub vendor_number: Option<Spanned<u32>>,
    /// ProductName.
    pub product_name: Option<String>,
    /// ProductNumber (1018h sub 2).
    pub product_number: Option<Spanned<u32>>,
    /// RevisionNumber (1018h sub 3).
    pub revision_number: Option<Spanned<u32>>,
    /// OrderCode.
    pub order_code: Option<String>,
    /// Supported bit rates in kbit/s, with the value written (`BaudRate_250=1` gives `(250, true)`).
    pub baud_rates: Vec<(u32, bool)>,
    /// SimpleBootUpMaster.
    pub simple_boot_up_master: bool,
    /// SimpleBootUpSlave.
    pub simple_boot_up_slave: bool,
    /// Granularity (0: mapping not modifiable, 1..64).
    pub granularity: Option<Spanned<u32>>,
    /// DynamicChannelsSupported.
    pub dynamic_channels_supported: u32,
    /// GroupMessaging.
    pub group_messaging: bool,
    /// NrOfRXPDO.
    pub nr_of_rx_pdo: Option<Spanned<u32>>,
    /// NrOfTXPDO.
    pub nr_of_tx_pdo: Option<Spanned<u32>>,
    /// LSS_Supported.
    pub lss_supported: bool,
    /// CompactPDO bitmask.
    pub compact_pdo: Option<Spanned<u32>>,
    /// Where the section is (its header), if present.
    pub span: Option<Span>,
}

/// `[DeviceComissioning]` (DCF) or `deviceCommissioning` (XDC).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Commissioning {
    /// NodeID.
    pub node_id: Option<Spanned<u32>>,
    /// NodeName.
    pub node_name: Option<String>,
    /// Baudrate in kbit/s.
    pub baudrate: Option<Spanned<u32>>,
    /// NetNumber.
    pub net_number: Option<u32>,
    /// NetworkName.
    pub network_name: Option<String>,
    /// CANopenManager.
    pub canopen_manager: bool,
    /// LSS_SerialNumber (1018h sub 4).
    pub lss_serial_number: Option<u32>,
    /// Where the section is.
    pub span: Span,
}

/// A section or key the reader kept without interpreting it, for round trips and for the module
/// and dynamic-channel sections that later stages may use.
#[derive(Debug, Clone, PartialEq)]
pub struct RawSection {
    /// The section name as written (without brackets).
    pub name: String,
    /// The keys in file order, as written.
    pub entries: Vec<RawEntry>,
    /// The section header's span.
    pub span: Span,
}

/// One `key=value` line kept verbatim.
#[derive(Debug, Clone, PartialEq)]
pub struct RawEntry {
    /// The key as written.
    pub key: String,
    /// The value, trimmed.
    pub value: String,
    /// Where the line is.
    pub span: Span,
}

/// A complete device description.
#[derive(Debug, Clone, PartialEq)]
pub struct Device {
    /// The file it was read from.
    pub source: Source,
    /// File information.
    pub file_info: FileInfo,
    /// Device information.
    pub device_info: DeviceInfo,
    /// `[DummyUsage]`: data type index → whether it may be used as a dummy mapping entry.
    pub dummy_usage: BTreeMap<u16, bool>,
    /// Where dummy usage is declared (the `[DummyUsage]` header or the XML element), if it is.
    pub dummy_usage_span: Option<Span>,
    /// `[Comments]` lines, in order.
    pub comments: Vec<String>,
    /// `[Comments]` `Lines` as written (the declared number of comment lines), for the validator.
    pub comment_lines: Option<Spanned<u32>>,
    /// The objects, by index. DEFTYPE/DEFSTRUCT objects (0x0001-0x0FFF) are here too.
    pub objects: BTreeMap<u16, Object>,
    /// The object lists (`[MandatoryObjects]`, `[OptionalObjects]`, `[ManufacturerObjects]`) as
    /// written, for the validator; `objects` is the union of the lists and the sections.
    pub object_lists: Vec<ObjectList>,
    /// DCF commissioning data.
    pub commissioning: Option<Commissioning>,
    /// Sections the model does not interpret further: modules (`[SupportedModules]`, `[Mx...]`,
    /// `[ConnectedModules]`), `[DynamicChannels]`, `[Tools]`, and unknown sections, in file order.
    pub other_sections: Vec<RawSection>,
    /// Generated names the overlay sets (see [`crate::overlay`]); empty without one.
    pub naming: Naming,
    /// What an ESI file says beyond the CoE dictionary; `None` for CANopen descriptions.
    pub ethercat: Option<EtherCat>,
}

/// The EtherCAT side of a device read from an ESI file: what a CANopen description has no place
/// for. Identity goes in [`DeviceInfo`] (`vendor_number`, `product_number`, `revision_number`)
/// and the CoE dictionary in [`Device::objects`], as for CANopen.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EtherCat {
    /// The device's type name (`Device/Type` text), which picks it in a file with several.
    pub type_name: String,
    /// `Profile/ProfileNo` values (402 for a drive, 5001 for a modular device).
    pub profiles: Vec<u32>,
    /// The SyncManagers, in order (SM0, SM1, ...).
    pub sync_managers: Vec<SyncManager>,
    /// `RxPdo` elements: outputs, written by the master.
    pub rx_pdos: Vec<EcPdo>,
    /// `TxPdo` elements: inputs, read by the master.
    pub tx_pdos: Vec<EcPdo>,
    /// The CoE mailbox, if the device has one.
    pub coe: Option<CoeMailbox>,
    /// Distributed-clock operation modes (`Dc/OpMode`).
    pub op_modes: Vec<DcOpMode>,
    /// Other devices in the same file, by type name, product code and revision: the reader picks
    /// one (the first, unless told otherwise) and lists the rest here.
    pub other_devices: Vec<(String, u32, u32)>,
    /// Where the `Device` element is.
    pub span: Span,
}

/// What a SyncManager carries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SmKind {
    /// Mailbox, master to device (`MBoxOut`).
    MailboxOut,
    /// Mailbox, device to master (`MBoxIn`).
    MailboxIn,
    /// Process data outputs (`Outputs`): the assigned RxPDOs.
    Outputs,
    /// Process data inputs (`Inputs`): the assigned TxPDOs.
    Inputs,
    /// Anything else, as written (an empty or vendor-specific text).
    Other(String),
}

/// One `Sm` element.
#[derive(Debug, Clone, PartialEq)]
pub struct SyncManager {
    /// What it carries.
    pub kind: SmKind,
    /// `StartAddress` in the device's memory.
    pub start_address: u16,
    /// `DefaultSize` in bytes, if given.
    pub default_size: Option<u16>,
    /// `ControlByte`.
    pub control_byte: u8,
    /// `Enable`.
    pub enable: bool,
    /// Where the element is.
    pub span: Span,
}

/// One `RxPdo` or `TxPdo` element.
#[derive(Debug, Clone, PartialEq)]
pub struct EcPdo {
    /// The mapping object's index (1600h... for RxPDOs, 1A00h... for TxPDOs).
    pub index: u16,
    /// `Name`.
    pub name: String,
    /// The SyncManager it is assigned to by default (`Sm`); `None` when not assigned.
    pub sm: Option<u8>,
    /// `Fixed`: the mapping cannot be changed.
    pub fixed: bool,
    /// `Mandatory`: it must be assigned.
    pub mandatory: bool,
    /// `Exclude`: PDOs that cannot be assigned together with this one.
    pub exclude: Vec<Spanned<u16>>,
    /// The mapped entries, in process-image order.
    pub entries: Vec<EcPdoEntry>,
    /// Where the element is.
    pub span: Span,
}

/// One `Entry` of a PDO: a mapped object, or padding (index 0).
#[derive(Debug, Clone, PartialEq)]
pub struct EcPdoEntry {
    /// The mapped object's index; 0 for padding.
    pub index: u16,
    /// Its sub-index.
    pub sub: u8,
    /// `BitLen`.
    pub bit_len: u16,
    /// `Name`, if any.
    pub name: String,
    /// `DataType` as written (`UINT`, `DINT`, ...), if any.
    pub data_type: Option<String>,
    /// Where the element is.
    pub span: Span,
}

/// The `Mailbox/CoE` element.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CoeMailbox {
    /// `SdoInfo`: the SDO information service.
    pub sdo_info: bool,
    /// `PdoAssign`: PDO assignment (1C12h/1C13h) may be changed.
    pub pdo_assign: bool,
    /// `PdoConfig`: PDO mapping may be changed.
    pub pdo_config: bool,
    /// `CompleteAccess`: SDO complete access.
    pub complete_access: bool,
    /// `SegmentedSdo`.
    pub segmented_sdo: bool,
    /// `InitCmds`: SDO writes the master makes on a state transition.
    pub init_cmds: Vec<CoeInitCmd>,
}

/// One `InitCmd`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoeInitCmd {
    /// Transitions (`PS`, `IP`, ...).
    pub transitions: Vec<String>,
    /// Index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The data, as bytes.
    pub data: Vec<u8>,
    /// Whether it writes the whole object (`CompleteAccess`).
    pub complete_access: bool,
    /// Where the element is.
    pub span: Span,
}

/// One `Dc/OpMode`.
#[derive(Debug, Clone, PartialEq)]
pub struct DcOpMode {
    /// `Name` (`DC`, `FreeRun`, `SYNC0`, ...).
    pub name: String,
    /// `Desc`, if any.
    pub description: String,
    /// `AssignActivate`.
    pub assign_activate: u16,
    /// SYNC0 cycle time in ns (`CycleTimeSync0`; 0 when it follows the bus cycle).
    pub cycle_time_sync0: u32,
}

/// What an overlay says about generated names: the description cannot say how the device numbers
/// an array's elements, and its names may not suit Rust.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Naming {
    /// An object's name in generated code, in place of its ParameterName (its sub-objects'
    /// constants start with it).
    pub objects: BTreeMap<u16, String>,
    /// An entry's whole constant name, in place of the one made from its names.
    pub entries: BTreeMap<(u16, u8), String>,
    /// For an array, the number the device gives sub-index 1 (0 when sub-index = number + 1):
    /// its elements' constants end in that numbering, not in the sub-index.
    pub first_number: BTreeMap<u16, u32>,
}

/// Which object list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObjectListKind {
    /// `[MandatoryObjects]`.
    Mandatory,
    /// `[OptionalObjects]`.
    Optional,
    /// `[ManufacturerObjects]`.
    Manufacturer,
}

/// One object list section.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectList {
    /// Which list.
    pub kind: ObjectListKind,
    /// SupportedObjects as written.
    pub supported_objects: Option<Spanned<u32>>,
    /// The numbered entries: (key number, listed index).
    pub entries: Vec<(u32, Spanned<u16>)>,
    /// The section header's span.
    pub span: Span,
}

impl Device {
    /// The entry at (index, sub), if the model has it.
    pub fn entry(&self, index: u16, sub: u8) -> Option<&SubObject> {
        self.objects.get(&index)?.subs.get(&sub)
    }

    /// The basic type of an entry's data type, following DEFTYPE objects (an index above 0x001B):
    /// the basic type that sub-object 1, or sub-index 0, names as its value (as CANfestival files
    /// do), else the DEFTYPE's own DataType (as CiA 306 writes `[0060]` with `DataType=0x0007`).
    /// `None` for a chain that ends nowhere (a DEFTYPE naming itself) or at anything else.
    pub fn basic_type(&self, data_type: u16) -> Option<BasicType> {
        let mut data_type = data_type;
        // A chain longer than this loops: CiA 306 files have none longer than one.
        for _ in 0..8 {
            if let Some(t) = BasicType::from_index(data_type) {
                return Some(t);
            }
            let def = self.objects.get(&data_type)?;
            if def.object_type != ObjectType::DefType {
                return None;
            }
            let sub = def.subs.get(&1).or_else(|| def.subs.get(&0))?;
            let named = match sub.default.as_ref().and_then(|d| d.value.as_ref()) {
                Some(Value::Integer(v)) => u16::try_from(*v).ok().and_then(BasicType::from_index),
                _ => None,
            };
            if named.is_some() {
                return named;
            }
            data_type = sub.data_type?;
        }
        None
    }
}
