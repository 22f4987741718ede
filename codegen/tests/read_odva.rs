//! The ODVA EDS reader and the CIP rules on `tests/odva/io.eds`, a small hand-written file: the
//! text (comments, entries over many lines, quoted commas, adjacent strings), exact model values,
//! format detection against CiA 306, then one test per rule, each editing the file and asserting
//! the exact diagnostics.

use std::path::Path;

use edsgen_model::diag::Severity::{self, Error, Info, Warning};
use edsgen_model::model::*;
use edsgen_model::read::{detect_format, read_bytes, Read};
use edsgen_model::validate;

fn io() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/odva/io.eds"))
        .expect("tests/odva/io.eds")
}

fn read(text: &str) -> Read {
    read_bytes(Path::new("io.eds"), text.as_bytes())
}

fn cip(text: &str) -> Cip {
    read(text).device.cip().cloned().expect("an ODVA EDS")
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

fn edit(from: &str, to: &str) -> String {
    let text = io();
    assert!(text.contains(from), "io.eds has no `{from}`");
    text.replacen(from, to, 1)
}

fn d(
    code: &'static str,
    sev: Severity,
    line: u32,
    msg: &str,
) -> (&'static str, Severity, u32, String) {
    (code, sev, line, msg.to_owned())
}

#[test]
fn the_file_reads_clean() {
    assert_eq!(diagnostics(&io()), vec![]);
}

#[test]
fn identity_and_file() {
    let read = read(&io());
    assert_eq!(read.device.source.format, Format::OdvaEds);
    let cip = read.device.cip().cloned().expect("cip");
    assert_eq!(
        cip.file.desc_text.as_deref(),
        Some("Test adapter, with a comma, and $ inside")
    );
    assert_eq!(cip.file.revision.as_deref(), Some("1.0"));
    let id = &cip.identity;
    assert_eq!(id.vendor_code.as_ref().map(|v| v.value), Some(0x1234));
    assert_eq!(
        id.vendor_code.as_ref().map(|v| v.span),
        Some(Span::new(10, 20, 6))
    );
    assert_eq!(id.product_type.as_ref().map(|v| v.value), Some(12));
    assert_eq!(id.product_code.as_ref().map(|v| v.value), Some(7));
    assert_eq!(id.major_revision.as_ref().map(|v| v.value), Some(1));
    assert_eq!(id.minor_revision.as_ref().map(|v| v.value), Some(2));
    assert_eq!(id.product_name.as_deref(), Some("IO test"));
    assert_eq!(id.catalog.as_deref(), Some("T-1"));
    assert_eq!(cip.classifications[0].value, "EtherNetIP");
    assert_eq!(
        read.device.device_info.product_name.as_deref(),
        Some("IO test")
    );
    assert_eq!(
        read.device.device_info.vendor_number.map(|v| v.value),
        Some(0x1234)
    );
}

#[test]
fn parameters_and_enumerations() {
    let cip = cip(&io());
    let speed = &cip.params[&1];
    assert_eq!(speed.name, "Speed");
    assert_eq!(speed.units, "rpm");
    assert_eq!(speed.help, "Motor speed");
    assert_eq!(speed.data_type.as_ref().map(|t| t.value), Some(0xC7));
    assert_eq!(speed.data_size.as_ref().map(|t| t.value), Some(2));
    assert!(speed.read_only());
    assert_eq!(speed.min.as_ref().map(|v| v.value), Some(CipNumber::Int(0)));
    assert_eq!(
        speed.max.as_ref().map(|v| v.value),
        Some(CipNumber::Int(3000))
    );
    assert_eq!(
        speed.default.as_ref().map(|v| v.value),
        Some(CipNumber::Int(1500))
    );
    assert_eq!(
        speed.default.as_ref().map(|v| v.span),
        Some(Span::new(34, 24, 4))
    );
    assert_eq!(speed.scaling, [Some(1), Some(10), Some(1), Some(0)]);
    assert_eq!(speed.decimals, Some(1));
    assert!(!cip.params[&2].read_only());
    assert_eq!(
        cip.enums[&2].values,
        vec![
            (0, "Off".to_owned()),
            (1, "Slow".to_owned()),
            (2, "Fast".to_owned())
        ]
    );
}

#[test]
fn assemblies_with_members() {
    let cip = cip(&io());
    let inputs = &cip.assemblies[&100];
    assert_eq!(inputs.name, "Inputs");
    assert_eq!(inputs.path, None);
    assert_eq!(inputs.size.as_ref().map(|s| s.value), Some(3));
    assert_eq!(
        inputs
            .members
            .iter()
            .map(|m| (m.bits, m.member.clone()))
            .collect::<Vec<_>>(),
        vec![
            (Some(16), FieldRef::Param(1)),
            (Some(8), FieldRef::Param(2))
        ]
    );
    assert_eq!(inputs.instance(), 100);
    let outputs = &cip.assemblies[&150];
    assert_eq!(
        outputs.path.as_ref().map(|p| p.value.as_str()),
        Some("20 04 24 96")
    );
    assert_eq!(outputs.instance(), 150);
    assert_eq!(outputs.descriptor.as_ref().map(|d| d.value), Some(1));
}

#[test]
fn connections_with_their_words_decoded() {
    let cip = cip(&io());
    let c = &cip.connections[&1];
    assert_eq!(c.name, "Exclusive Owner");
    let tt = c.trigger_transport.as_ref().expect("word").value;
    assert_eq!(tt, TriggerTransport(0x8401_0002));
    assert_eq!(tt.classes(), vec![1]);
    assert_eq!(tt.triggers(), vec!["cyclic"]);
    assert_eq!(tt.application_types(), vec!["exclusive-owner"]);
    assert!(tt.server());
    let p = c.params.as_ref().expect("word").value;
    assert!(p.o_t_fixed() && !p.o_t_variable() && p.t_o_fixed() && !p.t_o_variable());
    assert_eq!(p.o_t_format(), 4);
    assert_eq!(
        real_time_format_name(p.o_t_format()),
        "32-bit run/idle header"
    );
    assert_eq!(p.t_o_format(), 0);
    assert_eq!(p.o_t_types(), vec!["point-to-point"]);
    assert_eq!(p.t_o_types(), vec!["multicast", "point-to-point"]);
    assert_eq!(p.o_t_priorities(), vec!["scheduled"]);
    assert_eq!(c.o_t.rpi.value, FieldRef::Param(3));
    assert_eq!(c.o_t.size.value, FieldRef::Number(2));
    assert_eq!(c.o_t.format.value, FieldRef::Assem(150));
    assert_eq!(c.t_o.size.value, FieldRef::Number(3));
    assert_eq!(c.t_o.format.value, FieldRef::Assem(100));
    assert_eq!(c.config1.size.value, FieldRef::Empty);
    assert_eq!(c.config2.size.value, FieldRef::Number(0));
    let path = c.path.as_ref().expect("path");
    assert_eq!(path.value, "20 04 24 01 2C 96 2C 64");
    assert_eq!(
        decode_path(&path.value),
        Ok(vec![
            PathSegment::Class(4),
            PathSegment::Instance(1),
            PathSegment::ConnectionPoint(150),
            PathSegment::ConnectionPoint(100)
        ])
    );
}

#[test]
fn paths_padded_and_packed() {
    assert_eq!(
        decode_path("21 00 04 00 25 00 96 00 30 03"),
        Ok(vec![
            PathSegment::Class(4),
            PathSegment::Instance(150),
            PathSegment::Attribute(3)
        ])
    );
    assert_eq!(
        decode_path("21 04 00 25 32 00 30 03"),
        Ok(vec![
            PathSegment::Class(4),
            PathSegment::Instance(50),
            PathSegment::Attribute(3)
        ])
    );
    assert_eq!(decode_path("20 F5 24 01 XY"), Err(4));
    assert_eq!(decode_path("20"), Err(1));
    assert_eq!(decode_path("E0 01"), Err(0));
}

#[test]
fn ports_capacity_and_class_sections() {
    let cip = cip(&io());
    let port = &cip.ports[&1];
    assert_eq!(
        (
            port.port_type.as_str(),
            port.name.as_str(),
            port.path.as_str(),
            port.port_number
        ),
        ("TCP", "EtherNet/IP", "20 F5 24 01", Some(1))
    );
    assert_eq!(
        cip.capacity
            .iter()
            .map(|e| (
                e.key.as_str(),
                e.fields.iter().map(|f| f.text.as_str()).collect::<Vec<_>>()
            ))
            .collect::<Vec<_>>(),
        vec![
            ("MaxIOConnections", vec!["1"]),
            ("TSpec1", vec!["TxRx", "3", "100"])
        ]
    );
    assert_eq!(cip.other_sections.len(), 1);
    assert_eq!(cip.other_sections[0].name, "TCP/IP Interface Class");
}

#[test]
fn told_from_a_cia_306_eds_by_its_sections() {
    let odva = io();
    assert_eq!(
        detect_format(Path::new("a.eds"), odva.as_bytes()),
        Format::OdvaEds
    );
    assert_eq!(
        detect_format(Path::new("a.EDS"), odva.as_bytes()),
        Format::OdvaEds
    );
    assert_eq!(
        detect_format(Path::new("a"), odva.as_bytes()),
        Format::OdvaEds
    );
    let cia = "[FileInfo]\nFileName=a.eds\n[DeviceInfo]\nVendorName=x\n";
    assert_eq!(
        detect_format(Path::new("a.eds"), cia.as_bytes()),
        Format::Eds
    );
    assert_eq!(detect_format(Path::new("a"), cia.as_bytes()), Format::Eds);
    let read = read_bytes(Path::new("a.eds"), cia.as_bytes());
    assert!(read.device.cip().is_none());
}

#[test]
fn syntax_errors_are_cip001_and_the_rest_is_read() {
    let text = edit("        MinRev = 2;\n", "        MinRev = 2\n");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP001",
            Error,
            16,
            "the entry `MinRev` has no `;` before the next entry"
        )]
    );
    assert_eq!(cip(&text).identity.minor_revision.map(|v| v.value), Some(2));
    let text = edit("        Catalog = \"T-1\";\n", "        Catalog = \"T-1;\n");
    assert_eq!(
        diagnostics(&text),
        vec![
            d(
                "CIP001",
                Error,
                19,
                "the entry `Catalog` has no `;` before the next section"
            ),
            d(
                "CIP001",
                Error,
                19,
                "a string without its closing `\"` on the line"
            ),
        ]
    );
    let text = edit("[Port]\n", "[Port\njust words\n");
    assert_eq!(
        diagnostics(&text),
        vec![
            d("CIP001", Error, 75, "a section header without `]`"),
            d(
                "CIP001",
                Error,
                76,
                "a line that is neither a `[section]`, an entry `Key = ...;` nor a `$` comment"
            ),
            d(
                "CIP002",
                Info,
                77,
                "the key `Port1` is not one [Connection Manager] defines (kept as written)"
            ),
        ]
    );
}

