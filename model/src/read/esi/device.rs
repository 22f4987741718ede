//! The device around its dictionary: vendor, identity, SyncManagers, PDOs and their alternative
//! assignments, the CoE mailbox with its init commands, the DC op-modes, slots and modules, into
//! [`DeviceInfo`] and [`EtherCat`].

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
                self.read_dictionary(dictionary, &mut device.objects);
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
            self.read_slots(slots, ec);
        }
        for mapping in node
            .descendants()
            .filter(|n| is_element(*n, "AlternativeSmMapping"))
        {
            let alternative = self.read_alternative(mapping);
            ec.alternative_mappings.push(alternative);
        }
    }

    /// The `Slots/Slot` elements, each with the increments it inherits from `Slots`.
    fn read_slots(&mut self, slots: Node, ec: &mut EtherCat) {
        let index_increment = self.attr_or(slots, "SlotIndexIncrement", 0u16);
        let pdo_increment = self.attr_or(slots, "SlotPdoIncrement", 0u16);
        for slot in children(slots, "Slot") {
            let index_increment = self.attr_or(slot, "SlotIndexIncrement", index_increment);
            let pdo_increment = self.attr_or(slot, "SlotPdoIncrement", pdo_increment);
            let min_instances = self.attr_or(slot, "MinInstances", 1u32);
            let max_instances = self.attr_or(slot, "MaxInstances", 1u32);
            let mut module_idents = Vec::new();
            let mut default_module = None;
            for ident in children(slot, "ModuleIdent") {
                let Some(value) = self
                    .element_number(ident)
                    .and_then(|n| u32::try_from(n).ok())
                else {
                    continue;
                };
                module_idents.push(value);
                if self.attr_bool(ident, "Default") {
                    default_module.get_or_insert(value);
                }
            }
            ec.slots.push(EcSlot {
                name: language_name(slot, "Name").unwrap_or_default(),
                min_instances,
                max_instances,
                module_idents,
                module_classes: children(slot, "ModuleClass")
                    .filter_map(|c| child(c, "Class").and_then(element_text))
                    .collect(),
                default_module,
                index_increment,
                pdo_increment,
                span: self.spans.element(slot),
            });
        }
    }

    /// A numeric attribute that fits `T`; `fallback` when absent or out of range (an `EDS604`
    /// error when it is no number).
    fn attr_or<T: TryFrom<i128>>(&mut self, node: Node, name: &str, fallback: T) -> T {
        self.attr_number(node, name)
            .and_then(|n| T::try_from(n).ok())
            .unwrap_or(fallback)
    }

    /// One `Modules/Module`: identity, PDOs, and its own dictionary, read with the device's
    /// `DataType`s except those the module redefines.
    pub(super) fn read_module(&mut self, node: Node<'a, 'input>) -> EcModule {
        let ty = child(node, "Type");
        let mut module = EcModule {
            ident: ty
                .and_then(|t| self.attr_number(t, "ModuleIdent"))
                .and_then(|n| u32::try_from(n).ok())
                .unwrap_or(0),
            type_name: ty.and_then(element_text).unwrap_or_default(),
            class: ty
                .and_then(|t| attribute(t, "ModuleClass"))
                .map(|a| a.value().trim().to_owned()),
            name: language_name(node, "Name").unwrap_or_default(),
            rx_pdos: Vec::new(),
            tx_pdos: Vec::new(),
            objects: Default::default(),
            slot_indices: SlotIndices::default(),
            span: self.spans.element(node),
        };
        for pdo in node.children().filter(|n| n.is_element()) {
            match local(pdo) {
                "RxPdo" => module.rx_pdos.extend(self.read_pdo(pdo)),
                "TxPdo" => module.tx_pdos.extend(self.read_pdo(pdo)),
                _ => {}
            }
        }
        for dictionary in children(node, "Profile").filter_map(|p| child(p, "Dictionary")) {
            let device_types = self.data_types.clone();
            let own = child(dictionary, "DataTypes")
                .into_iter()
                .flat_map(|t| children(t, "DataType"))
                .filter_map(|t| child(t, "Name").and_then(element_text));
            for name in own {
                self.data_types.remove(&name);
            }
            self.read_dictionary(dictionary, &mut module.objects);
            self.data_types = device_types;
            let objects = children(dictionary, "Objects").flat_map(|o| children(o, "Object"));
            for index in objects.filter_map(|o| child(o, "Index")) {
                if let Some(n) = self.slot_dependent(index) {
                    module.slot_indices.objects.insert(n);
                }
            }
        }
        let pdos = node
            .children()
            .filter(|n| is_element(*n, "RxPdo") || is_element(*n, "TxPdo"));
        for pdo in pdos {
            if let Some(n) = child(pdo, "Index").and_then(|i| self.slot_dependent(i)) {
                module.slot_indices.pdos.insert(n);
            }
            for index in children(pdo, "Entry").filter_map(|e| child(e, "Index")) {
                if let Some(n) = self.slot_dependent(index) {
                    module.slot_indices.entries.insert(n);
                }
            }
        }
        module
    }

    /// The index an `Index` element gives, if it says `DependOnSlot`.
    fn slot_dependent(&mut self, index: Node) -> Option<u16> {
        if !self.attr_bool(index, "DependOnSlot") {
            return None;
        }
        // Read quietly: a bad number was already reported where the index was read.
        let text = element_text(index).unwrap_or_default();
        parse_number(&text).and_then(|n| u16::try_from(n).ok())
    }

    /// One `AlternativeSmMapping`: its name, default flag and per-SM PDO indices.
    fn read_alternative(&mut self, node: Node) -> AlternativeSmMapping {
        let mut sms = Vec::new();
        for sm in children(node, "Sm") {
            let number = self
                .attr_number(sm, "No")
                .and_then(|n| u8::try_from(n).ok())
                .unwrap_or(0);
            let mut pdos = Vec::new();
            for pdo in children(sm, "Pdo") {
                let span = self.spans.text(pdo);
                if let Some(index) = self.element_number(pdo).and_then(|n| u16::try_from(n).ok()) {
                    pdos.push(Spanned::new(index, span));
                }
            }
            sms.push((number, pdos));
        }
        AlternativeSmMapping {
            name: language_name(node, "Name").unwrap_or_default(),
            default: self.attr_bool(node, "Default"),
            sms,
            span: self.spans.element(node),
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
