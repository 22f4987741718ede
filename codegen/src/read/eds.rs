//! EDS and DCF reader (CiA 306): text into a [`Device`], keeping every span, accepting the dialects
//! of real vendor files and reporting each one (rules EDS001-EDS0xx). It never judges semantics;
//! that is the validator's job.
//!
//! Policies, where CiA 306 leaves room:
//! - Duplicate sections are merged and duplicate keys keep the last value (see [`super::ini`]).
//! - Section and key names are matched case-insensitively; a known name written in another case is
//!   reported once per name and file (EDS008). Unknown keys are kept in `custom` where the model
//!   has a place for them, and reported once per name and file (EDS009).
//! - `[DeviceCommissioning]` (two m, CANopenEditor) is read like the spec's `[DeviceComissioning]`,
//!   with an EDS023 info.
//! - Module sections (`[SupportedModules]`, `[Mx...]`, `[ConnectedModules]`), `[DynamicChannels]`,
//!   `[Tools]` and `[ToolN]` go to `other_sections` without a diagnostic; unknown sections go there
//!   with EDS009.
//! - Inline `;` comments are stripped from numbers, enumerations and non-string values (EDS004),
//!   never from strings (where EDS004 only warns).
//! - Values are parsed against their entry's data type after all sections are read, DEFTYPE
//!   objects first, so a data type may point at a DEFTYPE index.
//! - CANopenEditor's commented keys (`;StorageLocation=RAM`, `;TPDODetectCos=1`) are kept in
//!   the entry's `custom` as `StorageLocation`/`TPDODetectCos`, as CANopenEditor reads them back.
//! - Keys that CiA 306 defines but that an object type does not use (`DataType` on an ARRAY
//!   without CompactSubObj, ...) are kept in the object's `custom` for the validator.
//! - A DOMAIN object without `DataType`/`AccessType` gets the spec's replacement values
//!   (0x000F, `rw`); a missing `ObjectType` means VAR. An `ObjectType` that is no CiA 301 code is
//!   an EDS011 error and read as RECORD when sub-index sections exist, else VAR.
//! - `ObjectType` (other than 7), `SubNumber` and `CompactSubObj` in a sub-index section stay in
//!   that entry's `custom`.
//! - Sections about an object or sub-index the file does not describe (a `[xxxxsubN]` without
//!   `[xxxx]`, a sub-index section of a VAR) are kept in `other_sections` with an EDS024 warning;
//!   a `[xxxxName]`/`[xxxxValue]`/`[xxxxDenotation]` entry for a missing sub-index gets EDS024 and
//!   is not applied. Nothing is invented: listed indices without a section are not objects.
//! - The same object section written two ways (`[1000]` and `[01000]`): the later wins, EDS005.
//! - CompactSubObj and CompactPDO are expanded into implicit sub-objects and objects (see
//!   [`expand_compact_sub_obj`] and [`expand_compact_pdo`]).

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;

use super::ini::{self, FastHash, IniEntry, IniSection};
use super::value::{parse_integer, parse_value, split_inline_comment, strips_inline_comment};
use super::Read;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::rules;

/// Reads an EDS or DCF file (a DCF when the extension is `.dcf`, case-insensitively).
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = super::text::decode(bytes);
    let format = match super::detect_format(path, bytes) {
        Format::Dcf => Format::Dcf,
        _ => Format::Eds,
    };
    let mut reader = Reader {
        device: empty_device(path, format, encoding),
        diags: Vec::new(),
        reported: HashSet::default(),
    };
    reader.check_encoding(&text, encoding);
    let file = ini::parse(&text, &mut reader.diags);
    if file.sections.is_empty() {
        reader.diags.push(Diagnostic::new(
            &rules::EMPTY_FILE,
            None,
            "the file holds no [sections]",
        ));
    }
    reader.read_sections(&file);
    // Sections kept while building objects join the others in file order.
    reader
        .device
        .other_sections
        .sort_by_key(|section| section.span.line);
    crate::diag::sort(&mut reader.diags);
    Read {
        device: reader.device,
        diagnostics: reader.diags,
        text,
    }
}

/// A device with nothing in it, for a reader to fill.
pub fn empty_device(path: &Path, format: Format, encoding: TextEncoding) -> Device {
    Device {
        source: Source {
            path: path.to_path_buf(),
            format,
            encoding,
        },
        file_info: FileInfo::default(),
        device_info: DeviceInfo::default(),
        dummy_usage: Default::default(),
        dummy_usage_span: None,
        comments: Vec::new(),
        comment_lines: None,
        objects: Default::default(),
        object_lists: Vec::new(),
        commissioning: None,
        other_sections: Vec::new(),
        naming: Default::default(),
        ethercat: None,
    }
}

/// What a section name says the section is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SectionKind {
    FileInfo,
    DeviceInfo,
    DummyUsage,
    Comments,
    ObjectList(ObjectListKind),
    Commissioning,
    /// Kept in `other_sections` without a diagnostic (modules, dynamic channels, tools).
    Kept,
    Object(u16),
    Sub(u16, u8),
    SubNames(u16),
    SubValues(u16),
    SubDenotations(u16),
    ObjectLinks(u16),
    Unknown,
}

/// Sections with a fixed name: canonical spelling and kind.
/// The help for a key python canopen looks up by its exact spelling (it raises without it).
const CASE_SENSITIVE_TOOLS: &str =
    "write it as CiA 306 does: python canopen looks it up case-sensitively and cannot import the file";

const NAMED_SECTIONS: &[(&str, SectionKind)] = &[
    ("FileInfo", SectionKind::FileInfo),
    ("DeviceInfo", SectionKind::DeviceInfo),
    ("DummyUsage", SectionKind::DummyUsage),
    ("Comments", SectionKind::Comments),
    (
        "MandatoryObjects",
        SectionKind::ObjectList(ObjectListKind::Mandatory),
    ),
    (
        "OptionalObjects",
        SectionKind::ObjectList(ObjectListKind::Optional),
    ),
    (
        "ManufacturerObjects",
        SectionKind::ObjectList(ObjectListKind::Manufacturer),
    ),
    ("DeviceComissioning", SectionKind::Commissioning),
    ("DeviceCommissioning", SectionKind::Commissioning),
    ("SupportedModules", SectionKind::Kept),
    ("ConnectedModules", SectionKind::Kept),
    ("DynamicChannels", SectionKind::Kept),
    ("Tools", SectionKind::Kept),
];

/// The keys of an object or sub-object section.
const OBJECT_KEYS: &[&str] = &[
    "ParameterName",
    "ObjectType",
    "DataType",
    "AccessType",
    "DefaultValue",
    "PDOMapping",
    "LowLimit",
    "HighLimit",
    "ObjFlags",
    "SubNumber",
    "CompactSubObj",
    "ParameterValue",
    "Denotation",
    "UploadFile",
    "DownloadFile",
];

const FILE_INFO_KEYS: &[&str] = &[
    "FileName",
    "FileVersion",
    "FileRevision",
    "EDSVersion",
    "Description",
    "CreationTime",
    "CreationDate",
    "CreatedBy",
    "ModificationTime",
    "ModificationDate",
    "ModifiedBy",
    "LastEDS",
];

const DEVICE_INFO_KEYS: &[&str] = &[
    "VendorName",
    "VendorNumber",
    "ProductName",
    "ProductNumber",
    "RevisionNumber",
    "OrderCode",
    "SimpleBootUpMaster",
    "SimpleBootUpSlave",
    "Granularity",
    "DynamicChannelsSupported",
    "GroupMessaging",
    "NrOfRXPDO",
    "NrOfTXPDO",
    "LSS_Supported",
    "CompactPDO",
];

/// The [DeviceInfo] keys python canopen reads with `int()` and no fallback for an empty value.
const PYTHON_INT_KEYS: &[&str] = &[
    "VendorNumber",
    "ProductNumber",
    "RevisionNumber",
    "SimpleBootUpMaster",
    "SimpleBootUpSlave",
    "Granularity",
    "DynamicChannelsSupported",
    "GroupMessaging",
    "NrOfRXPDO",
    "NrOfTXPDO",
    "LSS_Supported",
];

const COMMISSIONING_KEYS: &[&str] = &[
    "NodeID",
    "NodeName",
    "Baudrate",
    "NetNumber",
    "NetworkName",
    "CANopenManager",
    "LSS_SerialNumber",
];

