//! `[DeviceInfo]` rules (EDS105..EDS114): presence, identity against 1018h, bit rates,
//! granularity, PDO counts, CompactPDO, LSS and dynamic channels.
//!
//! `[DeviceInfo]` missing is an error (CiA 306 requires it and the identity comes from it); a
//! mismatch between the identity keys and the 1018h defaults is a warning, since the device
//! answers with its own 1018h anyway. Granularity above 64 and PDO counts above 512 are errors
//! (impossible values); count mismatches are warnings (CompactPDO and vendor habits make them
//! common and edsgen uses the objects as described). Unparseable numbers are the reader's (EDS011).

use super::{at, effective_int, is_ini, raw_section};
use crate::diag::Diagnostic;
use crate::model::{Device, Spanned};
use crate::rules;

/// The bit rates CiA 301 defines, in kbit/s.
pub(super) const STANDARD_BAUD_RATES: [u32; 8] = [10, 20, 50, 125, 250, 500, 800, 1000];

pub(super) fn check(device: &Device, out: &mut Vec<Diagnostic>) {
    let info = &device.device_info;
    if is_ini(device) && info.span.is_none() {
        out.push(
            Diagnostic::new(&rules::DEVICE_INFO_MISSING, None, "[DeviceInfo] is missing")
                .with_help("add a [DeviceInfo] section with VendorName, VendorNumber, ProductName, ProductNumber, RevisionNumber, the BaudRate_x keys and NrOfRXPDO/NrOfTXPDO"),
        );
    }
    identity(device, out);
    baud_rates(device, out);
    granularity(device, out);
    pdo_counts(device, out);
    if let Some(c) = &info.compact_pdo {
        if c.value & !0x3F != 0 {
            out.push(
                Diagnostic::new(
                    &rules::COMPACT_PDO_BITS,
                    Some(c.span),
                    format!(
                        "CompactPDO is {:#04X}; only bits 0..5 (0x3F) have a meaning",
                        c.value
                    ),
                )
                .with_label("bits above 0x3F set")
                .with_help("bit n stands for PDO communication sub n+1; clear the other bits"),
            );
        }
    }
    if info.lss_supported {
        let missing: Vec<String> = (1..=4)
            .filter(|s| device.entry(0x1018, *s).is_none())
            .map(|s| at(0x1018, s))
            .collect();
        if !missing.is_empty() {
            out.push(
                Diagnostic::new(
                    &rules::LSS_IDENTITY,
                    info.span,
                    format!(
                        "LSS_Supported=1 but {} missing; the LSS address needs vendor, product, revision and serial number",
                        if missing.len() == 1 { format!("{} is", missing[0]) } else { format!("{} are", missing.join(", ")) }
                    ),
                )
                .with_label("LSS is declared in this section"),
            );
        }
    }
    dynamic_channels(device, out);
}

fn identity(device: &Device, out: &mut Vec<Diagnostic>) {
    let info = &device.device_info;
    let keys: [(&str, &Option<Spanned<u32>>, u8); 3] = [
        ("VendorNumber", &info.vendor_number, 1),
        ("ProductNumber", &info.product_number, 2),
        ("RevisionNumber", &info.revision_number, 3),
    ];
    for (key, value, sub) in keys {
        let (Some(value), Some(entry)) = (value, device.entry(0x1018, sub)) else {
            continue;
        };
        let Some(default) = effective_int(entry) else {
            continue;
        };
        if default != i128::from(value.value) {
            out.push(
                Diagnostic::new(
                    &rules::IDENTITY_MISMATCH,
                    Some(value.span),
                    format!(
                        "{key} is {:#X} but the default of {} is {default:#X}",
                        value.value,
                        at(0x1018, sub)
                    ),
                )
                .with_label(format!("differs from {}", at(0x1018, sub)))
                .with_help("make the two agree; a master checks the identity it reads from 1018h"),
            );
        }
    }
}

