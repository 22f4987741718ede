//! The GSDML items: device access points (slots, limits, useable modules, interface and port
//! submodules, subslot labels), modules, virtual submodules with their IO data (typed data items and their bits)
//! and parameter records (typed fields, constants, defaults, allowed values).

use roxmltree::Node;

use super::{parse_ranges, GsdmlReader};
use crate::diag::Diagnostic;
use crate::model::*;
use crate::read::esi::values::parse_number;
use crate::read::xml::{attribute, child, children};
use crate::rules;

impl GsdmlReader<'_, '_> {
    pub(super) fn read_access_point(&mut self, node: Node) -> AccessPoint {
        let id = attribute(node, "ID").map_or(String::new(), |a| a.value().to_owned());
        let info = child(node, "ModuleInfo");
        let name = info.and_then(|i| self.child_text(i, "Name"));
        let module_ident = self.attr_unsigned::<u32>(node, "ModuleIdentNumber");
        if attribute(node, "ModuleIdentNumber").is_none() {
            self.required(node, "ModuleIdentNumber");
        }
        let physical_slots = self.attr_slots(node, "PhysicalSlots");
        let fixed_in_slots = self.attr_slots(node, "FixedInSlots");
        let min_device_interval = self
            .attr_unsigned::<u32>(node, "MinDeviceInterval")
            .map(|n| n.value);
        let text = |name: &str| attribute(node, name).map(|a| a.value().to_owned());
        let io = child(node, "IOConfigData");
        let max_input_length = io.and_then(|io| self.attr_unsigned::<u32>(io, "MaxInputLength"));
        let max_output_length = io.and_then(|io| self.attr_unsigned::<u32>(io, "MaxOutputLength"));
        let mut useable_modules = Vec::new();
        for item in child(node, "UseableModules")
            .into_iter()
            .flat_map(|u| children(u, "ModuleItemRef"))
        {
            let Some(target) = self.required(item, "ModuleItemTarget") else {
                continue;
            };
            let fixed_in_slots = self.attr_slots(item, "FixedInSlots");
            let used_in_slots = self.attr_slots(item, "UsedInSlots");
            let mut allowed_in_slots = self.attr_slots(item, "AllowedInSlots");
            if attribute(item, "AllowedInSlots").is_none() {
                allowed_in_slots = fixed_in_slots
                    .iter()
                    .chain(&used_in_slots)
                    .copied()
                    .collect();
                allowed_in_slots.sort_unstable();
                allowed_in_slots.dedup();
            }
            useable_modules.push(ModuleRef {
                target,
                allowed_in_slots,
                fixed_in_slots,
                used_in_slots,
                span: self.spans.element(item),
            });
        }
        let submodules = self.read_virtual_submodules(node);
        let system = child(node, "SystemDefinedSubmoduleList");
        let interface = system
            .and_then(|s| child(s, "InterfaceSubmoduleItem"))
            .map(|i| self.read_system_submodule(i, 0x8000));
        let ports = system
            .into_iter()
            .flat_map(|s| children(s, "PortSubmoduleItem"))
            .enumerate()
            .map(|(n, p)| self.read_system_submodule(p, 0x8001 + n as u16))
            .collect();
        AccessPoint {
            id,
            name,
            module_ident,
            physical_slots,
            fixed_in_slots,
            min_device_interval,
            dns_compatible_name: text("DNS_CompatibleName"),
            pnio_version: text("PNIO_Version"),
            max_input_length,
            max_output_length,
            useable_modules,
            submodules,
            subslot_labels: self.read_subslot_labels(node),
            interface,
            ports,
            span: self.spans.element(node),
        }
    }

    pub(super) fn read_module(&mut self, node: Node) -> PnModule {
        let id = attribute(node, "ID").map_or(String::new(), |a| a.value().to_owned());
        if attribute(node, "ModuleIdentNumber").is_none() {
            self.required(node, "ModuleIdentNumber");
        }
        let module_ident = self.attr_unsigned::<u32>(node, "ModuleIdentNumber");
        let info = child(node, "ModuleInfo");
        let name = info.and_then(|i| self.child_text(i, "Name"));
        let info_text = info.and_then(|i| self.child_text(i, "InfoText"));
        let submodules = self.read_virtual_submodules(node);
        PnModule {
            id,
            module_ident,
            name,
            info_text,
            submodules,
            subslot_labels: self.read_subslot_labels(node),
            span: self.spans.element(node),
        }
    }