/// Parses a hex number written without `0x` (as in section names and `DummyXXXX` keys), at most
/// eight digits and at most `max_value`.
fn parse_hex_name(text: &str, max_value: u32) -> Option<u32> {
    if text.is_empty() || text.len() > 8 || !text.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(text, 16)
        .ok()
        .filter(|value| *value <= max_value)
}

/// Classifies a section name. Returns the kind, and whether an index/sub-index in it has extra
/// leading zeros (more than four index digits, or a sub-index with a leading 0), and whether `sub`
/// is spelled other than lowercase.
fn classify(name: &str) -> (SectionKind, bool, bool) {
    for (canonical, kind) in NAMED_SECTIONS {
        if name.eq_ignore_ascii_case(canonical) {
            return (*kind, false, false);
        }
    }
    let lower = name.to_ascii_lowercase();
    // Module sections: [M<n>...] and tool sections: [Tool<n>].
    let bytes = lower.as_bytes();
    if bytes.first() == Some(&b'm')
        && bytes.get(1).is_some_and(u8::is_ascii_digit)
        && lower[1..]
            .trim_start_matches(|c: char| c.is_ascii_digit())
            .starts_with(|c: char| c.is_ascii_alphabetic())
    {
        return (SectionKind::Kept, false, false);
    }
    if let Some(n) = lower.strip_prefix("tool") {
        if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) {
            return (SectionKind::Kept, false, false);
        }
    }
    let index_of = |text: &str| -> Option<(u16, bool)> {
        let value = parse_hex_name(text, 0xFFFF)?;
        Some((u16::try_from(value).ok()?, text.len() > 4))
    };
    for (suffix, make) in [
        (
            "objectlinks",
            SectionKind::ObjectLinks as fn(u16) -> SectionKind,
        ),
        ("denotation", SectionKind::SubDenotations),
        ("value", SectionKind::SubValues),
        ("name", SectionKind::SubNames),
    ] {
        if let Some(prefix) = lower.strip_suffix(suffix) {
            if let Some((index, zeros)) = index_of(prefix) {
                return (make(index), zeros, false);
            }
        }
    }
    if let Some(at) = lower.rfind("sub") {
        let (index_text, sub_text) = (&lower[..at], &lower[at + 3..]);
        if let (Some((index, index_zeros)), Some(sub)) =
            (index_of(index_text), parse_hex_name(sub_text, 0xFF))
        {
            let sub_zeros = sub_text.len() > 1 && sub_text.starts_with('0');
            let odd_spelling = &name[at..at + 3] != "sub";
            return (
                SectionKind::Sub(index, u8::try_from(sub).unwrap_or(0)),
                index_zeros || sub_zeros,
                odd_spelling,
            );
        }
    }
    if let Some((index, zeros)) = index_of(&lower) {
        return (SectionKind::Object(index), zeros, false);
    }
    (SectionKind::Unknown, false, false)
}

/// The position of `key` in `keys`, computed at compile time (a missing key fails the build).
const fn key_index(keys: &[&str], key: &str) -> usize {
    let mut i = 0;
    while i < keys.len() {
        let (a, b) = (keys[i].as_bytes(), key.as_bytes());
        if a.len() == b.len() {
            let mut j = 0;
            while j < a.len() && a[j] == b[j] {
                j += 1;
            }
            if j == a.len() {
                return i;
            }
        }
        i += 1;
    }
    panic!("not a known key");
}

const KEY_ACCESS_TYPE: usize = key_index(OBJECT_KEYS, "AccessType");
const KEY_COMPACT_SUB_OBJ: usize = key_index(OBJECT_KEYS, "CompactSubObj");
const KEY_DATA_TYPE: usize = key_index(OBJECT_KEYS, "DataType");
const KEY_DEFAULT_VALUE: usize = key_index(OBJECT_KEYS, "DefaultValue");
const KEY_DENOTATION: usize = key_index(OBJECT_KEYS, "Denotation");
const KEY_DOWNLOAD_FILE: usize = key_index(OBJECT_KEYS, "DownloadFile");
const KEY_HIGH_LIMIT: usize = key_index(OBJECT_KEYS, "HighLimit");
const KEY_LOW_LIMIT: usize = key_index(OBJECT_KEYS, "LowLimit");
const KEY_OBJ_FLAGS: usize = key_index(OBJECT_KEYS, "ObjFlags");
const KEY_OBJECT_TYPE: usize = key_index(OBJECT_KEYS, "ObjectType");
const KEY_PDO_MAPPING: usize = key_index(OBJECT_KEYS, "PDOMapping");
const KEY_PARAMETER_NAME: usize = key_index(OBJECT_KEYS, "ParameterName");
const KEY_PARAMETER_VALUE: usize = key_index(OBJECT_KEYS, "ParameterValue");
const KEY_SUB_NUMBER: usize = key_index(OBJECT_KEYS, "SubNumber");
const KEY_UPLOAD_FILE: usize = key_index(OBJECT_KEYS, "UploadFile");

/// An access type written exactly as CiA 306 spells it: what [`AccessType::parse`] gives for it,
/// without that function's lowercase copy.
fn canonical_access(text: &str) -> Option<AccessType> {
    Some(match text {
        "ro" => AccessType::Ro,
        "wo" => AccessType::Wo,
        "rw" => AccessType::Rw,
        "rwr" => AccessType::Rwr,
        "rww" => AccessType::Rww,
        "const" => AccessType::Const,
        _ => return None,
    })
}

/// The most keys a known-key list ([`OBJECT_KEYS`], ...) has.
const MAX_KNOWN_KEYS: usize = 16;
const _: () = assert!(
    OBJECT_KEYS.len() <= MAX_KNOWN_KEYS
        && FILE_INFO_KEYS.len() <= MAX_KNOWN_KEYS
        && DEVICE_INFO_KEYS.len() <= MAX_KNOWN_KEYS
        && COMMISSIONING_KEYS.len() <= MAX_KNOWN_KEYS
);

/// The entries of a section found for a list of known keys, by canonical key.
struct KnownKeys<'s> {
    known: &'static [&'static str],
    /// The entry for `known[i]`, at `i`.
    found: [Option<&'s IniEntry<'s>>; MAX_KNOWN_KEYS],
}

impl<'s> KnownKeys<'s> {
    /// The entry for a canonical key.
    fn get(&self, key: &str) -> Option<&&'s IniEntry<'s>> {
        let at = self.known.iter().position(|k| *k == key)?;
        self.found.get(at)?.as_ref()
    }

    /// The entry for `known[at]`.
    fn at(&self, at: usize) -> Option<&'s IniEntry<'s>> {
        self.found.get(at).copied().flatten()
    }

    /// The found (canonical key, entry) pairs, sorted by key.
    fn sorted(&self) -> Vec<(&'static str, &'s IniEntry<'s>)> {
        let mut pairs: Vec<_> = self
            .known
            .iter()
            .zip(self.found.iter())
            .filter_map(|(key, entry)| entry.map(|e| (*key, e)))
            .collect();
        pairs.sort_by_key(|(key, _)| *key);
        pairs
    }
}

/// What `Reader::read_entry` does with the object-level keys (`ObjectType`, `SubNumber`,
/// `CompactSubObj`) of the section it reads.
#[derive(Clone, Copy)]
enum ObjectKeys {
    /// Keep them in the entry's `custom`.
    Keep,
    /// Keep them, except an `ObjectType` of 7 (VAR), which a sub-index section may state.
    KeepUnlessVarType,
    /// Leave them out (a VAR or DOMAIN main section: they belong to the object).
    Drop,
}

/// The sections that describe one object, gathered before it is built.
#[derive(Default)]
struct ObjectSections<'a> {
    main: Option<&'a IniSection<'a>>,
    subs: BTreeMap<u8, &'a IniSection<'a>>,
    names: Option<&'a IniSection<'a>>,
    values: Option<&'a IniSection<'a>>,
    denotations: Option<&'a IniSection<'a>>,
    links: Option<&'a IniSection<'a>>,
}

