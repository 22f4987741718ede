//! The ESI reader and the EtherCAT rules (EDS8xx) on `tests/esi/drive.xml`, a small hand-written
//! two-device file (ISO-8859-1): exact model values for the type mapping, SyncManagers, PDOs,
//! CoE and DC; then one test per rule, each editing the file and asserting the exact diagnostics.

use std::path::Path;

use edsgen_model::diag::Severity::{self, Error, Info, Warning};
use edsgen_model::model::*;
use edsgen_model::read::esi::{self, DeviceChoice};
use edsgen_model::read::{detect_format, read_bytes, read_bytes_device, Read};
use edsgen_model::validate;

fn drive_bytes() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/esi/drive.xml"))
        .expect("tests/esi/drive.xml")
}

/// The file as text (it is ISO-8859-1: one byte, one character).
fn drive() -> String {
    drive_bytes().iter().map(|&b| char::from(b)).collect()
}

fn latin1(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| u8::try_from(u32::from(c)).expect("a Latin-1 character"))
        .collect()
}

fn read(text: &str) -> Read {
    read_bytes(Path::new("drive.xml"), &latin1(text))
}

/// Reader and validator diagnostics as (code, severity, line, message), in file order.
fn diagnostics(text: &str) -> Vec<(&'static str, Severity, u32, String)> {
    let read = read(text);
    let mut all = read.diagnostics.clone();
    all.extend(validate::validate(&read.device));
    edsgen_model::diag::sort(&mut all);
    all.into_iter()
        .map(|d| {
            (
                d.rule.code,
                d.severity,
                d.span.map_or(0, |s| s.line),
                d.message,
            )
        })
        .collect()
}

/// [`diagnostics`] without the EDS814 info the file has on purpose (RxPdo 1601h has no Sm).
fn findings(text: &str) -> Vec<(&'static str, Severity, u32, String)> {
    diagnostics(text)
        .into_iter()
        .filter(|d| d.0 != "EDS814")
        .collect()
}

fn edit(from: &str, to: &str) -> String {
    let text = drive();
    assert!(text.contains(from), "`{from}` not in drive.xml");
    text.replacen(from, to, 1)
}

fn custom<'a>(sub: &'a SubObject, key: &str) -> Option<&'a str> {
    sub.custom
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

fn default(sub: &SubObject) -> Option<&Value> {
    sub.default.as_ref().and_then(|d| d.value.as_ref())
}

// ---------------------------------------------------------------------------------------------
// Reader

#[test]
fn esi_files_are_recognised_by_root_element_or_extension() {
    let bytes = drive_bytes();
    assert_eq!(detect_format(Path::new("a.xml"), &bytes), Format::Esi);
    assert_eq!(detect_format(Path::new("a.esi"), b"<x/>"), Format::Esi);
    assert_eq!(
        detect_format(
            Path::new("a.xml"),
            b"\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<!-- c -->\n<ISO15745ProfileContainer/>"
        ),
        Format::Xdd
    );
    assert_eq!(
        detect_format(Path::new("a"), b"<?xml version=\"1.0\"?><EtherCATModule/>"),
        Format::Esi
    );
}

#[test]
fn identity_names_and_encoding() {
    let read = read(&drive());
    let device = &read.device;
    assert_eq!(device.source.format, Format::Esi);
    assert_eq!(device.source.encoding, TextEncoding::Latin1);
    let info = &device.device_info;
    assert_eq!(info.vendor_name.as_deref(), Some("edsgen test vendor"));
    assert_eq!(
        info.vendor_number,
        Some(Spanned::new(0x1234, Span::new(4, 9, 10)))
    );
    assert_eq!(info.product_number.as_ref().map(|n| n.value), Some(0x9252));
    assert_eq!(info.revision_number.as_ref().map(|n| n.value), Some(1));
    // English is picked over the German name written first.
    assert_eq!(info.product_name.as_deref(), Some("Test drive"));
    let ec = device.ethercat().expect("EtherCAT part");
    assert_eq!(ec.type_name, "TD-1");
    assert_eq!(ec.profiles, vec![402]);
    assert_eq!(ec.span, Span::new(15, 7, 7));
    assert_eq!(ec.other_devices, vec![("TD-2".to_owned(), 0x9253, 2)]);
}

