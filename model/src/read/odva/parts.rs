//! The sections of an ODVA EDS into the CIP model, one method per section: `[File]`, `[Device]`,
//! `[Device Classification]`, `[Params]`, `[Assembly]`, `[Connection Manager]`, `[Port]`,
//! `[Capacity]`. Fields in the wrong form are CIP004 and read as absent; unknown keys CIP002.

use super::{field_ref, key_number, number};
use crate::diag::Diagnostic;
use crate::model::*;
use crate::rules;

/// The model being filled and the diagnostics.
pub struct Parts<'a> {
    pub cip: &'a mut Cip,
    pub diags: &'a mut Vec<Diagnostic>,
}

/// Keys every object section of the specification may carry (the class attributes).
const CLASS_KEYS: &[&str] = &[
    "Revision",
    "Object_Name",
    "Object_Class_Code",
    "MaxInst",
    "Number_Of_Static_Instances",
    "Max_Number_Of_Dynamic_Instances",
    "Class_Attributes",
    "Instance_Attributes",
    "Class_Services",
    "Instance_Services",
];

/// The keys of `[File]`, as the specification spells them.
const FILE_KEYS: &[&str] = &[
    "DescText",
    "CreateDate",
    "CreateTime",
    "ModDate",
    "ModTime",
    "Revision",
    "HomeURL",
    "Exclude",
];

/// The keys of `[Device]`, as the specification spells them.
const DEVICE_KEYS: &[&str] = &[
    "VendCode",
    "VendName",
    "ProdType",
    "ProdTypeStr",
    "ProdCode",
    "MajRev",
    "MinRev",
    "ProdName",
    "Catalog",
    "Icon",
    "IconContents",
];

fn known(key: &str, list: &[&str]) -> bool {
    list.iter().any(|k| k.eq_ignore_ascii_case(key))
}

/// The span of a field, or of the entry's key when the field is empty or missing.
fn field_span(entry: &CipEntry, i: usize) -> Span {
    match entry.fields.get(i) {
        Some(f) if f.span.line != 0 => f.span,
        _ => entry.span,
    }
}

fn text(entry: &CipEntry, i: usize) -> String {
    entry
        .fields
        .get(i)
        .map_or(String::new(), |f| f.text.clone())
}

