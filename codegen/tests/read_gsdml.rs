//! The GSDML reader and the PROFINET rules (PN0xx) on the Goodrive350 PROFINET card's GSDML
//! (`eds/goodrive350-pn.xml`, written from chapter 4 of the manual): exact model values per table
//! of the manual, then one test per rule, each editing the file and asserting the exact
//! diagnostics.

use std::path::Path;

use edsgen_model::diag::Severity::{self, Error, Warning};
use edsgen_model::model::*;
use edsgen_model::read::{detect_format, read_bytes, Read};
use edsgen_model::validate;

fn card() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.xml"))
        .expect("eds/goodrive350-pn.xml")
}

fn read(text: &str) -> Read {
    read_bytes(Path::new("goodrive350-pn.xml"), text.as_bytes())
}

fn pn(read: &Read) -> &Profinet {
    read.device.profinet().expect("a PROFINET side")
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
                d.code(),
                d.severity,
                d.span.map_or(0, |s| s.line),
                d.message,
            )
        })
        .collect()
}

/// The card with the first `from` replaced by `to` (which must be there).
fn edit(from: &str, to: &str) -> String {
    let text = card();
    assert!(text.contains(from), "the card has no `{from}`");
    text.replacen(from, to, 1)
}

/// The line (1-based) of the first occurrence of `needle` in the card.
fn line_of(needle: &str) -> u32 {
    let text = card();
    let at = text.find(needle).expect("present");
    text[..at].lines().count() as u32 + u32::from(text[..at].ends_with('\n'))
}

#[test]
fn the_card_is_gsdml_by_content_and_reads_clean() {
    let text = card();
    assert_eq!(
        detect_format(Path::new("goodrive350-pn.xml"), text.as_bytes()),
        Format::Gsdml
    );
    assert_eq!(diagnostics(&text), vec![]);
}

#[test]
fn identity_and_access_point_are_the_recorded_choices() {
    let read = read(&card());
    let pn = pn(&read);
    assert_eq!(pn.vendor_id.as_ref().map(|v| v.value), Some(0x0350));
    assert_eq!(pn.device_id.as_ref().map(|v| v.value), Some(0x0350));
    assert_eq!(pn.vendor_name.as_deref(), Some("INVT"));
    assert_eq!(
        read.device
            .device_info
            .vendor_number
            .as_ref()
            .map(|v| v.value),
        Some(0x0350)
    );
    assert_eq!(pn.access_points.len(), 1);
    let dap = &pn.access_points[0];
    assert_eq!(dap.id, "DAP_GD350_PN");
    assert_eq!(dap.name.as_deref(), Some("Goodrive350 PROFINET card"));
    assert_eq!(dap.module_ident.as_ref().map(|v| v.value), Some(1));
    assert_eq!(dap.physical_slots, vec![0, 1]);
    assert_eq!(dap.fixed_in_slots, vec![0]);
    assert_eq!(dap.min_device_interval, Some(32));
    assert_eq!(dap.dns_compatible_name.as_deref(), Some("goodrive350-pn"));
    // Table 4-3: RT user data up to 1440 bytes.
    assert_eq!(dap.max_input_length.as_ref().map(|v| v.value), Some(1440));
    assert_eq!(dap.max_output_length.as_ref().map(|v| v.value), Some(1440));
    assert_eq!(dap.useable_modules.len(), 1);
    assert_eq!(dap.useable_modules[0].target.value, "MOD_PKW_PZD_16");
    assert_eq!(dap.useable_modules[0].allowed_in_slots, vec![1]);
    assert_eq!(dap.useable_modules[0].used_in_slots, vec![1]);
    assert_eq!(dap.submodules.len(), 1);
    assert_eq!(dap.submodules[0].subslot, 1);
    // Tables 4-3 and 4-4: RT and IRT.
    let interface = dap.interface.as_ref().expect("an interface");
    assert_eq!(interface.subslot, 0x8000);
    assert_eq!(
        interface.rt_classes.as_deref(),
        Some("RT_CLASS_1;RT_CLASS_3")
    );
    assert_eq!(interface.send_clock, vec![32]);
    assert_eq!(
        interface.reduction_ratio,
        vec![1, 2, 4, 8, 16, 32, 64, 128, 256, 512]
    );
    // 4.2: two ports.
    let ports: Vec<(u16, Option<&str>)> = dap
        .ports
        .iter()
        .map(|p| (p.subslot, p.name.as_deref()))
        .collect();
    assert_eq!(
        ports,
        vec![(0x8001, Some("X1 P1")), (0x8002, Some("X1 P2"))]
    );
}