struct Reader {
    device: Device,
    diags: Vec<Diagnostic>,
    /// (rule code, lowercase name) pairs already reported, to report each dialect once per file.
    reported: HashSet<(&'static str, String), FastHash>,
}

impl Reader {
    fn check_encoding(&mut self, text: &str, encoding: TextEncoding) {
        if encoding == TextEncoding::Ascii {
            return;
        }
        let name = super::text::encoding_name(encoding);
        let utf16 = matches!(encoding, TextEncoding::Utf16Le | TextEncoding::Utf16Be);
        let diag = match super::text::first_non_ascii(text) {
            _ if utf16 => Diagnostic::new(
                &rules::NON_ASCII,
                Some(Span::new(1, 1, 0)),
                format!("the file is {name}; it was decoded as such"),
            ),
            Some((line, column)) => Diagnostic::new(
                &rules::NON_ASCII,
                Some(Span::new(line, column, 1)),
                format!("the file is not ASCII; it was decoded as {name} (first non-ASCII character on line {line})"),
            ),
            None => Diagnostic::new(
                &rules::NON_ASCII,
                Some(Span::new(1, 1, 0)),
                format!("the file starts with a byte-order mark; it was decoded as {name}"),
            ),
        };
        self.diags.push(
            diag.with_help(
                "CiA 306 files are ASCII (ISO 646); other tools may misread these bytes",
            ),
        );
    }

    /// Reports a dialect or unknown name once per (code, name) and file.
    fn once(&mut self, diag: Diagnostic, name: &str) {
        if self
            .reported
            .insert((diag.rule.code, name.to_ascii_lowercase()))
        {
            self.diags.push(diag);
        }
    }

    fn read_sections(&mut self, file: &ini::IniFile) {
        let mut objects: BTreeMap<u16, ObjectSections<'_>> = BTreeMap::new();
        for section in &file.sections {
            let (kind, leading_zeros, odd_sub) = classify(&section.name);
            if leading_zeros {
                self.diags.push(
                    Diagnostic::new(
                        &rules::LEADING_ZEROS,
                        Some(section.span),
                        format!("section name [{}] has extra leading zeros", section.name),
                    )
                    .with_help(
                        "CiA 306 writes indices and sub-indices in hex without further leading 0",
                    ),
                );
            }
            if odd_sub {
                self.once(
                    Diagnostic::new(
                        &rules::CASE_ONLY_MATCH,
                        Some(section.span),
                        format!("`sub` is spelled differently in [{}]", section.name),
                    )
                    .with_help("CiA 306 writes sub-index sections as [<index>sub<sub-index>]"),
                    "sub",
                );
            }
            if let Some((canonical, _)) = NAMED_SECTIONS
                .iter()
                .find(|(c, _)| c.eq_ignore_ascii_case(&section.name))
            {
                if *canonical != section.name {
                    self.once(
                        Diagnostic::new(
                            &rules::CASE_ONLY_MATCH,
                            Some(section.span),
                            format!(
                                "section [{}] is spelled [{canonical}] in CiA 306",
                                section.name
                            ),
                        ),
                        canonical,
                    );
                }
            }
            match kind {
                SectionKind::FileInfo => self.read_file_info(section),
                SectionKind::DeviceInfo => self.read_device_info(section),
                SectionKind::DummyUsage => self.read_dummy_usage(section),
                SectionKind::Comments => self.read_comments(section),
                SectionKind::ObjectList(list) => self.read_object_list(section, list),
                SectionKind::Commissioning => self.read_commissioning(section),
                SectionKind::Kept => self.keep(section),
                SectionKind::Unknown => {
                    self.diags.push(Diagnostic::new(
                        &rules::UNKNOWN_ITEM,
                        Some(section.span),
                        format!(
                            "unknown section [{}] is kept but not interpreted",
                            section.name
                        ),
                    ));
                    self.keep(section);
                }
                SectionKind::Object(index) => {
                    let slot = &mut objects.entry(index).or_default().main;
                    let replaced = slot.replace(section);
                    self.same_section_twice(replaced, section);
                }
                SectionKind::Sub(index, sub) => {
                    let replaced = objects.entry(index).or_default().subs.insert(sub, section);
                    self.same_section_twice(replaced, section);
                }
                SectionKind::SubNames(index) => {
                    let replaced = objects.entry(index).or_default().names.replace(section);
                    self.same_section_twice(replaced, section);
                }
                SectionKind::SubValues(index) => {
                    let replaced = objects.entry(index).or_default().values.replace(section);
                    self.same_section_twice(replaced, section);
                }
                SectionKind::SubDenotations(index) => {
                    let replaced = objects
                        .entry(index)
                        .or_default()
                        .denotations
                        .replace(section);
                    self.same_section_twice(replaced, section);
                }
                SectionKind::ObjectLinks(index) => {
                    let replaced = objects.entry(index).or_default().links.replace(section);
                    self.same_section_twice(replaced, section);
                }
            }
        }
        for (index, sections) in &objects {
            self.build_object(*index, sections);
        }
        self.expand_compact_pdo();
        self.resolve_values();
    }

    /// Two differently written names for the same object section (`[1000]` and `[01000]`): the
    /// later one wins (EDS005), and the earlier one is kept in `other_sections`.
    fn same_section_twice(&mut self, earlier: Option<&IniSection>, later: &IniSection) {
        let Some(earlier) = earlier else { return };
        self.diags.push(
            Diagnostic::new(
                &rules::DUPLICATE_SECTION,
                Some(later.span),
                format!(
                    "section [{}] describes the same item as [{}] on line {}; this one wins",
                    later.name, earlier.name, earlier.span.line
                ),
            )
            .with_label("the earlier section is kept but not interpreted"),
        );
        self.keep(earlier);
    }

    fn keep(&mut self, section: &IniSection) {
        self.device.other_sections.push(RawSection {
            name: section.name.clone(),
            entries: section
                .entries
                .iter()
                .map(|e| RawEntry {
                    key: e.key.as_str().to_owned(),
                    value: e.value.as_str().to_owned(),
                    span: e.line_span(),
                })
                .collect(),
            span: section.span,
        });
    }

