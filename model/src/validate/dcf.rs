//! DCF and commissioning rules (EDS501..EDS508): NodeID, Baudrate, LSS serial number, name
//! lengths, DCF-only items in an EDS, a DCF without commissioning, UploadFile/DownloadFile, and
//! configured values a download cannot write.
//!
//! A NodeID outside 1..127 or a bit rate the device cannot run are errors: the configuration
//! cannot be applied. The rest are warnings; DCF-only items in an EDS and ParameterValue on
//! read-only entries are aggregated into one diagnostic per file, since tools write them by the
//! hundred. XDC files carry the same data (deviceCommissioning, actualValue) and get the same rules.

use super::device_info::STANDARD_BAUD_RATES;
use super::{at, effective_int, entry_name, EntryName};
use crate::diag::short_list;
use crate::diag::{Diagnostic, Severity};
use crate::model::{AccessType, Device, Format, ObjectType, Span};
use crate::rules;

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    commissioning(device, out);
    dcf_items(device, out);
    domain_files(device, out);
}

fn commissioning(device: &Device, out: &mut Vec<Diagnostic>) {
    let Some(c) = &device.commissioning else {
        if device.source.format == Format::Dcf {
            out.push(
                Diagnostic::new(
                    &rules::DCF_WITHOUT_COMMISSIONING,
                    None,
                    "this .dcf file has no [DeviceComissioning] section, so it configures no node",
                )
                .with_help(
                    "add [DeviceComissioning] with NodeID and Baudrate, or name the file .eds",
                ),
            );
        }
        return;
    };
    if let Some(id) = &c.node_id {
        if id.value == 255 {
            out.push(
                Diagnostic::new(&rules::DCF_NODE_ID, Some(id.span), "NodeID 255 means unconfigured: the node-ID is assigned by LSS")
                    .with_severity(Severity::Warning)
                    .with_label("unconfigured node-ID")
                    .with_help("$NODEID values of this DCF cannot be resolved until LSS assigns a node-ID 1..127"),
            );
        } else if id.value == 0 {
            out.push(
                Diagnostic::new(&rules::DCF_NODE_ID, Some(id.span), "NodeID 0 means not commissioned: the DCF names no node-ID")
                    .with_severity(Severity::Warning)
                    .with_label("no node-ID")
                    .with_help("set the node-ID 1..127 the device will use; CANopenEditor writes 0 when none is set"),
            );
        } else if !(1..=127).contains(&id.value) {
            out.push(
                Diagnostic::new(
                    &rules::DCF_NODE_ID,
                    Some(id.span),
                    format!("NodeID {} is outside 1..127", id.value),
                )
                .with_label("not a CANopen node-ID")
                .with_help("a CANopen node-ID is 1..127"),
            );
        }
    }
    if let Some(rate) = &c.baudrate {
        if rate.value == 0 {
            out.push(
                Diagnostic::new(&rules::DCF_BAUDRATE, Some(rate.span), "Baudrate 0 means not commissioned: the DCF names no bit rate")
                    .with_severity(Severity::Warning)
                    .with_label("no bit rate")
                    .with_help("set the bit rate in kbit/s (10, 20, 50, 125, 250, 500, 800 or 1000); CANopenEditor writes 0 when none is set"),
            );
        } else if !STANDARD_BAUD_RATES.contains(&rate.value) {
            out.push(
                Diagnostic::new(
                    &rules::DCF_BAUDRATE,
                    Some(rate.span),
                    format!("Baudrate {} kbit/s is not a CiA 301 bit rate", rate.value),
                )
                .with_label("not a CiA 301 bit rate")
                .with_help("use 10, 20, 50, 125, 250, 500, 800 or 1000 (kbit/s)"),
            );
        } else {
            let rates = &device.device_info.baud_rates;
            let enabled = rates.iter().any(|(r, on)| *r == rate.value && *on);
            if !rates.is_empty() && !enabled {
                out.push(
                    Diagnostic::new(
                        &rules::DCF_BAUDRATE,
                        Some(rate.span),
                        format!("Baudrate {} kbit/s is not supported: [DeviceInfo] has no BaudRate_{}=1", rate.value, rate.value),
                    )
                    .with_label("the device does not support this bit rate")
                    .with_help("pick a bit rate [DeviceInfo] enables"),
                );
            }
        }
    }
    if let (Some(serial), Some(entry)) = (c.lss_serial_number, device.entry(0x1018, 4)) {
        if let Some(v) = effective_int(entry) {
            if v != i128::from(serial) {
                out.push(
                    Diagnostic::new(
                        &rules::LSS_SERIAL_MISMATCH,
                        Some(c.span),
                        format!(
                            "LSS_SerialNumber is {serial:#X} but {} is {v:#X}",
                            at(0x1018, 4)
                        ),
                    )
                    .with_label("in this section")
                    .with_help("make LSS_SerialNumber and 1018h sub 4 agree"),
                );
            }
        }
    }
    for (key, value, max) in [
        ("NodeName", &c.node_name, 246),
        ("NetworkName", &c.network_name, 243),
    ] {
        if let Some(len) = value
            .as_ref()
            .map(|v| v.chars().count())
            .filter(|l| *l > max)
        {
            out.push(
                Diagnostic::new(
                    &rules::COMMISSIONING_NAME_LENGTH,
                    Some(c.span),
                    format!("{key} is {len} characters long; CiA 306 allows {max}"),
                )
                .with_label("in this section"),
            );
        }
    }
}

