//! XDD and XDC reader (CiA 311): an `ISO15745ProfileContainer` into the shared [`Device`] model.
//!
//! Elements are matched by local name, so the 1.0 and 1.1 namespaces, prefixed elements and files
//! without any namespace read alike. Each `CANopenObject`/`CANopenSubObject` is resolved against the
//! `ApplicationProcess/parameterList/parameter` its `uniqueIDRef` names: the parameter's access,
//! values, data type, limits and denotation override the object's own attributes (as CANopenEditor
//! does), and `rw` with PDOmapping TPDO/RPDO becomes `rwr`/`rww`. Every object, sub-object and value
//! keeps the line and column of its element or attribute.

use std::collections::HashMap;
use std::path::Path;

use roxmltree::{Document, Node};

use super::value::parse_integer;
use super::xml::{
    attribute, decoded_as_windows1252, is_element, local, not_a_number, parse, parse_xml_bool,
    Spans,
};
use super::Read;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::rules;

mod device;
mod objects;
mod parameters;

/// Reads an XDD or XDC file. Malformed XML gives an empty device and one `EDS601` error.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = super::text::decode(bytes);
    let format = match super::detect_format(path, bytes) {
        Format::Xdc => Format::Xdc,
        _ => Format::Xdd,
    };
    let mut device = super::eds::empty_device(path, format, encoding);
    let mut diagnostics = Vec::new();
    if encoding == TextEncoding::Windows1252 {
        diagnostics.push(decoded_as_windows1252(
            "save the file as UTF-8, as its XML declaration most likely says",
        ));
    }
    if let Some(doc) = parse(&text, &mut diagnostics) {
        let mut reader = XmlReader::new(&doc, &text, &mut diagnostics);
        reader.read_device(&mut device);
    }
    Read {
        device,
        diagnostics,
        text,
    }
}

/// The reader's state: the document, its text and line index for spans, the diagnostics, and
/// every `parameter` and `dataTypeList` entry by `uniqueID`.
struct XmlReader<'a, 'input> {
    doc: &'a Document<'input>,
    spans: Spans<'input>,
    diags: &'a mut Vec<Diagnostic>,
    parameters: HashMap<&'a str, Node<'a, 'input>>,
    data_types: HashMap<&'a str, Node<'a, 'input>>,
}

/// A hexBinary attribute (`"1018"`, `"0A"`), tolerating a `0x` prefix.
fn parse_hex_binary(text: &str) -> Option<u32> {
    let t = text.trim();
    let t = t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .unwrap_or(t);
    if t.is_empty() {
        return None;
    }
    u32::from_str_radix(t, 16).ok()
}

impl<'a, 'input> XmlReader<'a, 'input> {
    fn new(doc: &'a Document<'input>, text: &'input str, diags: &'a mut Vec<Diagnostic>) -> Self {
        XmlReader {
            doc,
            spans: Spans::new(text),
            diags,
            parameters: HashMap::new(),
            data_types: HashMap::new(),
        }
    }

    fn push(&mut self, diag: Diagnostic) {
        self.diags.push(diag);
    }

    fn read_device(&mut self, device: &mut Device) {
        let doc = self.doc;
        let root = doc.root_element();
        if local(root) != "ISO15745ProfileContainer" {
            // Lenient: read whatever CANopen elements are present, but say the root is unusual.
            let span = self.spans.element(root);
            self.push(
                Diagnostic::new(
                    &rules::XML_NO_OBJECT_LIST,
                    Some(span),
                    format!(
                        "the root element is `{}`, not `ISO15745ProfileContainer`",
                        local(root)
                    ),
                )
                .with_severity(Severity::Warning),
            );
        }
        self.index_ids(root);

        for body in root.descendants().filter(|n| is_element(*n, "ProfileBody")) {
            self.read_file_info(body, &mut device.file_info);
        }
        for identity in root
            .descendants()
            .filter(|n| is_element(*n, "DeviceIdentity"))
        {
            self.read_identity(identity, device);
        }
        let mut found_list = false;
        for list in root
            .descendants()
            .filter(|n| is_element(*n, "CANopenObjectList"))
        {
            found_list = true;
            self.read_object_list(list, device);
        }
        if !found_list {
            let span = self.spans.element(root);
            self.push(Diagnostic::new(
                &rules::XML_NO_OBJECT_LIST,
                Some(span),
                "no `CANopenObjectList` element: the description has no objects",
            ));
        }
        for node in root.descendants().filter(|n| n.is_element()) {
            match local(node) {
                "dummyUsage" => self.read_dummy_usage(node, device),
                "baudRate" => self.read_baud_rates(node, device),
                "CANopenGeneralFeatures" => self.read_general_features(node, device),
                "CANopenMasterFeatures" => self.read_master_features(node, device),
                "deviceCommissioning" => self.read_commissioning(node, device),
                "dynamicChannels" => self.read_dynamic_channels(node, device),
                _ => {}
            }
        }
    }

    /// Collects every `parameter` and `dataTypeList` entry by its `uniqueID`.
    fn index_ids(&mut self, root: Node<'a, 'input>) {
        for node in root.descendants().filter(|n| n.is_element()) {
            let parent_name = node.parent_element().map(local);
            let map_is_parameters = match (local(node), parent_name) {
                ("parameter", Some("parameterList")) => true,
                (_, Some("dataTypeList")) => false,
                _ => continue,
            };
            let Some(id) = attribute(node, "uniqueID") else {
                continue;
            };
            let span = self.spans.attribute(&id);
            let id = id.value();
            let map = if map_is_parameters {
                &mut self.parameters
            } else {
                &mut self.data_types
            };
            if map.insert(id, node).is_some() {
                self.diags.push(Diagnostic::new(
                    &rules::XML_DUPLICATE,
                    Some(span),
                    format!("uniqueID `{id}` is defined twice; the last definition is used"),
                ));
            }
        }
    }

    fn optional_number(&mut self, node: Node, name: &str) -> Option<Spanned<u32>> {
        let attr = attribute(node, name)?;
        let span = self.spans.attribute(&attr);
        match parse_integer(attr.value()).and_then(|n| u32::try_from(n).ok()) {
            Some(n) => Some(Spanned::new(n, span)),
            None => {
                self.push(not_a_number(name, attr.value(), span));
                None
            }
        }
    }

    fn optional_bool(&mut self, node: Node, name: &str) -> Option<bool> {
        let attr = attribute(node, name)?;
        match parse_xml_bool(attr.value()) {
            Some(b) => Some(b),
            None => {
                let span = self.spans.attribute(&attr);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`{name}` is `{}`, not `true` or `false`", attr.value()),
                ));
                None
            }
        }
    }
}
