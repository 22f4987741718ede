//! XML plumbing the XDD/XDC and ESI readers share: parsing with bounded nesting, elements by
//! local name, element and attribute spans, texts, and the IEC 61131 type names.

use roxmltree::{Attribute, Document, Node};

use super::text::LineIndex;
use crate::diag::Diagnostic;
use crate::model::{BasicType, Span};
use crate::rules;

/// `EDS002` for an XML file that is not UTF-8 and was decoded as Windows-1252; `help` says how
/// to fix it.
pub(super) fn decoded_as_windows1252(help: &str) -> Diagnostic {
    Diagnostic::new(
        &rules::NON_ASCII,
        None,
        "the XML file is not valid UTF-8; it was decoded as Windows-1252",
    )
    .with_help(help)
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
pub(super) const MAX_DEPTH: usize = 256;

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

/// A document's text and its line index: the spans of its elements, attributes and texts.
pub(super) struct Spans<'input> {
    text: &'input str,
    lines: LineIndex,
}

impl<'input> Spans<'input> {
    pub(super) fn new(text: &'input str) -> Self {
        Spans {
            text,
            lines: LineIndex::new(text),
        }
    }

    /// The span of an element's start tag name (`<CANopenObject`).
    pub(super) fn element(&self, node: Node) -> Span {
        let start = node.range().start;
        let tag_len = self.text.get(start..).map_or(0, |rest| {
            rest.find(|c: char| c.is_whitespace() || c == '>' || c == '/')
                .unwrap_or(rest.len())
        });
        self.lines.span(self.text, start..start + tag_len)
    }

    /// The span of an attribute's value (inside the quotes).
    pub(super) fn attribute(&self, attr: &Attribute) -> Span {
        self.lines.span(self.text, attr.range_value())
    }

    /// The span of an element's text (trimmed), else of the element.
    pub(super) fn text(&self, node: Node) -> Span {
        let Some(range) = node.children().find(|c| c.is_text()).map(|t| t.range()) else {
            return self.element(node);
        };
        let raw = self.text.get(range.clone()).unwrap_or("");
        let start = range.start + (raw.len() - raw.trim_start().len());
        let text_span = self.lines.span(self.text, start..start + raw.trim().len());
        if raw.trim().is_empty() {
            self.element(node)
        } else {
            text_span
        }
    }
}

/// `EDS604` for an attribute or element `name` whose value `text` (at `span`) is no number.
pub(super) fn not_a_number(name: &str, text: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        &rules::XML_BAD_ATTRIBUTE,
        Some(span),
        format!("`{name}` is `{text}`, not a number"),
    )
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

/// The text of a multi-language element group: the one `is_english` picks, else the first one.
pub(super) fn english_text(
    node: Node,
    name: &str,
    is_english: impl Fn(Node) -> bool,
) -> Option<String> {
    let mut first = None;
    for item in children(node, name) {
        let text = element_text(item);
        if is_english(item) && text.is_some() {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_is_bounded_before_parsing() {
        let deep = format!("{}{}", "<a>".repeat(20_000), "</a>".repeat(20_000));
        assert_eq!(nesting_beyond(&deep, MAX_DEPTH), Some(3 * MAX_DEPTH));
        let read = crate::read::xdd::read(std::path::Path::new("deep.xdd"), deep.as_bytes());
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