fn baud_rates(device: &Device, out: &mut Vec<Diagnostic>) {
    let info = &device.device_info;
    let Some(section) = info.span else {
        return;
    };
    for (rate, _) in &info.baud_rates {
        if !STANDARD_BAUD_RATES.contains(rate) {
            out.push(
                Diagnostic::new(
                    &rules::BAUD_RATES,
                    Some(section),
                    format!("BaudRate_{rate} is not a CiA 301 bit rate"),
                )
                .with_label("in this section")
                .with_help("the keys are BaudRate_10/20/50/125/250/500/800/1000"),
            );
        }
    }
    if is_ini(device) && !info.baud_rates.iter().any(|(_, on)| *on) {
        out.push(
            Diagnostic::new(
                &rules::BAUD_RATES,
                Some(section),
                "no bit rate is supported: no BaudRate_x=1 key",
            )
            .with_label("in this section")
            .with_help("add BaudRate_x=1 for each supported bit rate, e.g. BaudRate_250=1"),
        );
    }
}

fn granularity(device: &Device, out: &mut Vec<Diagnostic>) {
    let Some(g) = &device.device_info.granularity else {
        return;
    };
    if g.value > 64 {
        out.push(
            Diagnostic::new(
                &rules::GRANULARITY_RANGE,
                Some(g.span),
                format!("Granularity {} is above 64", g.value),
            )
            .with_label("must be 0..64")
            .with_help(
                "use 8 for byte-wise mapping, 1 for bit-wise, 0 if the mapping cannot be changed",
            ),
        );
    }
    if g.value == 0 {
        let writable = device
            .objects
            .values()
            .filter(|o| matches!(o.index, 0x1600..=0x17FF | 0x1A00..=0x1BFF))
            .flat_map(|o| o.subs.values().map(move |s| (o.index, s)))
            .find(|(_, s)| s.access.is_some_and(|a| a.writable()));
        if let Some((index, sub)) = writable {
            out.push(
                Diagnostic::new(
                    &rules::GRANULARITY_ZERO_WRITABLE,
                    Some(g.span),
                    format!(
                        "Granularity is 0 (mapping not modifiable) but {} is writable",
                        at(index, sub.sub_index)
                    ),
                )
                .with_label("mapping declared not modifiable")
                .with_help("set Granularity=8 if the mapping can be changed, or make the mapping objects ro"),
            );
        }
    }
}

fn pdo_counts(device: &Device, out: &mut Vec<Diagnostic>) {
    let info = &device.device_info;
    let count = |range: std::ops::RangeInclusive<u16>| device.objects.range(range).count();
    for (key, value, range, kind) in [
        (
            "NrOfRXPDO",
            &info.nr_of_rx_pdo,
            0x1400..=0x15FF,
            "RPDO communication objects (1400h..15FFh)",
        ),
        (
            "NrOfTXPDO",
            &info.nr_of_tx_pdo,
            0x1800..=0x19FF,
            "TPDO communication objects (1800h..19FFh)",
        ),
    ] {
        let Some(value) = value else { continue };
        if value.value > 512 {
            out.push(
                Diagnostic::new(
                    &rules::PDO_COUNT_LIMIT,
                    Some(value.span),
                    format!("{key} is {}; a device has at most 512", value.value),
                )
                .with_label("above 512"),
            );
            continue;
        }
        let found = count(range);
        if found != value.value as usize {
            out.push(
                Diagnostic::new(
                    &rules::PDO_COUNT_MISMATCH,
                    Some(value.span),
                    format!(
                        "{key} is {} but the file describes {found} {kind}",
                        value.value
                    ),
                )
                .with_label(format!("{found} described"))
                .with_help(format!(
                    "set {key}={found}, or describe the missing PDOs (or use CompactPDO)"
                )),
            );
        }
    }
}

fn dynamic_channels(device: &Device, out: &mut Vec<Diagnostic>) {
    let section = raw_section(device, "DynamicChannels");
    let flag = device.device_info.dynamic_channels_supported;
    match (flag != 0, section) {
        (true, None) => out.push(
            Diagnostic::new(
                &rules::DYNAMIC_CHANNELS_FLAG,
                device.device_info.span,
                format!(
                    "DynamicChannelsSupported={flag} but there is no [DynamicChannels] section"
                ),
            )
            .with_label("declared in this section")
            .with_help("add [DynamicChannels], or set DynamicChannelsSupported=0"),
        ),
        (false, Some(s)) if is_ini(device) => out.push(
            Diagnostic::new(
                &rules::DYNAMIC_CHANNELS_FLAG,
                Some(s.span),
                "[DynamicChannels] is present but DynamicChannelsSupported is 0 or missing",
            )
            .with_label("this section is ignored by tools that honour the flag")
            .with_help("set DynamicChannelsSupported=1 in [DeviceInfo]"),
        ),
        _ => {}
    }
}
