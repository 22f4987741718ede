//! `edsgen ecat check --iface IFACE --esi FILE [--device NAME|#xCODE] [--position N]`: a live
//! EtherCAT SubDevice judged against its ESI, in the validator's diagnostic format (as `edsgen
//! check` judges a CANopen node): its SII read back through the EEPROM interface (identity and
//! order string, CHK006; SyncManagers, CHK007, with the ESC's SyncManager count), the PDO
//! assignment and the default PDOs' mappings read by SDO against what the ESI says the device
//! powers up with (CHK008: the dictionary's 1C1xh and mapping defaults, else the `Sm`
//! attributes and `Entry` lists), and every readable entry of
//! the ESI's dictionary read by SDO: missing (CHK001), refused (CHK003), of another length than
//! its type (CHK002), or, for a constant or a read-only entry no PDO can carry, other than the
//! ESI's default (CHK005). Reading the SubDevice ([`observe`], ethercrab in Pre-Op) is apart
//! from judging what was read ([`judge`]).

use std::path::Path;
use std::process::ExitCode;

use edsgen_model::diag::Diagnostic;
use edsgen_model::model::{AccessType, Device, EcPdo, ObjectType, SmKind, Span, SubObject, Value};
use edsgen_model::read;
use edsgen_model::rules::{
    CHK_MISSING as CHK001, CHK_PDO_ASSIGNMENT as CHK008, CHK_SII_IDENTITY as CHK006,
    CHK_SYNC_MANAGER as CHK007, CHK_UNREADABLE as CHK003,
};
use edsgen_runtime::wire::sdo::{abort_meaning, Multiplexer};
use ethercrab::{MainDevice, SubDevice, SubDeviceRef};

use super::sdo::upload;
use super::{discover, runtime, SubDeviceArgs};
use crate::cmd::canopen::check::{default_differs, length_differs, report, Format};
use crate::cmd::canopen::sdo::show_mux;
use crate::cmd::fail;

/// `edsgen ecat check` options.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    sub_device: SubDeviceArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// Treat warnings (read-only values differing from defaults) as differences too (exit 1).
    #[arg(long)]
    deny_warnings: bool,
}

/// What was read from the SubDevice, for [`judge`].
#[derive(Debug)]
pub struct Observed {
    /// Its SII image read back through the EEPROM interface, as the SII reader models it.
    pub sii: Device,
    /// ESC register 0x0005: how many SyncManager channels the ESC has.
    pub sm_channels: u8,
    /// Per process-data SyncManager of the ESI, 1C10h + its number read by SDO: the PDOs
    /// assigned (sub-indices 1..), or the abort code.
    pub assignments: Vec<(u8, Result<Vec<u16>, u32>)>,
    /// Per PDO the ESI assigns by default, its mapping object read by SDO: the entries
    /// (index << 16 | sub << 8 | bits), or the abort code.
    pub mappings: Vec<(u16, Result<Vec<u32>, u32>)>,
    /// Every readable entry of the ESI's dictionary, in order: its bytes, or the abort code.
    /// An object whose sub-index 0 answers 0602 0000h (no such object) has no more entries.
    pub entries: Vec<(Multiplexer, Result<Vec<u8>, u32>)>,
}

/// Runs `edsgen ecat check`: 0 when the SubDevice matches, 1 for errors (or warnings with
/// `--deny-warnings`), 2 when the ESI, the interface or the SubDevice cannot be read.
pub fn run(args: &CheckArgs) -> ExitCode {
    let read = match crate::cmd::load(&args.sub_device.esi, args.sub_device.device.as_deref()) {
        Ok(read) => read,
        Err(err) => return fail(err),
    };
    if read.nothing_read || read.device.ethercat().is_none() {
        return fail(format!(
            "{}: not an ESI device",
            args.sub_device.esi.display()
        ));
    }
    let runtime = match runtime() {
        Ok(runtime) => runtime,
        Err(message) => return fail(message),
    };
    let position = args.sub_device.position;
    let observed = runtime.block_on(async {
        let (maindevice, group) = discover(&args.sub_device.iface).await?;
        let sub_device = group
            .subdevice(&maindevice, position)
            .map_err(|_| format!("no SubDevice at position {position}"))?;
        observe(&maindevice, &sub_device, &read.device).await
    });
    let observed = match observed {
        Ok(observed) => observed,
        Err(message) => return fail(format!("{}: {message}", args.sub_device.iface)),
    };
    let diags = judge(&read.device, position, &observed);
    let what = format!("SubDevice {position}");
    report(
        args.format,
        &args.sub_device.esi,
        &read.text,
        diags,
        &what,
        args.deny_warnings,
    )
}

