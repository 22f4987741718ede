//! An ESI device's chosen configuration: module instances in its `Slots/Slot`s, checked against
//! each slot's `ModuleIdent` / `ModuleClass` lists and `MinInstances` / `MaxInstances`, and the
//! device as configured ([`EtherCat::configured`]): the modules' PDOs added to its own, their
//! indices moved by `SlotPdoIncrement` per slot instance (ETG.2000's module slots).

use super::{find_named, ModuleChoice};
use crate::model::{EcModule, EcSlot, EtherCat, SmKind};

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
    /// instance's, indices moved by the slot's `SlotPdoIncrement` times the instance's slot
    /// number, those without a SyncManager assigned to the device's first output (RxPdo) or
    /// input (TxPdo) SyncManager; without one, the device as described.
    pub fn configured(&self) -> EtherCat {
        let mut ec = self.clone();
        let Some(chosen) = &self.chosen else {
            return ec;
        };
        let first_sm = |kind: SmKind| {
            self.sync_managers
                .iter()
                .position(|s| s.kind == kind)
                .and_then(|n| u8::try_from(n).ok())
        };
        let (out_sm, in_sm) = (first_sm(SmKind::Outputs), first_sm(SmKind::Inputs));
        for (number, plugged) in chosen.slots.iter().enumerate() {
            let (Some(slot), Some(module)) = (
                self.slots.get(plugged.slot),
                self.modules.get(plugged.module),
            ) else {
                continue;
            };
            let shift = u16::try_from(number)
                .unwrap_or(u16::MAX)
                .wrapping_mul(slot.pdo_increment);
            for (pdos, own, sm) in [
                (&mut ec.rx_pdos, &module.rx_pdos, out_sm),
                (&mut ec.tx_pdos, &module.tx_pdos, in_sm),
            ] {
                pdos.extend(own.iter().map(|pdo| {
                    let mut pdo = pdo.clone();
                    pdo.index = pdo.index.wrapping_add(shift);
                    pdo.sm = pdo.sm.or(sm);
                    pdo
                }));
            }
        }
        ec
    }
}
