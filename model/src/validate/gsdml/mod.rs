//! PROFINET rules (PN002..PN018; PN001 is the reader's) over the GSDML part of the model: access
//! points, modules, submodules, IO data, parameter records, references, channel diagnostics,
//! subslot labels.
//!
//! Severities: an error where a controller following the file would build a connection the device
//! refuses or misreads (a type without size, IO data over the limits, a record field past its
//! end or over another, a reference to nothing, two things with one ident number); a warning
//! where the file is only incomplete (a module no slot can take, a text that is missing).
//!
//! IO data lengths count the status bytes as the IOCRs carry them: in the input CR each
//! submodule's input data and its IOPS (one byte, also for a submodule without data) and an IOCS
//! for each submodule with outputs; the output CR mirrors it.

use std::collections::{HashMap, HashSet};

use crate::diag::short_list;
use crate::diag::{self, Diagnostic, Severity};
use crate::model::{
    AccessPoint, ChannelDiag, PnDataType, PnModule, Profinet, RecordField, Span, Submodule,
};
use crate::rules;

mod records;
mod station_name;
use records::{field_type, field_value};

pub(super) fn check(pn: &Profinet, out: &mut Vec<Diagnostic>) {
    if pn.access_points.is_empty() {
        out.push(Diagnostic::new(
            &rules::PN_NO_ACCESS_POINT,
            Some(pn.span),
            "the file describes no `DeviceAccessPointItem`: a controller has nothing to connect to",
        ));
    }
    let all_submodules = pn
        .access_points
        .iter()
        .flat_map(|d| &d.submodules)
        .chain(pn.modules.iter().flat_map(|m| &m.submodules));
    for sub in all_submodules {
        submodule(pn, sub, out);
    }
    for dap in &pn.access_points {
        access_point(pn, dap, out);
        station_name::check(dap, out);
    }
    unused_modules(pn, out);
    duplicates(pn, out);
    for diag in &pn.channel_diagnostics {
        ext_channel_diagnostics(diag, out);
    }
    missing_texts(pn, out);
}

/// The bytes a submodule takes in the input CR and in the output CR, with IOPS and IOCS; `None`
/// when an item's size is unknown.
pub fn iocr_lengths(sub: &Submodule) -> Option<(u32, u32)> {
    let sum = |items: &[crate::model::DataItem]| -> Option<u32> {
        items.iter().map(|i| i.size()).sum::<Option<u32>>()
    };
    let (input, output) = (sum(&sub.inputs)?, sum(&sub.outputs)?);
    let has_out = !sub.outputs.is_empty();
    let has_in = !sub.inputs.is_empty() || !has_out;
    let in_cr = if has_in { input + 1 } else { 0 } + u32::from(has_out);
    let out_cr = if has_out { output + 1 } else { 0 } + u32::from(has_in);
    Some((in_cr, out_cr))
}

