//! ESI reader (ETG.2000): an `EtherCATInfo` file into the shared [`Device`] model.
//!
//! The CoE dictionary (`Profile/Dictionary`) becomes [`Device::objects`], exactly as a CANopen
//! object dictionary: IEC 61131 type names map to CiA 301 data types, a `DTxxxx` type with
//! `SubItem`s makes an ARRAY or RECORD, `DefaultData` (little-endian hex) becomes a typed value.
//! Identity goes to [`DeviceInfo`]; SyncManagers, PDOs, the CoE mailbox and the DC op-modes to
//! [`EtherCat`]. A file may describe several devices: one is read (the first, or the one a
//! [`DeviceChoice`] names) and the others are listed in [`EtherCat::other_devices`].

use std::collections::HashMap;
use std::path::Path;

use roxmltree::{Attribute, Node};

use super::text::LineIndex;
use super::xdd::{attribute, child, children, element_span, element_text, is_element, local};
use super::Read;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::rules;

/// Which device of an ESI file to read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DeviceChoice {
    /// The first device whose `Type` text is this name (exact, else ignoring case).
    TypeName(String),
    /// The first device with this `ProductCode`.
    ProductCode(u32),
    /// The device at this position (0-based) in `Descriptions/Devices`.
    Position(usize),
}

impl DeviceChoice {
    /// `#x9252` or `0x9252` is a product code; anything else a type name.
    pub fn parse(text: &str) -> Self {
        let t = text.trim();
        match hex_digits(t).and_then(|h| u32::from_str_radix(h, 16).ok()) {
            Some(code) => DeviceChoice::ProductCode(code),
            None => DeviceChoice::TypeName(t.to_owned()),
        }
    }
}

/// Reads the first device of an ESI file.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    read_device(path, bytes, None)
}

/// Reads the device `choice` names (the first when `None`). When no device matches, the model
/// has no objects and an `EDS801` error lists the devices there are.
pub fn read_device(path: &Path, bytes: &[u8], choice: Option<&DeviceChoice>) -> Read {
    let (text, encoding, mut diagnostics) = decode(bytes);
    let mut device = super::eds::empty_device(path, Format::Esi, encoding);
    if let Some(doc) = super::xdd::parse(&text, &mut diagnostics) {
        let mut reader = EsiReader::new(&text, &mut diagnostics);
        reader.read_file(doc.root_element(), &mut device, choice);
    }
    Read {
        device,
        diagnostics,
        text,
    }
}

/// Reads every device of an ESI file from one parse, each with its own diagnostics (the ones
/// about the file as a whole repeated in each). Empty for a file without devices.
pub fn read_all(path: &Path, bytes: &[u8]) -> Vec<(Device, Vec<Diagnostic>)> {
    let (text, encoding, diagnostics) = decode(bytes);
    let mut scratch = diagnostics.clone();
    let Some(doc) = super::xdd::parse(&text, &mut scratch) else {
        return Vec::new();
    };
    let count = devices(doc.root_element()).count();
    (0..count)
        .map(|n| {
            let mut diags = diagnostics.clone();
            let mut device = super::eds::empty_device(path, Format::Esi, encoding);
            EsiReader::new(&text, &mut diags).read_file(
                doc.root_element(),
                &mut device,
                Some(&DeviceChoice::Position(n)),
            );
            (device, diags)
        })
        .collect()
}

/// Decodes the bytes: as ISO-8859-1 when the XML declaration says so (and the bytes are not
/// ASCII), else as [`super::text::decode`] does (UTF-8, a BOM, UTF-16, else Windows-1252 with
/// an `EDS002` warning).
fn decode(bytes: &[u8]) -> (String, TextEncoding, Vec<Diagnostic>) {
    let mut diagnostics = Vec::new();
    if declares_latin1(bytes) && !bytes.is_ascii() && super::text::utf16(bytes).is_none() {
        let text = bytes.iter().map(|&b| char::from(b)).collect();
        return (text, TextEncoding::Latin1, diagnostics);
    }
    let (text, encoding) = super::text::decode(bytes);
    if encoding == TextEncoding::Windows1252 {
        diagnostics.push(
            Diagnostic::new(
                &rules::NON_ASCII,
                None,
                "the XML file is not valid UTF-8; it was decoded as Windows-1252",
            )
            .with_help("save the file as UTF-8, or declare encoding=\"ISO-8859-1\""),
        );
    }
    (text, encoding, diagnostics)
}

/// Whether the XML declaration names ISO-8859-1 (also the non-IANA spelling `iso8859-1`).
fn declares_latin1(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(200)];
    let Some(end) = head.windows(2).position(|w| w == b"?>") else {
        return false;
    };
    let decl = String::from_utf8_lossy(&head[..end]).to_ascii_lowercase();
    let Some(at) = decl.find("encoding") else {
        return false;
    };
    let label: String = decl[at + "encoding".len()..]
        .chars()
        .skip_while(|c| *c == '=' || *c == '"' || *c == '\'' || c.is_whitespace())
        .take_while(|c| *c != '"' && *c != '\'')
        .collect();
    matches!(
        label.trim(),
        "iso-8859-1" | "iso8859-1" | "iso_8859-1" | "latin1" | "latin-1" | "l1"
    )
}

/// The hex digits of `#x1A00` or `0x1A00`.
fn hex_digits(text: &str) -> Option<&str> {
    ["#x", "#X", "0x", "0X"]
        .iter()
        .find_map(|p| text.strip_prefix(p))
}

/// An ESI number: `#x` (or `0x`) hex, else decimal, optionally negative.
pub(crate) fn parse_number(text: &str) -> Option<i128> {
    let t = text.trim();
    let (negative, t) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t),
    };
    let value = match hex_digits(t) {
        Some(hex) if !hex.is_empty() => i128::from_str_radix(hex, 16).ok()?,
        Some(_) => return None,
        None if !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) => t.parse().ok()?,
        None => return None,
    };
    Some(if negative { -value } else { value })
}