/// Reads from the SubDevice in Pre-Op what [`judge`] compares with `esi`.
pub async fn observe(
    maindevice: &MainDevice<'_>,
    sub_device: &SubDeviceRef<'_, &SubDevice>,
    esi: &Device,
) -> Result<Observed, String> {
    let size = sub_device
        .eeprom_size(maindevice)
        .await
        .map_err(|e| format!("SII size: {e}"))?;
    let mut image = vec![0u8; size];
    sub_device
        .eeprom_read_raw(maindevice, 0, &mut image)
        .await
        .map_err(|e| format!("SII: {e}"))?;
    let sii = read::sii::read(Path::new("SII"), &image).device;
    let sm_channels: u8 = sub_device
        .register_read(0x0005u16)
        .await
        .map_err(|e| format!("ESC register 0x0005: {e}"))?;
    let mut observed = Observed {
        sii,
        sm_channels,
        assignments: Vec::new(),
        mappings: Vec::new(),
        entries: Vec::new(),
    };
    // Without CoE there is no SDO: the SII is all a SubDevice says of itself.
    let Some(ec) = esi.ethercat().filter(|ec| ec.coe.is_some()) else {
        return Ok(observed);
    };
    for (n, sm) in ec.sync_managers.iter().enumerate() {
        if !matches!(sm.kind, SmKind::Outputs | SmKind::Inputs) {
            continue;
        }
        let index = 0x1C10 + n as u16;
        let list = read_list(sub_device, index, 2).await?;
        let list = list.map(|l| l.into_iter().map(|v| v as u16).collect());
        observed.assignments.push((n as u8, list));
    }
    for pdo in default_pdos(esi) {
        let list = read_list(sub_device, pdo.index, 4).await?;
        observed.mappings.push((pdo.index, list));
    }
    for object in esi.objects.values() {
        if !checked(object.index, &object.object_type) {
            continue;
        }
        for sub in object.subs.values().filter(|s| readable(s)) {
            let mux = Multiplexer::new(object.index, sub.sub_index);
            let value = upload(sub_device, mux).await?;
            let gone = value == Err(0x0602_0000);
            observed.entries.push((mux, value));
            if gone {
                break;
            }
        }
    }
    Ok(observed)
}

/// An array object's entries 1..=sub 0 read by SDO, each `width` bytes, little-endian.
async fn read_list(
    sub_device: &SubDeviceRef<'_, &SubDevice>,
    index: u16,
    width: usize,
) -> Result<Result<Vec<u32>, u32>, String> {
    let count = match upload(sub_device, Multiplexer::new(index, 0)).await? {
        Ok(bytes) => bytes.first().copied().unwrap_or(0),
        Err(code) => return Ok(Err(code)),
    };
    let mut list = Vec::new();
    for sub in 1..=count {
        match upload(sub_device, Multiplexer::new(index, sub)).await? {
            Ok(bytes) => {
                let mut wide = [0u8; 4];
                let n = bytes.len().min(width);
                wide[..n].copy_from_slice(&bytes[..n]);
                list.push(u32::from_le_bytes(wide));
            }
            Err(code) => return Ok(Err(code)),
        }
    }
    Ok(Ok(list))
}

/// Whether the dictionary check reads the object: a communication or application object, not
/// a type definition.
fn checked(index: u16, object_type: &ObjectType) -> bool {
    index >= 0x1000 && !matches!(object_type, ObjectType::DefType | ObjectType::DefStruct)
}

