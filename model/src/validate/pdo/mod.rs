//! PDO rules (EDS401..EDS416): communication/mapping pairs, communication sub-object types,
//! COB-IDs, transmission types, and every mapping entry against the entry it maps.
//!
//! Errors are what breaks the generated PDO structs or a device's PDO configuration: a mapping
//! to a missing, non-mappable or wrong-direction entry, a length that is not the entry's width,
//! more than 64 bits, a dummy entry that `[DummyUsage]` does not enable, a missing mapping or
//! communication object, and sub-objects of the wrong type. The reserved sub-index 4 and the
//! TPDO-only sub-objects on an RPDO are common in vendor files and harmless: one info per file.
//! With module sections present a mapping may name objects that modules add, so a missing
//! target is then a warning. Values are the DCF ParameterValue where given, else the default.

use std::collections::BTreeMap;

use super::{at, effective_int, effective_value, obj, value_span};
use crate::diag::short_list;
use crate::diag::Diagnostic;
use crate::model::{BasicType, Device, Object, Span, Value};
use crate::rules;

mod mapping;
use mapping::mapping_entries;

/// The direction of a PDO.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Dir {
    Rx,
    Tx,
}

impl Dir {
    fn name(self) -> &'static str {
        match self {
            Dir::Rx => "RPDO",
            Dir::Tx => "TPDO",
        }
    }
}

/// The direction and number (0-based) of a PDO communication object.
fn comm(index: u16) -> Option<(Dir, u16)> {
    match index {
        0x1400..=0x15FF => Some((Dir::Rx, index - 0x1400)),
        0x1800..=0x19FF => Some((Dir::Tx, index - 0x1800)),
        _ => None,
    }
}

/// The direction and number (0-based) of a PDO mapping object.
fn mapping(index: u16) -> Option<(Dir, u16)> {
    match index {
        0x1600..=0x17FF => Some((Dir::Rx, index - 0x1600)),
        0x1A00..=0x1BFF => Some((Dir::Tx, index - 0x1A00)),
        _ => None,
    }
}

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    no_default_pdos(device, out);
    let mut sub4 = Vec::new();
    let mut rx_only = Vec::new();
    let mut first_sub4: Option<Span> = None;
    let mut first_rx_only: Option<Span> = None;
    for o in device.objects.values() {
        if let Some((dir, _)) = comm(o.index) {
            if !device.objects.contains_key(&(o.index + 0x200)) {
                out.push(pair_diag(o, o.index + 0x200, "mapping"));
            }
            comm_subs(device, o, dir, out);
            if let Some(s) = o.subs.get(&4).filter(|s| !s.implicit) {
                sub4.push(obj(o.index));
                first_sub4.get_or_insert(s.span);
            }
            if dir == Dir::Rx {
                if let Some(s) = [3u8, 6]
                    .iter()
                    .find_map(|i| o.subs.get(i))
                    .filter(|s| !s.implicit)
                {
                    rx_only.push(obj(o.index));
                    first_rx_only.get_or_insert(s.span);
                }
            }
        } else if let Some((dir, _)) = mapping(o.index) {
            if !device.objects.contains_key(&(o.index - 0x200)) {
                out.push(pair_diag(o, o.index - 0x200, "communication"));
            }
            mapping_entries(device, o, dir, out);
        }
    }
    if !sub4.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::PDO_COMM_SUB4,
                first_sub4,
                format!(
                    "{} PDO communication record(s) implement the reserved sub-index 4: {}",
                    sub4.len(),
                    short_list(&sub4)
                ),
            )
            .with_label("reserved (compatibility entry)")
            .with_help(
                "CiA 301 says sub-index 4 shall not be implemented; edsgen keeps it as described",
            ),
        );
    }
    if !rx_only.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::RPDO_TPDO_ONLY_SUB,
                first_rx_only,
                format!(
                    "{} RPDO communication record(s) implement inhibit time (sub 3) or SYNC start (sub 6), which only TPDOs use: {}",
                    rx_only.len(),
                    short_list(&rx_only)
                ),
            )
            .with_label("TPDO-only sub-object"),
        );
    }
    duplicate_cob_ids(device, out);
    dummy_usage_keys(device, out);
}