#[test]
fn unknown_sections_and_keys_are_kept_and_reported() {
    let text = edit(
        "[Port]\n",
        "[Vendor Stuff]\n        Foo = 1, 2;\n[Port]\n        Bar = x;\n",
    );
    assert_eq!(
        diagnostics(&text),
        vec![
            d(
                "CIP002",
                Info,
                75,
                "the section [Vendor Stuff] is not one this reader interprets (kept as written)"
            ),
            d(
                "CIP002",
                Info,
                78,
                "the key `Bar` is not one [Port] defines (kept as written)"
            ),
        ]
    );
    let cip = cip(&text);
    let kept = cip
        .other_sections
        .iter()
        .find(|s| s.name == "Vendor Stuff")
        .expect("kept");
    assert_eq!(kept.entries[0].key, "Foo");
    assert_eq!(kept.entries[0].fields.len(), 2);
}

#[test]
fn duplicates_and_bad_fields() {
    let text = edit(
        "        ProdCode = 7;\n",
        "        ProdCode = 7;\n        ProdCode = seven;\n",
    );
    assert_eq!(
        diagnostics(&text),
        vec![
            d("CIP005", Error, 9, "[Device] has no ProdCode"),
            d("CIP003", Error, 15, "the key `ProdCode` appears again in [Device] (first at line 14); the last one wins"),
            d("CIP004", Error, 15, "field 1 of `ProdCode` (product code) is `seven`, not a number in range"),
        ]
    );
    let text = edit(
        "        Port1 = TCP",
        "        Port1 = TCP, x;\n        Port2 = TCP",
    );
    assert_eq!(cip(&text).ports.len(), 2);
    let text = edit("                0x44640405,", "");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP004",
            Error,
            64,
            "`Connection1` has 14 fields; a connection has 15 (trigger and transport, connection \
             parameters, O->T RPI, size, format, T->O RPI, size, format, config #1 size, format, \
             config #2 size, format, name, help, path)"
        ), d("CIP004", Error, 67, "field 2 of `Connection1` (connection parameters) is `Param3`, not a number in range")]
    );
}

