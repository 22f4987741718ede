//! EtherCAT rules (EDS803, EDS804, EDS807..EDS817): the identity, the PDOs against the CoE
//! dictionary (and the modules' dictionaries), and the default and alternative PDO assignments
//! against the SyncManagers of a device read from an ESI file.
//!
//! Severities: an error where a master following the file would configure the device wrongly (an
//! entry that maps nothing, a length that disagrees, an assignment that does not fit its
//! SyncManager, or assigns two PDOs that exclude each other); a warning where the file is only
//! inconsistent (an Exclude naming nothing) or where the generator cannot type the layout (an
//! entry that is not byte-aligned); an info for PDOs that are simply not assigned by default.

use std::collections::BTreeSet;

use super::EntryName;
use crate::diag::short_list;
use crate::diag::Diagnostic;
use crate::model::{Device, EcPdo, EtherCat, SmKind};
use crate::rules;

pub(super) fn check(device: &Device, ec: &EtherCat, out: &mut Vec<Diagnostic>) {
    identity(device, ec, out);
    let pdos: Vec<(&str, &EcPdo)> = ec
        .rx_pdos
        .iter()
        .map(|p| ("RxPdo", p))
        .chain(ec.tx_pdos.iter().map(|p| ("TxPdo", p)))
        .collect();
    for (kind, pdo) in &pdos {
        entries(device, kind, pdo, out);
    }
    duplicates(&pdos, out);
    super::esi_assign::swapped(ec, out);
    super::esi_assign::assignment_defaults(device, ec, out);
    excludes(&pdos, out);
    assignment(ec, &pdos, out);
    alternatives(ec, &pdos, out);
}

/// `RxPdo 1600h`.
fn pdo_name(kind: &str, pdo: &EcPdo) -> String {
    format!("{kind} {:04X}h", pdo.index)
}

fn identity(device: &Device, ec: &EtherCat, out: &mut Vec<Diagnostic>) {
    let info = &device.device_info;
    for (missing, what, help) in [
        (
            info.vendor_number.is_none(),
            "no Vendor Id",
            "write the vendor's ETG number in `Vendor/Id` (e.g. `#x000004D8`)",
        ),
        (
            info.product_number.is_none(),
            "no ProductCode",
            "add `ProductCode=\"#x...\"` to the device's `Type`",
        ),
        (
            info.revision_number.is_none(),
            "no RevisionNo",
            "add `RevisionNo=\"#x...\"` to the device's `Type`",
        ),
    ] {
        if missing {
            out.push(
                Diagnostic::new(
                    &rules::ESI_IDENTITY,
                    Some(ec.span),
                    format!(
                        "device `{}` has {what} (or it is not a number)",
                        ec.type_name
                    ),
                )
                .with_label("a master identifies the device by it")
                .with_help(help),
            );
        }
    }
    if !device.objects.is_empty() && ec.profiles.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::ESI_PROFILE,
                Some(ec.span),
                format!(
                    "device `{}` has a CoE dictionary but no Profile/ProfileNo",
                    ec.type_name
                ),
            )
            .with_help("add `<ProfileNo>402</ProfileNo>` (a drive) or 5001 (a modular device)"),
        );
    }
}

/// EDS807 (missing target), EDS808 (length) and EDS809 (alignment) for one PDO's entries.
fn entries(device: &Device, kind: &str, pdo: &EcPdo, out: &mut Vec<Diagnostic>) {
    let name = pdo_name(kind, pdo);
    let mut offset: u64 = 0;
    for entry in &pdo.entries {
        let at = offset;
        offset += u64::from(entry.bit_len);
        if entry.bit_len >= 8 && !at.is_multiple_of(8) {
            out.push(
                Diagnostic::new(
                    &rules::ESI_PDO_ALIGNMENT,
                    Some(entry.span),
                    format!(
                        "{name} maps {:04X}h sub {} ({} bits) at bit {at}, not on a byte boundary",
                        entry.index, entry.sub, entry.bit_len
                    ),
                )
                .with_label(format!("starts at bit {} of byte {}", at % 8, at / 8))
                .with_help("pad the entries before it to a whole byte (an Entry with Index #x0)"),
            );
        }
        // Padding, or a device whose file carries no dictionary to check against.
        if entry.index == 0 || device.objects.is_empty() {
            continue;
        }
        let target = EntryName::new(device, entry.index, entry.sub);
        if module_defines(device, entry.index) {
            continue;
        }
        let Some(object) = device.objects.get(&entry.index) else {
            out.push(
                Diagnostic::new(
                    &rules::ESI_PDO_ENTRY_MISSING,
                    Some(entry.span),
                    format!(
                        "{name} maps {:04X}h sub {}, but the dictionary has no object {:04X}h",
                        entry.index, entry.sub, entry.index
                    ),
                )
                .with_label("no such object")
                .with_help("describe the object in Dictionary/Objects, or remove the entry"),
            );
            continue;
        };
        let Some(sub) = object.subs.get(&entry.sub) else {
            out.push(
                Diagnostic::new(
                    &rules::ESI_PDO_ENTRY_MISSING,
                    Some(entry.span),
                    format!(
                        "{name} maps {:04X}h sub {}, but {:04X}h has no sub-index {}",
                        entry.index, entry.sub, entry.index, entry.sub
                    ),
                )
                .with_label("no such sub-index")
                .with_help("correct SubIndex, or describe the sub-index in the object's type"),
            );
            continue;
        };
        let declared = sub
            .custom
            .iter()
            .find(|(k, _)| k == "BitSize")
            .and_then(|(_, v)| v.parse::<u32>().ok());
        let basic = sub.data_type.and_then(|t| device.basic_type(t));
        let Some(bits) = declared.or_else(|| basic.and_then(|b| b.bits())) else {
            continue;
        };
        if u32::from(entry.bit_len) != bits {
            out.push(
                Diagnostic::new(
                    &rules::ESI_PDO_ENTRY_LENGTH,
                    Some(entry.span),
                    format!(
                        "{name} maps {target} with BitLen {}, but {target} is {bits} bits{}",
                        entry.bit_len,
                        basic.map_or(String::new(), |b| format!(" ({})", b.name()))
                    ),
                )
                .with_label(format!("BitLen {}", entry.bit_len))
                .with_help(format!("set BitLen to {bits}")),
            );
        }
    }
}

