//! GSDML reader (PROFINET, `ISO15745Profile`): a GSDML file into the shared [`Device`] model.
//!
//! Identity goes to [`DeviceInfo`] (VendorID as the vendor number, DeviceID as the product
//! number) and to [`Profinet`]; the access points, modules, submodules with their typed IO data
//! and parameter records, value lists and channel diagnostics (with their extended channel
//! diagnostics) to [`Profinet`] (`items`). Texts
//! are resolved from the `ExternalTextList` (the primary language, else the first language);
//! a `TextId` without a text is kept in [`Profinet::missing_texts`] for the validator. XML is
//! handled as the ESI reader does it: ISO-8859-1 where declared, no DTD, bounded nesting.

use std::collections::HashMap;
use std::path::Path;

use roxmltree::Node;

use super::esi::values::parse_number;
use super::xml::{attribute, child, children, is_element, local, not_a_number, Spans};
use super::Read;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::rules;

mod items;
mod names;

/// Reads a GSDML file.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding, mut diagnostics) = super::esi::decode(bytes);
    let mut device = super::eds::empty_device(path, Format::Gsdml, encoding);
    if let Some(doc) = super::xml::parse(&text, &mut diagnostics) {
        let mut reader = GsdmlReader::new(&text, &mut diagnostics);
        let profinet = reader.read_root(doc.root_element(), &mut device);
        names::check(doc.root_element(), &reader.spans, reader.diags);
        device.bus = Bus::Profinet(profinet);
    }
    Read {
        device,
        diagnostics,
        text,
    }
}

/// Whether the bytes look like a GSDML file: root `ISO15745Profile` with a
/// `ProfileBody/DeviceIdentity` (checked on the text, without parsing the whole file).
pub fn looks_like_gsdml(root: &str, bytes: &[u8]) -> bool {
    root == "ISO15745Profile"
        && bytes
            .windows("DeviceIdentity".len())
            .any(|w| w == b"DeviceIdentity")
}

/// A slot or subslot list (`0..4`, `1 2 3`, `1..4 7`); `None` when a part is no number.
pub(crate) fn parse_ranges(text: &str) -> Option<Vec<(i128, i128)>> {
    let mut out = Vec::new();
    for part in text.split_whitespace() {
        match part.split_once("..") {
            Some((lo, hi)) => {
                let (lo, hi) = (parse_number(lo)?, parse_number(hi)?);
                out.push((lo.min(hi), lo.max(hi)));
            }
            None => {
                let v = parse_number(part)?;
                out.push((v, v));
            }
        }
    }
    Some(out)
}

/// The reader's state: spans, diagnostics, the resolved texts by `TextId`.
struct GsdmlReader<'a, 'input> {
    spans: Spans<'input>,
    diags: &'a mut Vec<Diagnostic>,
    texts: HashMap<String, String>,
    missing_texts: Vec<Spanned<String>>,
}

impl<'a, 'input> GsdmlReader<'a, 'input> {
    fn new(text: &'input str, diags: &'a mut Vec<Diagnostic>) -> Self {
        GsdmlReader {
            spans: Spans::new(text),
            diags,
            texts: HashMap::new(),
            missing_texts: Vec::new(),
        }
    }

    fn push(&mut self, diag: Diagnostic) {
        self.diags.push(diag);
    }

    fn read_root(&mut self, root: Node, device: &mut Device) -> Profinet {
        let root_span = self.spans.element(root);
        let mut pn = Profinet {
            span: root_span,
            ..Profinet::default()
        };
        if local(root) != "ISO15745Profile" {
            self.push(
                Diagnostic::new(
                    &rules::PN_IDENTITY,
                    Some(root_span),
                    format!(
                        "the root element is `{}`, not `ISO15745Profile`",
                        local(root)
                    ),
                )
                .with_severity(Severity::Warning),
            );
        }
        let Some(body) = child(root, "ProfileBody") else {
            self.push(Diagnostic::new(
                &rules::PN_IDENTITY,
                Some(root_span),
                "the file has no `ProfileBody`: nothing is read",
            ));
            return pn;
        };
        let process = child(body, "ApplicationProcess");
        if let Some(list) = process.and_then(|p| child(p, "ExternalTextList")) {
            self.read_texts(list);
        }
        self.read_identity(body, device, &mut pn);
        if let Some(family) = child(body, "DeviceFunction").and_then(|f| child(f, "Family")) {
            let get = |name| attribute(family, name).map_or(String::new(), |a| a.value().into());
            pn.family = Some((get("MainFamily"), get("ProductFamily")));
        }
        if let Some(process) = process {
            self.read_process(process, &mut pn);
        }
        if let Some(dap) = pn.access_points.first() {
            device.device_info.product_name = dap.name.clone();
            device.device_info.order_code = None;
        }
        pn.missing_texts = std::mem::take(&mut self.missing_texts);
        pn
    }

