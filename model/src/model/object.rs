//! Objects and their entries (sub-objects), with the values read for them and where each key is
//! written.

use super::{AccessType, ObjectType, Span, Spanned, Subs};

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
    pub subs: Subs,
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

impl Object {
    /// An object as a reader starts it: no entries yet, no SubNumber, CompactSubObj, ObjFlags,
    /// custom keys or links, and written out (not implicit).
    pub(crate) fn new(index: u16, name: String, object_type: ObjectType, span: Span) -> Self {
        Object {
            index,
            name,
            object_type,
            subs: Subs::new(),
            sub_number: None,
            compact_sub_obj: None,
            obj_flags: 0,
            span,
            custom: Vec::new(),
            object_links: Vec::new(),
            implicit: false,
        }
    }
}
