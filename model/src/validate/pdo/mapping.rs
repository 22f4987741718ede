//! The mapping entries of a PDO (EDS404..EDS409, EDS415): each entry against the object it maps
//! (present, mappable, in the PDO's direction), its length against the entry's width, dummy
//! entries against `[DummyUsage]`, and the total against 64 bits.

use super::super::{at, effective_int, entry_name, obj, value_span};
use super::Dir;
use crate::diag::short_list;
use crate::diag::{Diagnostic, Severity};
use crate::model::{AccessType, BasicType, Device, Object, Span};
use crate::rules;

/// A mapped object that does not exist, reported once per mapping that names it: its index, the
/// mapping's sub-indices naming it, the sub-indices they map, and the first one's span and raw
/// value.
type MissingTarget = (u16, Vec<String>, Vec<String>, (Option<Span>, u32));

pub(super) fn mapping_entries(device: &Device, o: &Object, dir: Dir, out: &mut Vec<Diagnostic>) {
    let Some(sub0) = o.subs.get(&0) else { return };
    let Some(count) = effective_int(sub0) else {
        return;
    };
    if count == 0xFE || count == 0xFF {
        // CiA 301 multiplexed PDOs: FEh is SAM-MPDO, FFh DAM-MPDO; the mapping then lives in
        // the object scanner/dispatcher lists (1FA0h..1FCFh), not in sub-indices 1..64.
        return;
    }
    if count > 64 {
        out.push(
            Diagnostic::new(
                &rules::MAPPING_COUNT,
                Some(value_span(sub0)),
                format!("{} maps {count} objects; at most 64 fit", at(o.index, 0)),
            )
            .with_label("above 64"),
        );
        return;
    }
    let count = count.max(0) as u8;
    let present = (1..=count).filter(|s| o.subs.contains_key(s)).count();
    if present < count as usize {
        let missing: Vec<String> = (1..=count)
            .filter(|s| !o.subs.contains_key(s))
            .map(|s| s.to_string())
            .collect();
        out.push(
            Diagnostic::new(
                &rules::MAPPING_COUNT,
                Some(value_span(sub0)),
                format!(
                    "{} maps {count} objects but sub-index {} is not described",
                    at(o.index, 0),
                    short_list(&missing)
                ),
            )
            .with_label(format!("{present} mapping entries present"))
            .with_help(format!(
                "set the number of mapped objects to {present}, or describe the missing entries"
            )),
        );
    }
    let modules = has_modules(device);
    let granularity = device.device_info.granularity.as_ref().map(|g| g.value);
    if granularity == Some(8) && count > 8 {
        out.push(
            Diagnostic::new(
                &rules::MAPPING_GRANULARITY,
                Some(value_span(sub0)),
                format!(
                    "{} maps {count} objects with Granularity 8; byte-wise mapping fits at most 8",
                    at(o.index, 0)
                ),
            )
            .with_label(format!("{count} entries"))
            .with_help("CANopenNode and most devices accept at most 8 entries per PDO"),
        );
    }
    let mut total_bits: u32 = 0;
    let mut empty = Vec::new();
    let mut first_empty = None;
    let mut missing: Vec<MissingTarget> = Vec::new();
    for s in 1..=count {
        let Some(entry) = o.subs.get(&s) else {
            continue;
        };
        let Some(raw) = effective_int(entry) else {
            continue;
        };
        let raw = raw as u32;
        let (index, sub, len) = ((raw >> 16) as u16, (raw >> 8) as u8, raw & 0xFF);
        total_bits += len;
        let here = at(o.index, s);
        let span = Some(value_span(entry));
        if let Some(g) = granularity.filter(|g| (1..64).contains(g)) {
            if len % g != 0 {
                out.push(
                    Diagnostic::new(
                        &rules::MAPPING_GRANULARITY,
                        span,
                        format!("{here} maps {len} bits, not a multiple of Granularity {g}"),
                    )
                    .with_label(format!("{len} bits")),
                );
            }
        }
        if index == 0 {
            empty.push(s.to_string());
            first_empty.get_or_insert(value_span(entry));
            continue;
        }
        if (0x0001..=0x001F).contains(&index) && sub == 0 {
            dummy(device, &here, index, len, span, out);
            continue;
        }
        let Some(mapped) = device.entry(index, sub) else {
            let target_sub = sub.to_string();
            match missing.iter_mut().find(|(i, _, _, _)| *i == index) {
                Some((_, subs, target_subs, _)) => {
                    subs.push(s.to_string());
                    if !target_subs.contains(&target_sub) {
                        target_subs.push(target_sub);
                    }
                }
                None => missing.push((index, vec![s.to_string()], vec![target_sub], (span, raw))),
            }
            continue;
        };
        let target = entry_name(device, index, sub);
        if !mapped.pdo_mapping {
            out.push(
                Diagnostic::new(
                    &rules::MAPPING_NOT_MAPPABLE,
                    span,
                    format!("{here} maps {target}, which has PDOMapping=0"),
                )
                .with_label("not mappable")
                .with_help(format!(
                    "set PDOMapping=1 on {target}, or remove it from the mapping"
                )),
            );
        }
        if let Some(access) = mapped.access {
            let wrong = match dir {
                Dir::Rx => matches!(access, AccessType::Ro | AccessType::Const | AccessType::Rwr),
                Dir::Tx => matches!(access, AccessType::Wo | AccessType::Rww),
            };
            if wrong {
                out.push(
                    Diagnostic::new(
                        &rules::MAPPING_DIRECTION,
                        span,
                        format!(
                            "{here} maps {target} ({}) into an {}",
                            access.as_str(),
                            dir.name()
                        ),
                    )
                    .with_label(format!(
                        "{} cannot carry a {} entry",
                        dir.name(),
                        access.as_str()
                    ))
                    .with_help(match dir {
                        Dir::Rx => "an RPDO writes the entry: it must be wo, rw or rww",
                        Dir::Tx => "a TPDO reads the entry: it must be ro, const, rw or rwr",
                    }),
                );
            }
        }
        if let Some(ty) = mapped.data_type.and_then(|dt| device.basic_type(dt)) {
            length(&here, &target, ty, len, granularity, span, out);
        }
    }
    for (index, subs, target_subs, (span, raw)) in missing {
        let targets = format!("{index:04X}h sub {}", short_list(&target_subs));
        let subs = short_list(&subs);
        let message = if target_subs.len() > 1 {
            format!(
                "{} sub {subs} map {targets}, which do not exist",
                obj(o.index)
            )
        } else if subs.contains(", ") {
            format!(
                "{} sub {subs} map {targets}, which does not exist",
                obj(o.index)
            )
        } else {
            format!(
                "{} sub {subs} maps {targets}, which does not exist",
                obj(o.index)
            )
        };
        out.push(
            Diagnostic::new(&rules::MAPPING_TARGET_MISSING, span, message)
                .with_severity(if modules { Severity::Warning } else { Severity::Error })
                .with_label(format!("{raw:#010X}: no such entry"))
                .with_help("describe the mapped entry, or fix the mapping value (index << 16 | sub << 8 | bits)"),
        );
    }
    if !empty.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::MAPPING_TARGET_MISSING,
                first_empty,
                format!(
                    "{} maps {count} objects but sub-index {} {} empty (0)",
                    obj(o.index),
                    short_list(&empty),
                    if empty.len() == 1 { "is" } else { "are" }
                ),
            )
            .with_severity(Severity::Warning)
            .with_label("empty mapping entry")
            .with_help(format!(
                "set {} to the number of real entries",
                at(o.index, 0)
            )),
        );
    }
    if total_bits > 64 {
        out.push(
            Diagnostic::new(
                &rules::MAPPING_TOO_LONG,
                Some(value_span(sub0)),
                format!(
                    "{} maps {total_bits} bits; a CAN frame holds 64",
                    obj(o.index)
                ),
            )
            .with_label(format!("{total_bits} bits mapped"))
            .with_help("map fewer or shorter entries"),
        );
    }
}

