//! The sections around the objects: `[FileInfo]`, `[DeviceInfo]`, `[DummyUsage]`, `[Comments]`,
//! the object lists and `[DeviceComissioning]`.

use super::keys::MAX_KNOWN_KEYS;
use super::sections::parse_hex_name;
use super::Reader;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::read::ini::{IniEntry, IniSection};
use crate::read::value::{octal_objection, parse_integer};
use crate::rules;

/// The help for a key python canopen looks up by its exact spelling (it raises without it).
const CASE_SENSITIVE_TOOLS: &str =
    "write it as CiA 306 does: python canopen looks it up case-sensitively and cannot import the file";

pub(super) const FILE_INFO_KEYS: &[&str] = &[
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

pub(super) const DEVICE_INFO_KEYS: &[&str] = &[
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

pub(super) const COMMISSIONING_KEYS: &[&str] = &[
    "NodeID",
    "NodeName",
    "Baudrate",
    "NetNumber",
    "NetworkName",
    "CANopenManager",
    "LSS_SerialNumber",
];

const _: () = assert!(
    FILE_INFO_KEYS.len() <= MAX_KNOWN_KEYS
        && DEVICE_INFO_KEYS.len() <= MAX_KNOWN_KEYS
        && COMMISSIONING_KEYS.len() <= MAX_KNOWN_KEYS
);
impl Reader {
    pub(super) fn read_file_info(&mut self, section: &IniSection) {
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

    pub(super) fn read_device_info(&mut self, section: &IniSection) {
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

    pub(super) fn read_dummy_usage(&mut self, section: &IniSection) {
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
    pub(super) fn numbered_key(&mut self, entry: &IniEntry, prefix: &str) -> Option<u32> {
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

    pub(super) fn read_comments(&mut self, section: &IniSection) {
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
    pub(super) fn index_entries(
        &mut self,
        section: &IniSection,
        count_key: &str,
    ) -> Vec<(u32, Spanned<u16>)> {
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
                None => {
                    let diag = match octal_objection(text) {
                        Some((why, help)) => Diagnostic::new(
                            &rules::BAD_NUMBER,
                            Some(span),
                            format!("entry {n} of [{}]: {why}", section.name),
                        )
                        .with_help(help),
                        None => Diagnostic::new(
                            &rules::BAD_NUMBER,
                            Some(span),
                            format!(
                                "entry {n} of [{}] is not an object index: `{text}`",
                                section.name
                            ),
                        ),
                    };
                    self.diags.push(diag);
                }
            }
        }
        out.sort_by_key(|(n, _)| *n);
        out
    }

    pub(super) fn read_object_list(&mut self, section: &IniSection, kind: ObjectListKind) {
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

    pub(super) fn read_commissioning(&mut self, section: &IniSection) {
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
}
