//! An ESI device's chosen configuration: module instances in its `Slots/Slot`s, checked against
//! each slot's `ModuleIdent` / `ModuleClass` lists and `MinInstances` / `MaxInstances`, and the
//! device as configured ([`EtherCat::configured`], [`Device::configured`]): the modules' PDOs
//! and objects added to its own, the indices written with `DependOnSlot` moved per slot
//! instance by `SlotPdoIncrement` (PDOs) or `SlotIndexIncrement` (entries, objects), as
//! ETG.2000's module slots say.

use std::collections::BTreeSet;

use super::{find_named, ModuleChoice};
use crate::model::{Device, EcModule, EcSlot, EtherCat, SmKind};

/// A module instance in a slot of an EtherCAT device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EcPlugged {
    /// The slot: its index in [`EtherCat::slots`].
    pub slot: usize,
    /// The module: its index in [`EtherCat::modules`].
    pub module: usize,
}

/// An EtherCAT device's configuration: module instances, in slot order (an instance's position
/// in the list is its slot number, 0 first, which moves its PDO indices).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EcConfiguration {
    /// The instances, slot by slot.
    pub slots: Vec<EcPlugged>,
}

/// Whether `slot` takes `module` (by ident or class).
fn takes(slot: &EcSlot, module: &EcModule) -> bool {
    slot.module_idents.contains(&module.ident)
        || module
            .class
            .as_ref()
            .is_some_and(|c| slot.module_classes.contains(c))
}

/// The configuration of the choices: `SLOT=NAME` puts an instance of the module (by `Type`,
/// `Name`, or `#x` ident) into the `SLOT`th `Slots/Slot` (1 first), `NAME` into the first slot
/// that takes it and has room. Slots with fewer instances than `MinInstances` are filled with
/// their default module. Every problem found, each a sentence.
pub fn choose_ec(ec: &EtherCat, choices: &[ModuleChoice]) -> Result<EcConfiguration, Vec<String>> {
    let mut errors = Vec::new();
    let mut counts = vec![0u32; ec.slots.len()];
    let mut plugged = Vec::new();
    for choice in choices {
        let wanted = choice.module.as_str();
        let by_ident = wanted
            .strip_prefix("#x")
            .and_then(|h| u32::from_str_radix(h, 16).ok())
            .and_then(|ident| ec.modules.iter().position(|m| m.ident == ident));
        let module = match by_ident {
            Some(n) => n,
            None => match find_named(
                wanted,
                ec.modules.iter().map(|m| m.type_name.as_str()),
                "module",
            )
            .or_else(|e| ec.modules.iter().position(|m| m.name == wanted).ok_or(e))
            {
                Ok(n) => n,
                Err(e) => {
                    errors.push(e);
                    continue;
                }
            },
        };
        let m = &ec.modules[module];
        let slot = match choice.slot {
            Some(number) => {
                let Some(index) = (number as usize)
                    .checked_sub(1)
                    .filter(|i| *i < ec.slots.len())
                else {
                    errors.push(format!(
                        "slot {number}: the device has slots 1 to {}",
                        ec.slots.len()
                    ));
                    continue;
                };
                if !takes(&ec.slots[index], m) {
                    errors.push(format!(
                        "slot {number} (\"{}\") does not take module {}",
                        ec.slots[index].name, m.type_name
                    ));
                    continue;
                }
                index
            }
            None => {
                let free = (0..ec.slots.len())
                    .find(|&i| takes(&ec.slots[i], m) && counts[i] < ec.slots[i].max_instances);
                let Some(index) = free else {
                    errors.push(format!(
                        "module {}: no slot with room takes it",
                        m.type_name
                    ));
                    continue;
                };
                index
            }
        };
        counts[slot] += 1;
        if counts[slot] > ec.slots[slot].max_instances {
            errors.push(format!(
                "slot {} (\"{}\") takes at most {} module(s)",
                slot + 1,
                ec.slots[slot].name,
                ec.slots[slot].max_instances
            ));
            continue;
        }
        plugged.push(EcPlugged { slot, module });
    }
    for (index, slot) in ec.slots.iter().enumerate() {
        let default = slot
            .default_module
            .and_then(|ident| ec.modules.iter().position(|m| m.ident == ident));
        while counts[index] < slot.min_instances {
            let Some(module) = default else {
                errors.push(format!(
                    "slot {} (\"{}\") needs at least {} module(s)",
                    index + 1,
                    slot.name,
                    slot.min_instances
                ));
                break;
            };
            counts[index] += 1;
            plugged.push(EcPlugged {
                slot: index,
                module,
            });
        }
    }
    // Slot order; the instances of one slot in the order chosen.
    plugged.sort_by_key(|p| p.slot);
    if errors.is_empty() {
        Ok(EcConfiguration { slots: plugged })
    } else {
        Err(errors)
    }
}