/// Whether a module of the file defines object `index`: at its own index, or moved by a whole
/// number of a slot's `SlotIndexIncrement`, up to the slots' instances.
fn module_defines(device: &Device, index: u16) -> bool {
    let Some(ec) = device.ethercat() else {
        return false;
    };
    let positions: u32 = ec.slots.iter().map(|s| s.max_instances).sum();
    ec.modules
        .iter()
        .flat_map(|m| m.objects.keys())
        .any(|&own| {
            own == index
                || ec.slots.iter().any(|slot| {
                    let step = u32::from(slot.index_increment);
                    let offset = u32::from(index).wrapping_sub(u32::from(own));
                    step > 0 && index > own && offset % step == 0 && offset / step < positions
                })
        })
}

/// EDS813: the same Index on two PDO elements.
fn duplicates(pdos: &[(&str, &EcPdo)], out: &mut Vec<Diagnostic>) {
    let mut seen = BTreeSet::new();
    for (kind, pdo) in pdos {
        if !seen.insert(pdo.index) {
            out.push(
                Diagnostic::new(
                    &rules::ESI_DUPLICATE_PDO,
                    Some(pdo.span),
                    format!("{} is described twice", pdo_name(kind, pdo)),
                )
                .with_label("second description")
                .with_help("give each PDO its own mapping index"),
            );
        }
    }
}

/// EDS811 (Exclude naming nothing) and EDS812 (two excluding PDOs both assigned).
fn excludes(pdos: &[(&str, &EcPdo)], out: &mut Vec<Diagnostic>) {
    let mut reported = BTreeSet::new();
    for (kind, pdo) in pdos {
        for excluded in &pdo.exclude {
            let Some((other_kind, other)) = pdos.iter().find(|(_, p)| p.index == excluded.value)
            else {
                out.push(
                    Diagnostic::new(
                        &rules::ESI_EXCLUDE_MISSING,
                        Some(excluded.span),
                        format!(
                            "{} excludes {:04X}h, which is not a PDO of the device",
                            pdo_name(kind, pdo),
                            excluded.value
                        ),
                    )
                    .with_label("no such PDO"),
                );
                continue;
            };
            let pair = (pdo.index.min(other.index), pdo.index.max(other.index));
            if pdo.sm.is_some() && other.sm.is_some() && reported.insert(pair) {
                out.push(
                    Diagnostic::new(
                        &rules::ESI_EXCLUDE_CONFLICT,
                        Some(excluded.span),
                        format!(
                            "{} excludes {}, but both are assigned by default (Sm {} and Sm {})",
                            pdo_name(kind, pdo),
                            pdo_name(other_kind, other),
                            pdo.sm.unwrap_or_default(),
                            other.sm.unwrap_or_default()
                        ),
                    )
                    .with_label("excluded, yet assigned")
                    .with_help(
                        "remove `Sm` from one of the two so that the default assignment is valid",
                    ),
                );
            }
        }
    }
}

/// The bytes `assigned` hold and the DefaultSize of SM `number`, when they do not fit a process
/// data SyncManager with a DefaultSize.
fn overflow(ec: &EtherCat, number: usize, assigned: &[&EcPdo]) -> Option<(u64, u16)> {
    let sm = ec.sync_managers.get(number)?;
    let size = sm.default_size.filter(|s| *s > 0)?;
    if !matches!(sm.kind, SmKind::Outputs | SmKind::Inputs) {
        return None;
    }
    let bits: u64 = assigned
        .iter()
        .flat_map(|p| &p.entries)
        .map(|e| u64::from(e.bit_len))
        .sum();
    let bytes = bits.div_ceil(8);
    (bytes > u64::from(size)).then_some((bytes, size))
}