/// Whether the ESI says an entry can be read.
fn readable(sub: &SubObject) -> bool {
    !matches!(sub.access, Some(AccessType::Wo) | None)
}

/// The ESI's PDOs assigned to a SyncManager by default (its `Sm` attribute), RxPDOs first.
fn default_pdos(esi: &Device) -> Vec<&EcPdo> {
    esi.ethercat().map_or(Vec::new(), |ec| {
        ec.rx_pdos
            .iter()
            .chain(&ec.tx_pdos)
            .filter(|p| p.sm.is_some())
            .collect()
    })
}

/// Where the SubDevice at `position`, as `observed`, differs from `esi`.
pub fn judge(esi: &Device, position: usize, observed: &Observed) -> Vec<Diagnostic> {
    let who = format!("SubDevice {position}");
    let mut diags = identity(esi, &who, &observed.sii);
    diags.extend(sync_managers(esi, &who, observed));
    diags.extend(assignment(esi, &who, observed));
    diags.extend(dictionary(esi, &who, &observed.entries));
    diags
}

/// CHK006: vendor, product code, revision and order string of the SII against the ESI.
fn identity(esi: &Device, who: &str, sii: &Device) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    let (want, have) = (&esi.device_info, &sii.device_info);
    for (what, expected, actual) in [
        ("vendor ID", &want.vendor_number, &have.vendor_number),
        ("product code", &want.product_number, &have.product_number),
        ("revision", &want.revision_number, &have.revision_number),
    ] {
        let (Some(expected), Some(actual)) = (expected, actual) else {
            continue;
        };
        if expected.value != actual.value {
            let message = format!(
                "the {what} in the SII of {who} is {:#010X}, the ESI says {:#010X}",
                actual.value, expected.value
            );
            diags.push(Diagnostic::new(&CHK006, Some(expected.span), message));
        }
    }
    let type_name = |d: &Device| d.ethercat().map(|ec| ec.type_name.clone());
    if let (Some(ec), Some(actual)) = (esi.ethercat(), type_name(sii)) {
        if ec.type_name != actual {
            let message = format!(
                "the order string in the SII of {who} is {actual:?}, the ESI's Type is {:?}",
                ec.type_name
            );
            diags.push(Diagnostic::new(&CHK006, Some(ec.span), message));
        }
    }
    diags
}

/// CHK007: each SyncManager of the SII against the ESI's, and the ESC's channel count.
fn sync_managers(esi: &Device, who: &str, observed: &Observed) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    let Some(ec) = esi.ethercat() else {
        return diags;
    };
    let empty = Vec::new();
    let sii = observed.sii.ethercat().map_or(&empty, |s| &s.sync_managers);
    if usize::from(observed.sm_channels) < ec.sync_managers.len() {
        let message = format!(
            "the ESC of {who} has {} SyncManager channel(s) (register 0x0005), the ESI describes {}",
            observed.sm_channels,
            ec.sync_managers.len()
        );
        diags.push(Diagnostic::new(&CHK007, Some(ec.span), message));
    }
    for (n, want) in ec.sync_managers.iter().enumerate() {
        let Some(have) = sii.get(n) else {
            let message = format!("SM{n} ({}) is not in the SII of {who}", kind(&want.kind));
            diags.push(Diagnostic::new(&CHK007, Some(want.span), message));
            continue;
        };
        let mut differences = Vec::new();
        if have.kind != want.kind {
            differences.push(format!(
                "carries {} (the ESI: {})",
                kind(&have.kind),
                kind(&want.kind)
            ));
        }
        if have.start_address != want.start_address {
            differences.push(format!(
                "starts at {:#06X} (the ESI: {:#06X})",
                have.start_address, want.start_address
            ));
        }
        if let (Some(length), Some(wanted)) = (have.default_size, want.default_size) {
            if length != wanted {
                differences.push(format!("is {length} bytes long (the ESI: {wanted})"));
            }
        }
        if have.control_byte != want.control_byte {
            differences.push(format!(
                "has control byte {:#04X} (the ESI: {:#04X})",
                have.control_byte, want.control_byte
            ));
        }
        if have.enable != want.enable {
            let state = |on: bool| if on { "enabled" } else { "disabled" };
            differences.push(format!(
                "is {} (the ESI: {})",
                state(have.enable),
                state(want.enable)
            ));
        }
        if !differences.is_empty() {
            let message = format!("SM{n} in the SII of {who} {}", differences.join(", "));
            diags.push(Diagnostic::new(&CHK007, Some(want.span), message));
        }
    }
    for (n, extra) in sii.iter().enumerate().skip(ec.sync_managers.len()) {
        let message = format!(
            "the SII of {who} has SM{n} ({}), the ESI describes {} SyncManager(s)",
            kind(&extra.kind),
            ec.sync_managers.len()
        );
        diags.push(Diagnostic::new(&CHK007, Some(ec.span), message));
    }
    diags
}

