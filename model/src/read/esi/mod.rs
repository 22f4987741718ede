//! ESI reader (ETG.2000): an `EtherCATInfo` file into the shared [`Device`] model.
//!
//! The CoE dictionary (`Profile/Dictionary`) becomes [`Device::objects`], exactly as a CANopen
//! object dictionary: IEC 61131 type names map to CiA 301 data types, a `DTxxxx` type with
//! `SubItem`s makes an ARRAY or RECORD, `DefaultData` (little-endian hex) becomes a typed value.
//! Identity goes to [`DeviceInfo`]; SyncManagers, PDOs, alternative PDO assignments, the CoE
//! mailbox, the DC op-modes, the device's slots and the file's modules to [`EtherCat`]. A file may describe several devices: one is read (the first, or the one a
//! [`DeviceChoice`] names) and the others are listed in [`EtherCat::other_devices`].

use std::collections::HashMap;
use std::path::Path;

use roxmltree::Node;

use super::xml::{
    attribute, child, decoded_as_windows1252, element_text, english_text, is_element, local,
    not_a_number, Spans,
};
use super::Read;
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::rules;
use values::{hex_digits, parse_bool, parse_number};

mod device;
mod dictionary;
pub mod values;

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
    if let Some(doc) = super::xml::parse(&text, &mut diagnostics) {
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
    let Some(doc) = super::xml::parse(&text, &mut scratch) else {
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
pub(super) fn decode(bytes: &[u8]) -> (String, TextEncoding, Vec<Diagnostic>) {
    let mut diagnostics = Vec::new();
    if declares_latin1(bytes) && !bytes.is_ascii() && super::text::utf16(bytes).is_none() {
        let text = bytes.iter().map(|&b| char::from(b)).collect();
        return (text, TextEncoding::Latin1, diagnostics);
    }
    let (text, encoding) = super::text::decode(bytes);
    if encoding == TextEncoding::Windows1252 {
        diagnostics.push(decoded_as_windows1252(
            "save the file as UTF-8, or declare encoding=\"ISO-8859-1\"",
        ));
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

/// The `Descriptions/Devices/Device` elements.
fn devices<'a, 'input>(root: Node<'a, 'input>) -> impl Iterator<Item = Node<'a, 'input>> {
    child(root, "Descriptions")
        .and_then(|d| child(d, "Devices"))
        .into_iter()
        .flat_map(|d| d.children().filter(|c| is_element(*c, "Device")))
}

/// The text of a `Name` group: the English one (`LcId="1033"`), else the first.
fn language_name(node: Node, name: &str) -> Option<String> {
    english_text(node, name, |item| {
        attribute(item, "LcId").is_some_and(|a| a.value().trim() == "1033")
    })
}

/// The reader's state: the text and line index for spans, the diagnostics, and the `DataType`
/// definitions by name.
struct EsiReader<'a, 'input> {
    spans: Spans<'input>,
    diags: &'a mut Vec<Diagnostic>,
    data_types: HashMap<String, Node<'a, 'input>>,
}

impl<'a, 'input> EsiReader<'a, 'input> {
    fn new(text: &'input str, diags: &'a mut Vec<Diagnostic>) -> Self {
        EsiReader {
            spans: Spans::new(text),
            diags,
            data_types: HashMap::new(),
        }
    }

    fn push(&mut self, diag: Diagnostic) {
        self.diags.push(diag);
    }

    /// A child element's text as a number, with an `EDS604` error when it is not one.
    fn child_number(&mut self, node: Node, name: &str) -> Option<i128> {
        self.element_number(child(node, name)?)
    }

    /// The `Index` child of a PDO or an `Object` (at `span`): an `EDS604` error when it is no
    /// 16-bit number, an `EDS603` error when it is missing (the element is then skipped).
    fn required_index(&mut self, node: Node, span: Span) -> Option<u16> {
        let index = self
            .child_number(node, "Index")
            .and_then(|n| u16::try_from(n).ok());
        if index.is_none() && child(node, "Index").is_none() {
            self.push(Diagnostic::new(
                &rules::XML_MISSING_ATTRIBUTE,
                Some(span),
                format!("`{}` without `Index`: it is skipped", local(node)),
            ));
        }
        index
    }

    /// An element's text as a number, with an `EDS604` error when it is not one.
    fn element_number(&mut self, item: Node) -> Option<i128> {
        let text = element_text(item).unwrap_or_default();
        let number = parse_number(&text);
        if number.is_none() {
            let span = self.spans.text(item);
            self.push(not_a_number(local(item), &text, span));
        }
        number
    }

    /// An attribute as a number, with an `EDS604` error when it is not one.
    fn attr_number(&mut self, node: Node, name: &str) -> Option<i128> {
        let attr = attribute(node, name)?;
        let number = parse_number(attr.value());
        if number.is_none() {
            let span = self.spans.attribute(&attr);
            self.push(not_a_number(name, attr.value(), span));
        }
        number
    }

    /// An attribute as a boolean (absent: `false`), with an `EDS604` warning when unreadable.
    fn attr_bool(&mut self, node: Node, name: &str) -> bool {
        let Some(attr) = attribute(node, name) else {
            return false;
        };
        parse_bool(attr.value()).unwrap_or_else(|| {
            let span = self.spans.attribute(&attr);
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
        let root_span = self.spans.element(root);
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
        let modules: Vec<Node> = root
            .descendants()
            .filter(|n| is_element(*n, "Module"))
            .filter(|n| n.parent_element().is_some_and(|p| is_element(p, "Modules")))
            .collect();
        let all: Vec<Node> = devices(root).collect();
        let idents: Vec<(String, u32, u32)> = all.iter().map(|d| identity(*d)).collect();
        if all.is_empty() {
            self.push(Diagnostic::new(
                &rules::ESI_NO_DEVICE,
                Some(root_span),
                "the file describes no Device (`Descriptions/Devices/Device`)",
            ));
            if !modules.is_empty() {
                self.push(Diagnostic::new(
                    &rules::ESI_MODULES,
                    Some(root_span),
                    format!(
                        "the file describes {} module(s) and no device to plug them into; they are not read",
                        modules.len()
                    ),
                ));
            }
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
                        "no device of the file {}; it has {}",
                        match choice {
                            Some(DeviceChoice::ProductCode(c)) => {
                                format!("has product code #x{c:08X}")
                            }
                            Some(DeviceChoice::TypeName(n)) => format!("is named `{n}`"),
                            _ => "is at that position".to_owned(),
                        },
                        crate::diag::short_list(&names)
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
        for module in modules {
            let module = self.read_module(module);
            ethercat.modules.push(module);
        }
        if !ethercat.modules.is_empty() || !ethercat.slots.is_empty() {
            let span = ethercat.slots.first().map_or(root_span, |s| s.span);
            self.push(Diagnostic::new(
                &rules::ESI_MODULES,
                Some(span),
                format!(
                    "the device has {} slot(s) and the file {} module(s): a module's PDOs join the process image when the overlay's [modules] plugs it",
                    ethercat.slots.len(),
                    ethercat.modules.len()
                ),
            ));
        }
        device.bus = Bus::EtherCat(ethercat);
    }
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