#[test]
fn the_module_is_16_words_each_way_as_figure_4_4_lays_them_out() {
    let read = read(&card());
    let pn = pn(&read);
    assert_eq!(pn.modules.len(), 1);
    let module = &pn.modules[0];
    assert_eq!(module.module_ident.as_ref().map(|v| v.value), Some(0x10));
    assert_eq!(module.name.as_deref(), Some("PKW PZD 16 words"));
    let sub = &module.submodules[0];
    assert_eq!(sub.submodule_ident.as_ref().map(|v| v.value), Some(0x10));
    for items in [&sub.inputs, &sub.outputs] {
        assert_eq!(items.len(), 16);
        assert!(items.iter().all(|i| i.kind == Some(PnDataType::Unsigned16)));
        assert_eq!(
            items.iter().map(|i| i.size()).sum::<Option<u32>>(),
            Some(32)
        );
    }
    let names = |items: &[DataItem]| -> Vec<String> {
        items
            .iter()
            .map(|i| i.name.clone().unwrap_or_default())
            .collect()
    };
    let inputs = names(&sub.inputs);
    assert_eq!(inputs[0], "PKW1 (response identification)");
    assert_eq!(inputs[4], "SW (status word)");
    assert_eq!(inputs[5], "PZD2 (actual value, P16.43)");
    assert_eq!(inputs[15], "PZD12 (actual value, P16.53)");
    let outputs = names(&sub.outputs);
    assert_eq!(outputs[0], "PKW1 (task identification)");
    assert_eq!(outputs[4], "CW (control word)");
    assert_eq!(outputs[5], "PZD2 (reference value, P16.32)");
    assert_eq!(outputs[15], "PZD12 (reference value, P16.42)");
    // Table 4-5 (CW) and Table 4-7 (SW): bits 8-15 named, bits 0-7 the command / state.
    let bits = |item: &DataItem| -> Vec<(u32, String)> {
        item.bits
            .iter()
            .map(|b| (b.bit_offset, b.name.clone().unwrap_or_default()))
            .collect()
    };
    assert!(sub.outputs[4].use_as_bits);
    assert_eq!(
        bits(&sub.outputs[4])[0],
        (8, "Enable writing (PKW)".to_owned())
    );
    assert_eq!(
        bits(&sub.outputs[4])[7],
        (15, "Heartbeat reference".to_owned())
    );
    assert_eq!(
        bits(&sub.inputs[4])[0],
        (8, "Bus voltage established (ready to run)".to_owned())
    );
    assert_eq!(
        bits(&sub.inputs[4])[4],
        (12, "Overload pre-alarm".to_owned())
    );
    assert_eq!(bits(&sub.inputs[4]).len(), 8);
}