fn pair_diag(o: &Object, other: u16, what: &str) -> Diagnostic {
    Diagnostic::new(
        &rules::PDO_PAIR,
        Some(o.span),
        format!("{} has no {what} object {}", obj(o.index), obj(other)),
    )
    .with_label(format!("{what} object missing"))
    .with_help(format!(
        "describe {} too; a PDO needs both its communication and mapping objects",
        obj(other)
    ))
}

fn comm_subs(device: &Device, o: &Object, dir: Dir, out: &mut Vec<Diagnostic>) {
    for (sub_index, want, what) in [
        (1u8, BasicType::Unsigned32, "COB-ID"),
        (2, BasicType::Unsigned8, "transmission type"),
        (3, BasicType::Unsigned16, "inhibit time"),
        (5, BasicType::Unsigned16, "event timer"),
        (6, BasicType::Unsigned8, "SYNC start value"),
    ] {
        let Some(sub) = o.subs.get(&sub_index) else {
            continue;
        };
        let Some(got) = sub.data_type.and_then(|dt| device.basic_type(dt)) else {
            continue;
        };
        if got != want {
            out.push(
                Diagnostic::new(
                    &rules::PDO_COMM_SUB_TYPE,
                    Some(sub.span),
                    format!(
                        "{} ({what}) is {} but must be {}",
                        at(o.index, sub_index),
                        got.name(),
                        want.name()
                    ),
                )
                .with_label(format!("expected {}", want.name()))
                .with_help(format!("set DataType={:#06X}", want.index())),
            );
        }
    }
    if let Some(sub) = o.subs.get(&1) {
        cob_id_range(o.index, sub, out);
    }
    if let Some(sub) = o.subs.get(&2) {
        if let Some(t) = effective_int(sub) {
            let reserved = match dir {
                Dir::Tx => (241..=251).contains(&t),
                Dir::Rx => (241..=253).contains(&t),
            };
            if reserved {
                out.push(
                    Diagnostic::new(
                        &rules::TRANSMISSION_TYPE_RESERVED,
                        Some(value_span(sub)),
                        format!(
                            "{} transmission type {t} is reserved for an {}",
                            at(o.index, 2),
                            dir.name()
                        ),
                    )
                    .with_label("reserved transmission type")
                    .with_help(match dir {
                        Dir::Tx => {
                            "use 0..240 (synchronous), 252/253 (RTR) or 254/255 (event-driven)"
                        }
                        Dir::Rx => "use 0..240 (synchronous) or 254/255 (event-driven)",
                    }),
                );
            }
        }
    }
}

/// CiA 301 restricted CAN-IDs, as (first, last, what).
const RESTRICTED: [(u32, u32, &str); 8] = [
    (0x000, 0x000, "NMT"),
    (0x001, 0x07F, "reserved"),
    (0x101, 0x180, "TIME / reserved"),
    (0x581, 0x5FF, "SDO server transmit"),
    (0x601, 0x67F, "SDO server receive"),
    (0x6E0, 0x6FF, "reserved"),
    (0x701, 0x77F, "NMT error control (heartbeat)"),
    (0x780, 0x7FF, "reserved (LSS)"),
];

fn cob_id_range(index: u16, sub: &crate::model::SubObject, out: &mut Vec<Diagnostic>) {
    let ids: Vec<(u32, Option<i128>)> = match effective_value(sub) {
        Some(Value::Integer(v)) => vec![(*v as u32, None)],
        Some(Value::NodeRelative(o)) => [1i128, 127]
            .iter()
            .map(|n| ((i128::from(*o) + n) as u32, Some(*n)))
            .collect(),
        _ => return,
    };
    for (cob, node) in ids {
        if cob & 0x8000_0000 != 0 || cob & 0x2000_0000 != 0 {
            return; // PDO not valid, or a 29-bit identifier.
        }
        let id = cob & 0x7FF;
        if let Some((_, _, what)) = RESTRICTED
            .iter()
            .find(|(lo, hi, _)| (*lo..=*hi).contains(&id))
        {
            let for_node = node.map_or(String::new(), |n| format!(" for node-ID {n}"));
            out.push(
                Diagnostic::new(
                    &rules::COB_ID_RESTRICTED,
                    Some(value_span(sub)),
                    format!(
                        "{} COB-ID {id:#05X}{for_node} is in a restricted range ({what})",
                        at(index, 1)
                    ),
                )
                .with_label("restricted CAN-ID")
                .with_help("use a CAN-ID of the PDO ranges, e.g. $NODEID+0x180 for TPDO1"),
            );
            return;
        }
    }
}