    /// Looks up the known keys of a section, reporting case-only matches (EDS008), and returns the
    /// entries that are not in `known`.
    fn split_keys<'s>(
        &mut self,
        section: &'s IniSection<'s>,
        known: &'static [&'static str],
    ) -> (KnownKeys<'s>, Vec<&'s IniEntry<'s>>) {
        let mut found = KnownKeys {
            known,
            found: [None; MAX_KNOWN_KEYS],
        };
        let mut rest = Vec::new();
        for entry in &section.entries {
            // Most files write the canonical spelling: try that before comparing case-blind.
            let at = known
                .iter()
                .position(|k| *k == entry.key.as_str())
                .or_else(|| {
                    known
                        .iter()
                        .position(|k| k.eq_ignore_ascii_case(&entry.key))
                });
            match at {
                Some(at) => {
                    let canonical = &known[at];
                    if *canonical != entry.key {
                        self.once(
                            Diagnostic::new(
                                &rules::CASE_ONLY_MATCH,
                                Some(entry.key_span),
                                format!("key `{}` is spelled `{canonical}` in CiA 306", entry.key),
                            ),
                            canonical,
                        );
                    }
                    if let Some(slot) = found.found.get_mut(at) {
                        *slot = Some(entry);
                    }
                }
                None => rest.push(entry),
            }
        }
        (found, rest)
    }

    fn unknown_key(&mut self, entry: &IniEntry, section: &IniSection) {
        self.once(
            Diagnostic::new(
                &rules::UNKNOWN_ITEM,
                Some(entry.key_span),
                format!(
                    "key `{}` in [{}] is not a CiA 306 key; it is kept but not interpreted",
                    entry.key, section.name
                ),
            ),
            &entry.key,
        );
    }

    /// The value of a numeric or enumerated key, with an inline comment stripped (EDS004).
    /// `None` when empty.
    fn plain_value<'e>(&mut self, entry: &'e IniEntry) -> Option<(&'e str, Span)> {
        let (value, comment) = split_inline_comment(&entry.value);
        if comment.is_some() {
            self.diags.push(
                Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(entry.value_span),
                    format!(
                        "inline comment after the value of `{}` is ignored",
                        entry.key
                    ),
                )
                .with_help("put the comment on its own line, starting with `;`"),
            );
        }
        if value.is_empty() {
            return None;
        }
        let len = u32::try_from(value.chars().count()).unwrap_or(u32::MAX);
        Some((
            value,
            Span::new(entry.value_span.line, entry.value_span.column, len),
        ))
    }

    /// A numeric key's value in `0..=max`; EDS011 when it is not one.
    fn number(&mut self, entry: Option<&IniEntry>, max: u32) -> Option<Spanned<u32>> {
        let entry = entry?;
        let (text, span) = self.plain_value(entry)?;
        match parse_integer(text).and_then(|v| u32::try_from(v).ok()) {
            Some(v) if v <= max => Some(Spanned::new(v, span)),
            _ => {
                self.diags.push(
                    Diagnostic::new(
                        &rules::BAD_NUMBER,
                        Some(span),
                        format!(
                            "`{}` value `{text}` is not a number in 0..={max}",
                            entry.key
                        ),
                    )
                    .with_label("ignored"),
                );
                None
            }
        }
    }

    /// EDS028 for an empty number or boolean that python canopen reads with `int()` and no
    /// fallback (the [DeviceInfo] numbers and booleans, [Comments] `Lines`): CiA 306 reads it
    /// as absent, which edsgen does, but python cannot import the file.
    fn empty_number(&mut self, entry: &IniEntry) {
        if !entry.value.as_str().trim().is_empty() {
            return;
        }
        self.diags.push(
            Diagnostic::new(
                &rules::EMPTY_NUMBER,
                Some(entry.key_span),
                format!("`{}` has an empty value", entry.key),
            )
            .with_label("read as absent, as CiA 306 says")
            .with_help(format!(
                "write the number, or remove the key: python canopen cannot import `{}=`",
                entry.key
            )),
        );
    }

    /// A boolean key: `0`/`1`; other spellings are read with EDS021. Missing or empty is false.
    fn boolean(&mut self, entry: Option<&IniEntry>) -> bool {
        let Some(entry) = entry else { return false };
        let Some((text, span)) = self.plain_value(entry) else {
            return false;
        };
        match parse_integer(text) {
            Some(0) => false,
            Some(1) => true,
            _ => {
                let lower = text.to_ascii_lowercase();
                let value = match lower.as_str() {
                    "true" | "yes" => Some(true),
                    "false" | "no" => Some(false),
                    _ => parse_integer(text).map(|v| v != 0),
                };
                self.diags.push(
                    Diagnostic::new(
                        &rules::BAD_BOOLEAN,
                        Some(span),
                        format!(
                            "`{}` value `{text}` is not 0 or 1; read as {}",
                            entry.key,
                            u8::from(value.unwrap_or(false))
                        ),
                    )
                    .with_help("write 0 or 1"),
                );
                value.unwrap_or(false)
            }
        }
    }

    fn string(entry: Option<&IniEntry>) -> Option<String> {
        entry
            .filter(|e| !e.value.is_empty())
            .map(|e| e.value.as_str().to_owned())
    }

    fn read_file_info(&mut self, section: &IniSection) {
        let (keys, rest) = self.split_keys(section, FILE_INFO_KEYS);
        for entry in rest {
            self.unknown_key(entry, section);
        }
        let get = |k: &str| Self::string(keys.get(k).copied());
        let info = FileInfo {
            file_name: get("FileName"),
            file_version: get("FileVersion"),
            file_revision: get("FileRevision"),
            eds_version: keys
                .get("EDSVersion")
                .filter(|e| !e.value.is_empty())
                .map(|e| Spanned::new(e.value.as_str().to_owned(), e.value_span)),
            description: get("Description"),
            creation_time: get("CreationTime"),
            creation_date: get("CreationDate"),
            created_by: get("CreatedBy"),
            modification_time: get("ModificationTime"),
            modification_date: get("ModificationDate"),
            modified_by: get("ModifiedBy"),
            last_eds: get("LastEDS"),
            span: Some(section.span),
            key_spans: keys
                .sorted()
                .into_iter()
                .map(|(key, entry)| ((*key).to_owned(), entry.value_span))
                .collect(),
        };
        self.device.file_info = info;
    }

    fn read_device_info(&mut self, section: &IniSection) {
        let (keys, rest) = self.split_keys(section, DEVICE_INFO_KEYS);
        let mut baud_rates = Vec::new();
        for entry in rest {
            let rate = entry
                .key
                .get(..9)
                .filter(|p| p.eq_ignore_ascii_case("BaudRate_"))
                .and_then(|_| entry.key.get(9..))
                .filter(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
                .and_then(|n| n.parse::<u32>().ok());
            match rate {
                Some(rate) => {
                    if !entry.key.starts_with("BaudRate_") {
                        self.once(
                            Diagnostic::new(
                                &rules::CASE_ONLY_MATCH,
                                Some(entry.key_span),
                                format!(
                                    "key `{}` is spelled `BaudRate_{rate}` in CiA 306",
                                    entry.key
                                ),
                            ),
                            "BaudRate_",
                        );
                    }
                    self.empty_number(entry);
                    let supported = self.boolean(Some(entry));
                    baud_rates.push((rate, supported));
                }
                None => self.unknown_key(entry, section),
            }
        }
        let get = |k: &str| keys.get(k).copied();
        for key in PYTHON_INT_KEYS {
            if let Some(entry) = get(key) {
                self.empty_number(entry);
            }
        }
        let info = DeviceInfo {
            vendor_name: Self::string(get("VendorName")),
            vendor_number: self.number(get("VendorNumber"), u32::MAX),
            product_name: Self::string(get("ProductName")),
            product_number: self.number(get("ProductNumber"), u32::MAX),
            revision_number: self.number(get("RevisionNumber"), u32::MAX),
            order_code: Self::string(get("OrderCode")),
            baud_rates,
            simple_boot_up_master: self.boolean(get("SimpleBootUpMaster")),
            simple_boot_up_slave: self.boolean(get("SimpleBootUpSlave")),
            granularity: self.number(get("Granularity"), u32::from(u8::MAX)),
            dynamic_channels_supported: self
                .number(get("DynamicChannelsSupported"), u32::MAX)
                .map_or(0, |n| n.value),
            group_messaging: self.boolean(get("GroupMessaging")),
            nr_of_rx_pdo: self.number(get("NrOfRXPDO"), u32::from(u16::MAX)),
            nr_of_tx_pdo: self.number(get("NrOfTXPDO"), u32::from(u16::MAX)),
            lss_supported: self.boolean(get("LSS_Supported")),
            compact_pdo: self.number(get("CompactPDO"), u32::from(u8::MAX)),
            span: Some(section.span),
        };
        self.device.device_info = info;
    }

    fn read_dummy_usage(&mut self, section: &IniSection) {
        self.device.dummy_usage_span = Some(section.span);
        for entry in &section.entries {
            let index = entry
                .key
                .get(..5)
                .filter(|p| p.eq_ignore_ascii_case("Dummy"))
                .and_then(|_| entry.key.get(5..))
                .and_then(|hex| parse_hex_name(hex, 0xFFFF))
                .and_then(|v| u16::try_from(v).ok());
            match index {
                Some(index) => {
                    if !entry.key.starts_with("Dummy") {
                        self.once(
                            Diagnostic::new(
                                &rules::CASE_ONLY_MATCH,
                                Some(entry.key_span),
                                format!(
                                    "key `{}` is spelled `Dummy{index:04X}` in CiA 306",
                                    entry.key
                                ),
                            )
                            .with_severity(Severity::Warning)
                            .with_help(CASE_SENSITIVE_TOOLS),
                            "Dummy",
                        );
                    }
                    let used = self.boolean(Some(entry));
                    self.device.dummy_usage.insert(index, used);
                }
                None => self.unknown_key(entry, section),
            }
        }
    }

    /// A numbered key (`1`, `Line1`, ...): the number after `prefix`, decimal. Reports leading
    /// zeros (EDS010).
    fn numbered_key(&mut self, entry: &IniEntry, prefix: &str) -> Option<u32> {
        let head = entry.key.get(..prefix.len())?;
        if !head.eq_ignore_ascii_case(prefix) {
            return None;
        }
        let digits = entry.key.get(prefix.len()..)?;
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        let n = digits.parse::<u32>().ok()?;
        if digits.len() > 1 && digits.starts_with('0') {
            self.diags.push(
                Diagnostic::new(
                    &rules::LEADING_ZEROS,
                    Some(entry.key_span),
                    format!(
                        "numbered key `{}` has leading zeros; read as {prefix}{n}",
                        entry.key
                    ),
                )
                .with_help(format!("CiA 306 keys are strings: write `{prefix}{n}`")),
            );
        }
        if head != prefix {
            let diag = Diagnostic::new(
                &rules::CASE_ONLY_MATCH,
                Some(entry.key_span),
                format!("key `{}` is spelled `{prefix}{n}` in CiA 306", entry.key),
            );
            // python canopen finds the [Comments] lines by their exact spelling.
            let diag = if prefix == "Line" {
                diag.with_severity(Severity::Warning)
                    .with_help(CASE_SENSITIVE_TOOLS)
            } else {
                diag
            };
            self.once(diag, prefix);
        }
        Some(n)
    }

    fn read_comments(&mut self, section: &IniSection) {
        let mut lines: Vec<(u32, String)> = Vec::new();
        for entry in &section.entries {
            if entry.key.eq_ignore_ascii_case("Lines") {
                self.empty_number(entry);
                self.device.comment_lines = self.number(Some(entry), u32::from(u16::MAX));
                continue;
            }
            match self.numbered_key(entry, "Line") {
                Some(n) => lines.push((n, entry.value.as_str().to_owned())),
                None => self.unknown_key(entry, section),
            }
        }
        lines.sort_by_key(|(n, _)| *n);
        self.device.comments = lines.into_iter().map(|(_, text)| text).collect();
    }

    /// The numbered entries `1..n=<index>` of a list section (object lists, object links).
    fn index_entries(&mut self, section: &IniSection, count_key: &str) -> Vec<(u32, Spanned<u16>)> {
        let mut out = Vec::new();
        for entry in &section.entries {
            if entry.key.eq_ignore_ascii_case(count_key) {
                continue;
            }
            let Some(n) = self.numbered_key(entry, "") else {
                self.unknown_key(entry, section);
                continue;
            };
            let Some((text, span)) = self.plain_value(entry) else {
                continue;
            };
            match parse_integer(text).and_then(|v| u16::try_from(v).ok()) {
                Some(index) => out.push((n, Spanned::new(index, span))),
                None => self.diags.push(Diagnostic::new(
                    &rules::BAD_NUMBER,
                    Some(span),
                    format!(
                        "entry {n} of [{}] is not an object index: `{text}`",
                        section.name
                    ),
                )),
            }
        }
        out.sort_by_key(|(n, _)| *n);
        out
    }

    fn read_object_list(&mut self, section: &IniSection, kind: ObjectListKind) {
        let count = section.get("SupportedObjects");
        if let Some(entry) = count {
            if entry.key != "SupportedObjects" {
                self.once(
                    Diagnostic::new(
                        &rules::CASE_ONLY_MATCH,
                        Some(entry.key_span),
                        format!(
                            "key `{}` is spelled `SupportedObjects` in CiA 306",
                            entry.key
                        ),
                    ),
                    "SupportedObjects",
                );
            }
        }
        let supported_objects = self.number(count, u32::from(u16::MAX));
        let entries = self.index_entries(section, "SupportedObjects");
        self.device.object_lists.push(ObjectList {
            kind,
            supported_objects,
            entries,
            span: section.span,
        });
    }

    fn read_commissioning(&mut self, section: &IniSection) {
        if section.name.eq_ignore_ascii_case("DeviceCommissioning") {
            self.diags.push(
                Diagnostic::new(
                    &rules::COMMISSIONING_SPELLING,
                    Some(section.span),
                    format!(
                        "[{}] is read as the spec's [DeviceComissioning]",
                        section.name
                    ),
                )
                .with_help(
                    "CiA 306 spells it with one m; python canopen and Lely read only that spelling",
                ),
            );
        }
        let (keys, rest) = self.split_keys(section, COMMISSIONING_KEYS);
        for entry in rest {
            self.unknown_key(entry, section);
        }
        let get = |k: &str| keys.get(k).copied();
        let commissioning = Commissioning {
            node_id: self.number(get("NodeID"), u32::from(u8::MAX)),
            node_name: Self::string(get("NodeName")),
            baudrate: self.number(get("Baudrate"), u32::from(u16::MAX)),
            net_number: self.number(get("NetNumber"), u32::MAX).map(|n| n.value),
            network_name: Self::string(get("NetworkName")),
            canopen_manager: self.boolean(get("CANopenManager")),
            lss_serial_number: self
                .number(get("LSS_SerialNumber"), u32::MAX)
                .map(|n| n.value),
            span: section.span,
        };
        self.device.commissioning = Some(commissioning);
    }

    /// A value key kept raw; parsed against the data type later.
    fn raw_value(entry: Option<&IniEntry>) -> Option<ValueSource> {
        entry.filter(|e| !e.value.is_empty()).map(|e| ValueSource {
            value: None,
            raw: e.value.as_str().to_owned(),
            span: e.value_span,
        })
    }

    /// Reads the entry keys of a section (an object's main section for VAR/DOMAIN, or a sub-index
    /// section) into a sub-object. Keys that belong to the object level are returned for the
    /// caller.
    fn read_entry(
        &mut self,
        section: &IniSection,
        sub_index: u8,
        object_keys: ObjectKeys,
    ) -> SubObject {
        let (keys, rest) = self.split_keys(section, OBJECT_KEYS);
        let get = |at: usize| keys.at(at);
        let data_type = self
            .number(get(KEY_DATA_TYPE), u32::from(u16::MAX))
            .and_then(|n| u16::try_from(n.value).ok());
        let access = match get(KEY_ACCESS_TYPE) {
            Some(entry) => match self.plain_value(entry) {
                Some((text, span)) => {
                    match canonical_access(text).or_else(|| AccessType::parse(text)) {
                        Some(access) => {
                            if access.as_str() != text {
                                self.once(
                                    Diagnostic::new(
                                        &rules::CASE_ONLY_MATCH,
                                        Some(span),
                                        format!(
                                            "AccessType `{text}` is spelled `{}` in CiA 306",
                                            access.as_str()
                                        ),
                                    ),
                                    &format!("access-{text}"),
                                );
                            }
                            Some(access)
                        }
                        None => {
                            self.diags.push(
                            Diagnostic::new(
                                &rules::BAD_VALUE,
                                Some(span),
                                format!("AccessType `{text}` is not one of ro, wo, rw, rwr, rww, const"),
                            )
                            .with_label("ignored"),
                        );
                            None
                        }
                    }
                }
                None => None,
            },
            None => None,
        };
        let mut custom = Vec::new();
        // Object-level keys: the caller decides what they mean here.
        for (key, at) in [
            ("ObjectType", KEY_OBJECT_TYPE),
            ("SubNumber", KEY_SUB_NUMBER),
            ("CompactSubObj", KEY_COMPACT_SUB_OBJ),
        ] {
            if let Some(entry) = get(at) {
                let dropped = match object_keys {
                    ObjectKeys::Keep => false,
                    ObjectKeys::KeepUnlessVarType => {
                        key == "ObjectType"
                            && parse_integer(split_inline_comment(&entry.value).0) == Some(7)
                    }
                    ObjectKeys::Drop => true,
                };
                if dropped {
                    continue;
                }
                custom.push((
                    entry.key.as_str().to_owned(),
                    entry.value.as_str().to_owned(),
                ));
            }
        }
        for entry in rest {
            self.unknown_key(entry, section);
            custom.push((
                entry.key.as_str().to_owned(),
                entry.value.as_str().to_owned(),
            ));
        }
        // CANopenEditor's commented keys, unless the key is also written for real.
        for entry in &section.commented {
            if !custom
                .iter()
                .any(|(k, _)| k.eq_ignore_ascii_case(&entry.key))
            {
                custom.push((
                    entry.key.as_str().to_owned(),
                    entry.value.as_str().to_owned(),
                ));
            }
        }
        SubObject {
            sub_index,
            name: Self::string(get(KEY_PARAMETER_NAME)).unwrap_or_default(),
            data_type,
            access,
            pdo_mapping: self.boolean(get(KEY_PDO_MAPPING)),
            default: Self::raw_value(get(KEY_DEFAULT_VALUE)),
            parameter_value: Self::raw_value(get(KEY_PARAMETER_VALUE)),
            low_limit: Self::raw_value(get(KEY_LOW_LIMIT)),
            high_limit: Self::raw_value(get(KEY_HIGH_LIMIT)),
            obj_flags: self
                .number(get(KEY_OBJ_FLAGS), u32::MAX)
                .map_or(0, |n| n.value),
            denotation: Self::string(get(KEY_DENOTATION)),
            upload_file: Self::string(get(KEY_UPLOAD_FILE)),
            download_file: Self::string(get(KEY_DOWNLOAD_FILE)),
            span: section.span,
            custom,
            implicit: false,
            key_spans: KeySpans {
                data_type: get(KEY_DATA_TYPE).map(|e| e.value_span),
                access: get(KEY_ACCESS_TYPE).map(|e| e.value_span),
                pdo_mapping: get(KEY_PDO_MAPPING).map(|e| e.value_span),
                upload_file: get(KEY_UPLOAD_FILE).map(|e| e.value_span),
                download_file: get(KEY_DOWNLOAD_FILE).map(|e| e.value_span),
            },
            capacity: None,
        }
    }

    fn object_type_of(&mut self, main: &IniSection, has_sub_sections: bool) -> ObjectType {
        let Some(entry) = main.get("ObjectType") else {
            return ObjectType::Var;
        };
        let Some((text, span)) = self.plain_value(entry) else {
            return ObjectType::Var;
        };
        let code = parse_integer(text).and_then(|c| u32::try_from(c).ok());
        match code.and_then(ObjectType::from_code) {
            Some(t) => t,
            None => {
                let fallback = if has_sub_sections {
                    ObjectType::Record
                } else {
                    ObjectType::Var
                };
                self.diags.push(
                    Diagnostic::new(
                        &rules::BAD_NUMBER,
                        Some(span),
                        format!(
                            "ObjectType `{text}` is not a CiA 301 object code; read as {}",
                            if has_sub_sections {
                                "RECORD (0x9)"
                            } else {
                                "VAR (0x7)"
                            }
                        ),
                    )
                    .with_help("object codes are 0x0, 0x2, 0x5, 0x6, 0x7, 0x8 and 0x9"),
                );
                fallback
            }
        }
    }

    fn build_object(&mut self, index: u16, sections: &ObjectSections<'_>) {
        let Some(main) = sections.main else {
            // Sections about an object whose [index] section is missing: keep them as they are.
            for section in sections
                .subs
                .values()
                .copied()
                .chain(sections.names)
                .chain(sections.values)
                .chain(sections.denotations)
                .chain(sections.links)
            {
                self.diags.push(Diagnostic::new(
                    &rules::ORPHAN_SECTION,
                    Some(section.span),
                    format!(
                        "section [{}] belongs to object {index:04X}h, which has no [{index:X}] section",
                        section.name
                    ),
                ).with_label("kept but not interpreted"));
                self.keep(section);
            }
            return;
        };
        let object_type = self.object_type_of(main, !sections.subs.is_empty());
        let name = Self::string(main.get("ParameterName")).unwrap_or_default();
        let uses_subs = object_type.has_subs()
            || (object_type == ObjectType::DefType && !sections.subs.is_empty());
        let mut object = Object {
            index,
            name,
            object_type,
            subs: BTreeMap::new(),
            sub_number: None,
            compact_sub_obj: None,
            obj_flags: 0,
            span: main.span,
            custom: Vec::new(),
            object_links: Vec::new(),
            implicit: false,
        };
        if uses_subs {
            let (keys, rest) = self.split_keys(main, OBJECT_KEYS);
            object.sub_number = self.number(keys.get("SubNumber").copied(), u32::from(u8::MAX));
            object.compact_sub_obj = self
                .number(keys.get("CompactSubObj").copied(), u32::from(u8::MAX))
                .filter(|n| n.value != 0);
            object.obj_flags = self
                .number(keys.get("ObjFlags").copied(), u32::MAX)
                .map_or(0, |n| n.value);
            for entry in rest {
                self.unknown_key(entry, main);
                object.custom.push((
                    entry.key.as_str().to_owned(),
                    entry.value.as_str().to_owned(),
                ));
            }
            // CANopenEditor's commented keys, unless the key is also written for real.
            for entry in &main.commented {
                if !object
                    .custom
                    .iter()
                    .any(|(k, _)| k.eq_ignore_ascii_case(&entry.key))
                {
                    object.custom.push((
                        entry.key.as_str().to_owned(),
                        entry.value.as_str().to_owned(),
                    ));
                }
            }
            // Standard keys that an ARRAY/RECORD main section does not use without
            // CompactSubObj stay visible to the validator in `custom`.
            if object.compact_sub_obj.is_none() {
                for (key, entry) in &keys.sorted() {
                    if !matches!(
                        *key,
                        "ParameterName" | "ObjectType" | "SubNumber" | "ObjFlags" | "CompactSubObj"
                    ) {
                        object.custom.push((
                            entry.key.as_str().to_owned(),
                            entry.value.as_str().to_owned(),
                        ));
                    }
                }
            }
            if let Some(count) = object.compact_sub_obj.clone() {
                let template = self.read_entry(main, 0, ObjectKeys::Keep);
                expand_compact_sub_obj(&mut object, &template, count);
            }
            for (sub, section) in &sections.subs {
                let entry = self.read_entry(section, *sub, ObjectKeys::KeepUnlessVarType);
                object.subs.insert(*sub, entry);
            }
        } else {
            // The object-level keys are not entry keys: they stay out of the entry's custom.
            let mut entry = self.read_entry(main, 0, ObjectKeys::Drop);
            object.obj_flags = entry.obj_flags;
            if object_type == ObjectType::Domain {
                entry.data_type.get_or_insert(BasicType::Domain.index());
                entry.access.get_or_insert(AccessType::Rw);
            }
            for key in ["SubNumber", "CompactSubObj"] {
                if let Some(e) = main.get(key) {
                    object
                        .custom
                        .push((e.key.as_str().to_owned(), e.value.as_str().to_owned()));
                }
            }
            object.subs.insert(0, entry);
            for section in sections.subs.values() {
                self.diags.push(
                    Diagnostic::new(
                        &rules::ORPHAN_SECTION,
                        Some(section.span),
                        format!(
                            "section [{}] describes a sub-index of {index:04X}h, which is a {} without sub-indices",
                            section.name,
                            if object_type == ObjectType::Domain { "DOMAIN" } else { "VAR" }
                        ),
                    )
                    .with_label("kept but not interpreted"),
                );
                self.keep(section);
            }
        }
        self.apply_per_sub_sections(&mut object, sections);
        if let Some(links) = sections.links {
            object.object_links = self
                .index_entries(links, "ObjectLinks")
                .into_iter()
                .map(|(_, index)| index.value)
                .collect();
        }
        self.device.objects.insert(index, object);
    }

    /// `[xxxxName]`, DCF `[xxxxValue]` and `[xxxxDenotation]`: per-sub names, values and
    /// denotations keyed by decimal sub-index.
    fn apply_per_sub_sections(&mut self, object: &mut Object, sections: &ObjectSections<'_>) {
        #[derive(Clone, Copy)]
        enum What {
            Name,
            Value,
            Denotation,
        }
        for (section, what) in [
            (sections.names, What::Name),
            (sections.values, What::Value),
            (sections.denotations, What::Denotation),
        ] {
            let Some(section) = section else { continue };
            for entry in &section.entries {
                if entry.key.eq_ignore_ascii_case("NrOfEntries") {
                    continue;
                }
                let sub = self
                    .numbered_key(entry, "")
                    .and_then(|n| u8::try_from(n).ok());
                let Some(sub) = sub else {
                    self.unknown_key(entry, section);
                    continue;
                };
                let Some(target) = object.subs.get_mut(&sub) else {
                    self.diags.push(
                        Diagnostic::new(
                            &rules::ORPHAN_SECTION,
                            Some(entry.key_span),
                            format!(
                                "[{}] names sub-index {sub} of {:04X}h, which does not exist",
                                section.name, object.index
                            ),
                        )
                        .with_label("ignored"),
                    );
                    continue;
                };
                if entry.value.is_empty() {
                    continue;
                }
                match what {
                    What::Name => target.name = entry.value.as_str().to_owned(),
                    What::Value => {
                        target.parameter_value = Some(ValueSource {
                            value: None,
                            raw: entry.value.as_str().to_owned(),
                            span: entry.value_span,
                        })
                    }
                    What::Denotation => target.denotation = Some(entry.value.as_str().to_owned()),
                }
            }
        }
    }

    /// Synthesises the PDO objects that `CompactPDO` leaves out.
    fn expand_compact_pdo(&mut self) {
        expand_compact_pdo(&mut self.device);
    }

    /// Parses every kept value text against its entry's data type, DEFTYPE objects first.
    fn resolve_values(&mut self) {
        type Parsed = (String, Span, Option<Value>);
        let mut parsed: HashMap<(Span, String, Option<BasicType>), Parsed, FastHash> =
            HashMap::default();
        // Only a span written into several entries (CompactSubObj) can hit the cache: count them
        // first, so values with a span of their own skip the cache (and its copies).
        let mut span_uses: HashMap<Span, u32, FastHash> = HashMap::default();
        for object in self.device.objects.values() {
            for entry in object.subs.values() {
                for source in [
                    &entry.default,
                    &entry.parameter_value,
                    &entry.low_limit,
                    &entry.high_limit,
                ]
                .into_iter()
                .flatten()
                {
                    *span_uses.entry(source.span).or_default() += 1;
                }
            }
        }
        for deftypes_pass in [true, false] {
            let mut work = Vec::new();
            for (index, object) in &self.device.objects {
                if (*index < 0x1000) != deftypes_pass {
                    continue;
                }
                for (sub, entry) in &object.subs {
                    let basic = entry.data_type.and_then(|t| self.device.basic_type(t));
                    work.push((*index, *sub, basic));
                }
            }
            for (index, sub, basic) in work {
                let Some(entry) = self
                    .device
                    .objects
                    .get_mut(&index)
                    .and_then(|o| o.subs.get_mut(&sub))
                else {
                    continue;
                };
                for (key, slot) in [
                    ("DefaultValue", &mut entry.default),
                    ("ParameterValue", &mut entry.parameter_value),
                    ("LowLimit", &mut entry.low_limit),
                    ("HighLimit", &mut entry.high_limit),
                ] {
                    let Some(source) = slot else { continue };
                    if span_uses.get(&source.span).copied().unwrap_or(0) < 2 {
                        resolve_value(source, key, basic, &mut self.diags);
                        continue;
                    }
                    // CompactSubObj copies one written value into many entries: parse it (and
                    // report it) once.
                    let cache_key = (source.span, source.raw.clone(), basic);
                    if let Some((raw, span, value)) = parsed.get(&cache_key) {
                        source.raw.clone_from(raw);
                        source.span = *span;
                        source.value.clone_from(value);
                        continue;
                    }
                    resolve_value(source, key, basic, &mut self.diags);
                    parsed.insert(
                        cache_key,
                        (source.raw.clone(), source.span, source.value.clone()),
                    );
                }
                if let Some(ty) = basic {
                    drop_inverting_hex_high_limit(entry, ty, &mut self.diags);
                }
            }
        }
    }
}