#[test]
fn the_pzd_parameters_are_records_as_tables_4_6_and_4_8_give_them() {
    let read = read(&card());
    let pn = pn(&read);
    let sub = &pn.modules[0].submodules[0];
    let records: Vec<(u16, u32, usize)> = sub
        .records
        .iter()
        .map(|r| (r.index.value, r.length.value, r.fields.len()))
        .collect();
    assert_eq!(records, vec![(256, 22, 11), (257, 22, 11)]);
    let rx = &sub.records[0];
    assert_eq!(
        rx.name.as_deref(),
        Some("Received PZD meanings (P16.32-P16.42)")
    );
    assert_eq!(rx.fields[0].name.as_deref(), Some("P16.32: received PZD2"));
    assert_eq!(
        rx.fields[10].name.as_deref(),
        Some("P16.42: received PZD12")
    );
    assert_eq!(rx.fields[10].byte_offset, 20);
    assert_eq!(rx.fields[0].allowed_values, vec![(0, 18)]);
    assert_eq!(
        rx.fields[0].default.as_ref().map(|d| d.value.as_str()),
        Some("0")
    );
    let tx = &sub.records[1];
    assert_eq!(
        tx.fields[0].name.as_deref(),
        Some("P16.43: transmitted PZD2")
    );
    assert_eq!(tx.fields[0].allowed_values, vec![(0, 26)]);
    let list = |id: &str| pn.value_lists.iter().find(|v| v.id == id).expect("listed");
    // Table 4-6: 0 invalid .. 18 position feedback setting flag.
    let vl_rx = list("VL_RX");
    assert_eq!(vl_rx.assignments.len(), 19);
    assert_eq!(
        vl_rx.assignments[1],
        (1, Some("Set frequency (0-Fmax, 0.01 Hz)".to_owned()))
    );
    // Table 4-8: 0 invalid .. 26 HDIB frequency.
    let vl_tx = list("VL_TX");
    assert_eq!(vl_tx.assignments.len(), 27);
    assert_eq!(vl_tx.assignments[11], (11, Some("Fault code".to_owned())));
    assert_eq!(
        vl_tx.assignments[26],
        (26, Some("HDIB frequency value (x100, kHz)".to_owned()))
    );
    assert_eq!(pn.channel_diagnostics.len(), 2);
    assert_eq!(pn.channel_diagnostics[0].error_type, 0x100);
    assert_eq!(
        pn.channel_diagnostics[0].name.as_deref(),
        Some("E-PN: PROFINET communication fault")
    );
    let fault = &pn.channel_diagnostics[1];
    assert_eq!(
        (fault.error_type, fault.name.as_deref()),
        (0x101, Some("Drive fault"))
    );
    assert_eq!(fault.ext.len(), 1);
    assert_eq!(
        (
            fault.ext[0].error_type.value,
            fault.ext[0].name.as_deref(),
            fault.ext[0].add_values.len()
        ),
        (1, Some("Fault type (P07.27)"), 1)
    );
}

fn pn_diag(
    code: &'static str,
    severity: Severity,
    line: u32,
    message: &str,
) -> (&'static str, Severity, u32, String) {
    (code, severity, line, message.to_owned())
}

#[test]
fn pn001_identity_numbers_are_16_bit() {
    let line = line_of("VendorID=");
    assert_eq!(
        diagnostics(&edit("VendorID=\"0x0350\"", "VendorID=\"0x10000\"")),
        vec![pn_diag(
            "PN001",
            Error,
            line,
            "`VendorID` is `0x10000`, not a 16-bit number"
        )]
    );
    let no_device_id = edit(" DeviceID=\"0x0350\"", "");
    assert_eq!(
        diagnostics(&no_device_id),
        vec![pn_diag(
            "PN001",
            Error,
            line,
            "`DeviceIdentity` has no `DeviceID`"
        )]
    );
}

#[test]
fn pn002_a_file_without_access_point() {
    let text = card()
        .replace("<DeviceAccessPointList>", "<OtherList>")
        .replace("</DeviceAccessPointList>", "</OtherList>");
    let diags = diagnostics(&text);
    assert_eq!(
        diags[0],
        pn_diag(
            "PN002",
            Error,
            line_of("<DeviceIdentity"),
            "the file describes no `DeviceAccessPointItem`: a controller has nothing to connect to"
        )
    );
    // Its module is then usable nowhere.
    assert_eq!(diags[1].0, "PN005");
    assert_eq!(diags.len(), 2);
}

#[test]
fn a_file_that_is_not_xml_gets_only_the_xml_error() {
    let text = card().replacen("</DeviceAccessPointList>", "</Broken>", 1);
    let codes: Vec<&str> = diagnostics(&text).iter().map(|d| d.0).collect();
    assert_eq!(codes, vec!["EDS601"]);
}

#[test]
fn pn003_unknown_data_types_and_strings_without_length() {
    let text = edit(
        "<DataItem DataType=\"Unsigned16\" TextId=\"T_IN_1\"/>",
        "<DataItem DataType=\"Unsigned17\" TextId=\"T_IN_1\"/>",
    );
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN003",
            Error,
            line_of("TextId=\"T_IN_1\""),
            "`Unsigned17` is not a GSDML data type"
        )]
    );
    let text = edit(
        "<Ref DataType=\"Unsigned16\" ByteOffset=\"0\"",
        "<Ref DataType=\"VisibleString\" ByteOffset=\"0\"",
    );
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN003",
            Error,
            line_of("TextId=\"T_REC_RX_2\""),
            "a `VisibleString` field without `Length`"
        )]
    );
}