#[test]
fn cip005_identity_incomplete() {
    let text = edit("        VendCode = 0x1234;\n", "").replace("        MajRev = 1;\n", "");
    assert_eq!(
        diagnostics(&text),
        vec![d("CIP005", Error, 9, "[Device] has no VendCode, MajRev")]
    );
    let text = edit("[File]", "[Filez]");
    assert_eq!(
        diagnostics(&text),
        vec![
            d("CIP005", Error, 0, "the file has no [File] section"),
            d(
                "CIP002",
                Info,
                4,
                "the section [Filez] is not one this reader interprets (kept as written)"
            ),
        ]
    );
}

#[test]
fn cip010_data_type_and_size() {
    let text = edit("0,,,0x0000,0xC6,1,", "0,,,0x0000,0xC6,2,");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP010",
            Error,
            39,
            "Param2 `Mode` is USINT (1 byte) but its data size says 2"
        )]
    );
    let text = edit("0,,,0x0000,0xC6,1,", "0,,,0x0000,0xB0,1,");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP010",
            Error,
            39,
            "Param2 `Mode` has data type 0xB0, not a CIP elementary type"
        )]
    );
}

#[test]
fn cip011_default_outside_limits() {
    let text = edit("0,3000,1500,", "0,3000,3001,");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP011",
            Error,
            34,
            "the default of Param1 `Speed`, 3001, is above its maximum, 3000"
        )]
    );
    let text = edit("0,3000,1500,", "3000,0,1500,");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP011",
            Error,
            34,
            "the minimum of Param1 `Speed`, 3000, exceeds its maximum, 0"
        )]
    );
    let text = edit("0,3000,1500,", "-1,3000,1500,");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP011",
            Error,
            34,
            "the minimum of Param1 `Speed`, -1, is outside its data type (0..=65535)"
        )]
    );
}