fn submodule(pn: &Profinet, sub: &Submodule, out: &mut Vec<Diagnostic>) {
    for item in sub.inputs.iter().chain(&sub.outputs) {
        if item.kind.is_none() {
            out.push(
                Diagnostic::new(
                    &rules::PN_UNKNOWN_TYPE,
                    Some(item.data_type.span),
                    format!("`{}` is not a GSDML data type", item.data_type.value),
                )
                .with_label("unknown type")
                .with_help("GSDML types are Unsigned8..64, Integer8..64, Float32/64, OctetString, VisibleString, ..."),
            );
        } else if item.size().is_none() {
            out.push(
                Diagnostic::new(
                    &rules::PN_UNKNOWN_TYPE,
                    Some(item.data_type.span),
                    format!("a `{}` data item without `Length`", item.data_type.value),
                )
                .with_help("give the string's length in bytes: `Length=\"4\"`"),
            );
        }
        let Some(size) = item.size() else { continue };
        for bit in &item.bits {
            if bit.bit_offset >= size * 8 {
                out.push(Diagnostic::new(
                    &rules::PN_BIT_OUTSIDE,
                    Some(bit.span),
                    format!(
                        "bit {} of a {size}-byte `{}` item, which has bits 0..{}",
                        bit.bit_offset,
                        item.data_type.value,
                        size * 8 - 1
                    ),
                ));
            }
        }
    }
    let mut indexes: HashMap<u16, Span> = HashMap::new();
    for record in &sub.records {
        if let Some(first) = indexes.insert(record.index.value, record.index.span) {
            out.push(Diagnostic::new(
                &rules::PN_DUPLICATE_RECORD,
                Some(record.index.span),
                format!(
                    "submodule `{}` has two parameter records with index {} (the other on line {})",
                    sub.id, record.index.value, first.line
                ),
            ));
        }
        let length_bits = u64::from(record.length.value) * 8;
        for (offset, bytes) in &record.consts {
            if u64::from(*offset) + bytes.len() as u64 > u64::from(record.length.value) {
                out.push(Diagnostic::new(
                    &rules::PN_RECORD_OVERRUN,
                    Some(record.span),
                    format!(
                        "a `Const` of {} byte(s) at byte {offset} runs past the record's {} bytes",
                        bytes.len(),
                        record.length.value
                    ),
                ));
            }
        }
        let mut taken: Vec<(u64, u64, &RecordField)> = Vec::new();
        for field in &record.fields {
            field_type(field, out);
            field_value(pn, field, out);
            let Some((start, bits)) = field.bit_range() else {
                continue;
            };
            if start + bits > length_bits {
                out.push(
                    Diagnostic::new(
                        &rules::PN_RECORD_OVERRUN,
                        Some(field.span),
                        format!(
                            "the `{}` field at byte {} ends at byte {}, past the record's length {}",
                            field.data_type.value,
                            field.byte_offset,
                            (start + bits).div_ceil(8),
                            record.length.value
                        ),
                    )
                    .with_label("beyond the record")
                    .with_help(format!(
                        "the record (index {}) is {} bytes long",
                        record.index.value, record.length.value
                    )),
                );
            }
            if let Some((_, _, other)) = taken
                .iter()
                .find(|(s, n, _)| *s < start + bits && start < s + n)
            {
                out.push(
                    Diagnostic::new(
                        &rules::PN_RECORD_OVERLAP,
                        Some(field.span),
                        format!(
                            "the `{}` field at byte {} shares bits with the `{}` field at byte {} (line {})",
                            field.data_type.value,
                            field.byte_offset,
                            other.data_type.value,
                            other.byte_offset,
                            other.span.line
                        ),
                    )
                    .with_label("overlaps another field"),
                );
            }
            taken.push((start, bits, field));
        }
    }
}

fn module_by_id<'p>(pn: &'p Profinet, id: &str) -> Option<&'p PnModule> {
    pn.modules.iter().find(|m| m.id == id)
}

/// The input and output CR lengths of some submodules; `None` when a size is unknown.
fn lengths<'s>(subs: impl Iterator<Item = &'s Submodule>) -> Option<(u32, u32)> {
    let mut total = (0, 0);
    for sub in subs {
        let (i, o) = iocr_lengths(sub)?;
        total = (total.0 + i, total.1 + o);
    }
    Some(total)
}

fn access_point(pn: &Profinet, dap: &AccessPoint, out: &mut Vec<Diagnostic>) {
    let base = lengths(dap.submodules.iter());
    let over = |what: String, span: Span, len: (u32, u32), out: &mut Vec<Diagnostic>| {
        for (n, limit, dir) in [
            (len.0, &dap.max_input_length, "input"),
            (len.1, &dap.max_output_length, "output"),
        ] {
            let Some(limit) = limit else { continue };
            if n > limit.value {
                out.push(
                    Diagnostic::new(
                        &rules::PN_IO_LIMIT,
                        Some(span),
                        format!(
                            "{what} takes {n} {dir} bytes (with IOPS/IOCS), over access point `{}`'s Max{}Length {}",
                            dap.id,
                            if dir == "input" { "Input" } else { "Output" },
                            limit.value
                        ),
                    )
                    .with_help(format!("the limit is on line {}", limit.span.line)),
                );
            }
        }
    };
    if let Some(base) = base {
        over(
            format!("access point `{}` alone", dap.id),
            dap.span,
            base,
            out,
        );
    }
    let mut default_config = base;
    for r in &dap.useable_modules {
        let Some(module) = module_by_id(pn, &r.target.value) else {
            out.push(
                Diagnostic::new(
                    &rules::PN_MISSING_MODULE,
                    Some(r.target.span),
                    format!(
                        "`ModuleItemTarget` `{}` names no `ModuleItem`",
                        r.target.value
                    ),
                )
                .with_label("no such ModuleItem"),
            );
            continue;
        };
        let slots: Vec<u16> = r
            .allowed_in_slots
            .iter()
            .copied()
            .filter(|s| dap.physical_slots.is_empty() || dap.physical_slots.contains(s))
            .filter(|s| !dap.fixed_in_slots.contains(s))
            .collect();
        if slots.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::PN_NO_SLOT,
                    Some(r.span),
                    format!(
                        "module `{}` is allowed in no slot of access point `{}` (its slots {:?}, the physical slots {:?})",
                        r.target.value, dap.id, r.allowed_in_slots, dap.physical_slots
                    ),
                )
                .with_help("give `AllowedInSlots` within `PhysicalSlots`"),
            );
        }
        let module_len = lengths(module.submodules.iter());
        if let (Some(b), Some(m)) = (base, module_len) {
            over(
                format!("module `{}` in access point `{}`", module.id, dap.id),
                r.span,
                (b.0 + m.0, b.1 + m.1),
                out,
            );
        }
        let placed = r.fixed_in_slots.len().max(r.used_in_slots.len()) as u32;
        default_config = match (default_config, module_len) {
            (Some(d), Some(m)) => Some((d.0 + m.0 * placed, d.1 + m.1 * placed)),
            _ => None,
        };
    }
    if let (Some(d), Some(b)) = (default_config, base) {
        if d != b {
            over(
                format!(
                    "the default configuration of `{}` (fixed and used modules)",
                    dap.id
                ),
                dap.span,
                d,
                out,
            );
        }
    }
}