/// A SyncManager's kind as the ESI names it.
fn kind(kind: &SmKind) -> String {
    match kind {
        SmKind::MailboxOut => "MBoxOut".into(),
        SmKind::MailboxIn => "MBoxIn".into(),
        SmKind::Outputs => "Outputs".into(),
        SmKind::Inputs => "Inputs".into(),
        SmKind::Other(text) => format!("{text:?}"),
    }
}

/// CHK008: 1C1xh against the ESI's default assignment; each default PDO's mapping against its
/// entries.
fn assignment(esi: &Device, who: &str, observed: &Observed) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    let Some(ec) = esi.ethercat() else {
        return diags;
    };
    let refused = |code: u32| {
        format!(
            "{code:08X}h ({})",
            abort_meaning(code).unwrap_or("unknown abort code")
        )
    };
    for (n, list) in &observed.assignments {
        let Some(sm) = ec.sync_managers.get(usize::from(*n)) else {
            continue;
        };
        let index = 0x1C10 + u16::from(*n);
        let pdos = if sm.kind == SmKind::Outputs {
            &ec.rx_pdos
        } else {
            &ec.tx_pdos
        };
        let (wanted, span) = match dictionary_list(esi, index) {
            Some((list, span)) => (list.into_iter().map(|v| v as u16).collect(), span),
            None => (
                pdos.iter()
                    .filter(|p| p.sm == Some(*n))
                    .map(|p| p.index)
                    .collect::<Vec<u16>>(),
                sm.span,
            ),
        };
        let message = match list {
            Err(code) => format!("{who} refuses to read {index:04X}h: {}", refused(*code)),
            Ok(list) if *list == wanted => continue,
            Ok(list) => format!(
                "{index:04X}h of {who} assigns {} to SM{n}, the ESI assigns {} by default",
                indices(list),
                indices(&wanted)
            ),
        };
        diags.push(Diagnostic::new(&CHK008, Some(span), message));
    }
    for (index, list) in &observed.mappings {
        let Some(pdo) = default_pdos(esi).into_iter().find(|p| p.index == *index) else {
            continue;
        };
        let (wanted, span) = dictionary_list(esi, *index).unwrap_or_else(|| {
            let entries = pdo.entries.iter().map(|e| {
                u32::from(e.index) << 16 | u32::from(e.sub) << 8 | u32::from(e.bit_len & 0xFF)
            });
            (entries.collect(), pdo.span)
        });
        // An entry of 0 (no object, 0 bits) maps nothing: a mapping object whose sub-index 0
        // counts empty slots maps what its other entries say.
        let list = list
            .as_ref()
            .map(|l| l.iter().copied().filter(|e| *e != 0).collect::<Vec<u32>>());
        let message = match list {
            Err(code) => format!("{who} refuses to read {index:04X}h: {}", refused(*code)),
            Ok(list) if list == wanted => continue,
            Ok(list) => format!(
                "{index:04X}h of {who} maps {}, the ESI's {index:04X}h ({}) maps {}",
                entries(&list),
                pdo.name,
                entries(&wanted)
            ),
        };
        diags.push(Diagnostic::new(&CHK008, Some(span), message));
    }
    diags
}

