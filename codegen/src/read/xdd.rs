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

use roxmltree::{Attribute, Document, Node};

use super::text::LineIndex;
use super::value::{parse_integer, parse_value};
use super::Read;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::rules;

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
        diagnostics.push(
            Diagnostic::new(
                &rules::NON_ASCII,
                None,
                "the XML file is not valid UTF-8; it was decoded as Windows-1252",
            )
            .with_help("save the file as UTF-8, as its XML declaration most likely says"),
        );
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

/// Parses XML text, refusing a file nested deeper than [`MAX_DEPTH`] and DTDs; a file that cannot
/// be parsed gives one `EDS601` error and `None`. Shared by the XDD/XDC and ESI readers.
pub(super) fn parse<'input>(
    text: &'input str,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<Document<'input>> {
    // The XML parser recurses per element: a file nested thousands deep would overflow the stack.
    // Device descriptions nest about ten deep; refuse anything past MAX_DEPTH before parsing.
    if let Some(at) = nesting_beyond(text, MAX_DEPTH) {
        let span = LineIndex::new(text).span(text, at..at + 1);
        diagnostics.push(
            Diagnostic::new(
                &rules::XML_MALFORMED,
                Some(span),
                format!("the XML nests elements more than {MAX_DEPTH} deep; it was not parsed"),
            )
            .with_label(format!("element {} levels deep", MAX_DEPTH + 1))
            .with_help("a device description nests about ten levels deep; is this the right file?"),
        );
        return None;
    }
    // DTDs stay refused (roxmltree's default): no device description has one, and entity
    // expansion is a way to make a small file huge.
    match Document::parse(text) {
        Ok(doc) => Some(doc),
        Err(roxmltree::Error::DtdDetected) => {
            // roxmltree reports no useful position for this one: point at the declaration.
            let at = text.find("<!DOCTYPE").unwrap_or(0);
            let span = LineIndex::new(text).span(text, at..at + "<!DOCTYPE".len());
            diagnostics.push(
                Diagnostic::new(
                    &rules::XML_MALFORMED,
                    Some(span),
                    "the file has a DTD (`<!DOCTYPE`), which a device description never needs",
                )
                .with_help("remove the DOCTYPE declaration"),
            );
            None
        }
        Err(err) => {
            let pos = err.pos();
            diagnostics.push(
                Diagnostic::new(
                    &rules::XML_MALFORMED,
                    Some(Span::new(pos.row, pos.col, 0)),
                    format!("the file is not well-formed XML: {err}"),
                )
                .with_label("the XML parser stopped here"),
            );
            None
        }
    }
}

/// How deep elements may nest before the file is refused unparsed.
const MAX_DEPTH: usize = 256;

/// The byte offset of the first start tag deeper than `max`, by a scan that knows just enough
/// XML for it: start, end and empty-element tags, quoted attribute values, comments, CDATA,
/// processing instructions and declarations. Not a validator: malformed files go on to the parser.
fn nesting_beyond(text: &str, max: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let skip_past = |from: usize, end: &str| {
        text.get(from..)
            .and_then(|rest| rest.find(end))
            .map_or(bytes.len(), |i| from + i + end.len())
    };
    let mut depth = 0usize;
    let mut i = 0;
    while let Some(offset) = bytes
        .get(i..)
        .and_then(|b| b.iter().position(|&c| c == b'<'))
    {
        let at = i + offset;
        let rest = &text[at..];
        if rest.starts_with("<!--") {
            i = skip_past(at, "-->");
        } else if rest.starts_with("<![CDATA[") {
            i = skip_past(at, "]]>");
        } else if rest.starts_with("<?") {
            i = skip_past(at, "?>");
        } else if rest.starts_with("</") {
            depth = depth.saturating_sub(1);
            i = skip_past(at, ">");
        } else if rest.starts_with("<!") {
            i = skip_past(at, ">");
        } else {
            // A start tag: find its end outside quoted attribute values.
            let mut quote = None;
            let mut end = at + 1;
            while end < bytes.len() {
                match (quote, bytes[end]) {
                    (None, b'"' | b'\'') => quote = Some(bytes[end]),
                    (Some(q), c) if c == q => quote = None,
                    (None, b'>') => break,
                    _ => {}
                }
                end += 1;
            }
            if bytes.get(end.wrapping_sub(1)) != Some(&b'/') {
                depth += 1;
                if depth > max {
                    return Some(at);
                }
            }
            i = end + 1;
        }
    }
    None
}

/// The IEC 61131 elementary type names CiA 311 uses, and the CANopen basic type of each.
/// `BITSTRING` is absent: it stands for OCTET_STRING or DOMAIN and is resolved separately.
pub(super) const IEC_TYPES: &[(&str, BasicType)] = &[
    ("BOOL", BasicType::Boolean),
    ("BYTE", BasicType::Unsigned8),
    ("CHAR", BasicType::Unsigned8),
    ("WORD", BasicType::Unsigned16),
    ("DWORD", BasicType::Unsigned32),
    ("LWORD", BasicType::Unsigned64),
    ("SINT", BasicType::Integer8),
    ("INT", BasicType::Integer16),
    ("DINT", BasicType::Integer32),
    ("LINT", BasicType::Integer64),
    ("USINT", BasicType::Unsigned8),
    ("UINT", BasicType::Unsigned16),
    ("UDINT", BasicType::Unsigned32),
    ("ULINT", BasicType::Unsigned64),
    ("REAL", BasicType::Real32),
    ("LREAL", BasicType::Real64),
    ("STRING", BasicType::VisibleString),
    ("WSTRING", BasicType::UnicodeString),
];