#[test]
fn iec_types_map_to_cia301_types() {
    let device = read(&drive()).device;
    let var = |index: u16| device.entry(index, 0).expect("entry");
    assert_eq!(var(0x1000).data_type, Some(0x0007));
    assert_eq!(default(var(0x1000)), Some(&Value::Integer(0x0002_0192)));
    assert_eq!(custom(var(0x1000), "Category"), Some("m"));
    assert_eq!(var(0x1000).access, Some(AccessType::Ro));
    // STRING(8): a VISIBLE_STRING of capacity 8; DefaultString is Latin-1 text.
    assert_eq!(var(0x1008).data_type, Some(0x0009));
    assert_eq!(var(0x1008).capacity, Some(8));
    assert_eq!(
        default(var(0x1008)),
        Some(&Value::Text("Test \u{b5}".to_owned()))
    );
    // rw mapped into RxPDOs only is rww, into TxPDOs only rwr, into both rw.
    assert_eq!(var(0x6040).access, Some(AccessType::Rww));
    assert!(var(0x6040).pdo_mapping);
    assert_eq!(var(0x6041).access, Some(AccessType::Ro));
    assert_eq!(var(0x607A).access, Some(AccessType::Rw));
    // An enum DataType with a BaseType resolves to the base: SINT, and #xFD is -3.
    assert_eq!(var(0x6060).data_type, Some(0x0002));
    assert_eq!(default(var(0x6060)), Some(&Value::Integer(-3)));
    assert_eq!(custom(var(0x6060), "Type"), Some("DT6060EN"));
    assert_eq!(custom(var(0x6060), "BitSize"), Some("8"));
    // MinData/MaxData are little-endian limits.
    let limit = |s: &Option<ValueSource>| s.as_ref().and_then(|v| v.value.clone());
    assert_eq!(
        limit(&var(0x607A).low_limit),
        Some(Value::Integer(i128::from(i32::MIN)))
    );
    assert_eq!(
        limit(&var(0x607A).high_limit),
        Some(Value::Integer(i128::from(i32::MAX)))
    );
    assert_eq!(var(0x607A).key_spans.data_type, Some(Span::new(214, 23, 4)));
    assert!(device
        .objects
        .values()
        .all(|o| o.object_type != ObjectType::Null));
    assert_eq!(device.objects[&0x1000].object_type, ObjectType::Var);
}

#[test]
fn complex_types_make_records_and_arrays() {
    let device = read(&drive()).device;
    let identity = &device.objects[&0x1018];
    assert_eq!(identity.object_type, ObjectType::Record);
    assert_eq!(
        identity.subs.keys().copied().collect::<Vec<_>>(),
        vec![0, 1, 2]
    );
    assert_eq!(identity.subs[&1].name, "Vendor ID");
    assert_eq!(identity.subs[&1].data_type, Some(0x0007));
    assert_eq!(default(&identity.subs[&1]), Some(&Value::Integer(0x1234)));
    assert_eq!(default(&identity.subs[&2]), Some(&Value::Integer(0x9252)));
    assert_eq!(identity.sub_number.as_ref().map(|n| n.value), Some(3));
    // DT1C12: sub 0 and an element array DT1C12ARR (LBound 1, 2 elements) make an ARRAY 0..2.
    let assign = &device.objects[&0x1C12];
    assert_eq!(assign.object_type, ObjectType::Array);
    assert_eq!(
        assign.subs.keys().copied().collect::<Vec<_>>(),
        vec![0, 1, 2]
    );
    assert_eq!(assign.subs[&2].name, "SubIndex 002");
    assert_eq!(assign.subs[&1].data_type, Some(0x0006));
    assert_eq!(assign.subs[&1].access, Some(AccessType::Rw));
    assert_eq!(custom(&assign.subs[&1], "WriteRestrictions"), Some("PreOP"));
    assert_eq!(default(&assign.subs[&1]), Some(&Value::Integer(0x1600)));
    assert_eq!(default(&assign.subs[&0]), Some(&Value::Integer(1)));
}