    /// `ExternalTextList`: the `PrimaryLanguage` texts, and those of other languages (English
    /// first) for ids the primary language lacks.
    fn read_texts(&mut self, list: Node) {
        let mut languages: Vec<Node> = children(list, "Language").collect();
        languages.sort_by_key(|l| {
            attribute(*l, "lang").map_or(1, |a| if a.value().starts_with("en") { 0 } else { 1 })
        });
        for lang in child(list, "PrimaryLanguage").into_iter().chain(languages) {
            for text in children(lang, "Text") {
                let (Some(id), Some(value)) = (attribute(text, "TextId"), attribute(text, "Value"))
                else {
                    continue;
                };
                self.texts
                    .entry(id.value().to_owned())
                    .or_insert_with(|| value.value().to_owned());
            }
        }
    }

    /// The text an element's `TextId` names; a missing one is remembered with its span.
    fn text_of(&mut self, node: Node) -> Option<String> {
        let id = attribute(node, "TextId")?;
        match self.texts.get(id.value()) {
            Some(text) => Some(text.clone()),
            None => {
                let span = self.spans.attribute(&id);
                self.missing_texts
                    .push(Spanned::new(id.value().to_owned(), span));
                None
            }
        }
    }

    /// The text of a child element (`Name`, `InfoText`) by its `TextId`.
    fn child_text(&mut self, node: Node, name: &str) -> Option<String> {
        let item = child(node, name)?;
        self.text_of(item)
    }

    fn read_identity(&mut self, body: Node, device: &mut Device, pn: &mut Profinet) {
        let Some(identity) = child(body, "DeviceIdentity") else {
            let span = self.spans.element(body);
            self.push(Diagnostic::new(
                &rules::PN_IDENTITY,
                Some(span),
                "`ProfileBody` has no `DeviceIdentity`: the device has no VendorID or DeviceID",
            ));
            return;
        };
        pn.span = self.spans.element(identity);
        pn.vendor_id = self.identity_number(identity, "VendorID");
        pn.device_id = self.identity_number(identity, "DeviceID");
        pn.vendor_name = child(identity, "VendorName")
            .and_then(|v| attribute(v, "Value"))
            .map(|a| a.value().to_owned());
        pn.info_text = self.child_text(identity, "InfoText");
        let info = &mut device.device_info;
        info.vendor_name = pn.vendor_name.clone();
        info.vendor_number = pn
            .vendor_id
            .as_ref()
            .map(|v| Spanned::new(u32::from(v.value), v.span));
        info.product_number = pn
            .device_id
            .as_ref()
            .map(|v| Spanned::new(u32::from(v.value), v.span));
        info.span = Some(pn.span);
    }

    /// `VendorID` or `DeviceID`: a 16-bit number, else a `PN001` error.
    fn identity_number(&mut self, identity: Node, name: &str) -> Option<Spanned<u16>> {
        let Some(attr) = attribute(identity, name) else {
            let span = self.spans.element(identity);
            self.push(Diagnostic::new(
                &rules::PN_IDENTITY,
                Some(span),
                format!("`DeviceIdentity` has no `{name}`"),
            ));
            return None;
        };
        let span = self.spans.attribute(&attr);
        match parse_number(attr.value()).and_then(|n| u16::try_from(n).ok()) {
            Some(v) => Some(Spanned::new(v, span)),
            None => {
                self.push(Diagnostic::new(
                    &rules::PN_IDENTITY,
                    Some(span),
                    format!("`{name}` is `{}`, not a 16-bit number", attr.value()),
                ));
                None
            }
        }
    }

    /// An attribute as a number, with an `EDS604` error when it is not one.
    fn attr_number(&mut self, node: Node, name: &str) -> Option<Spanned<i128>> {
        let attr = attribute(node, name)?;
        let span = self.spans.attribute(&attr);
        match parse_number(attr.value()) {
            Some(n) => Some(Spanned::new(n, span)),
            None => {
                self.push(not_a_number(name, attr.value(), span));
                None
            }
        }
    }