/// EDS709: mapping objects that all map nothing by default, so that the generator makes no
/// typed PDO; said here, where `edsgen validate` shows infos.
fn no_default_pdos(device: &Device, out: &mut Vec<Diagnostic>) {
    let mappings: Vec<&Object> = device
        .objects
        .range(0x1600..=0x1BFF)
        .map(|(_, o)| o)
        .filter(|o| matches!(o.index, 0x1600..=0x17FF | 0x1A00..=0x1BFF))
        .collect();
    let all_empty = mappings
        .iter()
        .all(|o| o.subs.get(&0).and_then(effective_int) == Some(0));
    let Some(first) = mappings.first().filter(|_| all_empty) else {
        return;
    };
    let indices: Vec<String> = mappings.iter().map(|o| obj(o.index)).collect();
    out.push(
        Diagnostic::new(
            &rules::NO_DEFAULT_PDOS,
            Some(first.span),
            format!(
                "no PDO struct is generated: the mapping objects ({}) map no objects by default",
                short_list(&indices)
            ),
        )
        .with_help(format!(
            "declare the mappings to generate in the overlay: [pdo_mapping] {:04X} = [\"6040\", ...]",
            first.index
        )),
    );
}

/// A COB-ID for comparison: fixed, or `$NODEID`-relative, flags masked.
#[derive(PartialEq, Eq, PartialOrd, Ord, Clone, Copy)]
enum CobKey {
    Fixed(u32),
    Relative(i64),
}

fn duplicate_cob_ids(device: &Device, out: &mut Vec<Diagnostic>) {
    for (range, dir) in [(0x1400..=0x15FF, Dir::Rx), (0x1800..=0x19FF, Dir::Tx)] {
        let mut seen: BTreeMap<CobKey, u16> = BTreeMap::new();
        for o in device.objects.range(range) {
            let (index, o) = o;
            let Some(sub) = o.subs.get(&1) else { continue };
            let key = match effective_value(sub) {
                Some(Value::Integer(v)) if (*v as u32) & 0x8000_0000 == 0 => {
                    CobKey::Fixed((*v as u32) & 0x1FFF_FFFF)
                }
                Some(Value::NodeRelative(off)) if (*off as u32) & 0x8000_0000 == 0 => {
                    CobKey::Relative(*off & 0x1FFF_FFFF)
                }
                _ => continue,
            };
            if let Some(first) = seen.get(&key) {
                out.push(
                    Diagnostic::new(
                        &rules::DUPLICATE_PDO_COB_ID,
                        Some(value_span(sub)),
                        format!(
                            "{} has the same COB-ID as {} ({} {})",
                            at(*index, 1),
                            at(*first, 1),
                            dir.name(),
                            "both enabled"
                        ),
                    )
                    .with_label("duplicate COB-ID")
                    .with_help("give each enabled PDO its own COB-ID, or disable one (bit 31)"),
                );
            } else {
                seen.insert(key, *index);
            }
        }
    }
}

fn dummy_usage_keys(device: &Device, out: &mut Vec<Diagnostic>) {
    if let Some(span) = device.dummy_usage_span {
        let missing: Vec<String> = (0x0001..=0x0007u16)
            .filter(|k| !device.dummy_usage.contains_key(k))
            .map(|k| format!("Dummy{k:04X}"))
            .collect();
        if !missing.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::DUMMY_USAGE_MISSING,
                    Some(span),
                    format!("[DummyUsage] has no {}", short_list(&missing)),
                )
                .with_label("CiA 306 lists Dummy0001..Dummy0007")
                .with_help(format!(
                    "add {}=0 (or =1 where the device accepts that dummy type); python canopen cannot import the file without them",
                    missing[0]
                )),
            );
        }
    }
    let odd: Vec<String> = device
        .dummy_usage
        .keys()
        .filter(|k| !(0x0001..=0x0007).contains(*k))
        .map(|k| format!("Dummy{k:04X}"))
        .collect();
    if !odd.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::DUMMY_USAGE_KEY,
                device.dummy_usage_span,
                format!(
                    "[DummyUsage] has keys outside Dummy0001..Dummy0007: {}",
                    short_list(&odd)
                ),
            )
            .with_help("CiA 306 defines Dummy0001..Dummy0007; other tools may ignore the rest"),
        );
    }
}