/// `LowLimit=0` with `HighLimit=0xFFFF` on an INTEGER16 (Sevcon, Faulhaber): read as two's
/// complement the high limit is -1, below the low limit, and every value would be refused. The
/// vendor means the unsigned number, which is above the type's maximum and restricts nothing: the
/// high limit is dropped and the two's-complement info (EDS014) becomes an EDS013 warning.
fn drop_inverting_hex_high_limit(entry: &mut SubObject, ty: BasicType, diags: &mut [Diagnostic]) {
    let (Some(low), Some(high)) = (entry.low_limit.as_ref(), entry.high_limit.as_mut()) else {
        return;
    };
    let (Some(Value::Integer(lo)), Some(Value::Integer(hi))) = (&low.value, &high.value) else {
        return;
    };
    let is_hex = high.raw.trim().to_ascii_lowercase().starts_with("0x");
    if !(ty.is_signed_integer() && is_hex && *hi < 0 && lo > hi) {
        return;
    }
    let (hi, span) = (*hi, high.span);
    high.value = None;
    // CompactSubObj entries share one written limit: report it once.
    let Some(at) = diags
        .iter()
        .rposition(|d| d.rule.code == rules::TWOS_COMPLEMENT.code && d.span == Some(span))
    else {
        return;
    };
    let max = ty.integer_range().map_or(0, |(_, max)| max);
    diags[at] = Diagnostic::new(
        &rules::OUT_OF_RANGE,
        Some(span),
        format!(
            "HighLimit `{}` read as two's complement ({hi}) is below the LowLimit; as the unsigned number meant, it is above the maximum {max} of {}: it restricts nothing and is ignored",
            high.raw.trim(),
            ty.name()
        ),
    )
    .with_severity(Severity::Warning)
    .with_help(format!("remove the HighLimit, or write {max}"));
}