#[test]
fn sync_managers_pdos_mailbox_and_op_modes() {
    let device = read(&drive()).device;
    let ec = device.ethercat().cloned().expect("EtherCAT part");
    assert_eq!(
        ec.sync_managers
            .iter()
            .map(|sm| (
                sm.kind.clone(),
                sm.start_address,
                sm.default_size,
                sm.control_byte,
                sm.enable
            ))
            .collect::<Vec<_>>(),
        vec![
            (SmKind::MailboxOut, 0x1000, Some(128), 0x26, true),
            (SmKind::MailboxIn, 0x1080, Some(128), 0x22, true),
            (SmKind::Outputs, 0x1100, Some(7), 0x64, true),
            (SmKind::Inputs, 0x1180, Some(2), 0x20, true),
        ]
    );
    let rx = &ec.rx_pdos[0];
    assert_eq!(
        (rx.index, rx.sm, rx.fixed, rx.mandatory),
        (0x1600, Some(2), true, true)
    );
    assert_eq!(rx.name, "Outputs");
    assert_eq!(
        rx.exclude,
        vec![Spanned::new(0x1601, Span::new(236, 20, 6))]
    );
    assert_eq!(
        rx.entries
            .iter()
            .map(|e| (e.index, e.sub, e.bit_len, e.data_type.as_deref()))
            .collect::<Vec<_>>(),
        vec![
            (0x6040, 0, 16, Some("UINT")),
            (0x6060, 0, 8, Some("SINT")),
            (0x607A, 0, 32, Some("DINT")),
        ]
    );
    assert_eq!(rx.entries[1].name, "Modes of operation");
    assert_eq!(rx.entries[1].span, Span::new(244, 11, 6));
    assert_eq!((ec.rx_pdos[1].index, ec.rx_pdos[1].sm), (0x1601, None));
    assert_eq!(ec.tx_pdos.len(), 1);
    assert_eq!(ec.tx_pdos[0].entries[0].index, 0x6041);
    let coe = ec.coe.expect("CoE");
    assert_eq!(
        (
            coe.sdo_info,
            coe.pdo_assign,
            coe.pdo_config,
            coe.complete_access,
            coe.segmented_sdo
        ),
        (true, false, false, true, true)
    );
    assert_eq!(coe.init_cmds.len(), 1);
    let cmd = &coe.init_cmds[0];
    assert_eq!(
        (
            cmd.transitions.clone(),
            cmd.index,
            cmd.sub,
            cmd.data.clone()
        ),
        (vec!["PS".to_owned()], 0x6060, 0, vec![0x08])
    );
    assert_eq!(
        ec.op_modes,
        vec![
            DcOpMode {
                name: "FreeRun".to_owned(),
                description: "FreeRun/SM-Synchron".to_owned(),
                assign_activate: 0,
                cycle_time_sync0: 0,
            },
            DcOpMode {
                name: "DC".to_owned(),
                description: "DC-Synchron".to_owned(),
                assign_activate: 0x300,
                cycle_time_sync0: 250_000,
            },
        ]
    );
}

#[test]
fn a_device_is_picked_by_type_name_or_product_code() {
    let bytes = drive_bytes();
    let path = Path::new("drive.xml");
    for choice in ["TD-2", "td-2", "#x00009253", "0x9253"] {
        let read = read_bytes_device(path, &bytes, Some(choice));
        let ec = read.device.ethercat().cloned().expect("EtherCAT part");
        assert_eq!(ec.type_name, "TD-2", "{choice}");
        assert_eq!(ec.other_devices, vec![("TD-1".to_owned(), 0x9252, 1)]);
        assert_eq!(
            read.device.device_info.product_name.as_deref(),
            Some("Second test drive")
        );
        assert!(read.device.objects.is_empty());
    }
    let read = esi::read_device(path, &bytes, Some(&DeviceChoice::Position(1)));
    assert_eq!(
        read.device.device_info.product_number.map(|n| n.value),
        Some(0x9253)
    );
    let all = esi::read_all(path, &bytes);
    assert_eq!(all.len(), 2);
    assert_eq!(all[0].0.objects.len(), 8);
}

#[test]
fn no_device_matching_the_choice_is_an_error_listing_the_devices() {
    let read = read_bytes_device(Path::new("drive.xml"), &drive_bytes(), Some("TD-9"));
    assert!(read.device.ethercat().is_none());
    assert!(read.device.objects.is_empty());
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.span.map(|s| s.line), d.message.as_str()))
        .collect();
    assert_eq!(
        found,
        vec![(
            "EDS801",
            Some(2),
            "no device of the file is named `TD-9`; it has TD-1 (#x00009252), TD-2 (#x00009253)"
        )]
    );
}