#[test]
fn cip012_enumeration_for_a_missing_parameter() {
    let text = edit("Enum2 =", "Enum9 =");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP012",
            Error,
            40,
            "Enum9 names the values of Param9, which the file does not have"
        )]
    );
}

#[test]
fn cip020_members_not_adding_up() {
    let text = edit("                3,\n", "                4,\n");
    assert_eq!(
        diagnostics(&text),
        vec![
            d("CIP020", Error, 50, "Assem100 `Inputs` is 4 bytes (32 bits) but its 2 members add up to 24 bits"),
            d("CIP030", Error, 68, "Connection1 `Exclusive Owner` gives T->O a size of 3 bytes, but its format Assem100 `Inputs` is 4 bytes"),
        ]
    );
}

#[test]
fn cip021_missing_references() {
    let text = edit("                8,Param2;", "                8,Param8;");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP021",
            Error,
            54,
            "a member of Assem100 `Inputs` is Param8, which the file does not have"
        )]
    );
    let text = edit("Param3,2,Assem150,", "Param4,2,Assem150,");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP021",
            Error,
            67,
            "Connection1 `Exclusive Owner` names Param4 (O->T), which the file does not have"
        )]
    );
}

#[test]
fn cip030_connection_size_disagrees_with_its_assembly() {
    let text = edit("Param3,2,Assem150,", "Param3,4,Assem150,");
    assert_eq!(
        diagnostics(&text),
        vec![d("CIP030", Error, 67, "Connection1 `Exclusive Owner` gives O->T a size of 4 bytes, but its format Assem150 `Outputs` is 2 bytes")]
    );
}

