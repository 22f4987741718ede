//! Object-list rules (EDS201..EDS209): `[MandatoryObjects]`, `[OptionalObjects]`,
//! `[ManufacturerObjects]` against the object sections, and the objects CiA 301 requires.
//!
//! edsgen builds the dictionary from the union of the lists and the sections, so list
//! bookkeeping (counts, duplicates, unlisted sections) cannot make generated code wrong: those
//! are warnings, because Lely (lists only) and python (sections only) would disagree on the file.
//! Errors: no `[MandatoryObjects]` at all, a listed object with no description (nothing to
//! generate), and a missing 1000h/1001h/1018h (CiA 301 mandatory objects). List rules apply to
//! EDS and DCF only; the required-object rules apply to every format.

use std::collections::BTreeMap;

use super::{is_ini, obj};
use crate::diag::short_list;
use crate::diag::{Diagnostic, Severity};
use crate::model::{Device, ObjectListKind, Span};
use crate::rules;

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    if is_ini(device) {
        lists(device, out);
    }
    // CoE has neither NMT error control nor a mandatory 1001h, and an ESI file may carry no
    // dictionary at all.
    if !device.source.format.is_coe() {
        required(device, out);
    }
}

fn list_name(kind: ObjectListKind) -> &'static str {
    match kind {
        ObjectListKind::Mandatory => "[MandatoryObjects]",
        ObjectListKind::Optional => "[OptionalObjects]",
        ObjectListKind::Manufacturer => "[ManufacturerObjects]",
    }
}

/// The list an index belongs in, by range. Data-type definitions (below 1000h) go in
/// `[OptionalObjects]`, as the CiA 306 example and the tools do.
fn home_list(index: u16) -> ObjectListKind {
    match index {
        0x1000 | 0x1001 | 0x1018 => ObjectListKind::Mandatory,
        0x2000..=0x5FFF => ObjectListKind::Manufacturer,
        _ => ObjectListKind::Optional,
    }
}

/// Whether `index` may sit in list `kind`. 1018h may also be in the optional list (files older
/// than CiA 301 v4 list it there).
fn allowed_in(index: u16, kind: ObjectListKind) -> bool {
    match kind {
        ObjectListKind::Mandatory => matches!(index, 0x1000 | 0x1001 | 0x1018),
        ObjectListKind::Manufacturer => (0x2000..=0x5FFF).contains(&index),
        ObjectListKind::Optional => !(0x2000..=0x5FFF).contains(&index),
    }
}