impl EtherCat {
    /// The device as configured: with a configuration chosen, its own PDOs then each module
    /// instance's, those without a SyncManager assigned to the device's first output (RxPdo)
    /// or input (TxPdo) SyncManager; a PDO index the module writes with `DependOnSlot` moved
    /// by the slot's `SlotPdoIncrement` times the instance's slot number (0 first), an entry's
    /// by its `SlotIndexIncrement` times that number
    /// ([`SlotIndices`](crate::model::SlotIndices)). Without a
    /// configuration, the device as described.
    pub fn configured(&self) -> EtherCat {
        let mut ec = self.clone();
        let first_sm = |kind: SmKind| {
            self.sync_managers
                .iter()
                .position(|s| s.kind == kind)
                .and_then(|n| u8::try_from(n).ok())
        };
        let (out_sm, in_sm) = (first_sm(SmKind::Outputs), first_sm(SmKind::Inputs));
        for (number, slot, module) in self.instances() {
            let moved = |index: u16, dependent: &BTreeSet<u16>, step: u16| {
                shifted(index, dependent, step, number)
            };
            let slot_indices = &module.slot_indices;
            for (pdos, own, sm) in [
                (&mut ec.rx_pdos, &module.rx_pdos, out_sm),
                (&mut ec.tx_pdos, &module.tx_pdos, in_sm),
            ] {
                pdos.extend(own.iter().map(|pdo| {
                    let mut pdo = pdo.clone();
                    pdo.index = moved(pdo.index, &slot_indices.pdos, slot.pdo_increment);
                    pdo.sm = pdo.sm.or(sm);
                    for entry in &mut pdo.entries {
                        entry.index =
                            moved(entry.index, &slot_indices.entries, slot.index_increment);
                    }
                    pdo
                }));
            }
        }
        ec
    }

    /// The module instances chosen, in slot order: each one's slot number (0 first), its slot
    /// and its module.
    fn instances(&self) -> impl Iterator<Item = (usize, &EcSlot, &EcModule)> {
        let chosen = self.chosen.iter().flat_map(|c| c.slots.iter());
        chosen.enumerate().filter_map(|(number, plugged)| {
            let slot = self.slots.get(plugged.slot)?;
            Some((number, slot, self.modules.get(plugged.module)?))
        })
    }
}

/// `index` moved by `step` times the slot `number` if it is one of `dependent`.
fn shifted(index: u16, dependent: &BTreeSet<u16>, step: u16, number: usize) -> u16 {
    if !dependent.contains(&index) {
        return index;
    }
    let number = u16::try_from(number).unwrap_or(u16::MAX);
    index.wrapping_add(step.wrapping_mul(number))
}