/// The list an assignment or mapping object of the ESI's dictionary holds at power-up (its
/// sub-index 0 and entries' defaults, up to the first 0) and where the object is; `None` when
/// the dictionary leaves it empty, and the device fills it from the `Sm` attributes and `Entry`
/// lists (as ETG.2000 devices and the simulator do). The ESI's two answers may differ (the
/// Nanotec C5-E's 1C12h holds 1600h where its `Sm` attributes assign 1600h and 1601h): the
/// SubDevice holds the dictionary's.
fn dictionary_list(esi: &Device, index: u16) -> Option<(Vec<u32>, Span)> {
    let object = esi.objects.get(&index)?;
    let default = |sub: u8| match object.subs.get(&sub)?.default.as_ref()?.value {
        Some(Value::Integer(v)) => u32::try_from(v).ok(),
        _ => None,
    };
    let count = default(0)?;
    let list: Vec<u32> = (1..=count.min(255) as u8)
        .map_while(|sub| default(sub).filter(|v| *v != 0))
        .collect();
    (!list.is_empty()).then_some((list, object.span))
}

/// `1600h, 1601h`, or `nothing`.
fn indices(list: &[u16]) -> String {
    if list.is_empty() {
        return "nothing".into();
    }
    let parts: Vec<String> = list.iter().map(|i| format!("{i:04X}h")).collect();
    parts.join(", ")
}

/// Mapping entries as `6041h:00h/16, ...`, or `nothing`.
fn entries(list: &[u32]) -> String {
    if list.is_empty() {
        return "nothing".into();
    }
    let parts: Vec<String> = list
        .iter()
        .map(|e| format!("{:04X}h:{:02X}h/{}", e >> 16, e >> 8 & 0xFF, e & 0xFF))
        .collect();
    parts.join(", ")
}

