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
//! - A sub-index section whose sub-index cannot exist (`[D000sub100]`: sub-index sections are
//!   hex, so 0x100) is an EDS030 error at its header, kept in `other_sections`; the help says
//!   what a file that counts in decimal meant.
//! - The same object section written two ways (`[1000]` and `[01000]`): the later wins, EDS005.
//! - CompactSubObj and CompactPDO are expanded into implicit sub-objects and objects (see
//!   [`expand_compact_sub_obj`] and [`expand_compact_pdo`]).

use std::collections::{BTreeMap, HashSet};
use std::path::Path;

use super::hash::FastHash;
use super::ini::{self, IniSection};
use super::Read;
use crate::diag::Diagnostic;
use crate::model::*;
use crate::rules;
use objects::ObjectSections;
use sections::{classify, SectionKind, NAMED_SECTIONS};

mod compact;
mod info;
mod keys;
mod objects;
mod sections;
mod values;

pub use compact::{expand_compact_pdo, expand_compact_sub_obj, IMPLICIT_MAPPING_ENTRIES};

/// Reads an EDS or DCF file (a DCF when the extension is `.dcf`, case-insensitively).
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = super::text::decode(bytes);
    read_text(path, text, encoding)
}

/// Reads an EDS or DCF file already decoded (`encoding` says from what).
pub(super) fn read_text(path: &Path, text: String, encoding: TextEncoding) -> Read {
    // A DCF by its extension alone, as `detect_format` has it (without its ODVA scan again).
    let dcf = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("dcf"));
    let format = if dcf { Format::Dcf } else { Format::Eds };
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
        bus: Bus::CanOpen,
    }
}

/// The reader's state while it walks a file's sections.
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
            // An object's or entry's name is none of the named sections (`classify` tells them).
            let named = !matches!(kind, SectionKind::Object(_) | SectionKind::Sub(..));
            if let Some((canonical, _)) = NAMED_SECTIONS
                .iter()
                .filter(|_| named)
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
                SectionKind::BadSub(index) => self.bad_sub_section(section, index),
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

    /// A sub-index section whose sub-index cannot exist (`[D000sub100]`): an EDS030 error at its
    /// header, the section kept in `other_sections`. Its keys are not read into the model.
    fn bad_sub_section(&mut self, section: &IniSection, index: u16) {
        let at = sections::rfind_sub(&section.name).unwrap_or(0);
        let sub_text = section.name.get(at + 3..).unwrap_or("");
        let (what, why, help) = sections::bad_sub_index(sub_text);
        self.diags.push(
            Diagnostic::new(
                &rules::BAD_SUB_INDEX,
                Some(section.span),
                format!(
                    "section [{}] names {what} of {index:04X}h: {why}; the section is kept but not read",
                    section.name
                ),
            )
            .with_label("no such sub-index")
            .with_help(help),
        );
        self.keep(section);
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
            name: section.name.as_str().to_owned(),
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
}
