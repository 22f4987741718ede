//! Rules on the sections the model keeps verbatim or lightly (EDS509..EDS513): modules,
//! `[Comments]`, object links and `[DynamicChannels]`.
//!
//! None of these feeds the generated object dictionary, so all are warnings (or an info for
//! network-variable objects described inside a dynamic-channel range): they tell an integrator
//! that other tools will read these sections differently.

use super::{obj, parse_int, raw_section};
use crate::diag::short_list;
use crate::diag::Diagnostic;
use crate::model::{AccessType, BasicType, Device, RawEntry, RawSection};
use crate::read::value::octal_objection;
use crate::rules;

/// Longest `[Comments]` line CiA 306 allows.
const MAX_COMMENT_LINE: usize = 249;

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    modules(device, out);
    comments(device, out);
    object_links(device, out);
    dynamic_channels(device, out);
}

fn key<'a>(section: &'a RawSection, name: &str) -> Option<&'a RawEntry> {
    section
        .entries
        .iter()
        .find(|e| e.key.trim().eq_ignore_ascii_case(name))
}

/// The numbered keys (`1=`, `2=`, ...) of a section, as (number, entry).
fn numbered(section: &RawSection) -> Vec<(u32, &RawEntry)> {
    section
        .entries
        .iter()
        .filter_map(|e| {
            let k = e.key.trim();
            (!k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
                .then(|| k.parse::<u32>().ok().map(|n| (n, e)))
                .flatten()
        })
        .collect()
}

/// Checks `NrOfEntries` against the numbered keys of a list section.
fn count_matches(section: &RawSection, out: &mut Vec<Diagnostic>) {
    let entries = numbered(section);
    let declared = key(section, "NrOfEntries");
    let Some(n) = declared.and_then(|d| parse_int(&d.value)) else {
        return;
    };
    if n != entries.len() as i128 {
        let span = declared.map_or(section.span, |d| d.span);
        out.push(
            Diagnostic::new(
                &rules::MODULES,
                Some(span),
                format!(
                    "[{}] NrOfEntries is {n} but {} entries are listed",
                    section.name.trim(),
                    entries.len()
                ),
            )
            .with_label(format!("{} listed", entries.len()))
            .with_help(format!("set NrOfEntries={}", entries.len())),
        );
    }
}

/// The module number of an `M<n>...` section, if the name is one of the module sections.
fn module_number(name: &str) -> Option<u32> {
    let rest = name.trim().strip_prefix(['M', 'm'])?;
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    let tail = rest[digits.len()..].to_ascii_lowercase();
    let known = [
        "moduleinfo",
        "comments",
        "fixedobjects",
        "subextends",
        "fixed",
        "subext",
    ];
    (!digits.is_empty() && known.iter().any(|k| tail.starts_with(k)))
        .then(|| digits.parse().ok())
        .flatten()
}

fn modules(device: &Device, out: &mut Vec<Diagnostic>) {
    let supported = raw_section(device, "SupportedModules");
    let supported_count = supported
        .and_then(|s| key(s, "NrOfEntries"))
        .and_then(|e| parse_int(&e.value));
    if let Some(connected) = raw_section(device, "ConnectedModules") {
        count_matches(connected, out);
        for (_, e) in numbered(connected) {
            let Some(module) = parse_int(&e.value) else {
                continue;
            };
            if supported_count.is_none_or(|max| module < 1 || module > max) {
                out.push(
                    Diagnostic::new(
                        &rules::MODULES,
                        Some(e.span),
                        match supported_count {
                            Some(max) => format!("[ConnectedModules] names module {module}; [SupportedModules] has {max}"),
                            None => format!("[ConnectedModules] names module {module} but there is no [SupportedModules]"),
                        },
                    )
                    .with_label("no such module"),
                );
            }
        }
    }
    let mut orphans = Vec::new();
    let mut first = None;
    for s in &device.other_sections {
        let Some(n) = module_number(&s.name) else {
            continue;
        };
        let lower = s.name.trim().to_ascii_lowercase();
        if lower.ends_with("fixedobjects") || lower.ends_with("subextends") {
            count_matches(s, out);
        }
        if lower.contains("subext") {
            if let Some(count) = key(s, "Count") {
                if !count_is_valid(&count.value) {
                    out.push(
                        Diagnostic::new(&rules::MODULES, Some(count.span), match count.value.split(';').find_map(octal_objection) {
                            Some((octal, _)) => format!("[{}] Count `{}` is not U8 or 0;U8: {octal}", s.name.trim(), count.value),
                            None => format!("[{}] Count `{}` is not U8 or 0;U8", s.name.trim(), count.value),
                        })
                            .with_label("malformed Count")
                            .with_help("write Count=n (sub-objects per module) or Count=0;n (n bits per module)"),
                    );
                }
            }
        }
        if supported_count.is_none_or(|max| n < 1 || i128::from(n) > max) {
            orphans.push(format!("[{}]", s.name.trim()));
            first.get_or_insert(s.span);
        }
    }
    if !orphans.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::MODULES,
                first,
                format!(
                    "{} module section(s) for modules that [SupportedModules] does not declare: {}",
                    orphans.len(),
                    short_list(&orphans)
                ),
            )
            .with_label("no such module")
            .with_help("declare the modules in [SupportedModules] NrOfEntries"),
        );
    }
}

fn count_is_valid(text: &str) -> bool {
    let u8_ok = |s: &str| parse_int(s).is_some_and(|n| (0..=255).contains(&n));
    match text.split_once(';') {
        None => u8_ok(text),
        Some((a, b)) => parse_int(a) == Some(0) && u8_ok(b),
    }
}