/// Strips an inline comment where the type allows it, then parses the value.
fn resolve_value(
    source: &mut ValueSource,
    key: &str,
    basic: Option<BasicType>,
    diags: &mut Vec<Diagnostic>,
) {
    if source.value.is_some() {
        return;
    }
    let (value, comment) = split_inline_comment(&source.raw);
    if comment.is_some() {
        if strips_inline_comment(basic) {
            diags.push(
                Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(source.span),
                    format!("inline comment after the {key} is ignored"),
                )
                .with_help("put the comment on its own line, starting with `;`"),
            );
            let value = value.to_owned();
            source.span.len = u32::try_from(value.chars().count()).unwrap_or(u32::MAX);
            source.raw = value;
        } else if basic.is_some() {
            diags.push(
                Diagnostic::new(
                    &rules::INLINE_COMMENT,
                    Some(source.span),
                    format!("the {key} contains `;`; it is kept as part of the string"),
                )
                .with_severity(Severity::Warning),
            );
        }
    }
    let mut found = Vec::new();
    source.value = parse_value(&source.raw, basic, source.span, &mut found);
    if let Some(ty) = basic {
        for diag in &mut found {
            soften_limit_beyond_type(diag, key, &source.raw, ty);
        }
    }
    diags.append(&mut found);
}