#[test]
fn a_file_of_modules_has_no_device() {
    let text = "<?xml version=\"1.0\"?>\n<EtherCATModule>\n  <Vendor><Id>2</Id></Vendor>\n  \
                <Modules>\n    <Module><Type ModuleIdent=\"#x1\">M1</Type></Module>\n  \
                </Modules>\n</EtherCATModule>\n";
    assert_eq!(
        diagnostics(text),
        vec![
            (
                "EDS801",
                Error,
                2,
                "the file describes no Device (`Descriptions/Devices/Device`)".to_owned()
            ),
            (
                "EDS802",
                Info,
                2,
                "the file describes 1 module(s) and no device to plug them into; they are not read"
                    .to_owned()
            ),
        ]
    );
}

#[test]
fn malformed_esi_is_one_error() {
    let found = diagnostics("<?xml version=\"1.0\"?>\n<EtherCATInfo><Vendor>AB&T</Vendor>\n");
    assert_eq!(found.len(), 1);
    assert_eq!((found[0].0, found[0].2), ("EDS601", 2));
}

// ---------------------------------------------------------------------------------------------
// Rules

#[test]
fn the_drive_is_clean_and_canopen_only_rules_stay_quiet() {
    // No EDS208/EDS209 (1001h, heartbeat), no EDS401 (1400h/1800h), no EDS320 (COB-IDs), no
    // EDS1xx FileInfo rules: only the PDO without Sm.
    assert_eq!(
        diagnostics(&drive()),
        vec![(
            "EDS814",
            Info,
            259,
            "1 PDO(s) without `Sm`, not assigned by default: RxPdo 1601h".to_owned()
        )]
    );
}

#[test]
fn object_rules_still_apply_to_the_coe_dictionary() {
    // EDS317: a default outside MinData/MaxData.
    let text = edit("<MinData>00000080</MinData>", "<MinData>01000000</MinData>");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS317",
            Warning,
            217,
            "DefaultValue 00000000 of 607Ah is below LowLimit 01000000".to_owned()
        )]
    );
}

#[test]
fn eds807_an_entry_naming_a_missing_object_or_sub_index() {
    let text = edit(
        "<Index>#x6060</Index>\n            <SubIndex>0</SubIndex>",
        "<Index>#x6061</Index>\n            <SubIndex>0</SubIndex>",
    );
    assert_eq!(
        findings(&text),
        vec![(
            "EDS807",
            Error,
            244,
            "RxPdo 1600h maps 6061h sub 0, but the dictionary has no object 6061h".to_owned()
        )]
    );
    let text = edit(
        "<Index>#x6040</Index>\n            <SubIndex>0</SubIndex>",
        "<Index>#x6040</Index>\n            <SubIndex>1</SubIndex>",
    );
    assert_eq!(
        findings(&text),
        vec![(
            "EDS807",
            Error,
            237,
            "RxPdo 1600h maps 6040h sub 1, but 6040h has no sub-index 1".to_owned()
        )]
    );
}

#[test]
fn eds808_bit_len_disagreeing_with_the_object() {
    let text = edit(
        "<Index>#x6041</Index>\n            <SubIndex>0</SubIndex>\n            <BitLen>16</BitLen>",
        "<Index>#x6041</Index>\n            <SubIndex>0</SubIndex>\n            <BitLen>8</BitLen>",
    );
    assert_eq!(
        findings(&text),
        vec![(
            "EDS808",
            Error,
            274,
            "TxPdo 1A00h maps 6041h with BitLen 8, but 6041h is 16 bits (UNSIGNED16)".to_owned()
        )]
    );
}

#[test]
fn eds809_an_entry_not_byte_aligned() {
    let text = edit(
        "</Entry>\n          <Entry>\n            <Index>#x6060",
        "</Entry><Entry><Index>#x0</Index><BitLen>4</BitLen></Entry>\n          <Entry>\n            <Index>#x6060",
    )
    .replacen("DefaultSize=\"7\"", "DefaultSize=\"8\"", 1);
    assert_eq!(
        findings(&text),
        vec![
            (
                "EDS809",
                Warning,
                244,
                "RxPdo 1600h maps 6060h sub 0 (8 bits) at bit 20, not on a byte boundary"
                    .to_owned()
            ),
            (
                "EDS809",
                Warning,
                251,
                "RxPdo 1600h maps 607Ah sub 0 (32 bits) at bit 28, not on a byte boundary"
                    .to_owned()
            ),
        ]
    );
}