/// The first span and the names of entries matching `pred`.
fn collect(
    device: &Device,
    pred: impl Fn(&crate::model::SubObject) -> Option<Span>,
) -> (Option<Span>, Vec<String>) {
    let mut first = None;
    let mut names = Vec::new();
    for o in device.objects.values() {
        for s in o.subs.values() {
            if let Some(span) = pred(s) {
                first.get_or_insert(span);
                names.push(entry_name(device, o.index, s.sub_index));
            }
        }
    }
    (first, names)
}

fn dcf_items(device: &Device, out: &mut Vec<Diagnostic>) {
    match device.source.format {
        Format::Eds => {
            if let Some(c) = &device.commissioning {
                out.push(
                    Diagnostic::new(
                        &rules::DCF_ITEM_IN_EDS,
                        Some(c.span),
                        "[DeviceComissioning] in an .eds file",
                    )
                    .with_label("DCF-only section")
                    .with_help("an EDS describes a device type; configuration belongs in a .dcf"),
                );
            }
            let (first, names) = collect(device, |s| s.parameter_value.as_ref().map(|v| v.span));
            if !names.is_empty() {
                out.push(
                    Diagnostic::new(
                        &rules::DCF_ITEM_IN_EDS,
                        first,
                        format!(
                            "ParameterValue on {} entr{} of an .eds file: {}",
                            names.len(),
                            if names.len() == 1 { "y" } else { "ies" },
                            short_list(&names)
                        ),
                    )
                    .with_label("DCF-only key")
                    .with_help("name the file .dcf, or remove the ParameterValue keys"),
                );
            }
            let (first, names) = collect(device, |s| s.denotation.as_ref().map(|_| s.span));
            if !names.is_empty() {
                out.push(
                    Diagnostic::new(
                        &rules::DCF_ITEM_IN_EDS,
                        first,
                        format!(
                            "Denotation on {} entr{} of an .eds file: {}",
                            names.len(),
                            if names.len() == 1 { "y" } else { "ies" },
                            short_list(&names)
                        ),
                    )
                    .with_label("DCF-only key")
                    .with_help("name the file .dcf, or remove the Denotation keys"),
                );
            }
        }
        Format::Dcf | Format::Xdc => {
            let is_xml = device.source.format == Format::Xdc;
            let (first, names) = collect(device, |s| {
                let read_only = matches!(s.access, Some(AccessType::Ro | AccessType::Const));
                // An entry refused on scan was not read back: its value claims nothing.
                let param = s
                    .parameter_value
                    .as_ref()
                    .filter(|_| s.obj_flags & super::REFUSE_READ_ON_SCAN == 0)?;
                let (Some(p), Some(d)) = (
                    param.value.as_ref(),
                    s.default.as_ref().and_then(|d| d.value.as_ref()),
                ) else {
                    return None;
                };
                (read_only && p != d).then_some(param.span)
            });
            if !names.is_empty() {
                out.push(
                    Diagnostic::new(
                        &rules::PARAMETER_VALUE_READ_ONLY,
                        first,
                        format!(
                            "{} read-only entr{} ha{} {} other than the {}, which a download cannot write: {}",
                            names.len(),
                            if names.len() == 1 { "y" } else { "ies" },
                            if names.len() == 1 { "s" } else { "ve" },
                            if is_xml { "an actualValue" } else { "a ParameterValue" },
                            if is_xml { "defaultValue" } else { "DefaultValue" },
                            short_list(&names)
                        ),
                    )
                    .with_label("read-only entry")
                    .with_help("a configuration tool cannot write ro/const entries; drop these values or make the entries writable"),
                );
            }
        }
        Format::Xdd | Format::Esi | Format::OdvaEds | Format::Gsdml | Format::Gsd => {}
    }
}

fn domain_files(device: &Device, out: &mut Vec<Diagnostic>) {
    for o in device.objects.values() {
        for s in o.subs.values() {
            let is_domain = o.object_type == ObjectType::Domain || s.data_type == Some(0x000F);
            let name = EntryName::new(device, o.index, s.sub_index);
            for (key, file, at_key, max, ok_access) in [
                (
                    "UploadFile",
                    &s.upload_file,
                    s.key_spans.upload_file,
                    244,
                    &[AccessType::Ro, AccessType::Const][..],
                ),
                (
                    "DownloadFile",
                    &s.download_file,
                    s.key_spans.download_file,
                    242,
                    &[AccessType::Wo][..],
                ),
            ] {
                let Some(file) = file else { continue };
                let problem = if !is_domain {
                    Some(format!("{name} has {key} but is not a DOMAIN"))
                } else if let Some(a) = s.access.filter(|a| !ok_access.contains(a)) {
                    Some(format!("{name} has {key} but its access is {}", a.as_str()))
                } else {
                    let len = file.chars().count();
                    (len > max).then(|| {
                        format!("{key} of {name} is {len} characters long; CiA 306 allows {max}")
                    })
                };
                if let Some(problem) = problem {
                    out.push(
                        Diagnostic::new(
                            &rules::DOMAIN_FILE_KEYS,
                            Some(at_key.unwrap_or(s.span)),
                            problem,
                        )
                        .with_label(format!("{key} here"))
                        .with_help(
                            "UploadFile belongs on ro/const DOMAINs, DownloadFile on wo DOMAINs",
                        ),
                    );
                }
            }
        }
    }
}