#[test]
fn pn004_io_data_beyond_the_access_point_limits() {
    // Input CR: the access point's submodule (IOPS, 1 byte) and the module's 32 bytes, its IOPS
    // and the IOCS of its outputs: 35 bytes.
    let text = edit("MaxInputLength=\"1440\"", "MaxInputLength=\"34\"");
    assert_eq!(
        diagnostics(&text),
        vec![
            pn_diag("PN004", Error, line_of("<DeviceAccessPointItem"), "the default configuration of `DAP_GD350_PN` (fixed and used modules) takes 35 input bytes (with IOPS/IOCS), over access point `DAP_GD350_PN`'s MaxInputLength 34"),
            pn_diag("PN004", Error, line_of("<ModuleItemRef"), "module `MOD_PKW_PZD_16` in access point `DAP_GD350_PN` takes 35 input bytes (with IOPS/IOCS), over access point `DAP_GD350_PN`'s MaxInputLength 34"),
        ]
    );
    assert_eq!(
        diagnostics(&edit("MaxInputLength=\"1440\"", "MaxInputLength=\"35\"")),
        vec![]
    );
}

#[test]
fn pn005_a_module_allowed_in_no_slot() {
    let text = edit(
        "AllowedInSlots=\"1\" UsedInSlots=\"1\"",
        "AllowedInSlots=\"2\"",
    );
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag("PN005", Warning, line_of("<ModuleItemRef"), "module `MOD_PKW_PZD_16` is allowed in no slot of access point `DAP_GD350_PN` (its slots [2], the physical slots [0, 1])")]
    );
}

#[test]
fn pn006_a_reference_to_a_missing_module() {
    let text = edit(
        "ModuleItemTarget=\"MOD_PKW_PZD_16\"",
        "ModuleItemTarget=\"MOD_X\"",
    );
    assert_eq!(
        diagnostics(&text),
        vec![
            pn_diag("PN006", Error, line_of("<ModuleItemRef"), "`ModuleItemTarget` `MOD_X` names no `ModuleItem`"),
            pn_diag("PN005", Warning, line_of("<ModuleItem ID"), "module `MOD_PKW_PZD_16` is in no access point's `UseableModules`: no slot can take it"),
        ]
    );
}

#[test]
fn pn007_a_reference_to_a_missing_text() {
    let text = edit("<Name TextId=\"T_MOD_NAME\"/>", "<Name TextId=\"T_NOPE\"/>");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN007",
            Warning,
            line_of("<Name TextId=\"T_MOD_NAME\"/>"),
            "`TextId` `T_NOPE` has no text in the `ExternalTextList`"
        )]
    );
    let read = read(&text);
    assert_eq!(pn(&read).modules[0].name, None);
}

#[test]
fn pn008_a_reference_to_a_missing_value_list() {
    let text = edit("ValueItemTarget=\"VL_RX\"", "ValueItemTarget=\"VL_NOPE\"");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN008",
            Error,
            line_of("TextId=\"T_REC_RX_2\""),
            "`ValueItemTarget` `VL_NOPE` names no `ValueItem`"
        )]
    );
}

#[test]
fn pn009_record_fields_that_overlap() {
    let text = edit(
        "ByteOffset=\"2\" DefaultValue",
        "ByteOffset=\"1\" DefaultValue",
    );
    let first = line_of("TextId=\"T_REC_RX_2\"");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag("PN009", Error, first + 1, &format!("the `Unsigned16` field at byte 1 shares bits with the `Unsigned16` field at byte 0 (line {first})"))]
    );
}

#[test]
fn pn010_a_record_field_past_the_record_length() {
    let text = edit(
        "ByteOffset=\"20\" DefaultValue=\"0\" AllowedValues=\"0..18\"",
        "ByteOffset=\"21\" DefaultValue=\"0\" AllowedValues=\"0..18\"",
    );
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN010",
            Error,
            line_of("TextId=\"T_REC_RX_12\""),
            "the `Unsigned16` field at byte 21 ends at byte 23, past the record's length 22"
        )]
    );
    let text = edit("Index=\"256\" Length=\"22\"", "Index=\"256\" Length=\"20\"");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN010",
            Error,
            line_of("TextId=\"T_REC_RX_12\""),
            "the `Unsigned16` field at byte 20 ends at byte 22, past the record's length 20"
        )]
    );
}