/// The attributes CiA 311 gives both `CANopenObject` and `CANopenSubObject`, as written.
#[derive(Default)]
struct EntryAttributes<'a, 'input> {
    data_type: Option<Attribute<'a, 'input>>,
    low_limit: Option<Attribute<'a, 'input>>,
    high_limit: Option<Attribute<'a, 'input>>,
    access_type: Option<Attribute<'a, 'input>>,
    default_value: Option<Attribute<'a, 'input>>,
    actual_value: Option<Attribute<'a, 'input>>,
    denotation: Option<Attribute<'a, 'input>>,
    pdo_mapping: Option<Attribute<'a, 'input>>,
    obj_flags: Option<Attribute<'a, 'input>>,
}

/// A value text and where it is: an attribute's value.
struct RawValue {
    text: String,
    span: Span,
}

/// What a `parameter` says about an entry.
#[derive(Default)]
struct ParameterFacts {
    /// Whether a parameter was found at all.
    resolved: bool,
    /// The parameter's `access`, if written.
    access: Option<AccessType>,
    /// Where the `access` value is written.
    access_span: Option<Span>,
    /// The data type from an IEC element, `derived`/`enum` base type, or `None`.
    data_type: Option<u16>,
    /// Where the type element (or `dataTypeIDRef`) is.
    data_type_span: Option<Span>,
    /// The parameter names `BITSTRING`: OCTET_STRING or DOMAIN, decided with the default value.
    bitstring: bool,
    default: Option<RawValue>,
    actual: Option<RawValue>,
    low: Option<RawValue>,
    high: Option<RawValue>,
    denotation: Option<String>,
    label: Option<String>,
    custom: Vec<(String, String)>,
}

struct XmlReader<'a, 'input> {
    doc: &'a Document<'input>,
    text: &'input str,
    lines: LineIndex,
    diags: &'a mut Vec<Diagnostic>,
    parameters: HashMap<&'a str, Node<'a, 'input>>,
    data_types: HashMap<&'a str, Node<'a, 'input>>,
}

/// The span of an element's start tag name (`<CANopenObject`).
pub(super) fn element_span(text: &str, lines: &LineIndex, node: Node) -> Span {
    let start = node.range().start;
    let tag_len = text.get(start..).map_or(0, |rest| {
        rest.find(|c: char| c.is_whitespace() || c == '>' || c == '/')
            .unwrap_or(rest.len())
    });
    lines.span(text, start..start + tag_len)
}

/// The local name of an element (namespace and prefix dropped).
pub(super) fn local<'a>(node: Node<'a, '_>) -> &'a str {
    node.tag_name().name()
}

pub(super) fn is_element(node: Node, name: &str) -> bool {
    node.is_element() && local(node) == name
}

pub(super) fn child<'a, 'input>(node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
    node.children().find(|c| is_element(*c, name))
}

pub(super) fn children<'a, 'input: 'a>(
    node: Node<'a, 'input>,
    name: &'a str,
) -> impl Iterator<Item = Node<'a, 'input>> + 'a {
    node.children().filter(move |c| is_element(*c, name))
}

pub(super) fn attribute<'a, 'input>(
    node: Node<'a, 'input>,
    name: &str,
) -> Option<Attribute<'a, 'input>> {
    node.attributes().find(|a| a.name() == name)
}

/// The text of an element, trimmed; `None` when empty.
pub(super) fn element_text(node: Node) -> Option<String> {
    let text: String = node
        .descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect();
    let text = text.trim();
    (!text.is_empty()).then(|| text.to_owned())
}

/// The text of a multi-language element group (`label`, `description`): English first, else the
/// first one.
fn language_text(node: Node, name: &str) -> Option<String> {
    let mut first = None;
    for item in children(node, name) {
        let text = element_text(item);
        let lang = item
            .attributes()
            .find(|a| a.name() == "lang")
            .map(|a| a.value());
        if lang.is_some_and(|l| l.eq_ignore_ascii_case("en")) && text.is_some() {
            return text;
        }
        if first.is_none() {
            first = text;
        }
    }
    first
}

pub(super) fn parse_xml_bool(text: &str) -> Option<bool> {
    match text.trim() {
        "true" | "1" => Some(true),
        "false" | "0" => Some(false),
        _ => None,
    }
}