    /// The `SubslotList/SubslotItem`s of a module or access point; an item without a 16-bit
    /// `SubslotNumber` is left out with the attribute's error.
    fn read_subslot_labels(&mut self, node: Node) -> Vec<SubslotLabel> {
        let items: Vec<Node> = child(node, "SubslotList")
            .into_iter()
            .flat_map(|l| children(l, "SubslotItem"))
            .collect();
        let mut labels = Vec::new();
        for item in items {
            if attribute(item, "SubslotNumber").is_none() {
                self.required(item, "SubslotNumber");
            }
            if let Some(subslot) = self.attr_unsigned::<u16>(item, "SubslotNumber") {
                let text = self.text_of(item);
                labels.push(SubslotLabel { subslot, text });
            }
        }
        labels
    }

    /// The `VirtualSubmoduleList/VirtualSubmoduleItem`s of a module or access point.
    fn read_virtual_submodules(&mut self, node: Node) -> Vec<Submodule> {
        let items: Vec<Node> = child(node, "VirtualSubmoduleList")
            .into_iter()
            .flat_map(|l| children(l, "VirtualSubmoduleItem"))
            .collect();
        items
            .into_iter()
            .enumerate()
            .map(|(n, item)| self.read_submodule(item, n))
            .collect()
    }

    fn read_submodule(&mut self, node: Node, position: usize) -> Submodule {
        let id = attribute(node, "ID").map_or(String::new(), |a| a.value().to_owned());
        if attribute(node, "SubmoduleIdentNumber").is_none() {
            self.required(node, "SubmoduleIdentNumber");
        }
        let submodule_ident = self.attr_unsigned::<u32>(node, "SubmoduleIdentNumber");
        let subslot = self
            .attr_slots(node, "FixedInSubslots")
            .first()
            .copied()
            .unwrap_or(position as u16 + 1);
        let name = child(node, "ModuleInfo").and_then(|i| self.child_text(i, "Name"));
        let io = child(node, "IOData");
        let inputs = io
            .and_then(|io| child(io, "Input"))
            .map(|i| self.read_data_items(i))
            .unwrap_or_default();
        let outputs = io
            .and_then(|io| child(io, "Output"))
            .map(|o| self.read_data_items(o))
            .unwrap_or_default();
        let mut records = Vec::new();
        for record in child(node, "RecordDataList")
            .into_iter()
            .flat_map(|l| children(l, "ParameterRecordDataItem"))
        {
            if let Some(record) = self.read_record(record) {
                records.push(record);
            }
        }
        Submodule {
            id,
            submodule_ident,
            subslot,
            name,
            inputs,
            outputs,
            records,
            pkw_pzd: false,
            span: self.spans.element(node),
        }
    }

    fn read_data_items(&mut self, node: Node) -> Vec<DataItem> {
        let mut out = Vec::new();
        for item in children(node, "DataItem") {
            let Some(data_type) = self.required(item, "DataType") else {
                continue;
            };
            let kind = PnDataType::from_name(&data_type.value);
            let length = self.attr_unsigned::<u32>(item, "Length").map(|n| n.value);
            let name = self.text_of(item);
            let use_as_bits = attribute(item, "UseAsBits").is_some_and(|a| a.value() == "true");
            let mut bits = Vec::new();
            for bit in children(item, "BitDataItem") {
                let Some(offset) = self.attr_unsigned::<u32>(bit, "BitOffset") else {
                    self.required(bit, "BitOffset");
                    continue;
                };
                let name = self.text_of(bit);
                bits.push(BitDataItem {
                    bit_offset: offset.value,
                    name,
                    span: self.spans.element(bit),
                });
            }
            out.push(DataItem {
                data_type,
                kind,
                length,
                name,
                use_as_bits,
                bits,
                span: self.spans.element(item),
            });
        }
        out
    }

    /// A `ParameterRecordDataItem`; `None` (with an error) without a readable `Index` or `Length`.
    fn read_record(&mut self, node: Node) -> Option<ParameterRecord> {
        if attribute(node, "Index").is_none() {
            self.required(node, "Index");
        }
        if attribute(node, "Length").is_none() {
            self.required(node, "Length");
        }
        let index = self.attr_unsigned::<u16>(node, "Index");
        let length = self.attr_unsigned::<u32>(node, "Length");
        let (index, length) = (index?, length?);
        let transfer_sequence = self
            .attr_unsigned::<u32>(node, "TransferSequence")
            .map(|n| n.value);
        let name = self.child_text(node, "Name");
        let mut consts = Vec::new();
        for c in children(node, "Const") {
            let offset = self
                .attr_unsigned::<u32>(c, "ByteOffset")
                .map_or(0, |n| n.value);
            let Some(data) = attribute(c, "Data") else {
                continue;
            };
            match const_bytes(data.value()) {
                Some(bytes) => consts.push((offset, bytes)),
                None => {
                    let span = self.spans.attribute(&data);
                    self.push(Diagnostic::new(
                        &rules::XML_BAD_ATTRIBUTE,
                        Some(span),
                        format!(
                            "`Data` is `{}`, not a list of bytes (`0x01,0x02`)",
                            data.value()
                        ),
                    ));
                }
            }
        }
        let mut fields = Vec::new();
        for r in children(node, "Ref") {
            if let Some(field) = self.read_field(r) {
                fields.push(field);
            }
        }
        Some(ParameterRecord {
            index,
            length,
            transfer_sequence,
            name,
            consts,
            fields,
            span: self.spans.element(node),
        })
    }