#[test]
fn pn011_duplicate_ids() {
    let text = card()
        .replace("<ValueItem ID=\"VL_TX\">", "<ValueItem ID=\"VL_RX\">")
        .replace("ValueItemTarget=\"VL_TX\"", "ValueItemTarget=\"VL_RX\"");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN011",
            Error,
            line_of("<ValueItem ID=\"VL_TX\">"),
            &format!(
                "a second item with ID `VL_RX` (the first on line {})",
                line_of("<ValueItem ID=\"VL_RX\">")
            )
        )]
    );
}

#[test]
fn pn012_a_default_outside_the_allowed_values() {
    let text = edit(
        "DefaultValue=\"0\" AllowedValues=\"0..18\"",
        "DefaultValue=\"19\" AllowedValues=\"0..18\"",
    );
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN012",
            Error,
            line_of("TextId=\"T_REC_RX_2\""),
            "`DefaultValue` 19 is not among the `AllowedValues` 0..18"
        )]
    );
    let text = edit("DefaultValue=\"0\"", "DefaultValue=\"70000\"");
    assert_eq!(
        diagnostics(&text)[0].3,
        "`DefaultValue` 70000 is outside a `Unsigned16` field's range 0..65535"
    );
}

#[test]
fn pn013_a_bit_beyond_its_data_item() {
    let text = edit("BitOffset=\"15\"", "BitOffset=\"16\"");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN013",
            Error,
            line_of("BitOffset=\"15\""),
            "bit 16 of a 2-byte `Unsigned16` item, which has bits 0..15"
        )]
    );
}

#[test]
fn pn014_two_records_with_one_index() {
    let text = edit("Index=\"257\"", "Index=\"256\"");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag("PN014", Error, line_of("Index=\"257\""), &format!("submodule `SUB_PKW_PZD_16` has two parameter records with index 256 (the other on line {})", line_of("Index=\"256\"")))]
    );
}

/// The card's channel diagnosis with an `ExtChannelDiagList` of two finer causes, the second
/// with `add` as its `ExtChannelAddValue` data items.
fn with_ext_diagnosis(first: u32, second: u32, add: &str) -> String {
    edit(
        "          <Help TextId=\"T_DIAG_EPN_HELP\"/>\n        </ChannelDiagItem>",
        &format!(
            "          <Help TextId=\"T_DIAG_EPN_HELP\"/>\n          <ExtChannelDiagList>\n            \
             <ExtChannelDiagItem ErrorType=\"{first}\">\n              <Name TextId=\"T_DIAG_EPN\"/>\n            \
             </ExtChannelDiagItem>\n            <ExtChannelDiagItem ErrorType=\"{second}\">\n              \
             <Name TextId=\"T_DIAG_EPN_HELP\"/>\n              <ExtChannelAddValue>{add}</ExtChannelAddValue>\n            \
             </ExtChannelDiagItem>\n          </ExtChannelDiagList>\n        </ChannelDiagItem>"
        ),
    )
}

/// The line of the `n`th (from 1) `<ExtChannelDiagItem` in `text`.
fn ext_line(text: &str, n: usize) -> u32 {
    let at = text
        .match_indices("<ExtChannelDiagItem")
        .nth(n - 1)
        .expect("present")
        .0;
    text[..at].lines().count() as u32
}