/// Hex bytes as `DefaultData` and `InitCmd/Data` write them (`6C020000`), in written order.
fn parse_hex_bytes(text: &str) -> Option<Vec<u8>> {
    let t: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if t.len() % 2 != 0 || !t.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    (0..t.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&t[i..i + 2], 16).ok())
        .collect()
}

/// `1`/`true` and `0`/`false`.
fn parse_bool(text: &str) -> Option<bool> {
    super::xdd::parse_xml_bool(&text.trim().to_ascii_lowercase())
}

/// The `Descriptions/Devices/Device` elements.
fn devices<'a, 'input>(root: Node<'a, 'input>) -> impl Iterator<Item = Node<'a, 'input>> {
    child(root, "Descriptions")
        .and_then(|d| child(d, "Devices"))
        .into_iter()
        .flat_map(|d| d.children().filter(|c| is_element(*c, "Device")))
}

/// The text of a `Name` group: the English one (`LcId="1033"`), else the first.
fn language_name(node: Node, name: &str) -> Option<String> {
    let mut first = None;
    for item in children(node, name) {
        let text = element_text(item);
        if attribute(item, "LcId").is_some_and(|a| a.value().trim() == "1033") && text.is_some() {
            return text;
        }
        if first.is_none() {
            first = text;
        }
    }
    first
}

/// What a `Type` name stands for.
enum Resolved<'a, 'input> {
    /// A CiA 301 basic type, with the capacity in bytes of a `STRING(n)` or byte array.
    Basic(BasicType, Option<usize>),
    /// A `DataType` with `SubItem`s: an ARRAY or RECORD.
    Complex(Node<'a, 'input>),
    /// A `DataType` with `ArrayInfo` used as a SubItem: its elements become sub-indices.
    Elements {
        lbound: u32,
        count: u32,
        base: String,
    },
    /// Nothing known.
    Unknown,
}

/// The IEC 61131 names ESI files use beyond CiA 311's (`BIT`, `BITn`, `BITARRn`, the 24..56-bit
/// integers), and the CANopen type each maps to. A `BITn` keeps its width in the entry's
/// `BitSize`.
const ESI_TYPES: &[(&str, BasicType)] = &[
    ("BIT", BasicType::Boolean),
    ("BIT1", BasicType::Boolean),
    ("BIT2", BasicType::Unsigned8),
    ("BIT3", BasicType::Unsigned8),
    ("BIT4", BasicType::Unsigned8),
    ("BIT5", BasicType::Unsigned8),
    ("BIT6", BasicType::Unsigned8),
    ("BIT7", BasicType::Unsigned8),
    ("BIT8", BasicType::Unsigned8),
    ("BITARR8", BasicType::Unsigned8),
    ("BITARR16", BasicType::Unsigned16),
    ("BITARR32", BasicType::Unsigned32),
    ("INT24", BasicType::Integer24),
    ("INT40", BasicType::Integer40),
    ("INT48", BasicType::Integer48),
    ("INT56", BasicType::Integer56),
    ("UINT24", BasicType::Unsigned24),
    ("UINT40", BasicType::Unsigned40),
    ("UINT48", BasicType::Unsigned48),
    ("UINT56", BasicType::Unsigned56),
    ("OCTET_STRING", BasicType::OctetString),
    ("UNICODE_STRING", BasicType::UnicodeString),
];

/// An elementary IEC 61131 name, `STRING(n)`, or `ARRAY [a..b] OF BYTE|USINT` (a byte string).
fn elementary(name: &str) -> Option<(BasicType, Option<usize>)> {
    let upper = name.trim().to_ascii_uppercase();
    if let Some((_, t)) = super::xdd::IEC_TYPES
        .iter()
        .chain(ESI_TYPES)
        .find(|(n, _)| *n == upper)
    {
        return Some((*t, None));
    }
    if let Some(n) = upper
        .strip_prefix("STRING(")
        .and_then(|r| r.strip_suffix(')'))
    {
        return Some((BasicType::VisibleString, Some(n.trim().parse().ok()?)));
    }
    let (low, high, base) = array_bounds(&upper)?;
    matches!(base.as_str(), "BYTE" | "USINT")
        .then(|| (BasicType::OctetString, usize::try_from(high - low + 1).ok()))
}

/// `ARRAY [a..b] OF T` as (a, b, T).
fn array_bounds(upper: &str) -> Option<(i64, i64, String)> {
    let rest = upper
        .strip_prefix("ARRAY")?
        .trim_start()
        .strip_prefix('[')?;
    let (range, rest) = rest.split_once(']')?;
    let (low, high) = range.split_once("..")?;
    let (low, high): (i64, i64) = (low.trim().parse().ok()?, high.trim().parse().ok()?);
    let base = rest.trim().strip_prefix("OF")?.trim().to_owned();
    (high >= low).then_some((low, high, base))
}

/// The access an entry gets from `Flags`: `rw` mapped only into RxPDOs is `rww`, only into
/// TxPDOs `rwr` (as the XDD reader does with PDOmapping).
fn access_of(access: &str, mapping: Option<&str>) -> Option<AccessType> {
    let base = AccessType::parse(access)?;
    Some(
        match (base, mapping.map(str::to_ascii_uppercase).as_deref()) {
            (AccessType::Rw, Some("R")) => AccessType::Rww,
            (AccessType::Rw, Some("T")) => AccessType::Rwr,
            _ => base,
        },
    )
}

