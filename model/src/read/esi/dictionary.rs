//! The CoE dictionary: `Profile/Dictionary` objects and `DataType`s into CiA 301 objects, with
//! the IEC 61131 type names mapped to CiA 301 data types.

use std::collections::BTreeMap;

use roxmltree::Node;

use super::values::{data_value, parse_hex_bytes, parse_number, twos_complement};
use super::{language_name, EsiReader};
use crate::diag::Diagnostic;
use crate::model::*;
use crate::read::xml::{attribute, child, children, element_text};
use crate::rules;

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
    if let Some((_, t)) = crate::read::xml::IEC_TYPES
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
    let length = high.checked_sub(low)?.checked_add(1)?;
    matches!(base.as_str(), "BYTE" | "USINT")
        .then(|| (BasicType::OctetString, usize::try_from(length).ok()))
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
/// An enum `DataType` without `BaseType` (only `BitSize` and `EnumInfo`, as some vendors write
/// them): BOOLEAN for one bit, else the smallest unsigned type of its `BitSize`.
fn enum_without_base<'a, 'input>(def: Node<'a, 'input>) -> Resolved<'a, 'input> {
    let bits = child(def, "BitSize")
        .and_then(element_text)
        .and_then(|t| parse_number(&t));
    match (child(def, "EnumInfo"), bits) {
        (Some(_), Some(1)) => Resolved::Basic(BasicType::Boolean, None),
        (Some(_), Some(2..=8)) => Resolved::Basic(BasicType::Unsigned8, None),
        (Some(_), Some(9..=16)) => Resolved::Basic(BasicType::Unsigned16, None),
        (Some(_), Some(17..=32)) => Resolved::Basic(BasicType::Unsigned32, None),
        _ => Resolved::Unknown,
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

impl<'a, 'input> EsiReader<'a, 'input> {
    /// Reads a `Dictionary` into `objects` (a device's, or a module's).
    pub(super) fn read_dictionary(
        &mut self,
        dictionary: Node<'a, 'input>,
        objects: &mut BTreeMap<u16, Object>,
    ) {
        if let Some(types) = child(dictionary, "DataTypes") {
            for ty in children(types, "DataType") {
                let Some(name) = child(ty, "Name").and_then(element_text) else {
                    continue;
                };
                if let Some(earlier) = self.data_types.insert(name.clone(), ty) {
                    // Vendors repeat elementary types verbatim; only a different one matters.
                    if !same_definition(earlier, ty) {
                        let span = self.spans.element(ty);
                        self.push(Diagnostic::new(
                            &rules::ESI_DUPLICATE_OBJECT,
                            Some(span),
                            format!("DataType `{name}` is defined twice, differently; the last definition is used"),
                        ));
                    }
                }
            }
        }
        let Some(list) = child(dictionary, "Objects") else {
            return;
        };
        for node in children(list, "Object") {
            let Some(object) = self.read_object(node) else {
                continue;
            };
            let (index, span) = (object.index, object.span);
            if objects.insert(index, object).is_some() {
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
                None => return enum_without_base(def),
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
        let span = self.spans.element(node);
        let index = self.required_index(node, span)?;
        let name = language_name(node, "Name").unwrap_or_default();
        let type_node = child(node, "Type");
        let type_name = type_node
            .and_then(element_text)
            .map(|t| (t, type_node.map_or(span, |n| self.spans.text(n))));
        let flags = child(node, "Flags");
        let info = child(node, "Info");
        let bit_size = child(node, "BitSize")
            .and_then(element_text)
            .and_then(|t| parse_number(&t))
            .and_then(|n| u32::try_from(n).ok());
        let mut object = Object::new(index, name.clone(), ObjectType::Var, span);
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
            let item_span = self.spans.element(item);
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
            let type_span = type_node.map_or(item_span, |n| self.spans.text(n));
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
                // Sub-indices end at 255: an array that would go past it is cut there.
                let last = first.saturating_add(count).min(256);
                if first.saturating_add(count) > 256 {
                    self.push(Diagnostic::new(
                        &rules::XML_BAD_ATTRIBUTE,
                        Some(item_span),
                        format!(
                            "{:04X}h: {count} elements from sub-index {first} go past sub-index 255; the rest is skipped",
                            object.index
                        ),
                    ));
                }
                for sub in first..last {
                    planned.push((
                        sub,
                        format!("SubIndex {sub:03}"),
                        (base.clone(), type_span),
                        element_bits,
                        item_flags,
                        item_span,
                    ));
                }
                next = last;
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
                next = sub.saturating_add(1);
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
        object.sub_number = Some(Spanned::new(described, self.spans.element(def)));
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
                let span = access_node.map_or(facts.span, |n| self.spans.text(n));
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
                    let span = reader.spans.text(node);
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
                let span = reader.spans.text(node);
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
                span: self.spans.text(node),
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
                access: access_node.map(|n| self.spans.text(n)),
                pdo_mapping: mapping_node.map(|n| self.spans.text(n)),
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
