//! `[FileInfo]` rules (EDS101..EDS104): presence, EDSVersion, date/time formats, field limits.
//!
//! Nothing generated depends on `[FileInfo]`, so none of these is an error: a missing section is a
//! warning (CiA 306 makes it mandatory), and the date/time format is an info aggregated into one
//! diagnostic per file, because vendor tools commonly write ISO dates and 24-hour times. XML
//! files have no `[FileInfo]` and are skipped.

use super::{is_ini, parse_int};
use crate::diag::Diagnostic;
use crate::model::Device;
use crate::read::value::octal_objection;
use crate::rules;

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    if !is_ini(device) {
        return;
    }
    let info = &device.file_info;
    let Some(section) = info.span else {
        out.push(
            Diagnostic::new(&rules::FILE_INFO_MISSING, None, "[FileInfo] is missing")
                .with_help("add a [FileInfo] section with FileName, FileVersion, FileRevision and EDSVersion=4.0"),
        );
        return;
    };

    match &info.eds_version {
        None => out.push(
            Diagnostic::new(
                &rules::EDS_VERSION,
                Some(section),
                "EDSVersion is missing, which CiA 306 reads as version 3.0",
            )
            .with_label("this section has no EDSVersion")
            .with_help("add `EDSVersion=4.0`"),
        ),
        Some(v) if !is_version(&v.value) => out.push(
            Diagnostic::new(
                &rules::EDS_VERSION,
                Some(v.span),
                format!("EDSVersion `{}` is not of the form x.y", v.value),
            )
            .with_label("expected e.g. 4.0")
            .with_help("write `EDSVersion=4.0`"),
        ),
        Some(_) => {}
    }

    let mut bad_formats = Vec::new();
    for (key, value) in [
        ("CreationTime", &info.creation_time),
        ("ModificationTime", &info.modification_time),
    ] {
        if let Some(v) = value.as_deref().filter(|v| !v.trim().is_empty()) {
            if !is_time(v) {
                bad_formats.push(format!("{key}=`{v}`"));
            }
        }
    }
    for (key, value) in [
        ("CreationDate", &info.creation_date),
        ("ModificationDate", &info.modification_date),
    ] {
        if let Some(v) = value.as_deref().filter(|v| !v.trim().is_empty()) {
            if !is_date(v) {
                bad_formats.push(format!("{key}=`{v}`"));
            }
        }
    }
    if !bad_formats.is_empty() {
        // At the first offending key in the file.
        let first_bad = bad_formats
            .iter()
            .filter_map(|b| b.split('=').next())
            .filter_map(|k| info.key_spans.get(k).copied())
            .min_by_key(|span| span.line);
        out.push(
            Diagnostic::new(
                &rules::FILE_DATE_FORMAT,
                first_bad.or(Some(section)),
                format!(
                    "[FileInfo] times/dates not in the CiA 306 form: {}",
                    bad_formats.join(", ")
                ),
            )
            .with_label("in this section")
            .with_help(
                "CiA 306 writes times as hh:mm(AM|PM), e.g. 09:30AM, and dates as mm-dd-yyyy",
            ),
        );
    }

    for (key, value) in [
        ("FileVersion", &info.file_version),
        ("FileRevision", &info.file_revision),
    ] {
        if let Some(v) = value.as_deref().filter(|v| !v.trim().is_empty()) {
            if let Some((message, help)) = octal_objection(v) {
                out.push(
                    Diagnostic::new(
                        &rules::FILE_INFO_LIMITS,
                        info.key_spans.get(key).copied().or(Some(section)),
                        format!("{key} {message}"),
                    )
                    .with_label("in this section")
                    .with_help(help),
                );
            } else if !parse_int(v).is_some_and(|n| (0..=255).contains(&n)) {
                out.push(
                    Diagnostic::new(
                        &rules::FILE_INFO_LIMITS,
                        info.key_spans.get(key).copied().or(Some(section)),
                        format!("{key} `{v}` is not an UNSIGNED8 (0..255)"),
                    )
                    .with_label("in this section")
                    .with_help(format!(
                        "write {key} as a whole number 0..255, e.g. `{key}=1`"
                    )),
                );
            }
        }
    }
    for (key, value, max) in [
        ("Description", &info.description, 243),
        ("CreatedBy", &info.created_by, 245),
        ("ModifiedBy", &info.modified_by, 244),
    ] {
        if let Some(v) = value {
            let len = v.chars().count();
            if len > max {
                out.push(
                    Diagnostic::new(
                        &rules::FILE_INFO_LIMITS,
                        info.key_spans.get(key).copied().or(Some(section)),
                        format!("{key} is {len} characters long; CiA 306 allows {max}"),
                    )
                    .with_label("in this section")
                    .with_help(format!("shorten {key} to {max} characters")),
                );
            }
        }
    }
}

/// `x.y` with decimal digits.
fn is_version(text: &str) -> bool {
    let mut parts = text.trim().split('.');
    let all_digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    matches!((parts.next(), parts.next(), parts.next()), (Some(a), Some(b), None) if all_digits(a) && all_digits(b))
}

/// `hh:mm(AM|PM)`, hours 1..12 (0 tolerated), an optional space before AM/PM.
fn is_time(text: &str) -> bool {
    let t = text.trim().to_ascii_uppercase();
    let Some(clock) = t.strip_suffix("AM").or_else(|| t.strip_suffix("PM")) else {
        return false;
    };
    let Some((h, m)) = clock.trim_end().split_once(':') else {
        return false;
    };
    let num = |s: &str, max: u32| {
        (1..=2).contains(&s.len())
            && s.bytes().all(|b| b.is_ascii_digit())
            && s.parse::<u32>().is_ok_and(|n| n <= max)
    };
    num(h, 12) && m.len() == 2 && num(m, 59)
}

/// `mm-dd-yyyy`.
fn is_date(text: &str) -> bool {
    let parts: Vec<&str> = text.trim().split('-').collect();
    let num = |s: &str, len: usize, lo: u32, hi: u32| {
        s.len() == len
            && s.bytes().all(|b| b.is_ascii_digit())
            && s.parse::<u32>().is_ok_and(|n| (lo..=hi).contains(&n))
    };
    parts.len() == 3
        && num(parts[0], 2, 1, 12)
        && num(parts[1], 2, 1, 31)
        && num(parts[2], 4, 0, 9999)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cia306_times_and_dates() {
        assert!(is_time("09:30AM"));
        assert!(is_time("12:05 pm"));
        assert!(!is_time("17:24:43"));
        assert!(!is_time("13:00PM"));
        assert!(is_date("03-25-2016"));
        assert!(!is_date("2016-03-25"));
        assert!(!is_date("13-01-2016"));
        assert!(is_version("4.0"));
        assert!(!is_version("4"));
        assert!(!is_version("v4.0"));
    }
}
