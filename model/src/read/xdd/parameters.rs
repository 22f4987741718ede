//! Parameters: what the `parameter` an entry's `uniqueIDRef` names says (access, type, values,
//! limits, denotation), and one OD entry built from it and the element's own attributes.

use roxmltree::{Attribute, Node};

use super::{parse_hex_binary, XmlReader};
use crate::diag::Diagnostic;
use crate::model::*;
use crate::read::value::parse_value;
use crate::read::xml::{attribute, child, children, english_text, local, IEC_TYPES};
use crate::rules;

/// The attributes CiA 311 gives both `CANopenObject` and `CANopenSubObject`, as written.
#[derive(Default)]
pub(super) struct EntryAttributes<'a, 'input> {
    pub(super) data_type: Option<Attribute<'a, 'input>>,
    pub(super) low_limit: Option<Attribute<'a, 'input>>,
    pub(super) high_limit: Option<Attribute<'a, 'input>>,
    pub(super) access_type: Option<Attribute<'a, 'input>>,
    pub(super) default_value: Option<Attribute<'a, 'input>>,
    pub(super) actual_value: Option<Attribute<'a, 'input>>,
    pub(super) denotation: Option<Attribute<'a, 'input>>,
    pub(super) pdo_mapping: Option<Attribute<'a, 'input>>,
    pub(super) obj_flags: Option<Attribute<'a, 'input>>,
}

/// A value text and where it is: an attribute's value.
pub(super) struct RawValue {
    pub(super) text: String,
    pub(super) span: Span,
}

/// What a `parameter` says about an entry.
#[derive(Default)]
pub(super) struct ParameterFacts {
    /// Whether a parameter was found at all.
    pub(super) resolved: bool,
    /// The parameter's `access`, if written.
    pub(super) access: Option<AccessType>,
    /// Where the `access` value is written.
    pub(super) access_span: Option<Span>,
    /// The data type from an IEC element, `derived`/`enum` base type, or `None`.
    pub(super) data_type: Option<u16>,
    /// Where the type element (or `dataTypeIDRef`) is.
    pub(super) data_type_span: Option<Span>,
    /// The parameter names `BITSTRING`: OCTET_STRING or DOMAIN, decided with the default value.
    pub(super) bitstring: bool,
    pub(super) default: Option<RawValue>,
    pub(super) actual: Option<RawValue>,
    pub(super) low: Option<RawValue>,
    pub(super) high: Option<RawValue>,
    pub(super) denotation: Option<String>,
    pub(super) label: Option<String>,
    pub(super) custom: Vec<(String, String)>,
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

/// The text of a CiA 311 multi-language group (`label`, `description`): `lang="en"`, else the
/// first one.
fn language_text(node: Node, name: &str) -> Option<String> {
    english_text(node, name, |item| {
        attribute(item, "lang").is_some_and(|a| a.value().eq_ignore_ascii_case("en"))
    })
}

impl<'a, 'input> XmlReader<'a, 'input> {
    fn raw_value(&self, attr: &Attribute) -> RawValue {
        RawValue {
            text: attr.value().trim().to_owned(),
            span: self.spans.attribute(attr),
        }
    }

    /// The facts of the parameter an element's `uniqueIDRef` names (empty if none).
    pub(super) fn parameter_facts(&mut self, node: Node) -> ParameterFacts {
        let Some(reference) = attribute(node, "uniqueIDRef") else {
            return ParameterFacts::default();
        };
        let Some(parameter) = self.parameters.get(reference.value()).copied() else {
            let span = self.spans.attribute(&reference);
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
            facts.access_span = Some(self.spans.attribute(&access));
            if facts.access.is_none() {
                let span = self.spans.attribute(&access);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!(
                        "parameter access `{}` has no CANopen access type; the entry's access is unknown",
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
                facts.data_type_span = Some(self.spans.element(item));
            } else if let Some((_, basic)) = IEC_TYPES.iter().find(|(n, _)| *n == name) {
                facts.data_type = Some(basic.index());
                facts.data_type_span = Some(self.spans.element(item));
            }
            match name {
                "dataTypeIDRef" => {
                    facts.data_type = self.referenced_type(item);
                    facts.data_type_span = Some(self.spans.element(item));
                }
                "variableRef" => {
                    let span = self.spans.element(item);
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
            let span = self.spans.attribute(&reference);
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
    pub(super) fn build_entry(
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
                let span = self.spans.attribute(a);
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
        let attribute_type_span = attrs.data_type.as_ref().map(|a| self.spans.attribute(a));
        let mut key_spans = KeySpans {
            data_type: match parameter.data_type {
                Some(_) => parameter.data_type_span,
                None => attribute_type_span.or(parameter.data_type_span),
            },
            access: parameter
                .access_span
                .or_else(|| attrs.access_type.as_ref().map(|a| self.spans.attribute(a))),
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

        key_spans.pdo_mapping = attrs.pdo_mapping.as_ref().map(|a| self.spans.attribute(a));
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
                    let span = self.spans.attribute(&attr);
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
                let span = self.spans.attribute(a);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`accessType` is `{}`, not ro, wo, rw or const", a.value()),
                ));
            }
            parsed
        });
        // The parameter's access wins; CiA 311 defaults it to `read`, which applies only when the
        // element does not say either. A parameter access with no CANopen access type
        // (`noAccess`, reported above) leaves the access unknown: no later diagnostic may quote
        // an access the file does not state.
        let unreadable_parameter_access =
            parameter.access.is_none() && parameter.access_span.is_some();
        let mut access = if unreadable_parameter_access {
            None
        } else {
            parameter
                .access
                .or(attribute_access)
                .or(parameter.resolved.then_some(AccessType::Ro))
        };
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
}
