//! Object sections: an object's main, sub-index, name, value, denotation and link sections into
//! one [`Object`] with its sub-objects.

use std::collections::BTreeMap;

use super::compact::{expand_compact_pdo, expand_compact_sub_obj};
use super::keys::{key_index, MAX_KNOWN_KEYS};
use super::Reader;
use crate::diag::Diagnostic;
use crate::model::*;
use crate::read::ini::{IniEntry, IniSection};
use crate::read::value::{octal_objection, parse_integer, split_inline_comment};
use crate::rules;

/// The keys of an object or sub-object section.
pub(super) const OBJECT_KEYS: &[&str] = &[
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

const _: () = assert!(OBJECT_KEYS.len() <= MAX_KNOWN_KEYS);

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
pub(super) struct ObjectSections<'a> {
    pub(super) main: Option<&'a IniSection<'a>>,
    pub(super) subs: BTreeMap<u8, &'a IniSection<'a>>,
    pub(super) names: Option<&'a IniSection<'a>>,
    pub(super) values: Option<&'a IniSection<'a>>,
    pub(super) denotations: Option<&'a IniSection<'a>>,
    pub(super) links: Option<&'a IniSection<'a>>,
}

impl Reader {
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
            Some(entry) => {
                match self.plain_value(entry) {
                    Some((text, span)) => match AccessType::parse(text) {
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
                    },
                    None => None,
                }
            }
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
                let read_as = if has_sub_sections {
                    "RECORD (0x9)"
                } else {
                    "VAR (0x7)"
                };
                let (message, help) = match octal_objection(text) {
                    Some((why, help)) => (format!("ObjectType {why}; read as {read_as}"), help),
                    None => (
                        format!(
                            "ObjectType `{text}` is not a CiA 301 object code; read as {read_as}"
                        ),
                        "object codes are 0x0, 0x2, 0x5, 0x6, 0x7, 0x8 and 0x9".to_owned(),
                    ),
                };
                self.diags
                    .push(Diagnostic::new(&rules::BAD_NUMBER, Some(span), message).with_help(help));
                fallback
            }
        }
    }

    pub(super) fn build_object(&mut self, index: u16, sections: &ObjectSections<'_>) {
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
        let mut object = Object::new(index, name, object_type, main.span);
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
            let compact = object
                .compact_sub_obj
                .as_ref()
                .map_or(0, |c| c.value as usize + 1);
            object.subs.reserve(compact.min(256) + sections.subs.len());
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
                let number = self.numbered_key(entry, "");
                let Some(sub) = number.and_then(|n| u8::try_from(n).ok()) else {
                    match number {
                        // A sub-index that cannot exist: an error, not an unknown key.
                        Some(n) => self.diags.push(
                            Diagnostic::new(
                                &rules::BAD_SUB_INDEX,
                                Some(entry.key_span),
                                format!(
                                    "[{}] names sub-index {n} of {:04X}h, beyond 255; the key is not read",
                                    section.name, object.index
                                ),
                            )
                            .with_label("no such sub-index"),
                        ),
                        None => self.unknown_key(entry, section),
                    }
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
    pub(super) fn expand_compact_pdo(&mut self) {
        expand_compact_pdo(&mut self.device);
    }
}