fn unused_modules(pn: &Profinet, out: &mut Vec<Diagnostic>) {
    let used: HashSet<&str> = pn
        .access_points
        .iter()
        .flat_map(|d| &d.useable_modules)
        .map(|r| r.target.value.as_str())
        .collect();
    for module in &pn.modules {
        if !used.contains(module.id.as_str()) {
            out.push(
                Diagnostic::new(
                    &rules::PN_NO_SLOT,
                    Some(module.span),
                    format!(
                        "module `{}` is in no access point's `UseableModules`: no slot can take it",
                        module.id
                    ),
                )
                .with_severity(Severity::Warning),
            );
        }
    }
}

fn duplicates(pn: &Profinet, out: &mut Vec<Diagnostic>) {
    // Access points are alternatives (a device runs one): they may share a ModuleIdentNumber, as
    // versions of one head module do. Modules are told apart by theirs.
    // By ident number: the module's ID, where the number is, its IO data lengths.
    type Seen = (String, Span, Option<(u32, u32)>);
    let mut idents: HashMap<u32, Seen> = HashMap::new();
    for module in &pn.modules {
        let Some(ident) = &module.module_ident else {
            continue;
        };
        let id = &module.id;
        let io = lengths(module.submodules.iter());
        let entry = (id.clone(), ident.span, io);
        if let Some((other, span, other_io)) = idents.insert(ident.value, entry) {
            // Vendors give variants of one module one number (ET 200M does 34 times): with the
            // same IO data a controller that takes one for the other exchanges the same bytes,
            // which is harmless. A warning only where the IO data differ: the device cannot
            // tell them apart in its RealIdentificationData, and a controller would misread.
            if io.is_some() && io == other_io {
                continue;
            }
            out.push(
                Diagnostic::new(
                    &rules::PN_DUPLICATE_IDENT,
                    Some(ident.span),
                    format!(
                        "module `{id}` has ModuleIdentNumber {:#010X}, as module `{other}` (line {}) has",
                        ident.value, span.line
                    ),
                )
                .with_severity(Severity::Warning)
                .with_help("the device reports modules by ident number: a controller cannot tell these two apart"),
            );
        }
    }
    let owners = pn
        .access_points
        .iter()
        .map(|d| (&d.id, &d.submodules))
        .chain(pn.modules.iter().map(|m| (&m.id, &m.submodules)));
    for (owner, subs) in owners {
        // Submodules in different subslots may share an ident number (an I-device's transfer
        // areas do); two in one subslot cannot both be there.
        let mut seen: HashMap<u16, &str> = HashMap::new();
        for sub in subs {
            if let Some(other) = seen.insert(sub.subslot, &sub.id) {
                out.push(Diagnostic::new(
                    &rules::PN_DUPLICATE_IDENT,
                    Some(sub.span),
                    format!(
                        "`{owner}` has two submodules in subslot {} (`{other}` and `{}`)",
                        sub.subslot, sub.id
                    ),
                ));
            }
        }
    }
    let labels = pn
        .access_points
        .iter()
        .map(|d| (&d.id, &d.subslot_labels))
        .chain(pn.modules.iter().map(|m| (&m.id, &m.subslot_labels)));
    for (owner, labels) in labels {
        let mut seen: HashMap<u16, Span> = HashMap::new();
        for label in labels {
            if let Some(first) = seen.insert(label.subslot.value, label.subslot.span) {
                out.push(Diagnostic::new(
                    &rules::PN_DUPLICATE_SUBSLOT_LABEL,
                    Some(label.subslot.span),
                    format!(
                        "`{owner}` labels subslot {} twice (the first on line {})",
                        label.subslot.value, first.line
                    ),
                ));
            }
        }
    }
    let mut ids: HashMap<&str, Span> = HashMap::new();
    let items = pn
        .access_points
        .iter()
        .map(|d| (d.id.as_str(), d.span))
        .chain(pn.modules.iter().map(|m| (m.id.as_str(), m.span)))
        .chain(pn.value_lists.iter().map(|v| (v.id.as_str(), v.span)));
    for (id, span) in items {
        if id.is_empty() {
            continue;
        }
        if let Some(first) = ids.insert(id, span) {
            out.push(Diagnostic::new(
                &rules::PN_DUPLICATE_IDENT,
                Some(span),
                format!(
                    "a second item with ID `{id}` (the first on line {})",
                    first.line
                ),
            ));
        }
    }
}