#[test]
fn ext_channel_diagnostics_are_read_and_dumped() {
    let text = with_ext_diagnosis(
        1,
        2,
        "<DataItem Id=\"1\" DataType=\"Unsigned16\"/><DataItem Id=\"2\" DataType=\"Unsigned16\"/>",
    );
    assert_eq!(diagnostics(&text), vec![]);
    let read = read(&text);
    let diag = &pn(&read).channel_diagnostics[0];
    assert_eq!(diag.ext.len(), 2);
    let (first, second) = (&diag.ext[0], &diag.ext[1]);
    assert_eq!(
        (
            first.error_type.value,
            first.name.as_deref(),
            first.add_values.len()
        ),
        (1, Some("E-PN: PROFINET communication fault"), 0)
    );
    assert_eq!(first.error_type.span.line, ext_line(&text, 1));
    let add: Vec<(Option<u32>, &str, Option<PnDataType>)> = second
        .add_values
        .iter()
        .map(|v| (v.id, v.data_type.value.as_str(), v.kind))
        .collect();
    assert_eq!(
        add,
        vec![
            (Some(1), "Unsigned16", Some(PnDataType::Unsigned16)),
            (Some(2), "Unsigned16", Some(PnDataType::Unsigned16))
        ]
    );
    let dump = edsgen_model::dump::to_json(&read.device);
    assert_eq!(
        dump["profinet"]["channel_diagnostics"][0]["ext"],
        serde_json::json!([
            {"error_type": 1, "name": "E-PN: PROFINET communication fault", "help": null, "add_values": []},
            {"error_type": 2, "name": "The controller's cyclic data stopped (watchdog); check the cable and the controller, then reset the fault (CW command 7).", "help": null, "add_values": [
                {"id": 1, "data_type": "Unsigned16", "length": null},
                {"id": 2, "data_type": "Unsigned16", "length": null}
            ]}
        ])
    );
}

#[test]
fn pn015_two_ext_channel_diagnostics_with_one_error_type() {
    let text = with_ext_diagnosis(7, 7, "");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN015",
            Error,
            ext_line(&text, 2),
            &format!(
                "a second ExtChannelDiagItem with ErrorType 7 in channel error type 256 (the first \
                 on line {})",
                ext_line(&text, 1)
            )
        )]
    );
}

#[test]
fn pn016_ext_add_values_beyond_32_bits_and_pn003_unknown_types() {
    let text = with_ext_diagnosis(
        1,
        2,
        "<DataItem Id=\"1\" DataType=\"Unsigned32\"/><DataItem Id=\"2\" DataType=\"Unsigned8\"/>",
    );
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN016",
            Error,
            ext_line(&text, 2),
            "ExtChannelDiagItem 2 of channel error type 256 adds 5 bytes of values; an alarm \
             carries 4 (ExtChannelAddValue, Unsigned32)"
        )]
    );
    let text = with_ext_diagnosis(1, 2, "<DataItem Id=\"1\" DataType=\"Unsigned24\"/>");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN003",
            Error,
            ext_line(&text, 2) + 2,
            "`Unsigned24` is not a GSDML data type"
        )]
    );
    // An ErrorType that is no 16-bit number: the attribute's error, and the item is left out.
    let text = with_ext_diagnosis(1, 70000, "");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "EDS604",
            Error,
            ext_line(&text, 2),
            "`ErrorType` is 70000, outside its range"
        )]
    );
    assert_eq!(pn(&read(&text)).channel_diagnostics[0].ext.len(), 1);
}

/// The card with a `SubslotList` on its access point labelling subslot `first` and `second`
/// (the interface's and the first port's labels by default).
fn with_subslot_list(first: u32, second: u32) -> String {
    edit(
        "          <IOConfigData MaxInputLength",
        &format!(
            "          <SubslotList>\n            <SubslotItem SubslotNumber=\"{first}\" \
             TextId=\"T_IF\"/>\n            <SubslotItem SubslotNumber=\"{second}\" \
             TextId=\"T_P1\"/>\n          </SubslotList>\n          <IOConfigData MaxInputLength"
        ),
    )
}

#[test]
fn subslot_labels_are_read_and_dumped() {
    let text = with_subslot_list(32768, 32769);
    assert_eq!(diagnostics(&text), vec![]);
    let read = read(&text);
    let labels: Vec<(u16, Option<&str>)> = pn(&read).access_points[0]
        .subslot_labels
        .iter()
        .map(|l| (l.subslot.value, l.text.as_deref()))
        .collect();
    let texts = |id: &str| {
        let at = text
            .find(&format!("TextId=\"{id}\" Value=\""))
            .expect("a text")
            + id.len()
            + 17;
        text[at..at + text[at..].find('"').expect("closed")].to_owned()
    };
    assert_eq!(
        labels,
        vec![
            (32768, Some(texts("T_IF").as_str())),
            (32769, Some(texts("T_P1").as_str()))
        ]
    );
    let dump = edsgen_model::dump::to_json(&read.device);
    assert_eq!(
        dump["profinet"]["access_points"][0]["subslot_labels"],
        serde_json::json!([
            {"subslot": 32768, "text": texts("T_IF")},
            {"subslot": 32769, "text": texts("T_P1")}
        ])
    );
    assert_eq!(
        dump["profinet"]["modules"][0]["subslot_labels"],
        serde_json::json!([])
    );
}