fn comments(device: &Device, out: &mut Vec<Diagnostic>) {
    let present = device.comments.len();
    if let Some(declared) = &device.comment_lines {
        if declared.value as usize != present {
            out.push(
                Diagnostic::new(
                    &rules::COMMENTS_LINES,
                    Some(declared.span),
                    format!(
                        "[Comments] Lines is {} but {present} LineN keys are present",
                        declared.value
                    ),
                )
                .with_label(format!("{present} lines present"))
                .with_help(format!(
                    "set Lines={present}; python's canopen fails on a missing LineN"
                )),
            );
        }
    }
    let long: Vec<String> = device
        .comments
        .iter()
        .enumerate()
        .filter(|(_, line)| line.chars().count() > MAX_COMMENT_LINE)
        .map(|(i, _)| format!("Line{}", i + 1))
        .collect();
    if !long.is_empty() {
        out.push(Diagnostic::new(
            &rules::COMMENTS_LINES,
            device.comment_lines.as_ref().map(|l| l.span),
            format!(
                "[Comments] lines longer than {MAX_COMMENT_LINE} characters: {}",
                short_list(&long)
            ),
        ));
    }
}

fn object_links(device: &Device, out: &mut Vec<Diagnostic>) {
    for o in device.objects.values() {
        let missing: Vec<String> = o
            .object_links
            .iter()
            .filter(|l| !device.objects.contains_key(l))
            .map(|l| obj(*l))
            .collect();
        if !missing.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::OBJECT_LINK_MISSING,
                    Some(o.span),
                    format!(
                        "the object links of {} name objects that do not exist: {}",
                        obj(o.index),
                        short_list(&missing)
                    ),
                )
                .with_label("links from this object")
                .with_help(format!(
                    "fix [{:X}ObjectLinks] or describe the linked objects",
                    o.index
                )),
            );
        }
    }
}

/// A `[DynamicChannels]` range `0xA000-0xA0FF`, parsed.
fn range(text: &str) -> Option<(u16, u16)> {
    let (a, b) = text.split_once('-')?;
    let (a, b) = (parse_int(a)?, parse_int(b)?);
    let (a, b) = (u16::try_from(a).ok()?, u16::try_from(b).ok()?);
    (a <= b).then_some((a, b))
}

fn dynamic_channels(device: &Device, out: &mut Vec<Diagnostic>) {
    let Some(section) = raw_section(device, "DynamicChannels") else {
        return;
    };
    let segment_keys = ["type", "dir", "range", "ppoffset"];
    let mut segments = std::collections::BTreeSet::new();
    for e in &section.entries {
        let k = e.key.trim().to_ascii_lowercase();
        for prefix in segment_keys {
            if let Some(n) = k.strip_prefix(prefix).and_then(|n| n.parse::<u32>().ok()) {
                segments.insert(n);
            }
        }
    }
    if let Some(declared) = key(section, "NrOfSeg") {
        let n = parse_int(&declared.value);
        let expected: Vec<u32> = n.map_or(Vec::new(), |n| (1..=n.clamp(0, 255) as u32).collect());
        if n.is_none() || segments.iter().copied().collect::<Vec<_>>() != expected {
            out.push(
                Diagnostic::new(
                    &rules::DYNAMIC_CHANNELS_SECTION,
                    Some(declared.span),
                    format!(
                        "[DynamicChannels] NrOfSeg is {} but segments {:?} are described",
                        declared.value, segments
                    ),
                )
                .with_label("segment count")
                .with_help("describe segments 1..NrOfSeg with TypeN, DirN, RangeN and PPOffsetN"),
            );
        }
    }
    let mut covered = Vec::new();
    for e in &section.entries {
        let k = e.key.trim().to_ascii_lowercase();
        let why = if k.starts_with("type") {
            parse_int(&e.value)
                .and_then(|t| u16::try_from(t).ok())
                .and_then(BasicType::from_index)
                .is_none()
                .then_some("is not a CiA 301 basic data type index")
        } else if k.starts_with("dir") {
            AccessType::parse(&e.value)
                .is_none()
                .then_some("is not an access type")
        } else if k.starts_with("range") {
            match range(&e.value) {
                Some(r) => {
                    covered.push((r, e.span));
                    None
                }
                None => Some("is not an index range `0xLLLL-0xHHHH`"),
            }
        } else {
            None
        };
        if let Some(why) = why {
            let why = match octal_objection(&e.value) {
                Some((octal, _)) => format!("{why}: {octal}"),
                None => why.to_owned(),
            };
            out.push(
                Diagnostic::new(
                    &rules::DYNAMIC_CHANNELS_SECTION,
                    Some(e.span),
                    format!("[DynamicChannels] {}=`{}` {why}", e.key.trim(), e.value),
                )
                .with_label("malformed")
                .with_help("TypeN is a data type index (e.g. 0x0007), DirN an access type (ro/rw/...), RangeN `0xA000-0xA0FF`"),
            );
        }
    }
    for ((lo, hi), span) in covered {
        let inside: Vec<String> = device
            .objects
            .range(lo..=hi)
            .filter(|(_, o)| !o.implicit)
            .map(|(i, _)| obj(*i))
            .collect();
        if !inside.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::DYNAMIC_CHANNEL_OBJECTS,
                    Some(span),
                    format!(
                        "{} object(s) described inside the dynamic-channel range {lo:04X}h..{hi:04X}h: {}",
                        inside.len(),
                        short_list(&inside)
                    ),
                )
                .with_label("this range is managed dynamically")
                .with_help("CiA 306 says network-variable arrays covered by [DynamicChannels] are not described in the EDS"),
            );
        }
    }
}