/// `DefaultData` bytes (little-endian) as a value of `basic`; `None` when the byte count does not
/// fit the type.
fn data_value(bytes: &[u8], basic: BasicType) -> Option<Value> {
    match basic {
        BasicType::VisibleString | BasicType::UnicodeString => {
            let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
            Some(Value::Text(
                bytes[..end].iter().map(|&b| char::from(b)).collect(),
            ))
        }
        BasicType::OctetString | BasicType::Domain => Some(Value::Bytes(bytes.to_vec())),
        BasicType::Real32 => {
            let raw: [u8; 4] = bytes.try_into().ok()?;
            Some(Value::Real(f64::from(f32::from_le_bytes(raw))))
        }
        BasicType::Real64 => {
            let raw: [u8; 8] = bytes.try_into().ok()?;
            Some(Value::Real(f64::from_le_bytes(raw)))
        }
        _ => {
            let bits = basic.bits()?;
            let width = usize::try_from(bits.div_ceil(8)).ok()?;
            if bytes.is_empty() || bytes.len() > width {
                return None;
            }
            let mut value: i128 = 0;
            for (i, b) in bytes.iter().enumerate() {
                value |= i128::from(*b) << (8 * i);
            }
            if basic.is_signed_integer() && bytes.len() == width && value >> (bits - 1) & 1 == 1 {
                value -= 1i128 << bits;
            }
            let (low, high) = basic.integer_range()?;
            (low..=high)
                .contains(&value)
                .then_some(Value::Integer(value))
        }
    }
}

/// A `#xFFFD` written for a signed type: the two's-complement value (-3 for an INT), as the
/// type's bit pattern means; other values unchanged.
fn twos_complement(value: i128, basic: BasicType) -> i128 {
    match (basic.integer_range(), basic.bits()) {
        (Some((_, high)), Some(bits)) if basic.is_signed_integer() && value > high => {
            if value < 1i128 << bits {
                value - (1i128 << bits)
            } else {
                value
            }
        }
        _ => value,
    }
}

/// What one entry's elements say (an object's, or one SubItem's with the object's as fallback).
struct EntryFacts<'a, 'input> {
    name: String,
    type_name: Option<(String, Span)>,
    basic: Option<(BasicType, Option<usize>)>,
    bit_size: Option<u32>,
    flags: Option<Node<'a, 'input>>,
    fallback_flags: Option<Node<'a, 'input>>,
    info: Option<Node<'a, 'input>>,
    span: Span,
}

struct EsiReader<'a, 'input> {
    text: &'input str,
    lines: LineIndex,
    diags: &'a mut Vec<Diagnostic>,
    data_types: HashMap<String, Node<'a, 'input>>,
}

impl<'a, 'input> EsiReader<'a, 'input> {
    fn new(text: &'input str, diags: &'a mut Vec<Diagnostic>) -> Self {
        EsiReader {
            text,
            lines: LineIndex::new(text),
            diags,
            data_types: HashMap::new(),
        }
    }

    fn span(&self, node: Node) -> Span {
        element_span(self.text, &self.lines, node)
    }

    fn attribute_span(&self, attr: &Attribute) -> Span {
        self.lines.span(self.text, attr.range_value())
    }

    /// The span of an element's text (trimmed), else of the element.
    fn text_span(&self, node: Node) -> Span {
        let Some(range) = node.children().find(|c| c.is_text()).map(|t| t.range()) else {
            return self.span(node);
        };
        let raw = self.text.get(range.clone()).unwrap_or("");
        let start = range.start + (raw.len() - raw.trim_start().len());
        let text_span = self.lines.span(self.text, start..start + raw.trim().len());
        if raw.trim().is_empty() {
            self.span(node)
        } else {
            text_span
        }
    }

    fn push(&mut self, diag: Diagnostic) {
        self.diags.push(diag);
    }

    /// A child element's text as a number, with an `EDS604` error when it is not one.
    fn child_number(&mut self, node: Node, name: &str) -> Option<i128> {
        let item = child(node, name)?;
        let text = element_text(item).unwrap_or_default();
        let number = parse_number(&text);
        if number.is_none() {
            let span = self.text_span(item);
            self.push(Diagnostic::new(
                &rules::XML_BAD_ATTRIBUTE,
                Some(span),
                format!("`{name}` is `{text}`, not a number"),
            ));
        }
        number
    }

    /// An attribute as a number, with an `EDS604` error when it is not one.
    fn attr_number(&mut self, node: Node, name: &str) -> Option<i128> {
        let attr = attribute(node, name)?;
        let number = parse_number(attr.value());
        if number.is_none() {
            let span = self.attribute_span(&attr);
            self.push(Diagnostic::new(
                &rules::XML_BAD_ATTRIBUTE,
                Some(span),
                format!("`{name}` is `{}`, not a number", attr.value()),
            ));
        }
        number
    }