    /// An attribute as an unsigned number of type `T`, with an `EDS604` error when it is not one.
    fn attr_unsigned<T: TryFrom<i128>>(&mut self, node: Node, name: &str) -> Option<Spanned<T>> {
        let n = self.attr_number(node, name)?;
        match T::try_from(n.value) {
            Ok(v) => Some(Spanned::new(v, n.span)),
            Err(_) => {
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(n.span),
                    format!("`{name}` is {}, outside its range", n.value),
                ));
                None
            }
        }
    }

    /// A slot list attribute as slot numbers; an `EDS604` error when unreadable or absurdly long.
    fn attr_slots(&mut self, node: Node, name: &str) -> Vec<u16> {
        let Some(attr) = attribute(node, name) else {
            return Vec::new();
        };
        let span = self.spans.attribute(&attr);
        let ranges = parse_ranges(attr.value()).filter(|r| {
            r.iter()
                .all(|(lo, hi)| *lo >= 0 && *hi <= i128::from(u16::MAX))
        });
        let Some(ranges) = ranges else {
            self.push(
                Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "`{name}` is `{}`, not a list of slot numbers (`1..4 7`)",
                        attr.value()
                    ),
                )
                .with_severity(Severity::Error),
            );
            return Vec::new();
        };
        let mut slots: Vec<u16> = ranges
            .iter()
            .flat_map(|(lo, hi)| (*lo as u16)..=(*hi as u16))
            .collect();
        slots.sort_unstable();
        slots.dedup();
        slots
    }

    /// A required attribute's text; an `EDS603` error at the element when it is missing.
    fn required(&mut self, node: Node, name: &str) -> Option<Spanned<String>> {
        match attribute(node, name) {
            Some(a) => Some(Spanned::new(a.value().to_owned(), self.spans.attribute(&a))),
            None => {
                let span = self.spans.element(node);
                self.push(Diagnostic::new(
                    &rules::XML_MISSING_ATTRIBUTE,
                    Some(span),
                    format!("`{}` without `{name}`", local(node)),
                ));
                None
            }
        }
    }

    fn read_process(&mut self, process: Node, pn: &mut Profinet) {
        if let Some(list) = child(process, "ValueList") {
            for item in children(list, "ValueItem") {
                let value_list = self.read_value_item(item);
                pn.value_lists.push(value_list);
            }
        }
        if let Some(list) = child(process, "DeviceAccessPointList") {
            for dap in children(list, "DeviceAccessPointItem") {
                let dap = self.read_access_point(dap);
                pn.access_points.push(dap);
            }
        }
        if let Some(list) = child(process, "ModuleList") {
            for module in children(list, "ModuleItem") {
                let module = self.read_module(module);
                pn.modules.push(module);
            }
        }
        for (list, item, number) in [
            ("ChannelDiagList", "ChannelDiagItem", "ErrorType"),
            (
                "UnitDiagTypeList",
                "UnitDiagTypeItem",
                "UserStructureIdentifier",
            ),
        ] {
            for diag in child(process, list)
                .into_iter()
                .flat_map(|l| l.children().filter(move |c| is_element(*c, item)))
            {
                let span = self.spans.element(diag);
                let error_type = self.attr_unsigned::<u32>(diag, number);
                let name = self.child_text(diag, "Name");
                let help = self.child_text(diag, "Help");
                let ext = child(diag, "ExtChannelDiagList")
                    .into_iter()
                    .flat_map(|l| children(l, "ExtChannelDiagItem"))
                    .filter_map(|item| self.read_ext_channel_diag(item))
                    .collect();
                pn.channel_diagnostics.push(ChannelDiag {
                    error_type: error_type.as_ref().map_or(0, |n| n.value),
                    name,
                    help,
                    ext,
                    error_type_span: error_type.map_or(span, |n| n.span),
                    span,
                });
            }
        }
    }

    /// One `ExtChannelDiagItem`; `None` (with the attribute's error) without a 16-bit
    /// `ErrorType`.
    fn read_ext_channel_diag(&mut self, item: Node) -> Option<ExtChannelDiag> {
        if attribute(item, "ErrorType").is_none() {
            self.required(item, "ErrorType");
        }
        let error_type = self.attr_unsigned::<u16>(item, "ErrorType")?;
        let name = self.child_text(item, "Name");
        let help = self.child_text(item, "Help");
        let mut add_values = Vec::new();
        for data in child(item, "ExtChannelAddValue")
            .into_iter()
            .flat_map(|v| children(v, "DataItem"))
        {
            let Some(data_type) = self.required(data, "DataType") else {
                continue;
            };
            add_values.push(ExtAddValue {
                kind: PnDataType::from_name(&data_type.value),
                data_type,
                id: self.attr_unsigned::<u32>(data, "Id").map(|n| n.value),
                length: self.attr_unsigned::<u32>(data, "Length").map(|n| n.value),
                span: self.spans.element(data),
            });
        }
        Some(ExtChannelDiag {
            error_type,
            name,
            help,
            add_values,
            span: self.spans.element(item),
        })
    }

    fn read_value_item(&mut self, item: Node) -> ValueList {
        let id = attribute(item, "ID").map_or(String::new(), |a| a.value().to_owned());
        let mut assignments = Vec::new();
        for assign in child(item, "Assignments")
            .into_iter()
            .flat_map(|a| children(a, "Assign"))
        {
            if let Some(content) = self.attr_number(assign, "Content") {
                let text = self.text_of(assign);
                assignments.push((content.value, text));
            }
        }
        ValueList {
            id,
            assignments,
            span: self.spans.element(item),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slot_lists_are_ranges_and_numbers() {
        assert_eq!(parse_ranges("0..4"), Some(vec![(0, 4)]));
        assert_eq!(
            parse_ranges("1 2  7..9"),
            Some(vec![(1, 1), (2, 2), (7, 9)])
        );
        assert_eq!(parse_ranges("-3..3 0x10"), Some(vec![(-3, 3), (16, 16)]));
        assert_eq!(parse_ranges("1..x"), None);
        assert_eq!(parse_ranges(""), Some(vec![]));
    }
}