#[test]
fn eds810_an_assignment_larger_than_its_sync_manager() {
    let text = edit("DefaultSize=\"7\"", "DefaultSize=\"6\"");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS810",
            Error,
            231,
            "the PDOs assigned to SM2 (1600h) hold 7 bytes, but its DefaultSize is 6".to_owned()
        )]
    );
}

#[test]
fn eds811_an_exclude_naming_no_pdo() {
    let text = edit("<Exclude>#x1601</Exclude>", "<Exclude>#x1605</Exclude>");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS811",
            Warning,
            236,
            "RxPdo 1600h excludes 1605h, which is not a PDO of the device".to_owned()
        )]
    );
}

#[test]
fn eds812_two_excluding_pdos_both_assigned() {
    let text = edit("<RxPdo Fixed=\"0\">", "<RxPdo Fixed=\"0\" Sm=\"2\">").replacen(
        "DefaultSize=\"7\"",
        "DefaultSize=\"9\"",
        1,
    );
    assert_eq!(
        diagnostics(&text),
        vec![
            (
                "EDS820",
                Warning,
                152,
                "1C12h assigns 1600h to SM2 by default, but the PDOs whose `Sm` is 2 are 1600h, 1601h"
                    .to_owned()
            ),
            (
                "EDS812",
                Error,
                236,
                "RxPdo 1600h excludes RxPdo 1601h, but both are assigned by default (Sm 2 and Sm 2)"
                    .to_owned()
            )
        ]
    );
}

#[test]
fn eds813_two_pdos_with_one_index() {
    let text = edit("<Index>#x1A00</Index>", "<Index>#x1600</Index>");
    assert_eq!(
        findings(&text),
        vec![
            (
                "EDS813",
                Error,
                271,
                "TxPdo 1600h is described twice".to_owned()
            ),
            (
                "EDS819",
                Error,
                271,
                "TxPdo `Inputs` has Index 1600h, an RxPDO mapping object".to_owned()
            )
        ]
    );
}

#[test]
fn eds806_an_object_described_twice() {
    let text = edit(
        "<Index>#x6041</Index>\n                <Name>",
        "<Index>#x6040</Index>\n                <Name>",
    );
    assert_eq!(
        findings(&text),
        vec![
            (
                "EDS806",
                Error,
                188,
                "object 6040h is described twice; the last description is used".to_owned()
            ),
            (
                "EDS807",
                Error,
                274,
                "TxPdo 1A00h maps 6041h sub 0, but the dictionary has no object 6041h".to_owned()
            ),
        ]
    );
}

#[test]
fn eds803_identity_missing() {
    let text = edit("ProductCode=\"#x00009252\" ", "");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS803",
            Error,
            15,
            "device `TD-1` has no ProductCode (or it is not a number)".to_owned()
        )]
    );
    let text = edit("<Id>#x00001234</Id>", "<Id>twelve</Id>");
    assert_eq!(
        findings(&text),
        vec![
            (
                "EDS604",
                Error,
                4,
                "`Id` is `twelve`, not a number".to_owned()
            ),
            (
                "EDS803",
                Error,
                15,
                "device `TD-1` has no Vendor Id (or it is not a number)".to_owned()
            ),
        ]
    );
}

#[test]
fn eds804_a_dictionary_without_profile() {
    let text = edit("<ProfileNo>402</ProfileNo>", "");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS804",
            Warning,
            15,
            "device `TD-1` has a CoE dictionary but no Profile/ProfileNo".to_owned()
        )]
    );
}

#[test]
fn eds805_an_unknown_type_name() {
    let text = edit("<Type>DINT</Type>", "<Type>DINTEGER</Type>");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS805",
            Error,
            214,
            "type `DINTEGER` is neither an IEC 61131 type nor a DataType of the Dictionary"
                .to_owned()
        )]
    );
}