#[test]
fn cip031_path_naming_no_object() {
    let text = edit("\"20 04 24 01 2C 96 2C 64\"", "\"20 04 24 01 2C 97 2C 64\"");
    assert_eq!(
        diagnostics(&text),
        vec![d("CIP031", Error, 73, "the path of Connection1 `Exclusive Owner` names assembly 151 as its O->T connection point, which [Assembly] does not have")]
    );
    let text = edit("\"20 04 24 01 2C 96 2C 64\"", "\"20 04 24 01 2C 64 2C 96\"");
    assert_eq!(
        diagnostics(&text),
        vec![
            d("CIP031", Error, 73, "the path of Connection1 `Exclusive Owner` names assembly 100 (Assem100) as its O->T connection point, but its format is Assem150"),
            d("CIP031", Error, 73, "the path of Connection1 `Exclusive Owner` names assembly 150 (Assem150) as its T->O connection point, but its format is Assem100"),
        ]
    );
    let text = edit("\"20 04 24 01 2C 96 2C 64\"", "\"20 04 24 01 2C\"");
    assert_eq!(
        diagnostics(&text),
        vec![d(
            "CIP031",
            Error,
            73,
            "the path of Connection1 `Exclusive Owner` does not decode as an EPATH (at byte 5)"
        )]
    );
}

#[test]
fn cip032_connection_words() {
    let text = edit("0x84010002,", "0x84000000,");
    assert_eq!(
        diagnostics(&text),
        vec![d("CIP032", Warning, 65, "Connection1 `Exclusive Owner` allows no transport class (bits 0-15), no trigger (bits 16-18)")]
    );
}

#[test]
fn spans_point_at_fields_of_entries_over_many_lines() {
    let text = edit("Param3,2,Assem150,", "Param3,4,Assem150,");
    let read = read(&text);
    let diags = validate::validate(&read.device);
    assert_eq!(diags[0].span, Some(Span::new(67, 24, 1)));
}