impl Device {
    /// The device as configured (an ESI device with modules chosen): its EtherCAT side
    /// [`EtherCat::configured`], and each module instance's dictionary objects joined to its
    /// own, an index written with `DependOnSlot` moved by the slot's `SlotIndexIncrement` times
    /// the instance's slot number (an object the device has already stays the device's).
    /// Any other device as it is.
    pub fn configured(&self) -> Device {
        let mut device = self.clone();
        let Some(ec) = self.ethercat() else {
            return device;
        };
        for (number, slot, module) in ec.instances() {
            for (&index, object) in &module.objects {
                let index = shifted(
                    index,
                    &module.slot_indices.objects,
                    slot.index_increment,
                    number,
                );
                device.objects.entry(index).or_insert_with(|| {
                    let mut object = object.clone();
                    object.index = index;
                    object
                });
            }
        }
        if let Some(own) = device.ethercat_mut() {
            *own = ec.configured();
        }
        device
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    /// Two slots (`SlotIndexIncrement` 800h, `SlotPdoIncrement` 16), each taking the one module
    /// by default; the module's TxPDO 1A00h, its entries 6064h:1 and 6000h:1, and its objects
    /// 6064h and 8000h, of which 1A00h, 6064h (entry and object) say `DependOnSlot`.
    const ESI: &str = r##"<?xml version="1.0"?>
<EtherCATInfo><Vendor><Id>#x1234</Id></Vendor><Descriptions><Devices>
<Device><Type ProductCode="#x1" RevisionNo="#x1">Two axes</Type><Name>Two axes</Name>
<Sm StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm>
<Sm StartAddress="#x1400" ControlByte="#x22" Enable="1">MBoxIn</Sm>
<Sm StartAddress="#x1800" ControlByte="#x64" Enable="1">Outputs</Sm>
<Sm StartAddress="#x1C00" ControlByte="#x20" Enable="1">Inputs</Sm>
<Slots SlotPdoIncrement="16" SlotIndexIncrement="#x800">
<Slot><Name>Axis 1</Name><ModuleIdent Default="1">#x100</ModuleIdent></Slot>
<Slot><Name>Axis 2</Name><ModuleIdent Default="1">#x100</ModuleIdent></Slot>
</Slots></Device></Devices>
<Modules><Module><Type ModuleIdent="#x100">Axis</Type><Name>Axis</Name>
<TxPdo Fixed="1" Sm="3"><Index DependOnSlot="true">#x1A00</Index><Name>Inputs</Name>
<Entry><Index DependOnSlot="1">#x6064</Index><SubIndex>1</SubIndex><BitLen>32</BitLen><Name>Position</Name><DataType>UDINT</DataType></Entry>
<Entry><Index>#x6000</Index><SubIndex>1</SubIndex><BitLen>16</BitLen><Name>Shared</Name><DataType>UINT</DataType></Entry>
</TxPdo>
<Profile><Dictionary><Objects>
<Object><Index DependOnSlot="1">#x6064</Index><Name>Position</Name><Type>UDINT</Type><BitSize>32</BitSize><Flags><Access>ro</Access></Flags></Object>
<Object><Index>#x8000</Index><Name>Settings</Name><Type>UDINT</Type><BitSize>32</BitSize><Flags><Access>rw</Access></Flags></Object>
</Objects></Dictionary></Profile>
</Module></Modules></Descriptions></EtherCATInfo>"##;

    #[test]
    fn depend_on_slot_indices_move_with_the_instances_slot() {
        let mut device = crate::read::read_bytes(Path::new("two.xml"), ESI.as_bytes()).device;
        let ec = device.ethercat_mut().expect("an ESI device");
        let module = &ec.modules[0];
        assert_eq!(module.slot_indices.pdos, BTreeSet::from([0x1A00]));
        assert_eq!(module.slot_indices.entries, BTreeSet::from([0x6064]));
        assert_eq!(module.slot_indices.objects, BTreeSet::from([0x6064]));
        // No choice: each slot takes its default module.
        ec.chosen = Some(choose_ec(ec, &[]).expect("the defaults"));
        let configured = device.configured();
        let pdos: Vec<(u16, Vec<u16>)> = configured
            .ethercat()
            .expect("an ESI device")
            .tx_pdos
            .iter()
            .map(|p| (p.index, p.entries.iter().map(|e| e.index).collect()))
            .collect();
        assert_eq!(
            pdos,
            [
                (0x1A00, vec![0x6064, 0x6000]),
                (0x1A10, vec![0x6864, 0x6000])
            ]
        );
        let objects: Vec<u16> = configured.objects.keys().copied().collect();
        assert_eq!(objects, [0x6064, 0x6864, 0x8000]);
        assert_eq!(configured.objects[&0x6864].index, 0x6864);
        // Without a configuration, the device as described.
        let mut plain = device.clone();
        if let Some(ec) = plain.ethercat_mut() {
            ec.chosen = None;
        }
        assert!(plain.configured().objects.is_empty());
        assert!(plain
            .configured()
            .ethercat()
            .expect("ESI")
            .tx_pdos
            .is_empty());
    }
}
