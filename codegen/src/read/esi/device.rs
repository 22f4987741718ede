//! The device around its dictionary: vendor, identity, SyncManagers, PDOs, the CoE mailbox
//! with its init commands, and the DC op-modes, into [`DeviceInfo`] and [`EtherCat`].

use roxmltree::Node;

use super::values::{parse_hex_bytes, parse_number};
use super::{language_name, EsiReader};
use crate::diag::{Diagnostic, Severity};
use crate::model::*;
use crate::read::xml::{attribute, child, children, element_text, is_element, local};
use crate::rules;

impl<'a, 'input> EsiReader<'a, 'input> {
    pub(super) fn read_vendor(&mut self, vendor: Node, device: &mut Device) {
        device.device_info.vendor_name = language_name(vendor, "Name");
        if let Some(id) = child(vendor, "Id") {
            let span = self.spans.text(id);
            let number = self.child_number(vendor, "Id");
            device.device_info.vendor_number = number
                .and_then(|n| u32::try_from(n).ok())
                .map(|n| Spanned::new(n, span));
        }
    }

    pub(super) fn read_device(
        &mut self,
        node: Node<'a, 'input>,
        device: &mut Device,
        ec: &mut EtherCat,
    ) {
        ec.span = self.spans.element(node);
        device.device_info.span = Some(ec.span);
        if let Some(ty) = child(node, "Type") {
            ec.type_name = element_text(ty).unwrap_or_default();
            for (name, slot) in [
                ("ProductCode", &mut device.device_info.product_number),
                ("RevisionNo", &mut device.device_info.revision_number),
            ] {
                if let Some(attr) = attribute(ty, name) {
                    let span = self.spans.attribute(&attr);
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
                let value = self.element_number(number);
                if let Some(n) = value.and_then(|n| u32::try_from(n).ok()) {
                    if !ec.profiles.contains(&n) {
                        ec.profiles.push(n);
                    }
                }
            }
            if let Some(file) = child(profile, "DictionaryFile") {
                let span = self.spans.element(file);
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
            let span = self.spans.element(slots);
            let entries = children(slots, "Slot")
                .map(|slot| RawEntry {
                    key: "Slot".to_owned(),
                    value: language_name(slot, "Name").unwrap_or_default(),
                    span: self.spans.element(slot),
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
            span: self.spans.element(sm),
        }
    }

    fn read_pdo(&mut self, node: Node) -> Option<EcPdo> {
        let span = self.spans.element(node);
        let index = self.required_index(node, span)?;
        let sm = self
            .attr_number(node, "Sm")
            .and_then(|n| u8::try_from(n).ok());
        let mut exclude = Vec::new();
        for item in children(node, "Exclude") {
            let span = self.spans.text(item);
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
            let span = self.spans.element(entry);
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
            let span = self.spans.element(cmd);
            let data = match child(cmd, "Data") {
                Some(data) => {
                    let text = element_text(data).unwrap_or_default();
                    parse_hex_bytes(&text).unwrap_or_else(|| {
                        let span = self.spans.text(data);
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
}