    fn read_field(&mut self, node: Node) -> Option<RecordField> {
        let data_type = self.required(node, "DataType")?;
        if attribute(node, "ByteOffset").is_none() {
            self.required(node, "ByteOffset");
        }
        let byte_offset = self.attr_unsigned::<u32>(node, "ByteOffset")?.value;
        let bit_offset = self
            .attr_unsigned::<u32>(node, "BitOffset")
            .map(|n| n.value);
        let bit_length = self
            .attr_unsigned::<u32>(node, "BitLength")
            .map(|n| n.value);
        let length = self.attr_unsigned::<u32>(node, "Length").map(|n| n.value);
        let default = attribute(node, "DefaultValue")
            .map(|a| Spanned::new(a.value().to_owned(), self.spans.attribute(&a)));
        let allowed_values = match attribute(node, "AllowedValues") {
            None => Vec::new(),
            Some(a) => parse_ranges(a.value()).unwrap_or_else(|| {
                let span = self.spans.attribute(&a);
                self.push(not_a_range(a.value(), span));
                Vec::new()
            }),
        };
        let value_item = attribute(node, "ValueItemTarget")
            .map(|a| Spanned::new(a.value().to_owned(), self.spans.attribute(&a)));
        let flag = |name: &str| attribute(node, name).is_none_or(|a| a.value() != "false");
        let name = self.text_of(node);
        Some(RecordField {
            kind: PnDataType::from_name(&data_type.value),
            data_type,
            byte_offset,
            bit_offset,
            bit_length,
            length,
            default,
            allowed_values,
            value_item,
            changeable: flag("Changeable"),
            visible: flag("Visible"),
            name,
            span: self.spans.element(node),
        })
    }

    fn read_system_submodule(&mut self, node: Node, default_subslot: u16) -> SystemSubmodule {
        let id = attribute(node, "ID").map_or(String::new(), |a| a.value().to_owned());
        let submodule_ident = self.attr_unsigned::<u32>(node, "SubmoduleIdentNumber");
        let subslot = self
            .attr_unsigned::<u16>(node, "SubslotNumber")
            .map_or(default_subslot, |n| n.value);
        let name = self.text_of(node);
        let timing = child(node, "ApplicationRelations").and_then(|a| child(a, "TimingProperties"));
        let list = |name: &str| -> Vec<u32> {
            timing
                .and_then(|t| attribute(t, name))
                .and_then(|a| parse_ranges(a.value()))
                .map(|r| {
                    r.iter()
                        .filter_map(|(lo, hi)| (lo == hi).then(|| u32::try_from(*lo).ok())?)
                        .collect()
                })
                .unwrap_or_default()
        };
        SystemSubmodule {
            id,
            submodule_ident,
            subslot,
            name,
            rt_classes: attribute(node, "SupportedRT_Classes").map(|a| a.value().to_owned()),
            send_clock: list("SendClock"),
            reduction_ratio: list("ReductionRatio"),
            span: self.spans.element(node),
        }
    }
}

/// A `Const/@Data` value: bytes written as `0x01,0x02` (commas and/or spaces).
fn const_bytes(text: &str) -> Option<Vec<u8>> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|p| !p.is_empty())
        .map(|p| parse_number(p).and_then(|n| u8::try_from(n).ok()))
        .collect()
}

fn not_a_range(text: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        &rules::XML_BAD_ATTRIBUTE,
        Some(span),
        format!("`AllowedValues` is `{text}`, not a list of numbers and ranges (`1..4 7`)"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn const_data_is_comma_separated_bytes() {
        assert_eq!(const_bytes("0x01,0x02, 0xFF"), Some(vec![1, 2, 255]));
        assert_eq!(const_bytes("0x100"), None);
        assert_eq!(const_bytes(""), Some(vec![]));
    }
}