/// `"250 Kbps"` (any case, with or without the space) as kbit/s; also accepts `"1 Mbps"`.
fn parse_baud_rate(text: &str) -> Option<u32> {
    let lower = text.trim().to_ascii_lowercase();
    if let Some(number) = lower.strip_suffix("kbps") {
        return number.trim().parse().ok();
    }
    if let Some(number) = lower.strip_suffix("mbps") {
        return number.trim().parse::<u32>().ok()?.checked_mul(1000);
    }
    None
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

fn parse_parameter_access(text: &str) -> Option<AccessType> {
    Some(match text.trim() {
        "const" => AccessType::Const,
        "read" => AccessType::Ro,
        "write" => AccessType::Wo,
        "readWrite" => AccessType::Rw,
        // Directions are the device application's: an input is written by the network (an
        // RPDO, `rww`), an output is read by it (a TPDO, `rwr`). Faulhaber's tooling writes
        // readWriteInput on every RPDO-mapped parameter.
        "readWriteInput" => AccessType::Rww,
        "readWriteOutput" => AccessType::Rwr,
        _ => return None,
    })
}

impl<'a, 'input> XmlReader<'a, 'input> {
    fn new(doc: &'a Document<'input>, text: &'input str, diags: &'a mut Vec<Diagnostic>) -> Self {
        XmlReader {
            doc,
            text,
            lines: LineIndex::new(text),
            diags,
            parameters: HashMap::new(),
            data_types: HashMap::new(),
        }
    }

    /// The span of an element's start tag name (`<CANopenObject`).
    fn element_span(&self, node: Node) -> Span {
        element_span(self.text, &self.lines, node)
    }

    /// The span of an attribute's value (inside the quotes).
    fn attribute_span(&self, attr: &Attribute) -> Span {
        self.lines.span(self.text, attr.range_value())
    }

    fn push(&mut self, diag: Diagnostic) {
        self.diags.push(diag);
    }

    fn read_device(&mut self, device: &mut Device) {
        let doc = self.doc;
        let root = doc.root_element();
        if local(root) != "ISO15745ProfileContainer" {
            // Lenient: read whatever CANopen elements are present, but say the root is unusual.
            let span = self.element_span(root);
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
            let span = self.element_span(root);
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
            let span = self.attribute_span(&id);
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

    fn read_file_info(&mut self, body: Node, info: &mut FileInfo) {
        let get = |name: &str| {
            attribute(body, name)
                .map(|a| a.value().trim().to_owned())
                .filter(|v| !v.is_empty())
        };
        // Both profile bodies usually repeat the same attributes; the first one written wins.
        let fill = |slot: &mut Option<String>, value: Option<String>| {
            if slot.is_none() {
                *slot = value;
            }
        };
        fill(&mut info.file_name, get("fileName"));
        fill(&mut info.file_version, get("fileVersion"));
        fill(&mut info.created_by, get("fileCreator"));
        fill(&mut info.creation_date, get("fileCreationDate"));
        fill(&mut info.creation_time, get("fileCreationTime"));
        fill(&mut info.modified_by, get("fileModifiedBy"));
        fill(&mut info.modification_date, get("fileModificationDate"));
        fill(&mut info.modification_time, get("fileModificationTime"));
        if info.span.is_none() {
            info.span = Some(self.element_span(body));
        }
    }

    fn read_identity(&mut self, identity: Node, device: &mut Device) {
        let span = self.element_span(identity);
        device.device_info.span.get_or_insert(span);
        let mut extra = Vec::new();
        for item in identity.children().filter(|n| n.is_element()) {
            let item_span = self.element_span(item);
            let text = element_text(item);
            match local(item) {
                "vendorName" => device.device_info.vendor_name = text,
                "productName" => device.device_info.product_name = text,
                "orderNumber" => device.device_info.order_code = text,
                "vendorID" | "productID" => {
                    let Some(text) = text else { continue };
                    let number = parse_integer(&text).and_then(|n| u32::try_from(n).ok());
                    let Some(number) = number else {
                        self.push(Diagnostic::new(
                            &rules::XML_BAD_ATTRIBUTE,
                            Some(item_span),
                            format!("`{}` is `{text}`, not a 32-bit number", local(item)),
                        ));
                        continue;
                    };
                    let slot = if local(item) == "vendorID" {
                        &mut device.device_info.vendor_number
                    } else {
                        &mut device.device_info.product_number
                    };
                    *slot = Some(Spanned::new(number, item_span));
                }
                other => {
                    let key = match attribute(item, "versionType") {
                        Some(kind) => format!("{other}@{}", kind.value()),
                        None => other.to_owned(),
                    };
                    if let Some(value) = text {
                        extra.push(RawEntry {
                            key,
                            value,
                            span: item_span,
                        });
                    }
                }
            }
        }
        if !extra.is_empty() {
            device.other_sections.push(RawSection {
                name: "DeviceIdentity".to_owned(),
                entries: extra,
                span,
            });
        }
    }

    fn read_object_list(&mut self, list: Node<'a, 'input>, device: &mut Device) {
        for node in children(list, "CANopenObject") {
            let Some(object) = self.read_object(node) else {
                continue;
            };
            let index = object.index;
            let span = object.span;
            if device.objects.insert(index, object).is_some() {
                self.push(Diagnostic::new(
                    &rules::XML_DUPLICATE,
                    Some(span),
                    format!("object {index:04X}h is described twice; the last description is used"),
                ));
            }
        }
        // Anything else directly in the list would be silently lost: say so.
        for node in list.children().filter(|n| n.is_element()) {
            if local(node) != "CANopenObject" {
                let span = self.element_span(node);
                self.push(
                    Diagnostic::new(
                        &rules::XML_BAD_ATTRIBUTE,
                        Some(span),
                        format!(
                            "unexpected `{}` in CANopenObjectList (ignored)",
                            local(node)
                        ),
                    )
                    .with_severity(Severity::Warning),
                );
            }
        }
    }

    /// A required hexBinary attribute, with diagnostics when missing or unreadable.
    fn required_hex(&mut self, node: Node, name: &str, max: u32) -> Option<u32> {
        let span = self.element_span(node);
        let Some(attr) = attribute(node, name) else {
            self.push(Diagnostic::new(
                &rules::XML_MISSING_ATTRIBUTE,
                Some(span),
                format!("`{}` without `{name}`: it is skipped", local(node)),
            ));
            return None;
        };
        let value_span = self.attribute_span(&attr);
        match parse_hex_binary(attr.value()).filter(|v| *v <= max) {
            Some(v) => Some(v),
            None => {
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(value_span),
                    format!(
                        "`{name}` is `{}`, not a hexBinary number up to {max:X}: the element is skipped",
                        attr.value()
                    ),
                ));
                None
            }
        }
    }

    fn entry_attributes(node: Node<'a, 'input>) -> EntryAttributes<'a, 'input> {
        EntryAttributes {
            data_type: attribute(node, "dataType"),
            low_limit: attribute(node, "lowLimit"),
            high_limit: attribute(node, "highLimit"),
            access_type: attribute(node, "accessType"),
            default_value: attribute(node, "defaultValue"),
            actual_value: attribute(node, "actualValue"),
            denotation: attribute(node, "denotation"),
            pdo_mapping: attribute(node, "PDOmapping"),
            obj_flags: attribute(node, "objFlags"),
        }
    }

    fn name_of(&mut self, node: Node, parameter: &ParameterFacts) -> String {
        if let Some(name) = attribute(node, "name") {
            return name.value().to_owned();
        }
        let span = self.element_span(node);
        let fallback = parameter.label.clone();
        self.push(Diagnostic::new(
            &rules::XML_MISSING_ATTRIBUTE,
            Some(span),
            match &fallback {
                Some(label) => format!(
                    "`{}` without `name`; the parameter label `{label}` is used",
                    local(node)
                ),
                None => format!("`{}` without `name`", local(node)),
            },
        ));
        fallback.unwrap_or_default()
    }

    fn read_object(&mut self, node: Node<'a, 'input>) -> Option<Object> {
        let index = u16::try_from(self.required_hex(node, "index", 0xFFFF)?).ok()?;
        let span = self.element_span(node);
        let attrs = Self::entry_attributes(node);
        let parameter = self.parameter_facts(node);
        let name = self.name_of(node, &parameter);
        let sub_elements: Vec<Node> = children(node, "CANopenSubObject").collect();
        let object_type = self.object_type(node, !sub_elements.is_empty());
        let obj_flags = self.obj_flags(&attrs);
        let sub_number = self.optional_number(node, "subNumber");

        let mut object = Object {
            index,
            name: name.clone(),
            object_type,
            subs: Default::default(),
            sub_number,
            compact_sub_obj: None,
            obj_flags,
            span,
            custom: Vec::new(),
            object_links: Vec::new(),
            implicit: false,
        };
        let single_entry = !object_type.has_subs() && object_type != ObjectType::Null;
        if single_entry {
            if let Some(first) = sub_elements.first() {
                let sub_span = self.element_span(*first);
                self.push(Diagnostic::new(
                    &rules::XML_SUBS_ON_VAR,
                    Some(sub_span),
                    format!(
                        "object {index:04X}h is a VAR or DOMAIN but holds {} CANopenSubObject element(s); they are ignored",
                        sub_elements.len()
                    ),
                ));
            }
            let entry = self.build_entry(0, name, span, &attrs, parameter, obj_flags);
            object.subs.insert(0, entry);
        } else {
            object.custom = parameter.custom;
            for sub_node in sub_elements {
                let Some(sub_index) = self.required_hex(sub_node, "subIndex", 0xFF) else {
                    continue;
                };
                let sub_index = u8::try_from(sub_index).unwrap_or(u8::MAX);
                let sub_span = self.element_span(sub_node);
                let sub_attrs = Self::entry_attributes(sub_node);
                let sub_parameter = self.parameter_facts(sub_node);
                let sub_name = self.name_of(sub_node, &sub_parameter);
                let sub_flags = self.obj_flags(&sub_attrs);
                let entry = self.build_entry(
                    sub_index,
                    sub_name,
                    sub_span,
                    &sub_attrs,
                    sub_parameter,
                    sub_flags,
                );
                if object.subs.insert(sub_index, entry).is_some() {
                    self.push(Diagnostic::new(
                        &rules::XML_DUPLICATE,
                        Some(sub_span),
                        format!("sub-index {sub_index:02X}h of {index:04X}h is described twice; the last description is used"),
                    ));
                }
            }
        }
        Some(object)
    }

    fn object_type(&mut self, node: Node, has_subs: bool) -> ObjectType {
        let guess = if has_subs {
            ObjectType::Record
        } else {
            ObjectType::Var
        };
        let span = self.element_span(node);
        let Some(attr) = attribute(node, "objectType") else {
            self.push(Diagnostic::new(
                &rules::XML_MISSING_ATTRIBUTE,
                Some(span),
                format!("`{}` without `objectType`; read as {guess:?}", local(node)),
            ));
            return guess;
        };
        let value_span = self.attribute_span(&attr);
        let code = parse_integer(attr.value()).and_then(|c| u32::try_from(c).ok());
        match code.and_then(ObjectType::from_code) {
            Some(t) => t,
            None => {
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(value_span),
                    format!(
                        "`objectType` is `{}`, not a CiA 301 object code; read as {guess:?}",
                        attr.value()
                    ),
                ));
                guess
            }
        }
    }

    fn obj_flags(&mut self, attrs: &EntryAttributes) -> u32 {
        let Some(attr) = &attrs.obj_flags else {
            return 0;
        };
        match parse_hex_binary(attr.value()) {
            Some(v) => v,
            None => {
                let span = self.attribute_span(attr);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`objFlags` is `{}`, not hexBinary; 0 is used", attr.value()),
                ));
                0
            }
        }
    }

    fn optional_number(&mut self, node: Node, name: &str) -> Option<Spanned<u32>> {
        let attr = attribute(node, name)?;
        let span = self.attribute_span(&attr);
        match parse_integer(attr.value()).and_then(|n| u32::try_from(n).ok()) {
            Some(n) => Some(Spanned::new(n, span)),
            None => {
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`{name}` is `{}`, not a number", attr.value()),
                ));
                None
            }
        }
    }

    fn optional_bool(&mut self, node: Node, name: &str) -> Option<bool> {
        let attr = attribute(node, name)?;
        match parse_xml_bool(attr.value()) {
            Some(b) => Some(b),
            None => {
                let span = self.attribute_span(&attr);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`{name}` is `{}`, not `true` or `false`", attr.value()),
                ));
                None
            }
        }
    }

    fn raw_value(&self, attr: &Attribute) -> RawValue {
        RawValue {
            text: attr.value().trim().to_owned(),
            span: self.attribute_span(attr),
        }
    }

    /// The facts of the parameter an element's `uniqueIDRef` names (empty if none).
    fn parameter_facts(&mut self, node: Node) -> ParameterFacts {
        let Some(reference) = attribute(node, "uniqueIDRef") else {
            return ParameterFacts::default();
        };
        let Some(parameter) = self.parameters.get(reference.value()).copied() else {
            let span = self.attribute_span(&reference);
            self.push(Diagnostic::new(
                &rules::XML_UNRESOLVED_REF,
                Some(span),
                format!(
                    "uniqueIDRef `{}` names no parameter in the parameterList; the element's own attributes are used",
                    reference.value()
                ),
            ));
            return ParameterFacts::default();
        };
        let mut facts = ParameterFacts {
            resolved: true,
            label: language_text(parameter, "label"),
            ..Default::default()
        };
        if let Some(access) = attribute(parameter, "access") {
            facts.access = parse_parameter_access(access.value());
            facts.access_span = Some(self.attribute_span(&access));
            if facts.access.is_none() {
                let span = self.attribute_span(&access);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "parameter access `{}` has no CANopen access type",
                        access.value()
                    ),
                ));
            }
        }
        if let Some(description) = language_text(parameter, "description") {
            facts.custom.push(("Description".to_owned(), description));
        }
        for item in parameter.children().filter(|n| n.is_element()) {
            let name = local(item);
            if name == "BITSTRING" {
                facts.bitstring = true;
                facts.data_type_span = Some(self.element_span(item));
            } else if let Some((_, basic)) = IEC_TYPES.iter().find(|(n, _)| *n == name) {
                facts.data_type = Some(basic.index());
                facts.data_type_span = Some(self.element_span(item));
            }
            match name {
                "dataTypeIDRef" => {
                    facts.data_type = self.referenced_type(item);
                    facts.data_type_span = Some(self.element_span(item));
                }
                "variableRef" => {
                    let span = self.element_span(item);
                    self.push(Diagnostic::new(
                        &rules::XML_UNKNOWN_TYPE,
                        Some(span),
                        "a parameter typed by `variableRef` has no CANopen data type; the object's dataType is used",
                    ));
                }
                "defaultValue" => {
                    facts.default = attribute(item, "value").map(|a| self.raw_value(&a))
                }
                "actualValue" => {
                    facts.actual = attribute(item, "value").map(|a| self.raw_value(&a))
                }
                "denotation" => facts.denotation = language_text(item, "label"),
                "allowedValues" => self.read_allowed_values(item, &mut facts),
                "property" => {
                    if let (Some(n), Some(v)) = (attribute(item, "name"), attribute(item, "value"))
                    {
                        facts
                            .custom
                            .push((n.value().to_owned(), v.value().to_owned()));
                    }
                }
                _ => {}
            }
        }
        facts
    }

    /// The CANopen type a `dataTypeIDRef` gives a single entry: the base type of a `derived` or
    /// `enum` definition. Arrays and structs describe ARRAY/RECORD objects, not entries.
    fn referenced_type(&mut self, item: Node) -> Option<u16> {
        let reference = attribute(item, "uniqueIDRef")?;
        let Some(definition) = self.data_types.get(reference.value()).copied() else {
            let span = self.attribute_span(&reference);
            self.push(Diagnostic::new(
                &rules::XML_UNRESOLVED_REF,
                Some(span),
                format!(
                    "dataTypeIDRef `{}` names no entry of the dataTypeList",
                    reference.value()
                ),
            ));
            return None;
        };
        if !matches!(local(definition), "derived" | "enum") {
            return None;
        }
        definition.children().find_map(|c| {
            IEC_TYPES
                .iter()
                .find(|(n, _)| c.is_element() && *n == local(c))
                .map(|(_, t)| t.index())
        })
    }

    fn read_allowed_values(&mut self, allowed: Node, facts: &mut ParameterFacts) {
        if let Some(range) = child(allowed, "range") {
            let bound = |name: &str| child(range, name).and_then(|b| attribute(b, "value"));
            facts.low = bound("minValue").map(|a| self.raw_value(&a));
            facts.high = bound("maxValue").map(|a| self.raw_value(&a));
        }
        let listed: Vec<&str> = children(allowed, "value")
            .filter_map(|v| attribute(v, "value"))
            .map(|a| a.value())
            .collect();
        if !listed.is_empty() {
            facts
                .custom
                .push(("AllowedValues".to_owned(), listed.join(",")));
        }
    }

    /// One OD entry from an element's attributes and its parameter (which overrides them).
    fn build_entry(
        &mut self,
        sub_index: u8,
        name: String,
        span: Span,
        attrs: &EntryAttributes,
        parameter: ParameterFacts,
        obj_flags: u32,
    ) -> SubObject {
        let attribute_type = attrs.data_type.as_ref().and_then(|a| {
            let parsed = parse_hex_binary(a.value()).and_then(|v| u16::try_from(v).ok());
            if parsed.is_none() {
                let span = self.attribute_span(a);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "`dataType` is `{}`, not a hexBinary data type index",
                        a.value()
                    ),
                ));
            }
            parsed
        });
        let default = parameter
            .default
            .or_else(|| attrs.default_value.as_ref().map(|a| self.raw_value(a)));
        let attribute_type_span = attrs.data_type.as_ref().map(|a| self.attribute_span(a));
        let mut key_spans = KeySpans {
            data_type: match parameter.data_type {
                Some(_) => parameter.data_type_span,
                None => attribute_type_span.or(parameter.data_type_span),
            },
            access: parameter
                .access_span
                .or_else(|| attrs.access_type.as_ref().map(|a| self.attribute_span(a))),
            ..KeySpans::default()
        };
        let data_type = match (parameter.data_type, attribute_type) {
            (Some(from_parameter), Some(from_attribute)) => {
                if from_parameter != from_attribute {
                    self.push(Diagnostic::new(
                        &rules::XML_TYPE_CONFLICT,
                        Some(span),
                        format!(
                            "dataType is {from_attribute:04X}h but the parameter's type is {from_parameter:04X}h; the parameter's type is used"
                        ),
                    ));
                }
                Some(from_parameter)
            }
            (Some(t), None) | (None, Some(t)) => Some(t),
            (None, None) if parameter.bitstring => {
                // CANopenEditor's reading: a BITSTRING with a value is an OCTET_STRING, one
                // without is a DOMAIN.
                let has_value = default.as_ref().is_some_and(|d| !d.text.is_empty());
                Some(if has_value {
                    BasicType::OctetString.index()
                } else {
                    BasicType::Domain.index()
                })
            }
            (None, None) => None,
        };

        key_spans.pdo_mapping = attrs.pdo_mapping.as_ref().map(|a| self.attribute_span(a));
        let pdo_mapping_kind = attrs.pdo_mapping.as_ref().map(|a| (a.value(), *a));
        let mut pdo_mapping = false;
        let mut direction = None;
        if let Some((kind, attr)) = pdo_mapping_kind {
            match kind.trim() {
                "no" => {}
                "default" | "optional" => pdo_mapping = true,
                "TPDO" => {
                    pdo_mapping = true;
                    direction = Some(AccessType::Rwr);
                }
                "RPDO" => {
                    pdo_mapping = true;
                    direction = Some(AccessType::Rww);
                }
                other => {
                    let span = self.attribute_span(&attr);
                    self.push(Diagnostic::new(
                        &rules::XML_BAD_ATTRIBUTE,
                        Some(span),
                        format!("`PDOmapping` is `{other}`, not no, default, optional, TPDO or RPDO; read as no"),
                    ));
                }
            }
        }

        let attribute_access = attrs.access_type.as_ref().and_then(|a| {
            let parsed = AccessType::parse(a.value());
            if parsed.is_none() {
                let span = self.attribute_span(a);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`accessType` is `{}`, not ro, wo, rw or const", a.value()),
                ));
            }
            parsed
        });
        // The parameter's access wins; CiA 311 defaults it to `read`, which applies only when the
        // element does not say either.
        let mut access = parameter
            .access
            .or(attribute_access)
            .or(parameter.resolved.then_some(AccessType::Ro));
        // PDOmapping TPDO/RPDO gives a read-write entry its direction (CANopenEditor's reading).
        if let (Some(current), Some(direction)) = (access, direction) {
            if matches!(current, AccessType::Rwr | AccessType::Rww) && current != direction {
                self.push(Diagnostic::new(
                    &rules::XML_TYPE_CONFLICT,
                    Some(span),
                    format!(
                        "the access is {} but PDOmapping says {}; {} is used",
                        current.as_str(),
                        direction.as_str(),
                        direction.as_str()
                    ),
                ));
            }
            if matches!(current, AccessType::Rw | AccessType::Rwr | AccessType::Rww) {
                access = Some(direction);
            }
        }

        let basic = data_type.and_then(BasicType::from_index);
        let value = |reader: &mut Self, raw: Option<RawValue>| {
            raw.map(|raw| ValueSource {
                value: parse_value(&raw.text, basic, raw.span, reader.diags),
                raw: raw.text,
                span: raw.span,
            })
        };
        let default = value(self, default);
        let actual = parameter
            .actual
            .or_else(|| attrs.actual_value.as_ref().map(|a| self.raw_value(a)));
        let parameter_value = value(self, actual);
        let low = parameter
            .low
            .or_else(|| attrs.low_limit.as_ref().map(|a| self.raw_value(a)));
        let low_limit = value(self, low);
        let high = parameter
            .high
            .or_else(|| attrs.high_limit.as_ref().map(|a| self.raw_value(a)));
        let high_limit = value(self, high);
        let denotation = parameter.denotation.or_else(|| {
            attrs
                .denotation
                .as_ref()
                .map(|a| a.value().trim().to_owned())
                .filter(|d| !d.is_empty())
        });

        SubObject {
            sub_index,
            name,
            data_type,
            access,
            pdo_mapping,
            default,
            parameter_value,
            low_limit,
            high_limit,
            obj_flags,
            denotation,
            upload_file: None,
            download_file: None,
            span,
            custom: parameter.custom,
            implicit: false,
            key_spans,
            capacity: None,
        }
    }

    fn read_dummy_usage(&mut self, node: Node, device: &mut Device) {
        device.dummy_usage_span = Some(self.element_span(node));
        for dummy in children(node, "dummy") {
            let Some(entry) = attribute(dummy, "entry") else {
                continue;
            };
            let span = self.attribute_span(&entry);
            let parsed = entry.value().split_once('=').and_then(|(key, value)| {
                let key = key.trim();
                let index = key
                    .get(..5)
                    .filter(|p| p.eq_ignore_ascii_case("dummy"))
                    .and_then(|_| u16::from_str_radix(key.get(5..)?, 16).ok())?;
                let used = match value.trim() {
                    "1" => true,
                    "0" => false,
                    _ => return None,
                };
                Some((index, used))
            });
            match parsed {
                Some((index, used)) => {
                    device.dummy_usage.insert(index, used);
                }
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("dummy entry `{}` is not `DummyXXXX=0|1`", entry.value()),
                )),
            }
        }
    }

    fn read_baud_rates(&mut self, node: Node, device: &mut Device) {
        let mut extra = Vec::new();
        if let Some(default) = attribute(node, "defaultValue") {
            extra.push(RawEntry {
                key: "defaultValue".to_owned(),
                value: default.value().to_owned(),
                span: self.attribute_span(&default),
            });
        }
        for rate in children(node, "supportedBaudRate") {
            let Some(value) = attribute(rate, "value") else {
                continue;
            };
            let span = self.attribute_span(&value);
            match parse_baud_rate(value.value()) {
                Some(kbit) => device.device_info.baud_rates.push((kbit, true)),
                None if value.value().trim() == "auto-baudRate" => extra.push(RawEntry {
                    key: "supportedBaudRate".to_owned(),
                    value: value.value().to_owned(),
                    span,
                }),
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "supported baud rate `{}` is not like `250 Kbps`",
                        value.value()
                    ),
                )),
            }
        }
        if !extra.is_empty() {
            device.other_sections.push(RawSection {
                name: "baudRate".to_owned(),
                entries: extra,
                span: self.element_span(node),
            });
        }
    }

    /// Attributes of `node` not in `known`, kept as a raw section so nothing is dropped.
    fn keep_other_attributes(&self, node: Node, known: &[&str], device: &mut Device) {
        let entries: Vec<RawEntry> = node
            .attributes()
            .filter(|a| !known.contains(&a.name()))
            .map(|a| RawEntry {
                key: a.name().to_owned(),
                value: a.value().to_owned(),
                span: self.attribute_span(&a),
            })
            .collect();
        if !entries.is_empty() {
            device.other_sections.push(RawSection {
                name: local(node).to_owned(),
                entries,
                span: self.element_span(node),
            });
        }
    }

    /// `dynamicChannels/dynamicChannel` (CiA 302/405): kept verbatim, one entry per attribute
    /// (`dynamicChannel1.startIndex`), like the EDS `[DynamicChannels]` section.
    fn read_dynamic_channels(&mut self, node: Node, device: &mut Device) {
        let mut entries = Vec::new();
        for (number, channel) in children(node, "dynamicChannel").enumerate() {
            for attr in channel.attributes() {
                entries.push(RawEntry {
                    key: format!("dynamicChannel{}.{}", number + 1, attr.name()),
                    value: attr.value().to_owned(),
                    span: self.attribute_span(&attr),
                });
            }
        }
        device.other_sections.push(RawSection {
            name: "dynamicChannels".to_owned(),
            entries,
            span: self.element_span(node),
        });
    }

    fn read_general_features(&mut self, node: Node, device: &mut Device) {
        let info = &mut device.device_info;
        info.span.get_or_insert(self.element_span(node));
        info.granularity = self.optional_number(node, "granularity");
        info.nr_of_rx_pdo = self.optional_number(node, "nrOfRxPDO");
        info.nr_of_tx_pdo = self.optional_number(node, "nrOfTxPDO");
        if let Some(group) = self.optional_bool(node, "groupMessaging") {
            info.group_messaging = group;
        }
        if let Some(channels) = self.optional_number(node, "dynamicChannels") {
            info.dynamic_channels_supported = channels.value;
        }
        if let Some(boot) = self.optional_bool(node, "bootUpSlave") {
            info.simple_boot_up_slave = boot;
        }
        if let Some(lss) = self.optional_bool(node, "layerSettingServiceSlave") {
            info.lss_supported = lss;
        }
        self.keep_other_attributes(
            node,
            &[
                "granularity",
                "nrOfRxPDO",
                "nrOfTxPDO",
                "groupMessaging",
                "dynamicChannels",
                "bootUpSlave",
                "layerSettingServiceSlave",
            ],
            device,
        );
    }

    fn read_master_features(&mut self, node: Node, device: &mut Device) {
        if let Some(boot) = self.optional_bool(node, "bootUpMaster") {
            device.device_info.simple_boot_up_master = boot;
        }
        self.keep_other_attributes(node, &["bootUpMaster"], device);
    }

    fn read_commissioning(&mut self, node: Node, device: &mut Device) {
        let text = |name: &str| attribute(node, name).map(|a| a.value().to_owned());
        let mut commissioning = Commissioning {
            node_id: self.optional_number(node, "nodeID"),
            node_name: text("nodeName"),
            network_name: text("networkName"),
            net_number: self.optional_number(node, "networkNumber").map(|n| n.value),
            canopen_manager: self.optional_bool(node, "CANopenManager").unwrap_or(false),
            span: self.element_span(node),
            ..Default::default()
        };
        if let Some(rate) = attribute(node, "actualBaudRate") {
            let span = self.attribute_span(&rate);
            match parse_baud_rate(rate.value()) {
                Some(kbit) => commissioning.baudrate = Some(Spanned::new(kbit, span)),
                None if !rate.value().trim().is_empty()
                    && rate.value().trim().bytes().all(|b| b.is_ascii_digit()) =>
                {
                    let kbit = rate.value().trim().parse::<u32>().ok();
                    commissioning.baudrate = kbit.map(|k| Spanned::new(k, span));
                    self.push(
                        Diagnostic::new(
                            &rules::XML_BAD_ATTRIBUTE,
                            Some(span),
                            format!(
                                "actualBaudRate `{}` has no unit; read as kbit/s",
                                rate.value()
                            ),
                        )
                        .with_severity(Severity::Info)
                        .with_help("write it as `250 Kbps`"),
                    );
                }
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("actualBaudRate `{}` is not like `250 Kbps`", rate.value()),
                )),
            }
        }
        device.commissioning = Some(commissioning);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_is_bounded_before_parsing() {
        let deep = format!("{}{}", "<a>".repeat(20_000), "</a>".repeat(20_000));
        assert_eq!(nesting_beyond(&deep, MAX_DEPTH), Some(3 * MAX_DEPTH));
        let read = read(Path::new("deep.xdd"), deep.as_bytes());
        assert_eq!(read.diagnostics.len(), 1);
        assert_eq!(
            read.diagnostics[0].message,
            "the XML nests elements more than 256 deep; it was not parsed"
        );
        assert_eq!(read.diagnostics[0].span, Some(Span::new(1, 769, 1)));
        // Empty elements, comments, CDATA and `>` inside attribute values do not nest.
        let flat = format!(
            "<?xml version=\"1.0\"?><r>{}</r>",
            "<e a='>'/><!-- <x> --><![CDATA[<y>]]><f b=\"/>\"></f>".repeat(1000)
        );
        assert_eq!(nesting_beyond(&flat, 2), None);
        assert_eq!(nesting_beyond("<a><b><c/></b></a>", 1), Some(3));
    }
}