/// A LowLimit below the type's minimum or a HighLimit above its maximum restricts nothing: the
/// limit is dropped (the type's own range applies) and EDS013 becomes a warning. Vendors write
/// `HighLimit=65535` on INTEGER16 or `0xFFFFFFFF` on UNSIGNED16 to mean "no limit". A limit beyond
/// the other end (which would exclude every value) stays an error, except `HighLimit=-1` on an
/// unsigned type, which C and .NET tools read as all ones.
fn soften_limit_beyond_type(diag: &mut Diagnostic, key: &str, raw: &str, ty: BasicType) {
    if diag.rule.code != rules::OUT_OF_RANGE.code {
        return;
    }
    let (Some(value), Some((min, max))) = (parse_integer(raw), ty.integer_range()) else {
        return;
    };
    let (beyond, bound) = match key {
        "HighLimit" if value > max => ("above the maximum", max),
        "LowLimit" if value < min => ("below the minimum", min),
        // Sevcon writes HighLimit=-1 on unsigned entries: all ones, the maximum, as C and .NET
        // tools read it.
        "HighLimit" if value == -1 && min == 0 => ("all ones, the maximum", max),
        _ => return,
    };
    *diag = Diagnostic::new(
        &rules::OUT_OF_RANGE,
        diag.span,
        format!(
            "{key} `{}` is {beyond} {bound} of {}; it restricts nothing and is ignored",
            raw.trim(),
            ty.name()
        ),
    )
    .with_severity(Severity::Warning)
    .with_help(format!("remove the {key}, or write {bound}"));
}

/// Expands `CompactSubObj=N` into implicit sub-objects 0..N (CiA 306 4.6.3.4): sub 0
/// `NrOfObjects` (UNSIGNED8, ro, default N), subs 1..N named `<ParameterName><n>` (decimal) with
/// the data type, access type, default value, PDO mapping and limits of the main section
/// (`template`).
pub fn expand_compact_sub_obj(object: &mut Object, template: &SubObject, count: Spanned<u32>) {
    let span = count.span;
    object.subs.insert(
        0,
        SubObject {
            sub_index: 0,
            name: "NrOfObjects".to_owned(),
            data_type: Some(BasicType::Unsigned8.index()),
            access: Some(AccessType::Ro),
            pdo_mapping: false,
            default: Some(ValueSource {
                value: Some(Value::Integer(i128::from(count.value))),
                raw: count.value.to_string(),
                span,
            }),
            parameter_value: None,
            low_limit: None,
            high_limit: None,
            obj_flags: 0,
            denotation: None,
            upload_file: None,
            download_file: None,
            span,
            custom: Vec::new(),
            implicit: true,
            key_spans: KeySpans::default(),
            capacity: None,
        },
    );
    for n in 1..=count.value.min(255) {
        let Ok(sub_index) = u8::try_from(n) else {
            break;
        };
        object.subs.insert(
            sub_index,
            SubObject {
                sub_index,
                name: numbered_name(&object.name, n),
                data_type: template.data_type,
                access: template.access,
                pdo_mapping: template.pdo_mapping,
                default: template.default.clone(),
                parameter_value: None,
                low_limit: template.low_limit.clone(),
                high_limit: template.high_limit.clone(),
                obj_flags: 0,
                denotation: None,
                upload_file: None,
                download_file: None,
                span,
                custom: Vec::new(),
                implicit: true,
                key_spans: template.key_spans,
                capacity: None,
            },
        );
    }
}