    /// An attribute as a boolean (absent: `false`), with an `EDS604` warning when unreadable.
    fn attr_bool(&mut self, node: Node, name: &str) -> bool {
        let Some(attr) = attribute(node, name) else {
            return false;
        };
        parse_bool(attr.value()).unwrap_or_else(|| {
            let span = self.attribute_span(&attr);
            self.push(
                Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "`{name}` is `{}`, not 1/0/true/false; read as 0",
                        attr.value()
                    ),
                )
                .with_severity(Severity::Warning),
            );
            false
        })
    }

    fn read_file(
        &mut self,
        root: Node<'a, 'input>,
        device: &mut Device,
        choice: Option<&DeviceChoice>,
    ) {
        let root_span = self.span(root);
        if !matches!(local(root), "EtherCATInfo" | "EtherCATModule") {
            self.push(
                Diagnostic::new(
                    &rules::XML_NO_OBJECT_LIST,
                    Some(root_span),
                    format!("the root element is `{}`, not `EtherCATInfo`", local(root)),
                )
                .with_severity(Severity::Warning),
            );
        }
        if let Some(vendor) = child(root, "Vendor") {
            self.read_vendor(vendor, device);
        }
        let modules = root
            .descendants()
            .filter(|n| is_element(*n, "Module"))
            .filter(|n| n.parent_element().is_some_and(|p| is_element(p, "Modules")))
            .count();
        if modules > 0 {
            self.push(Diagnostic::new(
                &rules::ESI_MODULES,
                Some(root_span),
                format!("the file describes {modules} module(s) of a modular device; modules are not read"),
            ));
        }
        let all: Vec<Node> = devices(root).collect();
        let idents: Vec<(String, u32, u32)> = all.iter().map(|d| identity(*d)).collect();
        if all.is_empty() {
            self.push(Diagnostic::new(
                &rules::ESI_NO_DEVICE,
                Some(root_span),
                "the file describes no Device (`Descriptions/Devices/Device`)",
            ));
            return;
        }
        let picked = match choice {
            None => Some(0),
            Some(DeviceChoice::Position(n)) => (*n < all.len()).then_some(*n),
            Some(DeviceChoice::ProductCode(code)) => idents.iter().position(|i| i.1 == *code),
            Some(DeviceChoice::TypeName(name)) => idents
                .iter()
                .position(|i| i.0 == *name)
                .or_else(|| idents.iter().position(|i| i.0.eq_ignore_ascii_case(name))),
        };
        let Some(picked) = picked else {
            let names: Vec<String> = idents
                .iter()
                .map(|(name, code, _)| format!("{name} (#x{code:08X})"))
                .collect();
            self.push(
                Diagnostic::new(
                    &rules::ESI_NO_DEVICE,
                    Some(root_span),
                    format!(
                        "no device of the file is {}; it has {}",
                        match choice {
                            Some(DeviceChoice::ProductCode(c)) => format!("product code #x{c:08X}"),
                            Some(DeviceChoice::TypeName(n)) => format!("named `{n}`"),
                            _ => "at that position".to_owned(),
                        },
                        crate::validate::short_list(&names)
                    ),
                )
                .with_help("pick one by its type name or its product code (`#x...`)"),
            );
            return;
        };
        let mut ethercat = EtherCat {
            other_devices: idents
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != picked)
                .map(|(_, ident)| ident.clone())
                .collect(),
            ..EtherCat::default()
        };
        self.read_device(all[picked], device, &mut ethercat);
        device.ethercat = Some(ethercat);
    }

    fn read_vendor(&mut self, vendor: Node, device: &mut Device) {
        device.device_info.vendor_name = language_name(vendor, "Name");
        if let Some(id) = child(vendor, "Id") {
            let span = self.text_span(id);
            let number = self.child_number(vendor, "Id");
            device.device_info.vendor_number = number
                .and_then(|n| u32::try_from(n).ok())
                .map(|n| Spanned::new(n, span));
        }
    }

    fn read_device(&mut self, node: Node<'a, 'input>, device: &mut Device, ec: &mut EtherCat) {
        ec.span = self.span(node);
        device.device_info.span = Some(ec.span);
        if let Some(ty) = child(node, "Type") {
            ec.type_name = element_text(ty).unwrap_or_default();
            for (name, slot) in [
                ("ProductCode", &mut device.device_info.product_number),
                ("RevisionNo", &mut device.device_info.revision_number),
            ] {
                if let Some(attr) = attribute(ty, name) {
                    let span = self.attribute_span(&attr);
                    *slot = self
                        .attr_number(ty, name)
                        .and_then(|n| u32::try_from(n).ok())
                        .map(|n| Spanned::new(n, span));
                }
            }
        }
        device.device_info.product_name = language_name(node, "Name");
        for profile in children(node, "Profile") {
            for number in profile
                .descendants()
                .filter(|n| is_element(*n, "ProfileNo"))
            {
                if let Some(n) = self.child_number(number.parent().unwrap_or(number), "ProfileNo") {
                    if let Ok(n) = u32::try_from(n) {
                        if !ec.profiles.contains(&n) {
                            ec.profiles.push(n);
                        }
                    }
                }
            }
            if let Some(file) = child(profile, "DictionaryFile") {
                let span = self.span(file);
                self.push(
                    Diagnostic::new(
                        &rules::XML_BAD_ATTRIBUTE,
                        Some(span),
                        "a `DictionaryFile` reference is not followed: the dictionary is not read",
                    )
                    .with_severity(Severity::Warning),
                );
            }
            if let Some(dictionary) = child(profile, "Dictionary") {
                self.read_dictionary(dictionary, device);
            }
        }
        for sm in children(node, "Sm") {
            let sync_manager = self.read_sm(sm);
            ec.sync_managers.push(sync_manager);
        }
        for pdo in node.children().filter(|n| n.is_element()) {
            match local(pdo) {
                "RxPdo" => ec.rx_pdos.extend(self.read_pdo(pdo)),
                "TxPdo" => ec.tx_pdos.extend(self.read_pdo(pdo)),
                _ => {}
            }
        }
        if let Some(coe) = child(node, "Mailbox").and_then(|m| child(m, "CoE")) {
            ec.coe = Some(self.read_coe(coe));
        }
        if let Some(dc) = child(node, "Dc") {
            for mode in children(dc, "OpMode") {
                let op_mode = self.read_op_mode(mode);
                ec.op_modes.push(op_mode);
            }
        }
        if let Some(slots) = child(node, "Slots") {
            let count = children(slots, "Slot").count();
            let span = self.span(slots);
            let entries = children(slots, "Slot")
                .map(|slot| RawEntry {
                    key: "Slot".to_owned(),
                    value: language_name(slot, "Name").unwrap_or_default(),
                    span: self.span(slot),
                })
                .collect();
            device.other_sections.push(RawSection {
                name: "Slots".to_owned(),
                entries,
                span,
            });
            self.push(Diagnostic::new(
                &rules::ESI_MODULES,
                Some(span),
                format!(
                    "the device has {count} slot(s) for modules; what a module adds is not read"
                ),
            ));
        }
    }

    fn read_sm(&mut self, sm: Node) -> SyncManager {
        let kind = match element_text(sm).as_deref() {
            Some("MBoxOut") => SmKind::MailboxOut,
            Some("MBoxIn") => SmKind::MailboxIn,
            Some("Outputs") => SmKind::Outputs,
            Some("Inputs") => SmKind::Inputs,
            other => SmKind::Other(other.unwrap_or_default().to_owned()),
        };
        SyncManager {
            kind,
            start_address: self
                .attr_number(sm, "StartAddress")
                .and_then(|n| u16::try_from(n).ok())
                .unwrap_or(0),
            default_size: self
                .attr_number(sm, "DefaultSize")
                .and_then(|n| u16::try_from(n).ok()),
            control_byte: self
                .attr_number(sm, "ControlByte")
                .and_then(|n| u8::try_from(n).ok())
                .unwrap_or(0),
            enable: self.attr_bool(sm, "Enable"),
            span: self.span(sm),
        }
    }

    fn read_pdo(&mut self, node: Node) -> Option<EcPdo> {
        let span = self.span(node);
        let Some(index) = self
            .child_number(node, "Index")
            .and_then(|n| u16::try_from(n).ok())
        else {
            if child(node, "Index").is_none() {
                self.push(Diagnostic::new(
                    &rules::XML_MISSING_ATTRIBUTE,
                    Some(span),
                    format!("`{}` without `Index`: it is skipped", local(node)),
                ));
            }
            return None;
        };
        let sm = self
            .attr_number(node, "Sm")
            .and_then(|n| u8::try_from(n).ok());
        let mut exclude = Vec::new();
        for item in children(node, "Exclude") {
            let span = self.text_span(item);
            let text = element_text(item).unwrap_or_default();
            match parse_number(&text).and_then(|n| u16::try_from(n).ok()) {
                Some(n) => exclude.push(Spanned::new(n, span)),
                None => self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`Exclude` is `{text}`, not an index"),
                )),
            }
        }
        let mut entries = Vec::new();
        for entry in children(node, "Entry") {
            let span = self.span(entry);
            let index = self
                .child_number(entry, "Index")
                .and_then(|n| u16::try_from(n).ok())
                .unwrap_or(0);
            let sub = self
                .child_number(entry, "SubIndex")
                .and_then(|n| u8::try_from(n).ok())
                .unwrap_or(0);
            let bit_len = self
                .child_number(entry, "BitLen")
                .and_then(|n| u16::try_from(n).ok())
                .unwrap_or(0);
            entries.push(EcPdoEntry {
                index,
                sub,
                bit_len,
                name: language_name(entry, "Name").unwrap_or_default(),
                data_type: child(entry, "DataType").and_then(element_text),
                span,
            });
        }
        Some(EcPdo {
            index,
            name: language_name(node, "Name").unwrap_or_default(),
            sm,
            fixed: self.attr_bool(node, "Fixed"),
            mandatory: self.attr_bool(node, "Mandatory"),
            exclude,
            entries,
            span,
        })
    }

    fn read_coe(&mut self, coe: Node) -> CoeMailbox {
        let mut mailbox = CoeMailbox {
            sdo_info: self.attr_bool(coe, "SdoInfo"),
            pdo_assign: self.attr_bool(coe, "PdoAssign"),
            pdo_config: self.attr_bool(coe, "PdoConfig"),
            complete_access: self.attr_bool(coe, "CompleteAccess"),
            segmented_sdo: self.attr_bool(coe, "SegmentedSdo"),
            init_cmds: Vec::new(),
        };
        for cmd in coe.descendants().filter(|n| is_element(*n, "InitCmd")) {
            let span = self.span(cmd);
            let data = match child(cmd, "Data") {
                Some(data) => {
                    let text = element_text(data).unwrap_or_default();
                    parse_hex_bytes(&text).unwrap_or_else(|| {
                        let span = self.text_span(data);
                        self.push(Diagnostic::new(
                            &rules::XML_BAD_ATTRIBUTE,
                            Some(span),
                            format!("InitCmd `Data` is `{text}`, not hex bytes"),
                        ));
                        Vec::new()
                    })
                }
                None => Vec::new(),
            };
            mailbox.init_cmds.push(CoeInitCmd {
                transitions: children(cmd, "Transition")
                    .filter_map(element_text)
                    .collect(),
                index: self
                    .child_number(cmd, "Index")
                    .and_then(|n| u16::try_from(n).ok())
                    .unwrap_or(0),
                sub: self
                    .child_number(cmd, "SubIndex")
                    .and_then(|n| u8::try_from(n).ok())
                    .unwrap_or(0),
                data,
                complete_access: self.attr_bool(cmd, "CompleteAccess"),
                span,
            });
        }
        mailbox
    }

    fn read_op_mode(&mut self, mode: Node) -> DcOpMode {
        DcOpMode {
            name: child(mode, "Name")
                .and_then(element_text)
                .unwrap_or_default(),
            description: child(mode, "Desc")
                .and_then(element_text)
                .unwrap_or_default(),
            assign_activate: self
                .child_number(mode, "AssignActivate")
                .and_then(|n| u16::try_from(n).ok())
                .unwrap_or(0),
            cycle_time_sync0: self
                .child_number(mode, "CycleTimeSync0")
                .and_then(|n| u32::try_from(n).ok())
                .unwrap_or(0),
        }
    }

    fn read_dictionary(&mut self, dictionary: Node<'a, 'input>, device: &mut Device) {
        if let Some(types) = child(dictionary, "DataTypes") {
            for ty in children(types, "DataType") {
                let Some(name) = child(ty, "Name").and_then(element_text) else {
                    continue;
                };
                if let Some(earlier) = self.data_types.insert(name.clone(), ty) {
                    // Vendors repeat elementary types verbatim; only a different one matters.
                    if !same_definition(earlier, ty) {
                        let span = self.span(ty);
                        self.push(Diagnostic::new(
                            &rules::ESI_DUPLICATE_OBJECT,
                            Some(span),
                            format!("DataType `{name}` is defined twice, differently; the last definition is used"),
                        ));
                    }
                }
            }
        }
        let Some(objects) = child(dictionary, "Objects") else {
            return;
        };
        for node in children(objects, "Object") {
            let Some(object) = self.read_object(node) else {
                continue;
            };
            let (index, span) = (object.index, object.span);
            if device.objects.insert(index, object).is_some() {
                self.push(Diagnostic::new(
                    &rules::ESI_DUPLICATE_OBJECT,
                    Some(span),
                    format!("object {index:04X}h is described twice; the last description is used"),
                ));
            }
        }
    }

    /// What a type name stands for, following `BaseType` (enums, derived types) a few levels.
    fn resolve(&self, name: &str) -> Resolved<'a, 'input> {
        let mut name = name.trim().to_owned();
        for _ in 0..8 {
            if let Some((basic, capacity)) = elementary(&name) {
                return Resolved::Basic(basic, capacity);
            }
            let Some(def) = self.data_types.get(&name).copied() else {
                return Resolved::Unknown;
            };
            if child(def, "SubItem").is_some() {
                return Resolved::Complex(def);
            }
            let base = child(def, "BaseType").and_then(element_text);
            if let (Some(info), Some(base)) = (child(def, "ArrayInfo"), &base) {
                let number = |n: &str| {
                    child(info, n)
                        .and_then(element_text)
                        .and_then(|t| parse_number(&t))
                        .and_then(|v| u32::try_from(v).ok())
                };
                return match (number("LBound"), number("Elements")) {
                    (Some(lbound), Some(count)) => Resolved::Elements {
                        lbound,
                        count,
                        base: base.clone(),
                    },
                    _ => Resolved::Unknown,
                };
            }
            match base {
                Some(base) => name = base,
                None => return Resolved::Unknown,
            }
        }
        Resolved::Unknown
    }

    /// The basic type of a type name, with an `EDS805` error at `span` when there is none.
    fn basic_of(&mut self, name: &str, span: Span) -> Option<(BasicType, Option<usize>)> {
        match self.resolve(name) {
            Resolved::Basic(basic, capacity) => Some((basic, capacity)),
            Resolved::Unknown => {
                self.push(
                    Diagnostic::new(
                        &rules::ESI_UNKNOWN_TYPE,
                        Some(span),
                        format!("type `{name}` is neither an IEC 61131 type nor a DataType of the Dictionary"),
                    )
                    .with_label("unknown type")
                    .with_help("add a DataType of this name to Dictionary/DataTypes"),
                );
                None
            }
            Resolved::Complex(_) | Resolved::Elements { .. } => {
                self.push(
                    Diagnostic::new(
                        &rules::ESI_UNKNOWN_TYPE,
                        Some(span),
                        format!("type `{name}` is structured where a single value is expected"),
                    )
                    .with_label("not a single value"),
                );
                None
            }
        }
    }

    fn read_object(&mut self, node: Node<'a, 'input>) -> Option<Object> {
        let span = self.span(node);
        let Some(index) = self
            .child_number(node, "Index")
            .and_then(|n| u16::try_from(n).ok())
        else {
            if child(node, "Index").is_none() {
                self.push(Diagnostic::new(
                    &rules::XML_MISSING_ATTRIBUTE,
                    Some(span),
                    "`Object` without `Index`: it is skipped",
                ));
            }
            return None;
        };
        let name = language_name(node, "Name").unwrap_or_default();
        let type_node = child(node, "Type");
        let type_name = type_node
            .and_then(element_text)
            .map(|t| (t, type_node.map_or(span, |n| self.text_span(n))));
        let flags = child(node, "Flags");
        let info = child(node, "Info");
        let bit_size = child(node, "BitSize")
            .and_then(element_text)
            .and_then(|t| parse_number(&t))
            .and_then(|n| u32::try_from(n).ok());
        let mut object = Object {
            index,
            name: name.clone(),
            object_type: ObjectType::Var,
            subs: Default::default(),
            sub_number: None,
            compact_sub_obj: None,
            obj_flags: 0,
            span,
            custom: Vec::new(),
            object_links: Vec::new(),
            implicit: false,
        };
        let resolved = type_name.as_ref().map(|(t, _)| self.resolve(t));
        if let Some(Resolved::Complex(def)) = resolved {
            self.read_complex(&mut object, def, flags, info);
            return Some(object);
        }
        let basic = match (&type_name, resolved) {
            (Some((_, _)), Some(Resolved::Basic(b, c))) => Some((b, c)),
            (Some((t, s)), _) => {
                let (t, s) = (t.clone(), *s);
                self.basic_of(&t, s)
            }
            (None, _) => {
                self.push(Diagnostic::new(
                    &rules::XML_MISSING_ATTRIBUTE,
                    Some(span),
                    format!("object {index:04X}h has no `Type`"),
                ));
                None
            }
        };
        if basic.is_some_and(|(b, _)| b == BasicType::Domain) {
            object.object_type = ObjectType::Domain;
        }
        let facts = EntryFacts {
            name,
            type_name,
            basic,
            bit_size,
            flags,
            fallback_flags: None,
            info,
            span,
        };
        let entry = self.entry(0, facts);
        object.subs.insert(0, entry);
        Some(object)
    }

    /// The sub-indices of an object whose type has `SubItem`s: each SubItem is one sub-index,
    /// or as many as its array type has elements (which makes the object an ARRAY).
    fn read_complex(
        &mut self,
        object: &mut Object,
        def: Node<'a, 'input>,
        flags: Option<Node<'a, 'input>>,
        info: Option<Node<'a, 'input>>,
    ) {
        object.object_type = ObjectType::Record;
        let info_subs: Vec<Node> = info
            .map(|i| children(i, "SubItem").collect())
            .unwrap_or_default();
        let info_for = |name: &str, position: usize, count: usize| {
            info_subs
                .iter()
                .find(|s| {
                    child(**s, "Name")
                        .and_then(element_text)
                        .is_some_and(|n| n == name)
                })
                .or_else(|| {
                    (info_subs.len() == count)
                        .then(|| info_subs.get(position))
                        .flatten()
                })
                .and_then(|s| child(*s, "Info"))
        };
        // The sub-indices, in order: (sub-index, name, type name and span, bit size, flags).
        let mut planned = Vec::new();
        let mut next: u32 = 0;
        for item in children(def, "SubItem") {
            let item_span = self.span(item);
            let item_name = child(item, "Name")
                .and_then(element_text)
                .unwrap_or_default();
            let type_node = child(item, "Type");
            let Some(type_name) = type_node.and_then(element_text) else {
                self.push(Diagnostic::new(
                    &rules::XML_MISSING_ATTRIBUTE,
                    Some(item_span),
                    format!(
                        "SubItem `{item_name}` of {:04X}h has no `Type`: it is skipped",
                        object.index
                    ),
                ));
                continue;
            };
            let type_span = type_node.map_or(item_span, |n| self.text_span(n));
            let item_flags = child(item, "Flags");
            let sub_idx = child(item, "SubIdx")
                .and_then(element_text)
                .and_then(|t| parse_number(&t))
                .and_then(|n| u32::try_from(n).ok());
            let bit_size = child(item, "BitSize")
                .and_then(element_text)
                .and_then(|t| parse_number(&t))
                .and_then(|n| u32::try_from(n).ok());
            if let Resolved::Elements {
                lbound,
                count,
                base,
            } = self.resolve(&type_name)
            {
                object.object_type = ObjectType::Array;
                let element_bits = bit_size.filter(|_| count > 0).map(|b| b / count.max(1));
                let first = sub_idx.unwrap_or(lbound);
                for k in 0..count {
                    let sub = first + k;
                    planned.push((
                        sub,
                        format!("SubIndex {sub:03}"),
                        (base.clone(), type_span),
                        element_bits,
                        item_flags,
                        item_span,
                    ));
                }
                next = first + count;
            } else {
                let sub = sub_idx.unwrap_or(next);
                planned.push((
                    sub,
                    item_name,
                    (type_name, type_span),
                    bit_size,
                    item_flags,
                    item_span,
                ));
                next = sub + 1;
            }
        }
        let count = planned.len();
        for (position, (sub, name, (type_name, type_span), bit_size, item_flags, item_span)) in
            planned.into_iter().enumerate()
        {
            let Ok(sub) = u8::try_from(sub) else {
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(item_span),
                    format!(
                        "{:04X}h has a sub-index {sub}, above 255: it is skipped",
                        object.index
                    ),
                ));
                continue;
            };
            let basic = self.basic_of(&type_name, type_span);
            let sub_info = info_for(&name, position, count);
            let facts = EntryFacts {
                name,
                type_name: Some((type_name, type_span)),
                basic,
                bit_size,
                flags: item_flags,
                fallback_flags: flags,
                info: sub_info,
                span: item_span,
            };
            let entry = self.entry(sub, facts);
            if object.subs.insert(sub, entry).is_some() {
                self.push(Diagnostic::new(
                    &rules::ESI_DUPLICATE_OBJECT,
                    Some(item_span),
                    format!("sub-index {sub} of {:04X}h is described twice; the last description is used", object.index),
                ));
            }
        }
        let described = u32::try_from(object.subs.len()).unwrap_or(u32::MAX);
        object.sub_number = Some(Spanned::new(described, self.span(def)));
    }

    fn entry(&mut self, sub_index: u8, facts: EntryFacts) -> SubObject {
        let flag = |name: &str| {
            facts
                .flags
                .and_then(|f| child(f, name))
                .or_else(|| facts.fallback_flags.and_then(|f| child(f, name)))
        };
        let access_node = flag("Access");
        let mapping_node = flag("PdoMapping");
        let mapping = mapping_node.and_then(element_text);
        let mut custom = Vec::new();
        if let Some((type_name, _)) = &facts.type_name {
            custom.push(("Type".to_owned(), type_name.clone()));
        }
        if let Some(bits) = facts.bit_size {
            custom.push(("BitSize".to_owned(), bits.to_string()));
        }
        if let Some(category) = flag("Category").and_then(element_text) {
            custom.push(("Category".to_owned(), category));
        }
        if let Some(restriction) = access_node.and_then(|a| attribute(a, "WriteRestrictions")) {
            custom.push((
                "WriteRestrictions".to_owned(),
                restriction.value().to_owned(),
            ));
        }
        let access = match access_node.and_then(element_text) {
            // Without Flags/Access an entry is read-only, as ETG.2000 defaults it.
            None => Some(AccessType::Ro),
            Some(text) => access_of(&text, mapping.as_deref()).or_else(|| {
                let span = access_node.map_or(facts.span, |n| self.text_span(n));
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`Access` is `{text}`, not ro, rw or wo"),
                ));
                None
            }),
        };
        let basic = facts.basic.map(|(b, _)| b);
        let value = |reader: &mut Self, data: &str, text: &str| {
            facts.info.and_then(|info| {
                if let Some(node) = child(info, data) {
                    let raw = element_text(node).unwrap_or_default();
                    let span = reader.text_span(node);
                    let bytes = parse_hex_bytes(&raw);
                    let value = match (bytes, basic) {
                        (Some(bytes), Some(basic)) => data_value(&bytes, basic),
                        _ => None,
                    };
                    if value.is_none() && basic.is_some() {
                        reader.push(Diagnostic::new(
                            &rules::BAD_VALUE,
                            Some(span),
                            format!(
                                "`{data}` is `{raw}`, not little-endian hex bytes of a {}",
                                basic.map_or("", BasicType::name)
                            ),
                        ));
                    }
                    return Some(ValueSource { value, raw, span });
                }
                let node = child(info, text)?;
                let raw = element_text(node).unwrap_or_default();
                let span = reader.text_span(node);
                let value = match basic {
                    Some(BasicType::VisibleString | BasicType::UnicodeString) => {
                        Some(Value::Text(raw.clone()))
                    }
                    Some(b) if b.is_integer() || b == BasicType::Boolean => {
                        parse_number(&raw).map(|v| Value::Integer(twos_complement(v, b)))
                    }
                    Some(b) if b.is_real() => raw.trim().parse().ok().map(Value::Real),
                    _ => None,
                };
                Some(ValueSource { value, raw, span })
            })
        };
        let default = value(self, "DefaultData", "DefaultValue").or_else(|| {
            let node = facts.info.and_then(|i| child(i, "DefaultString"))?;
            let raw = element_text(node).unwrap_or_default();
            Some(ValueSource {
                value: Some(Value::Text(raw.clone())),
                raw,
                span: self.text_span(node),
            })
        });
        let low_limit = value(self, "MinData", "MinValue");
        let high_limit = value(self, "MaxData", "MaxValue");
        SubObject {
            sub_index,
            name: facts.name,
            data_type: basic.map(BasicType::index),
            access,
            pdo_mapping: mapping.is_some_and(|m| !m.trim().is_empty()),
            default,
            parameter_value: None,
            low_limit,
            high_limit,
            obj_flags: 0,
            denotation: None,
            upload_file: None,
            download_file: None,
            span: facts.span,
            custom,
            implicit: false,
            key_spans: KeySpans {
                data_type: facts.type_name.as_ref().map(|(_, s)| *s),
                access: access_node.map(|n| self.text_span(n)),
                pdo_mapping: mapping_node.map(|n| self.text_span(n)),
                upload_file: None,
                download_file: None,
            },
            capacity: facts.basic.and_then(|(_, c)| c),
        }
    }
}