/// A channel error's `ExtChannelDiagItem`s: one meaning per ExtChannelErrorType, and additional
/// values that are data types GSDML defines and fit the alarm's 32 bits.
fn ext_channel_diagnostics(diag: &ChannelDiag, out: &mut Vec<Diagnostic>) {
    let mut seen: HashMap<u16, Span> = HashMap::new();
    for ext in &diag.ext {
        if let Some(first) = seen.insert(ext.error_type.value, ext.error_type.span) {
            out.push(Diagnostic::new(
                &rules::PN_DUPLICATE_EXT_DIAG,
                Some(ext.error_type.span),
                format!(
                    "a second ExtChannelDiagItem with ErrorType {} in channel error type {} (the \
                     first on line {})",
                    ext.error_type.value, diag.error_type, first.line
                ),
            ));
        }
        let mut bytes = Some(0u32);
        for value in &ext.add_values {
            let size = match value.kind {
                None => {
                    out.push(
                        Diagnostic::new(
                            &rules::PN_UNKNOWN_TYPE,
                            Some(value.data_type.span),
                            format!("`{}` is not a GSDML data type", value.data_type.value),
                        )
                        .with_label("unknown type"),
                    );
                    None
                }
                Some(
                    PnDataType::OctetString
                    | PnDataType::VisibleString
                    | PnDataType::UnicodeString8,
                ) => value.length,
                Some(kind) => kind.size(),
            };
            bytes = bytes.zip(size).map(|(a, b)| a.saturating_add(b));
        }
        if let Some(bytes) = bytes.filter(|b| *b > 4) {
            out.push(
                Diagnostic::new(
                    &rules::PN_EXT_ADD_VALUE_SIZE,
                    Some(ext.span),
                    format!(
                        "ExtChannelDiagItem {} of channel error type {} adds {bytes} bytes of \
                         values; an alarm carries 4 (ExtChannelAddValue, Unsigned32)",
                        ext.error_type.value, diag.error_type
                    ),
                )
                .with_label("too long"),
            );
        }
    }
}

fn missing_texts(pn: &Profinet, out: &mut Vec<Diagnostic>) {
    let mut found: Vec<Diagnostic> = pn
        .missing_texts
        .iter()
        .map(|t| {
            Diagnostic::new(
                &rules::PN_MISSING_TEXT,
                Some(t.span),
                format!(
                    "`TextId` `{}` has no text in the `ExternalTextList`",
                    t.value
                ),
            )
            .with_label("no such text")
        })
        .collect();
    let names: Vec<String> = pn.missing_texts.iter().map(|t| t.value.clone()).collect();
    diag::sort(&mut found);
    diag::fold(
        &mut found,
        |d| std::ptr::eq(d.rule, &rules::PN_MISSING_TEXT).then_some(()),
        "likewise on",
    );
    if names.len() > 1 {
        if let Some(first) = found.first_mut() {
            *first = first
                .clone()
                .with_help(format!("missing: {}", short_list(&names)));
        }
    }
    out.extend(found);
}