#[test]
fn cut_and_corrupted_files_read_without_a_panic() {
    let text = drive();
    let mut inputs: Vec<String> = (0..text.len())
        .step_by(97)
        .filter_map(|cut| text.get(..cut).map(str::to_owned))
        .collect();
    for (from, to) in [
        ("<Elements>2</Elements>", "<Elements>4294967295</Elements>"),
        ("<LBound>1</LBound>", "<LBound>4294967295</LBound>"),
        ("<SubIdx>2</SubIdx>", "<SubIdx>4294967295</SubIdx>"),
        ("<BitLen>32</BitLen>", "<BitLen>65535</BitLen>"),
        ("<Index>#x1600</Index>", "<Index>#x-1</Index>"),
        ("STRING(8)", "STRING(99999999999999999999)"),
        (
            "<Type>UINT</Type>",
            "<Type>ARRAY [-9223372036854775808..9223372036854775807] OF BYTE</Type>",
        ),
        (
            "<DefaultData>92010200</DefaultData>",
            "<DefaultData>9201020</DefaultData>",
        ),
        ("<BaseType>SINT</BaseType>", "<BaseType>DT6060EN</BaseType>"),
    ] {
        inputs.push(edit(from, to));
    }
    for input in &inputs {
        let read = read(input);
        let _ = validate::validate(&read.device);
        let _ = edsgen_model::dump::to_json(&read.device);
    }
    // The cyclic BaseType is an unknown type, not a loop.
    let cyclic = edit("<BaseType>SINT</BaseType>", "<BaseType>DT6060EN</BaseType>");
    assert_eq!(
        findings(&cyclic),
        vec![(
            "EDS805",
            Error,
            201,
            "type `DT6060EN` is neither an IEC 61131 type nor a DataType of the Dictionary"
                .to_owned()
        )]
    );
}

#[test]
fn profile_numbers_are_collected_from_channels_without_repeats() {
    let text = edit(
        "<ProfileNo>402</ProfileNo>",
        "<ChannelInfo><ProfileNo>402</ProfileNo></ChannelInfo>\
         <ChannelInfo><ProfileNo>402</ProfileNo><ProfileNo>5001</ProfileNo></ChannelInfo>",
    );
    let ec = read(&text)
        .device
        .ethercat()
        .cloned()
        .expect("EtherCAT part");
    assert_eq!(ec.profiles, vec![402, 5001]);
}

// ---------------------------------------------------------------------------------------------
// A modular device: `tests/esi/modular.xml` (UTF-8), with slots, modules and alternative
// PDO assignments.

fn modular() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/esi/modular.xml"))
        .expect("tests/esi/modular.xml")
}

fn edit_modular(from: &str, to: &str) -> String {
    let text = modular();
    assert!(text.contains(from), "`{from}` not in modular.xml");
    text.replacen(from, to, 1)
}

/// [`diagnostics`] without the two infos the modular file has on purpose (EDS802, EDS814).
fn modular_findings(text: &str) -> Vec<(&'static str, Severity, u32, String)> {
    diagnostics(text)
        .into_iter()
        .filter(|d| d.0 != "EDS802" && d.0 != "EDS814")
        .collect()
}