impl Parts<'_> {
    /// CIP002 for a key `section` does not define; `keys` and the numbered `families` (`Param`
    /// for `ParamN`) are the section's own, offered when the key is a misspelling of one.
    fn unknown_key(&mut self, section: &str, entry: &CipEntry, keys: &[&str], families: &[&str]) {
        let key = entry.key.as_str();
        let number = &key[key.trim_end_matches(|c: char| c.is_ascii_digit()).len()..];
        let numbered = families
            .iter()
            .filter(|_| !number.is_empty())
            .map(|family| format!("{family}{number}"));
        let candidates = keys
            .iter()
            .map(|k| (*k).to_owned())
            .chain(numbered)
            .map(|k| (k.clone(), k));
        let diag = Diagnostic::new(
            &rules::CIP_UNKNOWN,
            Some(entry.span),
            format!("the key `{key}` is not one [{section}] defines (kept as written)"),
        )
        .with_label("kept, not interpreted");
        self.diags
            .push(match crate::did_you_mean::misspelt(key, candidates) {
                Some(meant) => diag.with_help(format!("did you mean `{meant}`?")),
                None => diag,
            });
    }

    fn bad_field(&mut self, entry: &CipEntry, i: usize, what: &str) {
        let written = entry.fields.get(i).map_or("", |f| f.text.as_str());
        let message = if entry.fields.len() <= i {
            format!("`{}` has no field {} ({what})", entry.key, i + 1)
        } else {
            format!(
                "field {} of `{}` ({what}) is `{written}`, not a number in range",
                i + 1,
                entry.key
            )
        };
        self.diags.push(
            Diagnostic::new(&rules::CIP_BAD_FIELD, Some(field_span(entry, i)), message)
                .with_label(what.to_owned()),
        );
    }

    /// An integer field of a type `T`; empty reads as `None` without a diagnostic unless
    /// `required`.
    fn int<T: TryFrom<i128>>(
        &mut self,
        entry: &CipEntry,
        i: usize,
        what: &str,
        required: bool,
    ) -> Option<Spanned<T>> {
        let field = entry.fields.get(i);
        if field.is_none_or(|f| f.is_empty()) {
            if required {
                self.bad_field(entry, i, what);
            }
            return None;
        }
        let f = field?;
        match number(&f.text) {
            Some(CipNumber::Int(v)) => match T::try_from(v) {
                Ok(v) => Some(Spanned::new(v, f.span)),
                Err(_) => {
                    self.bad_field(entry, i, what);
                    None
                }
            },
            _ => {
                self.bad_field(entry, i, what);
                None
            }
        }
    }

    /// A numeric field (limits, defaults).
    fn num(&mut self, entry: &CipEntry, i: usize, what: &str) -> Option<Spanned<CipNumber>> {
        let f = entry.fields.get(i).filter(|f| !f.is_empty())?;
        match number(&f.text) {
            Some(v) => Some(Spanned::new(v, f.span)),
            None => {
                self.bad_field(entry, i, what);
                None
            }
        }
    }

    fn string_field(&self, entry: &CipEntry) -> Option<String> {
        entry.fields.first().map(|f| f.text.clone())
    }

    pub fn file(&mut self, section: &CipSection) {
        self.cip.file.span = Some(section.span);
        for entry in &section.entries {
            let value = self.string_field(entry);
            match entry.key.to_ascii_lowercase().as_str() {
                "desctext" => self.cip.file.desc_text = value,
                "createdate" => self.cip.file.create_date = value,
                "moddate" => self.cip.file.mod_date = value,
                "revision" => self.cip.file.revision = value,
                "createtime" | "modtime" | "homeurl" | "exclude" => {}
                _ => self.unknown_key("File", entry, FILE_KEYS, &[]),
            }
        }
    }

    pub fn device(&mut self, section: &CipSection) {
        self.cip.identity.span = Some(section.span);
        for entry in &section.entries {
            let value = self.string_field(entry);
            let id = &mut self.cip.identity;
            match entry.key.to_ascii_lowercase().as_str() {
                "vendcode" => self.cip.identity.vendor_code = self.int(entry, 0, "vendor ID", true),
                "vendname" => id.vendor_name = value,
                "prodtype" => {
                    self.cip.identity.product_type = self.int(entry, 0, "device type", true)
                }
                "prodtypestr" => id.product_type_str = value,
                "prodcode" => {
                    self.cip.identity.product_code = self.int(entry, 0, "product code", true)
                }
                "majrev" => {
                    self.cip.identity.major_revision = self.int(entry, 0, "major revision", true)
                }
                "minrev" => {
                    self.cip.identity.minor_revision = self.int(entry, 0, "minor revision", true)
                }
                "prodname" => id.product_name = value,
                "catalog" => id.catalog = value,
                "icon" | "iconcontents" => {}
                _ => self.unknown_key("Device", entry, DEVICE_KEYS, &[]),
            }
        }
    }

    pub fn classification(&mut self, section: &CipSection) {
        for entry in &section.entries {
            match (key_number(&entry.key, "Class"), entry.fields.first()) {
                (Some(_), Some(f)) => self
                    .cip
                    .classifications
                    .push(Spanned::new(f.text.clone(), f.span)),
                _ => self.unknown_key("Device Classification", entry, &[], &["Class"]),
            }
        }
    }

    pub fn params(&mut self, section: &CipSection) {
        for entry in &section.entries {
            if let Some(n) = key_number(&entry.key, "Param") {
                let param = self.param(n, entry);
                self.cip.params.insert(n, param);
            } else if let Some(n) = key_number(&entry.key, "Enum") {
                let e = self.enumeration(n, entry);
                self.cip.enums.insert(n, e);
            } else if !known(&entry.key, CLASS_KEYS) {
                self.unknown_key(&section.name, entry, CLASS_KEYS, &["Param", "Enum"]);
            }
        }
    }

    fn param(&mut self, number: u32, entry: &CipEntry) -> CipParam {
        if entry.fields.len() < 12 {
            self.diags.push(
                Diagnostic::new(
                    &rules::CIP_BAD_FIELD,
                    Some(entry.span),
                    format!(
                        "`{}` has {} fields; a parameter has at least 12 (reserved, link path size, \
                         link path, descriptor, data type, data size, name, units, help, min, max, default)",
                        entry.key,
                        entry.fields.len()
                    ),
                )
                .with_label("too few fields"),
            );
        }
        let link_path = entry
            .fields
            .get(2)
            .filter(|f| !f.is_empty())
            .map(|f| Spanned::new(f.text.clone(), f.span));
        let scale = |parts: &mut Parts<'_>, i: usize| {
            parts
                .int::<i64>(entry, i, "scaling", false)
                .map(|s| s.value)
        };
        let scaling = [
            scale(self, 12),
            scale(self, 13),
            scale(self, 14),
            scale(self, 15),
        ];
        CipParam {
            number,
            span: entry.span,
            link_path,
            descriptor: self.int(entry, 3, "descriptor", false),
            data_type: self.int(entry, 4, "data type", true),
            data_size: self.int(entry, 5, "data size", true),
            name: text(entry, 6),
            units: text(entry, 7),
            help: text(entry, 8),
            min: self.num(entry, 9, "minimum"),
            max: self.num(entry, 10, "maximum"),
            default: self.num(entry, 11, "default"),
            scaling,
            decimals: self
                .int::<u32>(entry, 20, "decimal places", false)
                .map(|d| d.value),
        }
    }

    fn enumeration(&mut self, number: u32, entry: &CipEntry) -> CipEnum {
        let mut values = Vec::new();
        let mut i = 0;
        while i < entry.fields.len() {
            if entry.fields[i].is_empty() && i + 1 == entry.fields.len() {
                break;
            }
            if let Some(v) = self.int::<i64>(entry, i, "enumerated value", true) {
                values.push((v.value, text(entry, i + 1)));
            }
            i += 2;
        }
        CipEnum {
            number,
            span: entry.span,
            values,
        }
    }

    pub fn assembly(&mut self, section: &CipSection) {
        for entry in &section.entries {
            let Some(n) = key_number(&entry.key, "Assem") else {
                if !known(&entry.key, CLASS_KEYS) {
                    self.unknown_key("Assembly", entry, CLASS_KEYS, &["Assem"]);
                }
                continue;
            };
            let path = entry
                .fields
                .get(1)
                .filter(|f| !f.text.trim().is_empty())
                .map(|f| Spanned::new(f.text.clone(), f.span));
            let mut members = Vec::new();
            let mut i = 6;
            while i < entry.fields.len() {
                let bits_field = &entry.fields[i];
                let member = entry.fields.get(i + 1).map_or(FieldRef::Empty, field_ref);
                if bits_field.is_empty() && member == FieldRef::Empty {
                    i += 2;
                    continue;
                }
                let bits = self.int::<u32>(entry, i, "member size in bits", false);
                members.push(AssemblyMember {
                    bits: bits.map(|b| b.value),
                    member,
                    span: field_span(entry, i),
                });
                i += 2;
            }
            let assembly = CipAssembly {
                number: n,
                span: entry.span,
                name: text(entry, 0),
                path,
                size: self.int(entry, 2, "size in bytes", false),
                descriptor: self.int(entry, 3, "descriptor", false),
                members,
            };
            self.cip.assemblies.insert(n, assembly);
        }
    }

    fn data(&mut self, entry: &CipEntry, first: usize, with_rpi: bool) -> ConnectionData {
        let at = |i: usize| {
            let f = entry.fields.get(i);
            Spanned::new(f.map_or(FieldRef::Empty, field_ref), field_span(entry, i))
        };
        if with_rpi {
            ConnectionData {
                rpi: at(first),
                size: at(first + 1),
                format: at(first + 2),
            }
        } else {
            ConnectionData {
                rpi: Spanned::new(FieldRef::Empty, entry.span),
                size: at(first),
                format: at(first + 1),
            }
        }
    }

    pub fn connections(&mut self, section: &CipSection) {
        for entry in &section.entries {
            let Some(n) = key_number(&entry.key, "Connection") else {
                // PITNS: production inhibit time network segment supported (Yes/No).
                if !known(&entry.key, CLASS_KEYS) && !entry.key.eq_ignore_ascii_case("PITNS") {
                    let keys = [CLASS_KEYS, &["PITNS"]].concat();
                    self.unknown_key("Connection Manager", entry, &keys, &["Connection"]);
                }
                continue;
            };
            if entry.fields.len() < 15 {
                self.diags.push(
                    Diagnostic::new(
                        &rules::CIP_BAD_FIELD,
                        Some(entry.span),
                        format!(
                            "`{}` has {} fields; a connection has 15 (trigger and transport, \
                             connection parameters, O->T RPI, size, format, T->O RPI, size, format, \
                             config #1 size, format, config #2 size, format, name, help, path)",
                            entry.key,
                            entry.fields.len()
                        ),
                    )
                    .with_label("too few fields"),
                );
            }
            let trigger_transport = self
                .int::<u32>(entry, 0, "trigger and transport", true)
                .map(|v| Spanned::new(TriggerTransport(v.value), v.span));
            let params = self
                .int::<u32>(entry, 1, "connection parameters", true)
                .map(|v| Spanned::new(ConnectionParams(v.value), v.span));
            let connection = CipConnection {
                number: n,
                span: entry.span,
                trigger_transport,
                params,
                o_t: self.data(entry, 2, true),
                t_o: self.data(entry, 5, true),
                config1: self.data(entry, 8, false),
                config2: self.data(entry, 10, false),
                name: text(entry, 12),
                help: text(entry, 13),
                path: entry
                    .fields
                    .get(14)
                    .filter(|f| !f.text.trim().is_empty())
                    .map(|f| Spanned::new(f.text.clone(), f.span)),
            };
            self.cip.connections.insert(n, connection);
        }
    }

    pub fn ports(&mut self, section: &CipSection) {
        for entry in &section.entries {
            let Some(n) = key_number(&entry.key, "Port") else {
                if !known(&entry.key, CLASS_KEYS) {
                    self.unknown_key("Port", entry, CLASS_KEYS, &["Port"]);
                }
                continue;
            };
            let port = CipPort {
                number: n,
                span: entry.span,
                port_type: text(entry, 0),
                name: text(entry, 1),
                path: text(entry, 2),
                port_number: self
                    .int::<u32>(entry, 3, "port number", false)
                    .map(|v| v.value),
            };
            self.cip.ports.insert(n, port);
        }
    }

    pub fn capacity(&mut self, section: &CipSection) {
        const KEYS: &[&str] = &[
            "MaxIOConnections",
            "MaxMsgConnections",
            "MaxCIPConnections",
            "MaxConsumersPerMcast",
            "MaxIOProduceConsume",
            "MaxIOMcastProducers",
            "MaxIOMcastConsumers",
            "ConnOverhead",
            "MaxIOProducers",
            "MaxIOConsumers",
        ];
        for entry in &section.entries {
            if !known(&entry.key, KEYS) && key_number(&entry.key, "TSpec").is_none() {
                self.unknown_key("Capacity", entry, KEYS, &["TSpec"]);
            }
            self.cip.capacity.push(entry.clone());
        }
    }
}