/// `<name><n>` (decimal), without the formatting machinery: it runs once per compact sub-object.
fn numbered_name(name: &str, n: u32) -> String {
    let mut digits = [0u8; 10];
    let mut at = digits.len();
    let mut rest = n;
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            break;
        }
    }
    let mut out = String::with_capacity(name.len() + digits.len() - at);
    out.push_str(name);
    out.extend(digits[at..].iter().map(|d| char::from(*d)));
    out
}

/// The entry layout of the PDO communication sub-indices 1..6 (CiA 301): name, data type.
const PDO_COMM_SUBS: [(&str, BasicType); 6] = [
    ("COB-ID used by {}PDO", BasicType::Unsigned32),
    ("Transmission type", BasicType::Unsigned8),
    ("Inhibit time", BasicType::Unsigned16),
    ("Compatibility entry", BasicType::Unsigned8),
    ("Event timer", BasicType::Unsigned16),
    ("SYNC start value", BasicType::Unsigned8),
];

/// How many mapping entries an implicit PDO mapping object gets: 8, enough for a classic CAN
/// frame at granularity 8 (eight one-byte objects). CAN FD devices describe their mapping
/// objects explicitly.
pub const IMPLICIT_MAPPING_ENTRIES: u8 = 8;

/// The highest PDO number (1-based) CiA 301 allows per direction.
const MAX_PDOS: u32 = 512;

/// An implicit entry: no value unless given, access rw unless said otherwise.
fn implicit_entry(
    sub_index: u8,
    name: String,
    data_type: BasicType,
    access: AccessType,
    default: Option<Value>,
    span: Span,
) -> SubObject {
    SubObject {
        sub_index,
        name,
        data_type: Some(data_type.index()),
        access: Some(access),
        pdo_mapping: false,
        default: default.map(|value| ValueSource {
            raw: match &value {
                Value::NodeRelative(offset) => format!("$NODEID+0x{offset:X}"),
                Value::Integer(v) if *v > 9 => format!("0x{v:X}"),
                Value::Integer(v) => v.to_string(),
                other => format!("{other:?}"),
            },
            value: Some(value),
            span,
        }),
        parameter_value: None,
        low_limit: None,
        high_limit: None,
        obj_flags: 0,
        denotation: None,
        upload_file: None,
        download_file: None,
        span,
        custom: Vec::new(),
        implicit: true,
        key_spans: KeySpans::default(),
        capacity: None,
    }
}

/// Synthesises the PDO communication (1400h+/1800h+) and mapping (1600h+/1A00h+) objects that
/// `CompactPDO` in `[DeviceInfo]` leaves out (CiA 306 4.6.3.4.1 / 5.3.3).
///
/// For each direction, the implicit count is NrOfRXPDO/NrOfTXPDO minus the PDOs described
/// explicitly (a PDO counts as explicit when its communication or its mapping object is
/// present), placed at the lowest free PDO numbers. A communication object gets sub 0 (UNSIGNED8,
/// ro, the highest sub-index of the bitmask) and the sub-indices whose bit is set (bit 0 = sub 1
/// ... bit 5 = sub 6), rw, without default values except the COB-ID: for PDOs 1-4 the predefined
/// connection set (`$NODEID+0x200/0x300/0x400/0x500` for RPDOs, `$NODEID+0x180/0x280/0x380/0x480`
/// for TPDOs), for the others `0x80000000` (not valid). In a DCF, where CompactPDO means "the PDOs
/// not written are disabled", bit 31 is set on the first four too. A mapping object gets sub 0
/// "Number of mapped application objects in PDO" (UNSIGNED8, rw, 0) and
/// [`IMPLICIT_MAPPING_ENTRIES`] UNSIGNED32 entries (rw, 0). Every synthesised object and entry is
/// marked `implicit`, with the span of the `CompactPDO` key.
pub fn expand_compact_pdo(device: &mut Device) {
    let Some(mask) = device.device_info.compact_pdo.clone() else {
        return;
    };
    let comm_bits = mask.value & 0x3F;
    if comm_bits == 0 {
        return;
    }
    let span = mask.span;
    let dcf = device.source.format == Format::Dcf;
    let highest_sub = 32 - comm_bits.leading_zeros();
    for (kind, count, comm_base, map_base, cob_base) in [
        (
            "R",
            device.device_info.nr_of_rx_pdo.clone(),
            0x1400u16,
            0x1600u16,
            0x200i64,
        ),
        (
            "T",
            device.device_info.nr_of_tx_pdo.clone(),
            0x1800,
            0x1A00,
            0x180,
        ),
    ] {
        let Some(count) = count else { continue };
        let wanted = count.value.min(MAX_PDOS);
        let present = |objects: &BTreeMap<u16, Object>, n: u16| {
            objects.contains_key(&(comm_base + n)) || objects.contains_key(&(map_base + n))
        };
        let explicit = (0..MAX_PDOS as u16)
            .filter(|n| present(&device.objects, *n))
            .count();
        let mut missing = wanted.saturating_sub(u32::try_from(explicit).unwrap_or(u32::MAX));
        for n in 0..MAX_PDOS as u16 {
            if missing == 0 {
                break;
            }
            if present(&device.objects, n) {
                continue;
            }
            missing -= 1;
            let number = n + 1;
            let mut comm = Object {
                index: comm_base + n,
                name: format!("{kind}PDO{number} communication parameter"),
                object_type: ObjectType::Record,
                subs: BTreeMap::new(),
                sub_number: None,
                compact_sub_obj: None,
                obj_flags: 0,
                span,
                custom: Vec::new(),
                object_links: Vec::new(),
                implicit: true,
            };
            comm.subs.insert(
                0,
                implicit_entry(
                    0,
                    "Highest sub-index supported".to_owned(),
                    BasicType::Unsigned8,
                    AccessType::Ro,
                    Some(Value::Integer(i128::from(highest_sub))),
                    span,
                ),
            );
            for (bit, (name, data_type)) in PDO_COMM_SUBS.iter().enumerate() {
                if comm_bits & (1 << bit) == 0 {
                    continue;
                }
                let sub = u8::try_from(bit + 1).unwrap_or(u8::MAX);
                let default = (sub == 1).then(|| {
                    let disabled = 0x8000_0000i64;
                    if n < 4 {
                        let cob = cob_base + 0x100 * i64::from(n);
                        Value::NodeRelative(if dcf { disabled + cob } else { cob })
                    } else {
                        Value::Integer(i128::from(disabled))
                    }
                });
                comm.subs.insert(
                    sub,
                    implicit_entry(
                        sub,
                        name.replace("{}", kind),
                        *data_type,
                        AccessType::Rw,
                        default,
                        span,
                    ),
                );
            }
            let mut mapping = Object {
                index: map_base + n,
                name: format!("{kind}PDO{number} mapping parameter"),
                subs: BTreeMap::new(),
                ..comm.clone()
            };
            mapping.subs.insert(
                0,
                implicit_entry(
                    0,
                    "Number of mapped application objects in PDO".to_owned(),
                    BasicType::Unsigned8,
                    AccessType::Rw,
                    Some(Value::Integer(0)),
                    span,
                ),
            );
            for sub in 1..=IMPLICIT_MAPPING_ENTRIES {
                mapping.subs.insert(
                    sub,
                    implicit_entry(
                        sub,
                        format!("Application object {sub}"),
                        BasicType::Unsigned32,
                        AccessType::Rw,
                        Some(Value::Integer(0)),
                        span,
                    ),
                );
            }
            device.objects.insert(comm.index, comm);
            device.objects.insert(mapping.index, mapping);
        }
    }
}