#[test]
fn alternative_mappings_slots_and_modules_are_read() {
    let read = read(&modular());
    let ec = read.device.ethercat().expect("an ESI device");
    type Sms = Vec<(u8, Vec<u16>)>;
    let alternatives: Vec<(&str, bool, Sms)> = ec
        .alternative_mappings
        .iter()
        .map(|a| {
            let sms = a
                .sms
                .iter()
                .map(|(sm, pdos)| (*sm, pdos.iter().map(|p| p.value).collect()))
                .collect();
            (a.name.as_str(), a.default, sms)
        })
        .collect();
    assert_eq!(
        alternatives,
        vec![
            ("Standard", true, vec![(2, vec![0x1600]), (3, vec![0x1A00])]),
            (
                "Short",
                false,
                vec![(2, vec![0x1601]), (3, vec![0x1A00, 0x1A01])]
            ),
        ]
    );
    assert_eq!(ec.alternative_mappings[1].sms[1].1[1].span.line, 31);
    assert_eq!(ec.slots.len(), 2);
    let first = &ec.slots[0];
    assert_eq!(
        (
            first.name.as_str(),
            first.min_instances,
            first.max_instances,
            first.module_idents.clone(),
            first.module_classes.clone(),
            first.default_module,
            first.index_increment,
            first.pdo_increment,
            first.span.line,
        ),
        (
            "Inputs",
            1,
            2,
            vec![0x100, 0x101],
            vec![],
            Some(0x100),
            0x10,
            1,
            126
        )
    );
    // The second slot has its own SlotIndexIncrement, inherits SlotPdoIncrement, and names a
    // module class instead of idents.
    let second = &ec.slots[1];
    assert_eq!(
        (
            second.name.as_str(),
            second.min_instances,
            second.max_instances,
            second.module_idents.clone(),
            second.module_classes.clone(),
            second.default_module,
            second.index_increment,
            second.pdo_increment,
        ),
        (
            "Extension",
            0,
            1,
            vec![],
            vec!["DI".to_owned()],
            None,
            0x20,
            1
        )
    );
    assert_eq!(ec.modules.len(), 2);
    let di = &ec.modules[0];
    assert_eq!(
        (
            di.ident,
            di.type_name.as_str(),
            di.class.as_deref(),
            di.name.as_str(),
            di.span.line
        ),
        (0x100, "TM-DI16", Some("DI"), "16 digital inputs", 142)
    );
    assert!(di.rx_pdos.is_empty());
    assert_eq!(di.tx_pdos.len(), 1);
    let pdo = &di.tx_pdos[0];
    assert_eq!((pdo.index, pdo.sm, pdo.fixed), (0x1A00, Some(3), true));
    assert_eq!(
        pdo.entries
            .iter()
            .map(|e| (e.index, e.sub, e.bit_len))
            .collect::<Vec<_>>(),
        vec![(0x6000, 1, 16)]
    );
    // The module's dictionary, with its own DataType, is the module's, not the device's.
    assert_eq!(di.objects.keys().copied().collect::<Vec<_>>(), vec![0x6000]);
    let inputs = &di.objects[&0x6000];
    assert_eq!(inputs.object_type, ObjectType::Record);
    assert_eq!(inputs.subs[&1].data_type, Some(0x0006));
    assert_eq!(
        read.device.objects.keys().copied().collect::<Vec<_>>(),
        vec![0x1000, 0x7000]
    );
    let empty = &ec.modules[1];
    assert_eq!(
        (
            empty.ident,
            empty.type_name.as_str(),
            empty.class.as_deref()
        ),
        (0x101, "TM-EMPTY", None)
    );
    assert!(empty.objects.is_empty() && empty.tx_pdos.is_empty());
}

#[test]
fn the_modular_device_is_clean_but_for_two_infos() {
    assert_eq!(
        diagnostics(&modular()),
        vec![
            (
                "EDS814",
                Info,
                88,
                "2 PDO(s) without `Sm`, not assigned by default: RxPdo 1601h, TxPdo 1A01h"
                    .to_owned()
            ),
            (
                "EDS802",
                Info,
                126,
                "the device has 2 slot(s) and the file 2 module(s): a module's PDOs join the \
                 process image when the overlay's [modules] plugs it"
                    .to_owned()
            ),
        ]
    );
}

#[test]
fn eds807_an_entry_that_no_module_defines_either() {
    // 6020h is the module's 6000h in the third slot position (SlotIndexIncrement #x10).
    let text = edit_modular("<Index>#x6010</Index>", "<Index>#x6020</Index>");
    assert_eq!(modular_findings(&text), vec![]);
    // 6030h would be a fourth position; the slots have three.
    for index in ["6005", "6030"] {
        let text = edit_modular(
            "<Index>#x6010</Index>",
            &format!("<Index>#x{index}</Index>"),
        );
        assert_eq!(
            modular_findings(&text),
            vec![(
                "EDS807",
                Error,
                114,
                format!(
                    "TxPdo 1A01h maps {index}h sub 1, but the dictionary has no object {index}h"
                )
            )]
        );
    }
}

#[test]
fn eds815_an_alternative_naming_no_pdo() {
    let text = edit_modular("<Pdo>#x1a01</Pdo>", "<Pdo>#x1a05</Pdo>");
    assert_eq!(
        modular_findings(&text),
        vec![(
            "EDS815",
            Error,
            31,
            "alternative `Short` assigns 1A05h to SM3, which is not a PDO of the device".to_owned()
        )]
    );
}

#[test]
fn eds816_an_alternative_larger_than_its_sync_manager() {
    let text = edit_modular("DefaultSize=\"4\"", "DefaultSize=\"3\"");
    assert_eq!(
        modular_findings(&text),
        vec![(
            "EDS816",
            Error,
            24,
            "alternative `Short` assigns 1A00h, 1A01h to SM3: 4 bytes, but its DefaultSize is 3"
                .to_owned()
        )]
    );
}