#[test]
fn pn017_a_subslot_labelled_twice() {
    let text = with_subslot_list(32768, 32768);
    let line = line_of("          <IOConfigData MaxInputLength");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN017",
            Warning,
            line + 2,
            &format!(
                "`DAP_GD350_PN` labels subslot 32768 twice (the first on line {})",
                line + 1
            )
        )]
    );
    // A subslot number that is not 16 bits: the attribute's error, the item left out.
    let text = with_subslot_list(32768, 65536);
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "EDS604",
            Error,
            line + 2,
            "`SubslotNumber` is 65536, outside its range"
        )]
    );
    assert_eq!(pn(&read(&text)).access_points[0].subslot_labels.len(), 1);
}

#[test]
fn pn018_a_default_name_of_station_profinet_forbids() {
    let text = edit(
        "DNS_CompatibleName=\"goodrive350-pn\"",
        "DNS_CompatibleName=\"GD350_PN\"",
    );
    let found: Vec<_> = validate::validate(&read(&text).device)
        .into_iter()
        .map(|d| (d.rule.code, d.span.map(|s| s.line), d.message, d.help))
        .collect();
    assert_eq!(
        found,
        [(
            "PN018",
            Some(54),
            "access point `DAP_GD350_PN`'s DNS_CompatibleName `GD350_PN` is not a name of station PROFINET allows".to_owned(),
            Some("a name of station is DNS labels of lowercase letters, digits and `-`, joined by `.`, at most 240 characters: `gd350-pn` is one".to_owned()),
        )]
    );
    // Capitals alone pass: DNS names are case-insensitive, and controllers lowercase them.
    let text = edit(
        "DNS_CompatibleName=\"goodrive350-pn\"",
        "DNS_CompatibleName=\"GD350-PN\"",
    );
    assert_eq!(validate::validate(&read(&text).device), vec![]);
}

/// PN019: an attribute or child element the schema does not allow, a letter or two from one it
/// does, is named with its help; one far from every allowed name raises nothing.
#[test]
fn pn019_a_misspelt_attribute_or_element_says_did_you_mean() {
    let text = edit(
        "Changeable=\"true\" Visible=\"true\" TextId=\"T_REC_RX_2\"",
        "Changeable=\"true\" Visble=\"true\" Colour=\"red\" TextId=\"T_REC_RX_2\"",
    )
    .replacen("<IOConfigData ", "<IOConfigData MaxDataLenght=\"2880\" ", 1);
    let read = read(&text);
    let mut all = read.diagnostics.clone();
    all.extend(validate::validate(&read.device));
    edsgen_model::diag::sort(&mut all);
    let found: Vec<_> = all
        .iter()
        .map(|d| {
            (
                d.code(),
                d.severity,
                d.span.map_or(0, |s| s.line),
                d.message.as_str(),
                d.help.as_deref(),
            )
        })
        .collect();
    assert_eq!(
        found,
        [
            (
                "PN019",
                Warning,
                line_of("<IOConfigData "),
                "the attribute `MaxDataLenght` is not one GSDML allows on `IOConfigData` (ignored)",
                Some("did you mean `MaxDataLength`?")
            ),
            (
                "PN019",
                Warning,
                line_of("TextId=\"T_REC_RX_2\""),
                "the attribute `Visble` is not one GSDML allows on `Ref` (ignored)",
                Some("did you mean `Visible`?")
            ),
        ]
    );
    let text = edit("<ModuleInfo", "<ModuleInf/>\n<ModuleInfo");
    assert_eq!(
        diagnostics(&text),
        vec![pn_diag(
            "PN019",
            Warning,
            line_of("<ModuleInfo"),
            "the element `ModuleInf` is not one GSDML allows on `DeviceAccessPointItem` (ignored)"
        )]
    );
}