fn lists(device: &Device, out: &mut Vec<Diagnostic>) {
    let has = |kind| device.object_lists.iter().any(|l| l.kind == kind);
    if !has(ObjectListKind::Mandatory) {
        out.push(
            Diagnostic::new(
                &rules::MANDATORY_LIST_MISSING,
                None,
                "[MandatoryObjects] is missing",
            )
            .with_help(
                "add [MandatoryObjects] with SupportedObjects=3 and 1=0x1000, 2=0x1001, 3=0x1018",
            ),
        );
    }
    for kind in [ObjectListKind::Optional, ObjectListKind::Manufacturer] {
        if has(kind) {
            continue;
        }
        let orphans: Vec<String> = device
            .objects
            .values()
            .filter(|o| !o.implicit && o.index >= 0x1000 && home_list(o.index) == kind)
            .map(|o| obj(o.index))
            .collect();
        if !orphans.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::OBJECT_LIST_MISSING,
                    None,
                    format!(
                        "{} is missing but {} object(s) of its range are described: {}",
                        list_name(kind),
                        orphans.len(),
                        short_list(&orphans)
                    ),
                )
                .with_help(format!("add {} listing them", list_name(kind))),
            );
        }
    }

    let mut first_listing: BTreeMap<u16, (ObjectListKind, Span)> = BTreeMap::new();
    // (list it is in, list it belongs in) -> (first entry, indices)
    let mut wrong: BTreeMap<(&str, &str), (Span, Vec<String>)> = BTreeMap::new();
    for list in &device.object_lists {
        let name = list_name(list.kind);
        match &list.supported_objects {
            None => out.push(
                Diagnostic::new(
                    &rules::SUPPORTED_OBJECTS_COUNT,
                    Some(list.span),
                    format!("{name} has no SupportedObjects"),
                )
                .with_label("no SupportedObjects key")
                .with_help(format!("add SupportedObjects={}", list.entries.len())),
            ),
            Some(n) if n.value as usize != list.entries.len() => out.push(
                Diagnostic::new(
                    &rules::SUPPORTED_OBJECTS_COUNT,
                    Some(n.span),
                    format!(
                        "{name} SupportedObjects is {} but {} entries are listed",
                        n.value,
                        list.entries.len()
                    ),
                )
                .with_label(format!("{} listed", list.entries.len()))
                .with_help(format!("set SupportedObjects={}", list.entries.len())),
            ),
            Some(_) => {
                let mut numbers: Vec<u32> = list.entries.iter().map(|(n, _)| *n).collect();
                numbers.sort_unstable();
                if let Some(missing) = (1..).zip(&numbers).find(|(want, got)| want != *got) {
                    out.push(
                        Diagnostic::new(
                            &rules::SUPPORTED_OBJECTS_COUNT,
                            Some(list.span),
                            format!(
                                "{name} entries are not numbered 1..{}: entry {} is missing",
                                numbers.len(),
                                missing.0
                            ),
                        )
                        .with_label("in this list")
                        .with_help("number the entries 1, 2, 3, ... without gaps"),
                    );
                }
            }
        }
        let count = list.supported_objects.as_ref().map(|n| n.value);
        for (number, entry) in &list.entries {
            let index = entry.value;
            if let Some((first_kind, first_span)) = first_listing.get(&index) {
                out.push(
                    Diagnostic::new(
                        &rules::LISTED_TWICE,
                        Some(entry.span),
                        format!(
                            "{} is listed twice (first in {} at line {})",
                            obj(index),
                            list_name(*first_kind),
                            first_span.line
                        ),
                    )
                    .with_label("listed again here")
                    .with_help("remove this entry and fix SupportedObjects"),
                );
                continue;
            }
            first_listing.insert(index, (list.kind, entry.span));
            if !allowed_in(index, list.kind) {
                wrong
                    .entry((list_name(list.kind), list_name(home_list(index))))
                    .or_insert((entry.span, Vec::new()))
                    .1
                    .push(obj(index));
            }
            let described = device
                .objects
                .get(&index)
                .is_some_and(|o| o.implicit || o.span != entry.span);
            if !described {
                // An entry numbered beyond SupportedObjects is not part of the list for tools
                // that honour the count (Lely); only a warning then (EDS203 reports the count).
                let beyond_count = count.is_some_and(|n| *number > n);
                let mut diag = Diagnostic::new(
                    &rules::LISTED_WITHOUT_SECTION,
                    Some(entry.span),
                    if beyond_count {
                        format!(
                            "{} is listed (entry {number}, beyond SupportedObjects) but has no [{:X}] section",
                            obj(index),
                            index
                        )
                    } else {
                        format!("{} is listed but has no [{:X}] section", obj(index), index)
                    },
                )
                .with_label("no description for this object")
                .with_help(format!(
                    "describe the object in a [{index:X}] section, or remove it from the list"
                ));
                if beyond_count {
                    diag = diag.with_severity(Severity::Warning);
                }
                out.push(diag);
            }
        }
    }

    for ((in_list, home), (span, items)) in wrong {
        out.push(
            Diagnostic::new(
                &rules::WRONG_OBJECT_LIST,
                Some(span),
                format!(
                    "{} index(es) listed in {in_list} belong in {home}: {}",
                    items.len(),
                    short_list(&items)
                ),
            )
            .with_label("wrong list for this index")
            .with_help(format!("move them to {home}")),
        );
    }

    // Unlisted sections: one diagnostic per list they belong in.
    let mut unlisted: BTreeMap<&str, (Span, Vec<String>)> = BTreeMap::new();
    for o in device.objects.values() {
        if o.implicit || o.index < 0x1000 || first_listing.contains_key(&o.index) {
            continue;
        }
        let home = home_list(o.index);
        if !has(home) {
            continue; // EDS201/EDS202 already cover the whole list.
        }
        unlisted
            .entry(list_name(home))
            .or_insert((o.span, Vec::new()))
            .1
            .push(obj(o.index));
    }
    for (home, (span, items)) in unlisted {
        out.push(
            Diagnostic::new(
                &rules::UNLISTED_OBJECT,
                Some(span),
                format!(
                    "{} described object(s) are not listed in any object list: {}",
                    items.len(),
                    short_list(&items)
                ),
            )
            .with_label("not listed")
            .with_help(format!("add them to {home} and raise SupportedObjects")),
        );
    }
}

fn required(device: &Device, out: &mut Vec<Diagnostic>) {
    for (index, what) in [
        (0x1000, "device type"),
        (0x1001, "error register"),
        (0x1018, "identity"),
    ] {
        if !device.objects.contains_key(&index) {
            out.push(
                Diagnostic::new(
                    &rules::REQUIRED_OBJECT_MISSING,
                    None,
                    format!("{} ({what}) is missing; CiA 301 requires it", obj(index)),
                )
                .with_help(format!(
                    "describe {} and list it in [MandatoryObjects]",
                    obj(index)
                )),
            );
        }
    }
    let has = |i| device.objects.contains_key(&i);
    if !has(0x1017) && !has(0x100C) && !has(0x100D) {
        out.push(
            Diagnostic::new(
                &rules::ERROR_CONTROL_MISSING,
                None,
                "no error control: neither 1017h (heartbeat producer) nor 100Ch/100Dh (node guarding) is described",
            )
            .with_help("describe 1017h (producer heartbeat time); CiA 301 requires one error-control mechanism"),
        );
    }
}