pub(super) fn length(
    here: &str,
    target: &str,
    ty: BasicType,
    len: u32,
    granularity: Option<u32>,
    span: Option<Span>,
    out: &mut Vec<Diagnostic>,
) {
    let wrong = |msg: String, sev: Severity| {
        Diagnostic::new(&rules::MAPPING_LENGTH, span, msg)
            .with_severity(sev)
            .with_label(format!("{len} bits"))
            .with_help("the low byte of a mapping entry is the entry's width in bits")
    };
    match ty.bits() {
        None => {
            if len == 0 || !len.is_multiple_of(8) {
                out.push(wrong(
                    format!(
                        "{here} maps {len} bits of {target} ({}), not a whole number of bytes",
                        ty.name()
                    ),
                    Severity::Error,
                ));
            }
        }
        Some(width) => {
            // BOOLEAN is mapped as 1 bit, or as 8 bits by byte-granular devices.
            let ok = len == width || (ty == BasicType::Boolean && len == 8);
            if ok {
                return;
            }
            let partial = len > 0
                && len < width
                && granularity.is_some_and(|g| g != 0 && g < 8 && len.is_multiple_of(g));
            out.push(wrong(
                format!(
                    "{here} maps {len} bits of {target}, which is {} ({width} bits)",
                    ty.name()
                ),
                if partial {
                    Severity::Warning
                } else {
                    Severity::Error
                },
            ));
        }
    }
}

pub(super) fn dummy(
    device: &Device,
    here: &str,
    index: u16,
    len: u32,
    span: Option<Span>,
    out: &mut Vec<Diagnostic>,
) {
    let ty = BasicType::from_index(index);
    let type_name = ty.map_or_else(|| format!("{index:04X}h"), |t| t.name().to_owned());
    if device.dummy_usage.get(&index) != Some(&true) {
        out.push(
            Diagnostic::new(
                &rules::DUMMY_NOT_ENABLED,
                span,
                format!("{here} maps a dummy {type_name} but [DummyUsage] does not enable Dummy{index:04X}"),
            )
            .with_label("dummy entry not supported")
            .with_help(format!("add `Dummy{index:04X}=1` to [DummyUsage]")),
        );
    }
    if let Some(width) = ty.and_then(BasicType::bits) {
        if len != width && !(ty == Some(BasicType::Boolean) && len == 8) {
            out.push(
                Diagnostic::new(
                    &rules::MAPPING_LENGTH,
                    span,
                    format!("{here} maps {len} bits of a dummy {type_name} ({width} bits)"),
                )
                .with_label(format!("{len} bits"))
                .with_help("the low byte of a mapping entry is the entry's width in bits"),
            );
        }
    }
}

fn has_modules(device: &Device) -> bool {
    device.other_sections.iter().any(|s| {
        let n = s.name.trim().to_ascii_lowercase();
        n == "supportedmodules" || n == "connectedmodules"
    })
}
