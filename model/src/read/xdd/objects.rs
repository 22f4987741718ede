//! `CANopenObjectList`: each `CANopenObject` and `CANopenSubObject` into an [`Object`] and its
//! entries, with the index, sub-index, object type and flags checked.

use roxmltree::Node;

use super::parameters::{EntryAttributes, ParameterFacts};
use super::{parse_hex_binary, XmlReader};
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::read::value::parse_integer;
use crate::read::xml::{attribute, children, local};
use crate::rules;

impl<'a, 'input> XmlReader<'a, 'input> {
    pub(super) fn read_object_list(&mut self, list: Node<'a, 'input>, device: &mut Device) {
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
                let span = self.spans.element(node);
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
        let span = self.spans.element(node);
        let Some(attr) = attribute(node, name) else {
            self.push(Diagnostic::new(
                &rules::XML_MISSING_ATTRIBUTE,
                Some(span),
                format!("`{}` without `{name}`: it is skipped", local(node)),
            ));
            return None;
        };
        let value_span = self.spans.attribute(&attr);
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
        let span = self.spans.element(node);
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
        let span = self.spans.element(node);
        let attrs = Self::entry_attributes(node);
        let parameter = self.parameter_facts(node);
        let name = self.name_of(node, &parameter);
        let sub_elements: Vec<Node> = children(node, "CANopenSubObject").collect();
        let object_type = self.object_type(node, !sub_elements.is_empty());
        let obj_flags = self.obj_flags(&attrs);
        let sub_number = self.optional_number(node, "subNumber");

        let mut object = Object {
            sub_number,
            obj_flags,
            ..Object::new(index, name.clone(), object_type, span)
        };
        let single_entry = !object_type.has_subs() && object_type != ObjectType::Null;
        if single_entry {
            if let Some(first) = sub_elements.first() {
                let sub_span = self.spans.element(*first);
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
                let sub_span = self.spans.element(sub_node);
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
        let span = self.spans.element(node);
        let Some(attr) = attribute(node, "objectType") else {
            self.push(Diagnostic::new(
                &rules::XML_MISSING_ATTRIBUTE,
                Some(span),
                format!("`{}` without `objectType`; read as {guess:?}", local(node)),
            ));
            return guess;
        };
        let value_span = self.spans.attribute(&attr);
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

    pub(super) fn obj_flags(&mut self, attrs: &EntryAttributes) -> u32 {
        let Some(attr) = &attrs.obj_flags else {
            return 0;
        };
        match parse_hex_binary(attr.value()) {
            Some(v) => v,
            None => {
                let span = self.spans.attribute(attr);
                self.push(Diagnostic::new(
                    &rules::XML_BAD_ATTRIBUTE,
                    Some(span),
                    format!("`objFlags` is `{}`, not hexBinary; 0 is used", attr.value()),
                ));
                0
            }
        }
    }
}