/// Whether two `DataType` elements say the same thing (their text, ignoring layout).
fn same_definition(a: Node, b: Node) -> bool {
    let words = |n: Node| -> Vec<String> {
        n.descendants()
            .filter(|d| d.is_text())
            .filter_map(|d| d.text())
            .map(|t| t.trim().to_owned())
            .filter(|t| !t.is_empty())
            .collect()
    };
    words(a) == words(b)
}

/// A device's type name, product code and revision, as far as they can be read (0 otherwise).
fn identity(device: Node) -> (String, u32, u32) {
    let ty = child(device, "Type");
    let number = |name: &str| {
        ty.and_then(|t| attribute(t, name))
            .and_then(|a| parse_number(a.value()))
            .and_then(|n| u32::try_from(n).ok())
            .unwrap_or(0)
    };
    (
        ty.and_then(element_text).unwrap_or_default(),
        number("ProductCode"),
        number("RevisionNo"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_hex_with_a_hash_x_or_decimal() {
        assert_eq!(parse_number("#x1A00"), Some(0x1A00));
        assert_eq!(parse_number(" 0x0F3F "), Some(0xF3F));
        assert_eq!(parse_number("560"), Some(560));
        assert_eq!(parse_number("-5"), Some(-5));
        assert_eq!(parse_number("#x"), None);
        assert_eq!(parse_number("1A"), None);
    }

    #[test]
    fn default_data_is_little_endian() {
        assert_eq!(
            data_value(&[0x6C, 0x02, 0, 0], BasicType::Unsigned32),
            Some(Value::Integer(0x26C))
        );
        assert_eq!(
            data_value(&[0xFF, 0xFF], BasicType::Integer16),
            Some(Value::Integer(-1))
        );
        assert_eq!(data_value(&[1, 2, 3], BasicType::Unsigned16), None);
        assert_eq!(twos_complement(0xFFFD, BasicType::Integer16), -3);
        assert_eq!(twos_complement(0xFFFD, BasicType::Unsigned16), 0xFFFD);
        assert_eq!(
            data_value(b"EL1004\0", BasicType::VisibleString),
            Some(Value::Text("EL1004".to_owned()))
        );
    }

    #[test]
    fn iec_names_map_to_cia301_types() {
        assert_eq!(elementary("UDINT"), Some((BasicType::Unsigned32, None)));
        assert_eq!(elementary("BIT2"), Some((BasicType::Unsigned8, None)));
        assert_eq!(
            elementary("STRING(13)"),
            Some((BasicType::VisibleString, Some(13)))
        );
        assert_eq!(
            elementary("ARRAY [0..11] OF BYTE"),
            Some((BasicType::OctetString, Some(12)))
        );
        assert_eq!(elementary("DT1018"), None);
    }

    #[test]
    fn latin1_is_honoured_where_declared() {
        assert!(declares_latin1(
            b"<?xml version=\"1.0\" encoding=\"iso8859-1\"?>"
        ));
        assert!(declares_latin1(
            b"<?xml version='1.0' encoding='ISO-8859-1'?>"
        ));
        assert!(!declares_latin1(
            b"<?xml version=\"1.0\" encoding=\"utf-8\"?>"
        ));
        let (text, encoding, diags) =
            decode(b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><a>\xB5s</a>");
        assert_eq!(encoding, TextEncoding::Latin1);
        assert!(text.ends_with("<a>\u{b5}s</a>"));
        assert!(diags.is_empty());
    }

    #[test]
    fn a_choice_is_a_product_code_or_a_name() {
        assert_eq!(
            DeviceChoice::parse("#x00009252"),
            DeviceChoice::ProductCode(0x9252)
        );
        assert_eq!(
            DeviceChoice::parse("EL1004"),
            DeviceChoice::TypeName("EL1004".to_owned())
        );
    }
}