/// `1600h`, `1601h` as a short list.
fn index_list(pdos: &[&EcPdo]) -> String {
    let names: Vec<String> = pdos.iter().map(|p| format!("{:04X}h", p.index)).collect();
    short_list(&names)
}

/// EDS810 (the default assignment larger than a SyncManager) and EDS814 (PDOs without Sm).
fn assignment(ec: &EtherCat, pdos: &[(&str, &EcPdo)], out: &mut Vec<Diagnostic>) {
    for (number, sm) in ec.sync_managers.iter().enumerate() {
        let assigned: Vec<&EcPdo> = pdos
            .iter()
            .map(|(_, p)| *p)
            .filter(|p| p.sm.map(usize::from) == Some(number))
            .collect();
        if let Some((bytes, size)) = overflow(ec, number, &assigned) {
            out.push(
                Diagnostic::new(
                    &rules::ESI_SM_OVERFLOW,
                    Some(sm.span),
                    format!(
                        "the PDOs assigned to SM{number} ({}) hold {bytes} bytes, but its DefaultSize is {size}",
                        index_list(&assigned)
                    ),
                )
                .with_label(format!("DefaultSize {size}"))
                .with_help(format!("raise DefaultSize to {bytes}, or assign fewer PDOs")),
            );
        }
    }
    let unassigned: Vec<&(&str, &EcPdo)> = pdos.iter().filter(|(_, p)| p.sm.is_none()).collect();
    if let Some((_, first)) = unassigned.first() {
        let names: Vec<String> = unassigned
            .iter()
            .map(|(kind, p)| pdo_name(kind, p))
            .collect();
        out.push(
            Diagnostic::new(
                &rules::ESI_PDO_WITHOUT_SM,
                Some(first.span),
                format!(
                    "{} PDO(s) without `Sm`, not assigned by default: {}",
                    names.len(),
                    short_list(&names)
                ),
            )
            .with_label("no Sm"),
        );
    }
}

/// EDS815 (a PDO that does not exist), EDS816 (more than a SyncManager's DefaultSize) and
/// EDS817 (two PDOs that exclude each other) for each `AlternativeSmMapping`.
fn alternatives(ec: &EtherCat, pdos: &[(&str, &EcPdo)], out: &mut Vec<Diagnostic>) {
    for alternative in &ec.alternative_mappings {
        let title = format!("alternative `{}`", alternative.name);
        let mut chosen: Vec<&EcPdo> = Vec::new();
        for (number, indices) in &alternative.sms {
            let mut assigned = Vec::new();
            for index in indices {
                match pdos.iter().find(|(_, p)| p.index == index.value) {
                    Some((_, pdo)) => assigned.push(*pdo),
                    None => out.push(
                        Diagnostic::new(
                            &rules::ESI_ALT_PDO_MISSING,
                            Some(index.span),
                            format!(
                                "{title} assigns {:04X}h to SM{number}, which is not a PDO of the device",
                                index.value
                            ),
                        )
                        .with_label("no such PDO")
                        .with_help("name an RxPdo/TxPdo Index of the device, or remove the Pdo"),
                    ),
                }
            }
            if let Some((bytes, size)) = overflow(ec, usize::from(*number), &assigned) {
                out.push(
                    Diagnostic::new(
                        &rules::ESI_ALT_SM_OVERFLOW,
                        Some(alternative.span),
                        format!(
                            "{title} assigns {} to SM{number}: {bytes} bytes, but its DefaultSize is {size}",
                            index_list(&assigned)
                        ),
                    )
                    .with_label(format!("{bytes} bytes on SM{number}"))
                    .with_help(format!(
                        "raise SM{number}'s DefaultSize to {bytes}, or assign fewer PDOs here"
                    )),
                );
            }
            chosen.extend(assigned);
        }
        let mut reported = BTreeSet::new();
        for pdo in &chosen {
            for excluded in &pdo.exclude {
                let Some(other) = chosen.iter().find(|p| p.index == excluded.value) else {
                    continue;
                };
                let pair = (pdo.index.min(other.index), pdo.index.max(other.index));
                if reported.insert(pair) {
                    out.push(
                        Diagnostic::new(
                            &rules::ESI_ALT_EXCLUDE_CONFLICT,
                            Some(alternative.span),
                            format!(
                                "{title} assigns {:04X}h and {:04X}h, but {:04X}h excludes {:04X}h",
                                pair.0, pair.1, pdo.index, other.index
                            ),
                        )
                        .with_label("excluding PDOs together")
                        .with_help("assign only one of the two in this alternative"),
                    );
                }
            }
        }
    }
}