#[test]
fn overlay_pkw_pzd_names_32_byte_assemblies() {
    use edsgen_model::overlay::apply;
    let mut device = read(&io()).device;
    let diags = apply(
        "[pkw_pzd]\noutput = 150\ninput = 100\nbyte_order = \"little\"\n",
        &mut device,
    );
    assert_eq!(
        diags.iter().map(|d| d.message.as_str()).collect::<Vec<_>>(),
        vec![
            "Assem150 is 2 bytes; a PKW/PZD image is 32 (16 words)",
            "Assem100 is 3 bytes; a PKW/PZD image is 32 (16 words)",
        ]
    );
    assert_eq!(device.cip().and_then(|c| c.pkw_pzd), None);
    let text = io()
        .replace(
            "                3,\n                0x0000,",
            "                32,\n                0x0000,",
        )
        .replace(
            "                8,Param2;",
            "                8,Param2,\n                232,;",
        )
        .replace(
            "                2,\n                0x0001,",
            "                32,\n                0x0001,",
        )
        .replace(
            "                16,Param1;",
            "                16,Param1,\n                240,;",
        )
        .replace("Param3,2,Assem150,", "Param3,32,Assem150,")
        .replace("Param3,3,Assem100,", "Param3,32,Assem100,");
    assert_eq!(diagnostics(&text), vec![]);
    let mut device = read(&text).device;
    let diags = apply(
        "[pkw_pzd]\noutput = 150\ninput = 100\nbyte_order = \"big\"\n",
        &mut device,
    );
    assert_eq!(diags, vec![]);
    assert_eq!(
        device.cip().and_then(|c| c.pkw_pzd),
        Some(PkwPzdImages {
            output: 150,
            input: 100,
            little_endian: false
        })
    );
    let mut device = read(&text).device;
    let diags = apply("[pkw_pzd]\noutput = 150\nwhat = 1\n", &mut device);
    assert_eq!(
        diags.iter().map(|d| d.message.as_str()).collect::<Vec<_>>(),
        vec!["`what` is not a key of [pkw_pzd] (output = N, input = N, byte_order = \"little\")"]
    );
    let mut cia = read_bytes(Path::new("a.eds"), b"[FileInfo]\nFileName=a.eds\n").device;
    let diags = apply("[pkw_pzd]\noutput = 150\n", &mut cia);
    assert_eq!(
        diags.iter().map(|d| d.message.as_str()).collect::<Vec<_>>(),
        vec![
            "[pkw_pzd] is for an ODVA EDS (EtherNet/IP), a GSD or a GSDML file; this description \
             is none of them"
        ]
    );
}

/// Reader and validator diagnostics as (code, line, message, help), in file order.
fn helps(text: &str) -> Vec<(&'static str, u32, String, Option<String>)> {
    let read = read(text);
    let mut all = read.diagnostics.clone();
    all.extend(validate::validate(&read.device));
    edsgen_model::diag::sort(&mut all);
    all.into_iter()
        .map(|d| (d.rule.code, d.span.map_or(0, |s| s.line), d.message, d.help))
        .collect()
}

#[test]
fn cip022_member_sizes_in_bytes_are_read_as_bytes_when_only_that_adds_up() {
    let text = edit(
        "16,Param1,\n                8,Param2;",
        "2,Param1,\n                1,Param2;",
    );
    assert_eq!(
        helps(&text),
        vec![(
            "CIP022",
            50,
            "Assem100 `Inputs`: member sizes read as bytes: 1 member of 2 bytes and 1 of 1 byte = 3 bytes, the assembly's size".to_owned(),
            Some("member sizes are bits in the EDS specification: write each member's size times 8 (read as bits, the members add up to 3 bits, not 3 bytes)".to_owned()),
        )]
    );
    // Honoured: the model holds bits, as the specification's reading of the file would.
    let members: Vec<_> = cip(&text).assemblies[&100]
        .members
        .iter()
        .map(|m| m.bits)
        .collect();
    assert_eq!(members, [Some(16), Some(8)]);
}

#[test]
fn cip020_help_names_the_reading_nearer_the_size_and_both_fixes() {
    let text = edit("                3,\n", "                4,\n");
    assert_eq!(
        helps(&text)[0].3.as_deref(),
        Some("read as bits, the members fill 3 bytes, not 4: correct the members (to 25 to 32 bits) or the size (to 3), whichever is wrong")
    );
    // Read as bytes the members are 4 bytes, the size 3: neither reading adds up.
    let text = edit(
        "16,Param1,\n                8,Param2;",
        "2,Param1,\n                2,Param2;",
    );
    assert_eq!(
        helps(&text),
        vec![
            (
                "CIP020",
                50,
                "Assem100 `Inputs` is 3 bytes (24 bits) but its 2 members add up to 4 bits".to_owned(),
                Some("read as bytes, as this file may write them, the members make 4 bytes, not 3 either: correct the members or the size, whichever is wrong".to_owned()),
            ),
            (
                "CIP023",
                53,
                "a member of Assem100 `Inputs` takes 2 bits of Param1 `Speed`, whose data size is 2 bytes (16 bits)".to_owned(),
                Some("a scanner places Param1's value in these bits: make the member 16 bits, or the parameter's data size match".to_owned()),
            ),
            (
                "CIP023",
                54,
                "a member of Assem100 `Inputs` takes 2 bits of Param2 `Mode`, whose data size is 1 byte (8 bits)".to_owned(),
                Some("a scanner places Param2's value in these bits: make the member 8 bits, or the parameter's data size match".to_owned()),
            ),
        ]
    );
}