#[test]
fn eds817_an_alternative_with_two_excluding_pdos() {
    let text = edit_modular("<Pdo>#x1601</Pdo>", "<Pdo>#x1601</Pdo><Pdo>#x1600</Pdo>").replacen(
        "DefaultSize=\"2\"",
        "DefaultSize=\"4\"",
        1,
    );
    assert_eq!(
        modular_findings(&text),
        vec![(
            "EDS817",
            Error,
            24,
            "alternative `Short` assigns 1600h and 1601h, but 1601h excludes 1600h".to_owned()
        )]
    );
}

#[test]
fn dump_shows_alternatives_slots_and_modules() {
    let json = edsgen_model::dump::to_json(&read(&modular()).device);
    let ec = &json["ethercat"];
    assert_eq!(
        ec["alternative_mappings"][1],
        serde_json::json!({
            "name": "Short",
            "default": false,
            "sms": [{"sm": 2, "pdos": [0x1601]}, {"sm": 3, "pdos": [0x1A00, 0x1A01]}],
        })
    );
    assert_eq!(
        ec["slots"][0],
        serde_json::json!({
            "name": "Inputs",
            "min_instances": 1,
            "max_instances": 2,
            "module_idents": [0x100, 0x101],
            "module_classes": [],
            "default_module": 0x100,
            "index_increment": 0x10,
            "pdo_increment": 1,
        })
    );
    let module = &ec["modules"][0];
    assert_eq!(
        (
            &module["ident"],
            &module["type_name"],
            &module["class"],
            &module["name"]
        ),
        (
            &serde_json::json!(0x100),
            &serde_json::json!("TM-DI16"),
            &serde_json::json!("DI"),
            &serde_json::json!("16 digital inputs")
        )
    );
    assert_eq!(module["tx_pdos"][0]["index"], 0x1A00);
    assert_eq!(module["tx_pdos"][0]["bits"], 16);
    assert_eq!(module["objects"][0]["index"], 0x6000);
    assert_eq!(ec["modules"][1]["class"], serde_json::Value::Null);
}

#[test]
fn an_enum_without_base_type_is_unsigned_by_its_bit_size() {
    let enum_info = "<EnumInfo><Text>Keep</Text><Enum>0</Enum></EnumInfo>";
    for (bits, data_type) in [("8", 0x0005), ("1", 0x0001)] {
        let text = edit(
            "<BaseType>SINT</BaseType>\n                <BitSize>8</BitSize>",
            &format!("<BitSize>{bits}</BitSize>{enum_info}"),
        );
        let device = read(&text).device;
        assert_eq!(
            device.entry(0x6060, 0).expect("6060h").data_type,
            Some(data_type)
        );
    }
    // Without EnumInfo, a DataType without BaseType or SubItems stays unknown.
    let text = edit("<BaseType>SINT</BaseType>\n", "");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS805",
            Error,
            200,
            "type `DT6060EN` is neither an IEC 61131 type nor a DataType of the Dictionary"
                .to_owned()
        )]
    );
}

#[test]
fn eds819_a_pdo_with_the_other_directions_index() {
    let text = edit("<Index>#x1A00</Index>", "<Index>#x1602</Index>");
    assert_eq!(
        findings(&text),
        vec![(
            "EDS819",
            Error,
            271,
            "TxPdo `Inputs` has Index 1602h, an RxPDO mapping object".to_owned()
        )]
    );
}

#[test]
fn eds820_the_dictionarys_default_assignment_against_sm() {
    let text = edit(
        "<DefaultData>0016</DefaultData>",
        "<DefaultData>0116</DefaultData>",
    );
    assert_eq!(
        findings(&text),
        vec![(
            "EDS820",
            Warning,
            152,
            "1C12h assigns 1601h to SM2 by default, but the PDOs whose `Sm` is 2 are 1600h"
                .to_owned()
        )]
    );
    // None assigned at power-up is the master's to fill from `Sm`.
    let text = edit(
        "<DefaultData>01</DefaultData>",
        "<DefaultData>00</DefaultData>",
    );
    assert_eq!(findings(&text), vec![]);
}