/// CHK001/2/3/5: each entry read against the ESI's dictionary. Defaults are compared for
/// constants, and for read-only entries no PDO can carry (a PDO-mappable one is live data),
/// except in the PDO mapping and assignment objects, which [`assignment`] judges by content (a
/// device may count a zero-terminated list's entries in sub-index 0 where the ESI gives the
/// maximum).
fn dictionary(
    esi: &Device,
    who: &str,
    entries: &[(Multiplexer, Result<Vec<u8>, u32>)],
) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    for (mux, value) in entries {
        let Some(object) = esi.objects.get(&mux.index) else {
            continue;
        };
        let Some(sub) = object.subs.get(&mux.sub) else {
            continue;
        };
        match value {
            Ok(bytes) => {
                // PDO mapping and assignment objects are CHK008's, judged by what they map.
                let pdo_object =
                    matches!(mux.index, 0x1600..=0x17FF | 0x1A00..=0x1BFF | 0x1C10..=0x1C2F);
                let fixed = !pdo_object
                    && match sub.access {
                        Some(AccessType::Const) => true,
                        Some(AccessType::Ro) => !sub.pdo_mapping,
                        _ => false,
                    };
                let found = length_differs(esi, who, *mux, sub, bytes).or_else(|| {
                    fixed
                        .then(|| default_differs(esi, who, 0, *mux, sub, bytes))
                        .flatten()
                });
                diags.extend(found);
            }
            Err(0x0602_0000) => {
                let message = format!("object {:04X}h is missing on {who}", mux.index);
                diags.push(Diagnostic::new(&CHK001, Some(object.span), message));
            }
            Err(0x0609_0011) => {
                let message = format!("{} is missing on {who}", show_mux(*mux));
                diags.push(Diagnostic::new(&CHK001, Some(sub.span), message));
            }
            Err(code) => {
                let meaning = abort_meaning(*code).unwrap_or("unknown abort code");
                let message = format!(
                    "{who} refuses to read {}: {code:08X}h ({meaning})",
                    show_mux(*mux)
                );
                diags.push(Diagnostic::new(&CHK003, Some(sub.span), message));
            }
        }
    }
    diags
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive() -> Device {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("codegen/tests/esi/drive.xml");
        read::read_file(&path).expect("drive.xml").device
    }

    /// What `judge` says, as (code, message) in its order.
    fn said(diags: &[Diagnostic]) -> Vec<(&'static str, &str)> {
        diags
            .iter()
            .map(|d| (d.code(), d.message.as_str()))
            .collect()
    }

    #[test]
    fn a_matching_subdevice_gives_nothing() {
        let esi = drive();
        let observed = Observed {
            sii: esi.clone(),
            sm_channels: 8,
            assignments: vec![(2, Ok(vec![0x1600])), (3, Ok(vec![0x1A00]))],
            mappings: vec![
                (0x1600, Ok(vec![0x6040_0010, 0x6060_0008, 0x607A_0020])),
                (0x1A00, Ok(vec![0x6041_0010])),
            ],
            entries: vec![
                (
                    Multiplexer::new(0x1000, 0),
                    Ok(vec![0x92, 0x01, 0x02, 0x00]),
                ),
                (Multiplexer::new(0x6041, 0), Ok(vec![0x37, 0x02])),
            ],
        };
        assert_eq!(said(&judge(&esi, 0, &observed)), []);
    }

    #[test]
    fn each_difference_is_one_diagnostic() {
        let esi = drive();
        let mut sii = esi.clone();
        if let Some(revision) = sii.device_info.revision_number.as_mut() {
            revision.value = 7;
        }
        let ec = sii.ethercat_mut().expect("ESI");
        ec.sync_managers[1].control_byte = 0x20;
        ec.sync_managers[1].enable = false;
        let extra = ec.sync_managers[3].clone();
        ec.sync_managers.push(extra);
        let observed = Observed {
            sii,
            sm_channels: 2,
            assignments: vec![(2, Err(0x0602_0000)), (3, Ok(Vec::new()))],
            mappings: vec![(0x1600, Ok(vec![0x6040_0010])), (0x1A00, Err(0x0800_0022))],
            entries: vec![
                (
                    Multiplexer::new(0x1000, 0),
                    Ok(vec![0x92, 0x01, 0x00, 0x00]),
                ),
                (Multiplexer::new(0x1008, 0), Err(0x0601_0001)),
                (Multiplexer::new(0x1018, 2), Err(0x0609_0011)),
                (Multiplexer::new(0x6041, 0), Ok(vec![0x37, 0x02, 0x00])),
            ],
        };
        assert_eq!(
            said(&judge(&esi, 1, &observed)),
            [
                ("CHK006", "the revision in the SII of SubDevice 1 is 0x00000007, the ESI says 0x00000001"),
                ("CHK007", "the ESC of SubDevice 1 has 2 SyncManager channel(s) (register 0x0005), the ESI describes 4"),
                ("CHK007", "SM1 in the SII of SubDevice 1 has control byte 0x20 (the ESI: 0x22), is disabled (the ESI: enabled)"),
                ("CHK007", "the SII of SubDevice 1 has SM4 (Inputs), the ESI describes 4 SyncManager(s)"),
                ("CHK008", "SubDevice 1 refuses to read 1C12h: 06020000h (object does not exist in the object dictionary)"),
                ("CHK008", "1C13h of SubDevice 1 assigns nothing to SM3, the ESI assigns 1A00h by default"),
                ("CHK008", "1600h of SubDevice 1 maps 6040h:00h/16, the ESI's 1600h (Outputs) maps 6040h:00h/16, 6060h:00h/8, 607Ah:00h/32"),
                ("CHK008", "SubDevice 1 refuses to read 1A00h: 08000022h (data cannot be transferred or stored to the application because of the present device state)"),
                ("CHK005", "1000h:00h Device type of SubDevice 1 holds 402 (0x00000192), the description's default is 92010200"),
                ("CHK003", "SubDevice 1 refuses to read 1008h:00h: 06010001h (attempt to read a write-only object)"),
                ("CHK001", "1018h:02h is missing on SubDevice 1"),
                ("CHK002", "6041h:00h of SubDevice 1 is 3 byte(s) long, its data type UNSIGNED16 has 2"),
            ]
        );
    }
}