#[test]
fn cip023_a_member_against_its_parameter_and_packed_bits_pass() {
    let text = edit("16,Param1;", "8,Param1,\n                8,;");
    assert_eq!(
        diagnostics(&text),
        vec![d("CIP023", Warning, 61, "a member of Assem150 `Outputs` takes 8 bits of Param1 `Speed`, whose data size is 2 bytes (16 bits)")]
    );
    // A BOOL takes one bit of its byte.
    let text = edit(
        "0xC6,1,\"Mode\",\"\",\"\",0,2,0",
        "0xC1,1,\"Mode\",\"\",\"\",0,1,0",
    )
    .replacen("8,Param2;", "1,Param2,\n                7,;", 1);
    assert_eq!(diagnostics(&text), vec![]);
}

#[test]
fn a_connection_is_sized_by_its_format_assembly_then_by_its_size() {
    let cip = cip(&io());
    let c = &cip.connections[&1];
    assert_eq!(
        (cip.connection_size(&c.o_t), cip.connection_size(&c.t_o)),
        (Some(2), Some(3))
    );
    // The size written disagrees (CIP030): the assembly, which the device holds, wins.
    let cip = self::cip(&edit("Param3,3,Assem100", "Param3,5,Assem100"));
    assert_eq!(cip.connection_size(&cip.connections[&1].t_o), Some(3));
    // No format: the size written, a number or a parameter's default.
    let cip = self::cip(&edit("Param3,3,Assem100", "Param3,7,"));
    assert_eq!(cip.connection_size(&cip.connections[&1].t_o), Some(7));
    let cip = self::cip(&edit("Param3,3,Assem100", "Param3,Param3,"));
    assert_eq!(cip.connection_size(&cip.connections[&1].t_o), Some(50000));
}

/// A key a letter or two from one its section defines (a numbered key with the same number), or
/// a section a letter or two from one the reader interprets, gets that name as its help; a key
/// near no name gets none.
#[test]
fn a_misspelt_key_or_section_says_did_you_mean() {
    let text = edit(
        "        ProdName",
        "        ProdTypStr = \"I/O\";\n        ProdName",
    )
    .replacen(
        "[Port]\n",
        "[Port]\n        Prot2 = TCP, \"x\", \"20 F5 24 01\", 2;\n        Bar = x;\n",
        1,
    ) + "\n[Capacty]\n        MaxIOConnections = 1;\n";
    assert_eq!(
        helps(&text),
        vec![
            (
                "CIP002",
                17,
                "the key `ProdTypStr` is not one [Device] defines (kept as written)".to_owned(),
                Some("did you mean `ProdTypeStr`?".to_owned())
            ),
            (
                "CIP002",
                77,
                "the key `Prot2` is not one [Port] defines (kept as written)".to_owned(),
                Some("did you mean `Port2`?".to_owned())
            ),
            (
                "CIP002",
                78,
                "the key `Bar` is not one [Port] defines (kept as written)".to_owned(),
                None
            ),
            (
                "CIP002",
                88,
                "the section [Capacty] is not one this reader interprets (kept as written)"
                    .to_owned(),
                Some("did you mean [Capacity]?".to_owned())
            ),
        ]
    );
}
