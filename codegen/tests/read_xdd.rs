//! The XDD/XDC reader: the ten XML files of the corpus, and small inline documents for uniqueIDRef
//! resolution, namespaces, PDOmapping and malformed input.

mod corpus_support;

use std::path::{Path, PathBuf};

use corpus_support::corpus_dir;
use edsgen_model::diag::Severity;
use edsgen_model::model::*;
use edsgen_model::read::{read_bytes, read_file, Read};

// ---------------------------------------------------------------------------------------------
// Corpus

fn read_corpus(dir: &Path, name: &str) -> Read {
    read_file(&dir.join(name)).expect("corpus file readable")
}

fn entry_count(device: &Device) -> usize {
    device.objects.values().map(|o| o.subs.len()).sum()
}

fn value(source: &Option<ValueSource>) -> Option<&Value> {
    source.as_ref().and_then(|s| s.value.as_ref())
}

fn raw(source: &Option<ValueSource>) -> Option<&str> {
    source.as_ref().map(|s| s.raw.as_str())
}

/// (file, format, objects, entries, diagnostics by code): every XML file of the corpus. Objects
/// and entries are counted from the file text (`<CANopenObject` elements; VAR objects plus
/// `<CANopenSubObject` elements); the diagnostics are the files' real problems: postfix
/// `0x80+$NODEID` (EDS016), signed limits written as unsigned hex (EDS014), C literals `0x...LL`
/// (EDS025), a baud rate without its unit (EDS604, info).
type CorpusCase = (
    &'static str,
    Format,
    usize,
    usize,
    &'static [(&'static str, usize)],
);

const CORPUS_XML: &[CorpusCase] = &[
    (
        "CANopenNode__CANopenDemo/demo__demoDevice.xdd",
        Format::Xdd,
        48,
        286,
        &[],
    ),
    (
        "CANopenNode__CANopenEditor/Tests__minimal_project.xdd",
        Format::Xdd,
        10,
        28,
        &[],
    ),
    (
        "CANopenNode__CANopenSocket/canopend__objDict__CANopenSocket.xdd",
        Format::Xdd,
        173,
        1149,
        &[("EDS025", 2)],
    ),
    (
        "CANopenNode__CANopenSocket/examples__basicDevice__basicDevice.xdd",
        Format::Xdd,
        44,
        279,
        &[("EDS016", 1)],
    ),
    (
        "canopen-python__canopen/test__sample.xdd",
        Format::Xdd,
        40,
        125,
        &[("EDS014", 3), ("EDS016", 1)],
    ),
    (
        "davidsenoner__emec-drv-canopen-tester/doc__Slave_06__emecdrv5.xdd",
        Format::Xdd,
        31,
        75,
        &[],
    ),
    (
        "dborgards__eds-dcf-net/tests__EdsDcfNet.Tests__Fixtures__minimal.xdc",
        Format::Xdc,
        2,
        2,
        &[],
    ),
    (
        "jrholand__EagleEyePhotography/Node1.config.xdc",
        Format::Xdc,
        178,
        671,
        &[("EDS604", 1)],
    ),
    (
        "oresat__oresat-firmware/src__f0__app_battery__source__ObjDict__app.xdd",
        Format::Xdd,
        106,
        631,
        &[("EDS016", 1)],
    ),
    (
        "oresat__oresat-firmware/src__f0__app_imu__source__ObjDict__app_OD.xdd",
        Format::Xdd,
        54,
        196,
        &[],
    ),
];

#[test]
fn every_corpus_xml_file_reads_with_exact_counts() {
    let Some(dir) = corpus_dir() else { return };
    for &(name, format, objects, entries, diagnostics) in CORPUS_XML {
        let read = read_corpus(&dir, name);
        assert_eq!(read.device.source.format, format, "{name}");
        assert_eq!(read.device.objects.len(), objects, "{name}: objects");
        assert_eq!(entry_count(&read.device), entries, "{name}: entries");
        let mut by_code = std::collections::BTreeMap::new();
        for d in &read.diagnostics {
            *by_code.entry(d.rule.code).or_insert(0) += 1;
        }
        let expected: std::collections::BTreeMap<&str, usize> =
            diagnostics.iter().copied().collect();
        assert_eq!(by_code, expected, "{name}: {:#?}", read.diagnostics);
        for object in read.device.objects.values() {
            assert!(
                object.span.line > 0,
                "{name}: {:04X} has no span",
                object.index
            );
            if matches!(object.object_type, ObjectType::Var | ObjectType::Domain) {
                assert_eq!(
                    object.subs.keys().copied().collect::<Vec<_>>(),
                    vec![0],
                    "{name}: {:04X}",
                    object.index
                );
            }
        }
    }
}

#[test]
fn corpus_xml_files_are_every_xml_file_of_the_corpus() {
    let Some(dir) = corpus_dir() else { return };
    let mut found = Vec::new();
    for project in std::fs::read_dir(&dir).unwrap() {
        let project = project.unwrap().path();
        if !project.is_dir() {
            continue;
        }
        for file in std::fs::read_dir(&project).unwrap() {
            let file = file.unwrap().path();
            let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
            if ext.eq_ignore_ascii_case("xdd") || ext.eq_ignore_ascii_case("xdc") {
                let rel = file
                    .strip_prefix(&dir)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                found.push(rel);
            }
        }
    }
    found.sort();
    let mut listed: Vec<String> = CORPUS_XML.iter().map(|c| c.0.to_owned()).collect();
    listed.sort();
    assert_eq!(found, listed);
}

#[test]
fn minimal_project_resolves_parameters() {
    let Some(dir) = corpus_dir() else { return };
    let read = read_corpus(
        &dir,
        "CANopenNode__CANopenEditor/Tests__minimal_project.xdd",
    );
    let device = &read.device;
    assert_eq!(
        device.file_info.file_name.as_deref(),
        Some("minimal_project.xdd")
    );
    assert_eq!(
        device.file_info.creation_date.as_deref(),
        Some("2024-07-22")
    );
    assert_eq!(
        device.device_info.product_name.as_deref(),
        Some("minimal_test")
    );
    assert_eq!(
        device.device_info.granularity.as_ref().map(|g| g.value),
        Some(8)
    );
    assert_eq!(
        device
            .dummy_usage
            .iter()
            .map(|(k, v)| (*k, *v))
            .collect::<Vec<_>>(),
        (1..=7).map(|i| (i, false)).collect::<Vec<_>>()
    );

    // <CANopenObject index="1001" ... PDOmapping="TPDO" uniqueIDRef="UID_OBJ_1001" /> at line
    // 243; the parameter has <USINT />, no access (read), <defaultValue value="0x00" /> at 67.
    let error_register = &device.objects[&0x1001];
    assert_eq!(error_register.object_type, ObjectType::Var);
    assert_eq!(error_register.span, Span::new(243, 11, 14));
    let sub = &error_register.subs[&0];
    assert_eq!(sub.name, "Error register");
    assert_eq!(sub.data_type, Some(0x0005));
    assert_eq!(sub.access, Some(AccessType::Ro));
    assert!(sub.pdo_mapping);
    assert_eq!(raw(&sub.default), Some("0x00"));
    assert_eq!(value(&sub.default), Some(&Value::Integer(0)));
    assert_eq!(sub.default.as_ref().unwrap().span, Span::new(67, 37, 4));
    assert!(sub
        .custom
        .contains(&("CO_countLabel".to_owned(), "EM".to_owned())));

    // 1003h: ARRAY, subNumber 17, sub 0 readWrite, subs 1.. read UDINT.
    let errors = &device.objects[&0x1003];
    assert_eq!(errors.object_type, ObjectType::Array);
    assert_eq!(errors.sub_number.as_ref().map(|n| n.value), Some(17));
    assert_eq!(errors.subs.len(), 17);
    assert_eq!(errors.subs[&0].access, Some(AccessType::Rw));
    assert_eq!(errors.subs[&0].data_type, Some(0x0005));
    assert_eq!(errors.subs[&0x10].name, "Standard error field");
    assert_eq!(errors.subs[&0x10].access, Some(AccessType::Ro));
    assert_eq!(errors.subs[&0x10].data_type, Some(0x0007));
    assert_eq!(errors.subs[&0x10].default, None);

    // 1014h: <defaultValue value="$NODEID+0x80" />.
    let emcy = &device.objects[&0x1014].subs[&0];
    assert_eq!(value(&emcy.default), Some(&Value::NodeRelative(0x80)));
    assert_eq!(emcy.access, Some(AccessType::Rw));
}

#[test]
fn minimal_xdc_without_namespace_reads_commissioning() {
    let Some(dir) = corpus_dir() else { return };
    let read = read_corpus(
        &dir,
        "dborgards__eds-dcf-net/tests__EdsDcfNet.Tests__Fixtures__minimal.xdc",
    );
    assert_eq!(read.diagnostics, vec![]);
    let device = &read.device;
    assert_eq!(device.source.format, Format::Xdc);
    assert_eq!(device.file_info.file_name.as_deref(), Some("minimal.xdc"));
    assert_eq!(
        device.file_info.created_by.as_deref(),
        Some("EdsDcfNet Test")
    );
    assert_eq!(
        device.device_info.vendor_name.as_deref(),
        Some("Test Vendor")
    );
    assert_eq!(
        device.device_info.vendor_number.as_ref().map(|v| v.value),
        Some(0x100)
    );
    assert_eq!(
        device.device_info.product_number.as_ref().map(|v| v.value),
        Some(1)
    );
    assert_eq!(
        device.device_info.baud_rates,
        vec![(250, true), (500, true)]
    );
    assert_eq!(
        device.device_info.granularity.as_ref().map(|g| g.value),
        Some(8)
    );
    assert_eq!(
        device.device_info.nr_of_rx_pdo.as_ref().map(|g| g.value),
        Some(0)
    );
    assert!(device.device_info.simple_boot_up_slave);
    assert!(!device.device_info.lss_supported);

    let commissioning = device.commissioning.as_ref().expect("deviceCommissioning");
    assert_eq!(commissioning.node_id.as_ref().map(|n| n.value), Some(5));
    assert_eq!(commissioning.node_name.as_deref(), Some("MinimalDevice"));
    assert_eq!(commissioning.baudrate.as_ref().map(|b| b.value), Some(500));
    assert_eq!(commissioning.net_number, Some(1));
    assert_eq!(
        commissioning.network_name.as_deref(),
        Some("CANopen Network")
    );
    assert!(!commissioning.canopen_manager);

    // <CANopenObject index="1000" ... defaultValue="0x00000000" ... actualValue="0x00000191"/>
    let device_type = &device.objects[&0x1000];
    assert_eq!(device_type.name, "Device Type");
    assert_eq!(device_type.span, Span::new(51, 11, 14));
    let sub = &device_type.subs[&0];
    assert_eq!(sub.data_type, Some(0x0007));
    assert_eq!(sub.access, Some(AccessType::Ro));
    assert!(!sub.pdo_mapping);
    assert_eq!(value(&sub.default), Some(&Value::Integer(0)));
    assert_eq!(value(&sub.parameter_value), Some(&Value::Integer(0x191)));
    assert_eq!(
        sub.parameter_value.as_ref().unwrap().span,
        Span::new(53, 39, 10)
    );
}

#[test]
fn faulhaber_xdc_namespace_1_0_resolves_limits_and_access() {
    let Some(dir) = corpus_dir() else { return };
    let read = read_corpus(&dir, "jrholand__EagleEyePhotography/Node1.config.xdc");
    let device = &read.device;
    assert_eq!(
        device.device_info.vendor_number.as_ref().map(|v| v.value),
        Some(327)
    );
    assert_eq!(device.device_info.product_name.as_deref(), Some("MC5005"));
    assert_eq!(
        device.device_info.granularity.as_ref().map(|g| g.value),
        Some(4)
    );
    assert!(device.device_info.lss_supported);
    assert!(!device.device_info.simple_boot_up_slave);
    // actualBaudRate="250", without a unit: read as kbit/s, with an info diagnostic.
    let commissioning = device.commissioning.as_ref().unwrap();
    assert_eq!(commissioning.baudrate.as_ref().map(|b| b.value), Some(250));
    assert_eq!(commissioning.node_id.as_ref().map(|n| n.value), Some(1));
    let codes: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.severity, d.span.map(|s| s.line)))
        .collect();
    assert!(
        codes.contains(&("EDS604", Severity::Info, Some(1551))),
        "{codes:?}"
    );

    // 1029h sub 1 takes everything from UID_PARAM_102901: readWrite, USINT, actual 0, default 0,
    // range 0..255, allowed values 0, 1, 2.
    let sub = &device.objects[&0x1029].subs[&1];
    assert_eq!(sub.name, "Communication error");
    assert_eq!(sub.access, Some(AccessType::Rw));
    assert_eq!(sub.data_type, Some(0x0005));
    assert_eq!(value(&sub.default), Some(&Value::Integer(0)));
    assert_eq!(value(&sub.parameter_value), Some(&Value::Integer(0)));
    assert_eq!(value(&sub.low_limit), Some(&Value::Integer(0)));
    assert_eq!(value(&sub.high_limit), Some(&Value::Integer(255)));
    assert_eq!(sub.low_limit.as_ref().unwrap().span.line, 76);
    assert!(sub
        .custom
        .contains(&("AllowedValues".to_owned(), "0,1,2".to_owned())));

    // <CANopenSubObject subIndex="08" ... accessType="wo" PDOmapping="no" objFlags="0003" .../>
    let debug = &device.objects[&0x2310].subs[&8];
    assert_eq!(debug.access, Some(AccessType::Wo));
    assert_eq!(
        debug.key_spans.data_type.map(|s| (s.line, s.len)),
        Some((858, 4))
    );
    assert_eq!(
        debug.key_spans.access.map(|s| (s.line, s.len)),
        Some((858, 2))
    );
    assert_eq!(
        debug.key_spans.pdo_mapping.map(|s| (s.line, s.len)),
        Some((858, 2))
    );
    assert_eq!(debug.obj_flags, 3);
    assert_eq!(value(&debug.high_limit), Some(&Value::Integer(255)));

    // 6041h: accessType="ro" PDOmapping="TPDO" actualValue="5159".
    let statusword = &device.objects[&0x6041].subs[&0];
    assert_eq!(statusword.access, Some(AccessType::Ro));
    assert!(statusword.pdo_mapping);
    assert_eq!(
        value(&statusword.parameter_value),
        Some(&Value::Integer(5159))
    );

    // 2313h sub 19h: accessType="rw" PDOmapping="RPDO" becomes rww.
    let virtual_input = &device.objects[&0x2313].subs[&0x19];
    assert_eq!(virtual_input.access, Some(AccessType::Rww));
    // 2313h sub 0Ah: the parameter says readWriteInput (written by the network), PDOmapping
    // says RPDO: rww, and no conflict.
    let enable = &device.objects[&0x2313].subs[&0x0A];
    assert_eq!(enable.access, Some(AccessType::Rww));
    assert!(!codes.iter().any(|c| c.0 == "EDS608"), "{codes:?}");
}

#[test]
fn emec_xdd_reads_attributes_without_parameters() {
    let Some(dir) = corpus_dir() else { return };
    let read = read_corpus(
        &dir,
        "davidsenoner__emec-drv-canopen-tester/doc__Slave_06__emecdrv5.xdd",
    );
    let device = &read.device;
    let device_type = &device.objects[&0x1000].subs[&0];
    assert_eq!(device_type.access, Some(AccessType::Const));
    assert_eq!(
        value(&device_type.default),
        Some(&Value::Integer(0x9202_0100))
    );
    let identity = &device.objects[&0x1018];
    assert_eq!(identity.object_type, ObjectType::Record);
    assert_eq!(identity.sub_number.as_ref().map(|n| n.value), Some(5));
    assert_eq!(identity.subs[&1].name, "Vendor Id");
    assert_eq!(
        value(&identity.subs[&1].default),
        Some(&Value::Integer(0x123))
    );
    let heartbeat = &device.objects[&0x1017].subs[&0];
    assert_eq!(heartbeat.access, Some(AccessType::Rw));
    assert_eq!(value(&heartbeat.default), Some(&Value::Integer(1000)));
}

#[test]
fn demo_device_bitstring_becomes_octet_string_or_domain() {
    let Some(dir) = corpus_dir() else { return };
    let read = read_corpus(&dir, "CANopenNode__CANopenDemo/demo__demoDevice.xdd");
    let device = &read.device;
    // <BITSTRING /> with <defaultValue value="00 00 00 00 00 00 00 00 00 00" />.
    let bits = &device.objects[&0x2100].subs[&0];
    assert_eq!(bits.data_type, Some(0x000A));
    assert_eq!(value(&bits.default), Some(&Value::Bytes(vec![0; 10])));
    assert!(bits.pdo_mapping);
    // <BITSTRING /> without a default: DOMAIN.
    let domain = &device.objects[&0x2122].subs[&0];
    assert_eq!(domain.data_type, Some(0x000F));
    assert_eq!(domain.access, Some(AccessType::Rw));
    // 2121h sub 3: readWrite BITSTRING "C8 3D BB".
    let octets = &device.objects[&0x2121].subs[&3];
    assert_eq!(octets.data_type, Some(0x000A));
    assert_eq!(
        value(&octets.default),
        Some(&Value::Bytes(vec![0xC8, 0x3D, 0xBB]))
    );
}

// ---------------------------------------------------------------------------------------------
// Inline documents

fn read_xml(name: &str, xml: &str) -> Read {
    read_bytes(Path::new(name), xml.as_bytes())
}

/// A container with one device profile body (`parameters`) and one network body (`objects`),
/// under the namespace declaration `ns` (e.g. `xmlns="http://www.canopen.org/xml/1.1"`).
fn container(ns: &str, parameters: &str, objects: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<ISO15745ProfileContainer {ns}>
<ISO15745Profile>
<ProfileBody fileName="t.xdd" fileVersion="2">
<ApplicationProcess>
<parameterList>
{parameters}
</parameterList>
</ApplicationProcess>
</ProfileBody>
</ISO15745Profile>
<ISO15745Profile>
<ProfileBody>
<ApplicationLayers>
<CANopenObjectList>
{objects}
</CANopenObjectList>
</ApplicationLayers>
</ProfileBody>
</ISO15745Profile>
</ISO15745ProfileContainer>
"#
    )
}

const PARAMETER: &str = r#"<parameter uniqueID="P1" access="readWrite">
<denotation><label lang="en">Speed set</label></denotation>
<INT/>
<defaultValue value="-5"/>
<actualValue value="7"/>
<allowedValues><range><minValue value="-100"/><maxValue value="100"/></range></allowedValues>
</parameter>"#;

const OBJECT: &str = r#"<CANopenObject index="2000" name="Speed" objectType="7" dataType="0003" accessType="ro" defaultValue="1" lowLimit="0" highLimit="9" PDOmapping="RPDO" uniqueIDRef="P1"/>"#;

#[test]
fn parameter_overrides_object_attributes() {
    let read = read_xml("t.xdd", &container("", PARAMETER, OBJECT));
    assert_eq!(read.diagnostics, vec![]);
    let sub = &read.device.objects[&0x2000].subs[&0];
    assert_eq!(sub.name, "Speed");
    assert_eq!(sub.data_type, Some(0x0003));
    // readWrite with PDOmapping RPDO.
    assert_eq!(sub.access, Some(AccessType::Rww));
    assert!(sub.pdo_mapping);
    assert_eq!(raw(&sub.default), Some("-5"));
    assert_eq!(value(&sub.default), Some(&Value::Integer(-5)));
    assert_eq!(sub.default.as_ref().unwrap().span, Span::new(10, 22, 2));
    assert_eq!(value(&sub.parameter_value), Some(&Value::Integer(7)));
    assert_eq!(value(&sub.low_limit), Some(&Value::Integer(-100)));
    assert_eq!(value(&sub.high_limit), Some(&Value::Integer(100)));
    assert_eq!(sub.denotation.as_deref(), Some("Speed set"));
    // The spans point at what decided: the parameter's <INT/> and access, the object's PDOmapping.
    assert_eq!(
        sub.key_spans,
        KeySpans {
            data_type: Some(Span::new(9, 1, 4)),
            access: Some(Span::new(7, 34, 9)),
            pdo_mapping: Some(Span::new(22, 145, 4)),
            ..KeySpans::default()
        }
    );
    assert_eq!(read.device.file_info.file_name.as_deref(), Some("t.xdd"));
    assert_eq!(read.device.file_info.file_version.as_deref(), Some("2"));
}

#[test]
fn namespaces_1_0_1_1_prefixed_and_none_read_alike() {
    let plain = read_xml("t.xdd", &container("", PARAMETER, OBJECT));
    let v10 = read_xml(
        "t.xdd",
        &container(
            r#"xmlns="http://www.canopen.org/xml/1.0""#,
            PARAMETER,
            OBJECT,
        ),
    );
    let v11 = read_xml(
        "t.xdd",
        &container(
            r#"xmlns="http://www.canopen.org/xml/1.1""#,
            PARAMETER,
            OBJECT,
        ),
    );
    let prefixed_xml = container(
        r#"xmlns:q1="http://www.canopen.org/xml/1.1""#,
        &PARAMETER
            .replace("<parameter ", "<q1:parameter ")
            .replace("</parameter>", "</q1:parameter>")
            .replace("<INT/>", "<q1:INT/>"),
        &OBJECT.replace("<CANopenObject ", "<q1:CANopenObject "),
    );
    let prefixed = read_xml("t.xdd", &prefixed_xml);
    assert_eq!(plain.device.objects.len(), 1);
    for other in [&v10, &v11] {
        assert_eq!(other.diagnostics, vec![]);
        assert_eq!(other.device.objects, plain.device.objects);
    }
    // The `q1:` prefix lengthens the element spans by three characters, and shifts what follows
    // a prefixed name on its line by three columns; nothing else.
    let mut unprefixed = prefixed.device.objects.clone();
    for object in unprefixed.values_mut() {
        object.span.len -= 3;
        for sub in object.subs.values_mut() {
            sub.span.len -= 3;
            let keys = &mut sub.key_spans;
            keys.data_type.as_mut().unwrap().len -= 3;
            keys.access.as_mut().unwrap().column -= 3;
            keys.pdo_mapping.as_mut().unwrap().column -= 3;
        }
    }
    assert_eq!(prefixed.diagnostics, vec![]);
    assert_eq!(unprefixed, plain.device.objects);
}

#[test]
fn pdo_mapping_sets_the_direction_of_read_write_entries() {
    let cases = [
        ("rw", "no", AccessType::Rw, false),
        ("rw", "default", AccessType::Rw, true),
        ("rw", "optional", AccessType::Rw, true),
        ("rw", "TPDO", AccessType::Rwr, true),
        ("rw", "RPDO", AccessType::Rww, true),
        ("ro", "TPDO", AccessType::Ro, true),
        ("wo", "RPDO", AccessType::Wo, true),
        ("const", "no", AccessType::Const, false),
    ];
    for (access, mapping, expected, mappable) in cases {
        let object = format!(
            r#"<CANopenObject index="6040" name="Controlword" objectType="7" dataType="0006" accessType="{access}" PDOmapping="{mapping}"/>"#
        );
        let read = read_xml("t.xdd", &container("", "", &object));
        assert_eq!(read.diagnostics, vec![], "{access} {mapping}");
        let sub = &read.device.objects[&0x6040].subs[&0];
        assert_eq!(sub.access, Some(expected), "{access} {mapping}");
        assert_eq!(sub.pdo_mapping, mappable, "{access} {mapping}");
    }
}

#[test]
fn parameter_access_values_map_to_canopen_access() {
    let cases = [
        (r#" access="const""#, AccessType::Const),
        (r#" access="read""#, AccessType::Ro),
        (r#" access="write""#, AccessType::Wo),
        (r#" access="readWrite""#, AccessType::Rw),
        (r#" access="readWriteInput""#, AccessType::Rww),
        (r#" access="readWriteOutput""#, AccessType::Rwr),
        ("", AccessType::Ro),
    ];
    for (attribute, expected) in cases {
        let parameter = format!(r#"<parameter uniqueID="P"{attribute}><UDINT/></parameter>"#);
        let object = r#"<CANopenObject index="2001" name="X" objectType="7" uniqueIDRef="P"/>"#;
        let read = read_xml("t.xdd", &container("", &parameter, object));
        assert_eq!(read.diagnostics, vec![], "{attribute}");
        let sub = &read.device.objects[&0x2001].subs[&0];
        assert_eq!(sub.access, Some(expected), "{attribute}");
        assert_eq!(sub.data_type, Some(0x0007), "{attribute}");
    }
}

#[test]
fn record_sub_objects_resolve_their_own_parameters() {
    let parameters = r#"
<parameter uniqueID="R"><dataTypeIDRef uniqueIDRef="T"/></parameter>
<parameter uniqueID="R0"><USINT/><defaultValue value="2"/></parameter>
<parameter uniqueID="R1" access="readWrite"><REAL/><defaultValue value="1.5"/></parameter>
<parameter uniqueID="R2" access="readWrite"><STRING/><defaultValue value="abc"/></parameter>"#;
    let objects = r#"<CANopenObject index="2100" name="Rec" objectType="9" subNumber="3" uniqueIDRef="R">
<CANopenSubObject subIndex="00" name="Count" objectType="7" uniqueIDRef="R0"/>
<CANopenSubObject subIndex="01" name="Gain" objectType="7" PDOmapping="TPDO" uniqueIDRef="R1"/>
<CANopenSubObject subIndex="0A" name="Label" objectType="7" uniqueIDRef="R2"/>
</CANopenObject>"#;
    let read = read_xml("t.xdd", &container("", parameters, objects));
    // T is not in a dataTypeList: an unresolved reference, reported, nothing else lost.
    let codes: Vec<_> = read.diagnostics.iter().map(|d| d.rule.code).collect();
    assert_eq!(codes, vec!["EDS605"]);
    let record = &read.device.objects[&0x2100];
    assert_eq!(record.object_type, ObjectType::Record);
    assert_eq!(
        record.subs.keys().copied().collect::<Vec<_>>(),
        vec![0, 1, 10]
    );
    assert_eq!(record.subs[&0].access, Some(AccessType::Ro));
    assert_eq!(value(&record.subs[&0].default), Some(&Value::Integer(2)));
    assert_eq!(record.subs[&1].data_type, Some(0x0008));
    assert_eq!(record.subs[&1].access, Some(AccessType::Rwr));
    assert_eq!(value(&record.subs[&1].default), Some(&Value::Real(1.5)));
    assert_eq!(record.subs[&10].data_type, Some(0x0009));
    assert_eq!(
        value(&record.subs[&10].default),
        Some(&Value::Text("abc".into()))
    );
    assert_eq!(record.subs[&10].span, Span::new(23, 1, 17));
}

#[test]
fn malformed_xml_is_one_error_with_its_line_and_an_empty_device() {
    let read = read_xml("bad.xdd", "<?xml version=\"1.0\"?>\n<a>\n  <b></a>\n");
    assert_eq!(read.device.objects.len(), 0);
    assert_eq!(read.diagnostics.len(), 1);
    let diag = &read.diagnostics[0];
    assert_eq!(diag.rule.code, "EDS601");
    assert_eq!(diag.severity, Severity::Error);
    assert_eq!(diag.span.map(|s| s.line), Some(3));
}

#[test]
fn missing_or_bad_indices_are_errors_not_losses() {
    let objects = r#"<CANopenObject name="No index" objectType="7" dataType="0007" accessType="ro"/>
<CANopenObject index="12345" name="Too wide" objectType="7"/>
<CANopenObject index="2000" name="Ok" objectType="8">
<CANopenSubObject name="No sub-index" objectType="7" dataType="0005" accessType="ro"/>
<CANopenSubObject subIndex="00" name="Count" objectType="7" dataType="0005" accessType="ro" defaultValue="1"/>
</CANopenObject>
<CANopenObject index="2000" name="Again" objectType="7" dataType="0005" accessType="ro"/>
<CANopenObject index="2001" name="Var with subs" objectType="7" dataType="0005" accessType="ro">
<CANopenSubObject subIndex="00" name="X" objectType="7" dataType="0005" accessType="ro"/>
</CANopenObject>"#;
    let read = read_xml("t.xdd", &container("", "", objects));
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.severity, d.span.map(|s| s.line)))
        .collect();
    assert_eq!(
        found,
        vec![
            ("EDS603", Severity::Error, Some(16)),
            ("EDS604", Severity::Error, Some(17)),
            ("EDS603", Severity::Error, Some(19)),
            ("EDS606", Severity::Error, Some(22)),
            ("EDS607", Severity::Error, Some(24)),
        ]
    );
    assert_eq!(read.device.objects[&0x2000].name, "Again");
    assert_eq!(read.device.objects[&0x2001].subs.len(), 1);
}

#[test]
fn a_document_without_an_object_list_says_so() {
    let read = read_xml(
        "t.xdd",
        "<ISO15745ProfileContainer><ISO15745Profile/></ISO15745ProfileContainer>",
    );
    let codes: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.severity))
        .collect();
    assert_eq!(codes, vec![("EDS602", Severity::Error)]);
}

#[test]
fn xdc_extension_gives_the_xdc_format() {
    let read = read_xml("t.XDC", &container("", PARAMETER, OBJECT));
    assert_eq!(read.device.source.format, Format::Xdc);
    let read = read_xml("t.xdd", &container("", PARAMETER, OBJECT));
    assert_eq!(read.device.source.format, Format::Xdd);
}

#[test]
fn pdo_mapping_direction_wins_over_a_contrary_access_with_a_warning() {
    let object = r#"<CANopenObject index="6040" name="Controlword" objectType="7" dataType="0006" accessType="rwr" PDOmapping="RPDO"/>"#;
    let read = read_xml("t.xdd", &container("", "", object));
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.severity, d.span.map(|s| s.line)))
        .collect();
    assert_eq!(found, vec![("EDS608", Severity::Warning, Some(16))]);
    assert_eq!(
        read.device.objects[&0x6040].subs[&0].access,
        Some(AccessType::Rww)
    );
}

/// The objects of a dump, by index, without the ones named in `except`.
fn dumped_objects(read: &Read, except: &[u64]) -> Vec<serde_json::Value> {
    let dump = edsgen_model::dump::to_json(&read.device);
    dump["objects"]
        .as_array()
        .expect("objects array")
        .iter()
        .filter(|o| !except.contains(&o["index"].as_u64().unwrap()))
        .cloned()
        .collect()
}

#[test]
fn canopen_editor_exports_read_the_same_as_eds_and_xdd() {
    let Some(dir) = corpus_dir() else { return };
    // CANopenEditor wrote both files of each pair from one project: every object, sub-object,
    // type, access, mapping, value and limit must agree.
    let eds = read_corpus(
        &dir,
        "CANopenNode__CANopenSocket/examples__basicDevice__basicDevice.eds",
    );
    let xdd = read_corpus(
        &dir,
        "CANopenNode__CANopenSocket/examples__basicDevice__basicDevice.xdd",
    );
    assert_eq!(dumped_objects(&xdd, &[]), dumped_objects(&eds, &[]));

    // The demo device's XDD also holds 1280h, which the project disables (CO_disabled) and the
    // EDS export leaves out.
    let eds = read_corpus(&dir, "CANopenNode__CANopenDemo/demo__demoDevice.eds");
    let xdd = read_corpus(&dir, "CANopenNode__CANopenDemo/demo__demoDevice.xdd");
    assert_eq!(dumped_objects(&xdd, &[0x1280]), dumped_objects(&eds, &[]));
    let disabled = &xdd.device.objects[&0x1280];
    assert!(disabled
        .custom
        .contains(&("CO_disabled".to_owned(), "true".to_owned())));
}

#[test]
fn truncated_xml_never_panics_and_reports_malformed_xml() {
    let Some(dir) = corpus_dir() else { return };
    let bytes = std::fs::read(dir.join("CANopenNode__CANopenEditor/Tests__minimal_project.xdd"))
        .expect("corpus file");
    for cut in (1..bytes.len()).step_by(97) {
        let read = read_bytes(Path::new("cut.xdd"), &bytes[..cut]);
        let codes: Vec<_> = read.diagnostics.iter().map(|d| d.rule.code).collect();
        assert_eq!(codes, vec!["EDS601"], "cut at {cut}");
        assert!(read.device.objects.is_empty(), "cut at {cut}");
    }
}

#[test]
fn byte_order_mark_and_windows_1252_text() {
    let xml = container("", PARAMETER, OBJECT);
    let mut with_bom = b"\xEF\xBB\xBF".to_vec();
    with_bom.extend_from_slice(xml.as_bytes());
    let read = read_bytes(Path::new("t.xdd"), &with_bom);
    assert_eq!(read.diagnostics, vec![]);
    assert_eq!(read.device.source.encoding, TextEncoding::Utf8Bom);
    assert_eq!(read.device.objects[&0x2000].span, Span::new(22, 1, 14));

    // "Vitesse d\xE9sir\xE9e" in Windows-1252: decoded, with one warning for the whole file.
    let latin = xml.replace(r#"name="Speed""#, "name=\"Vitesse d\u{e9}sir\u{e9}e\"");
    let (bytes, _, _) = encoding_rs::WINDOWS_1252.encode(&latin);
    let read = read_bytes(Path::new("t.xdd"), &bytes);
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.severity, d.span))
        .collect();
    assert_eq!(found, vec![("EDS002", Severity::Warning, None)]);
    assert_eq!(read.device.source.encoding, TextEncoding::Windows1252);
    assert_eq!(
        read.device.objects[&0x2000].name,
        "Vitesse d\u{e9}sir\u{e9}e"
    );
}

#[test]
fn dynamic_channels_and_unread_feature_attributes_are_kept() {
    let xml = container("", "", OBJECT).replace(
        "</ApplicationLayers>",
        r#"<dynamicChannels><dynamicChannel dataType="0007" accessType="readWriteOutput" startIndex="A4C0" endIndex="A4FF" maxNumber="64" addressOffset="0" bitAlignment="32"/></dynamicChannels>
</ApplicationLayers>
<NetworkManagement><CANopenGeneralFeatures granularity="8" SDORequestingDevice="false"/><CANopenMasterFeatures bootUpMaster="true" flyingMaster="false"/></NetworkManagement>"#,
    );
    let read = read_xml("t.xdd", &xml);
    let device = &read.device;
    let channels = device
        .other_sections
        .iter()
        .find(|s| s.name == "dynamicChannels")
        .expect("dynamicChannels kept");
    let keys: Vec<(&str, &str)> = channels
        .entries
        .iter()
        .map(|e| (e.key.as_str(), e.value.as_str()))
        .collect();
    assert_eq!(keys[0], ("dynamicChannel1.dataType", "0007"));
    assert_eq!(keys[2], ("dynamicChannel1.startIndex", "A4C0"));
    assert_eq!(keys.len(), 7);
    assert!(device.device_info.simple_boot_up_master);
    let general = device
        .other_sections
        .iter()
        .find(|s| s.name == "CANopenGeneralFeatures")
        .expect("unread general features kept");
    assert_eq!(general.entries[0].key, "SDORequestingDevice");
    let master = device
        .other_sections
        .iter()
        .find(|s| s.name == "CANopenMasterFeatures")
        .expect("unread master features kept");
    assert_eq!(master.entries[0].key, "flyingMaster");
}

#[test]
fn a_dtd_is_refused_as_malformed() {
    let xml = "<?xml version=\"1.0\"?>\n<!DOCTYPE a [<!ENTITY x \"xx\">]>\n<a>&x;</a>\n";
    let read = read_xml("t.xdd", xml);
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.span.map(|s| s.line)))
        .collect();
    assert_eq!(found, vec![("EDS601", Some(2))]);
}

#[test]
fn dump_of_the_minimal_xdc() {
    let Some(dir) = corpus_dir() else { return };
    let mut read = read_corpus(
        &dir,
        "dborgards__eds-dcf-net/tests__EdsDcfNet.Tests__Fixtures__minimal.xdc",
    );
    // The snapshot must not depend on where the corpus is.
    read.device.source.path = PathBuf::from("minimal.xdc");
    let dump = edsgen_model::dump::to_json(&read.device);
    insta::assert_snapshot!(serde_json::to_string_pretty(&dump).unwrap());
}

#[test]
fn object_counts_match_python_canopen_xdd_branch() {
    // The corpus baseline records what python canopen's XDD branch (PR 614) imports; python adds
    // one object per `DummyNNNN=1`, which edsgen keeps as dummy usage instead.
    let Some(dir) = corpus_dir() else { return };
    let table = std::fs::read_to_string(dir.join("python_canopen_baseline.tsv")).unwrap();
    let mut compared = 0;
    for line in table.lines().skip(1) {
        let cols: Vec<&str> = line.split('\t').collect();
        if cols.len() < 9 || cols[7] != "ok" {
            continue;
        }
        let read = read_corpus(&dir, cols[0]);
        let dummies = read
            .device
            .dummy_usage
            .values()
            .filter(|used| **used)
            .count();
        let python_objects: usize = cols[8].parse().unwrap();
        assert_eq!(
            read.device.objects.len() + dummies,
            python_objects,
            "{}",
            cols[0]
        );
        compared += 1;
    }
    assert_eq!(compared, 7);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

    /// Any byte edits of a valid description read without a panic, and whatever is read keeps
    /// spans inside the text.
    #[test]
    fn edited_xml_never_panics(edits in proptest::collection::vec((0usize..4096, proptest::prelude::any::<u8>()), 0..12)) {
        let mut bytes = container("", PARAMETER, OBJECT).into_bytes();
        for (at, byte) in edits {
            let at = at % bytes.len();
            bytes[at] = byte;
        }
        let read = read_bytes(Path::new("t.xdd"), &bytes);
        // Lines as the reader and the renderer count them: a lone CR ends a line too.
        let lines = edsgen_model::read::ini::lines(&read.text).len() as u32 + 1;
        for object in read.device.objects.values() {
            proptest::prop_assert!(object.span.line >= 1 && object.span.line <= lines);
        }
        for diag in &read.diagnostics {
            if let Some(span) = diag.span {
                proptest::prop_assert!(span.line >= 1 && span.line <= lines, "{:?}", diag);
            }
        }
    }
}

#[test]
fn xml_values_use_the_eds_value_forms() {
    let objects = r#"<CANopenObject index="1014" name="COB-ID EMCY" objectType="7" dataType="0007" accessType="ro" defaultValue="0x80+$NODEID"/>
<CANopenObject index="2000" name="Big" objectType="7" dataType="0015" accessType="ro" defaultValue="0x1234567890ABCDEFLL"/>
<CANopenObject index="2001" name="Min" objectType="7" dataType="0004" accessType="ro" lowLimit="0x80000000"/>"#;
    let read = read_xml("t.xdd", &container("", "", objects));
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.code(), d.severity, d.span.map_or(0, |s| s.line)))
        .collect();
    assert_eq!(
        found,
        vec![
            ("EDS016", Severity::Warning, 16),
            ("EDS025", Severity::Warning, 17),
            ("EDS014", Severity::Info, 18),
        ]
    );
    let entry = |index| &read.device.objects[&index].subs[&0];
    assert_eq!(
        value(&entry(0x1014).default),
        Some(&Value::NodeRelative(0x80))
    );
    assert_eq!(
        value(&entry(0x2000).default),
        Some(&Value::Integer(0x1234_5678_90AB_CDEF))
    );
    assert_eq!(
        value(&entry(0x2001).low_limit),
        Some(&Value::Integer(-0x8000_0000))
    );
}

#[test]
fn variable_ref_parameter_is_eds609_and_keeps_the_object_type() {
    let parameter = r#"<parameter uniqueID="V" access="read">
<variableRef position="1"><instanceIDRef uniqueIDRef="I"/></variableRef>
</parameter>"#;
    let object = r#"<CANopenObject index="2002" name="Ref" objectType="7" dataType="0006" accessType="ro" uniqueIDRef="V"/>"#;
    let read = read_xml("t.xdd", &container("", parameter, object));
    let found: Vec<(&str, Severity, u32)> = read
        .diagnostics
        .iter()
        .map(|d| (d.code(), d.severity, d.span.map_or(0, |s| s.line)))
        .collect();
    assert_eq!(found, vec![("EDS609", Severity::Warning, 8)]);
    assert_eq!(
        read.device.objects[&0x2002].subs[&0].data_type,
        Some(0x0006)
    );
}

#[test]
fn no_access_leaves_the_access_unknown_and_no_diagnostic_quotes_one() {
    // 6009h sub 1 is `noAccess`, and 1600h sub 1 maps it into an RPDO: the access the file does
    // not state is not read as `ro`, so no later diagnostic says "(ro)".
    let parameters = r#"<parameter uniqueID="P1" access="noAccess"><INT/></parameter>"#;
    let objects = r#"<CANopenObject index="1600" name="RPDO1 mapping" objectType="9" subNumber="2">
<CANopenSubObject subIndex="00" name="Count" objectType="7" dataType="0005" accessType="rw" defaultValue="1"/>
<CANopenSubObject subIndex="01" name="Entry 1" objectType="7" dataType="0007" accessType="rw" defaultValue="0x60090110"/>
</CANopenObject>
<CANopenObject index="6009" name="Inputs" objectType="8" subNumber="2">
<CANopenSubObject subIndex="00" name="Count" objectType="7" dataType="0005" accessType="ro" defaultValue="1"/>
<CANopenSubObject subIndex="01" name="Input 1" objectType="7" dataType="0003" accessType="ro" PDOmapping="optional" uniqueIDRef="P1"/>
</CANopenObject>"#;
    let read = read_xml("t.xdd", &container("", parameters, objects));
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.span.map(|s| s.line), d.message.as_str()))
        .collect();
    assert_eq!(
        found,
        vec![(
            "EDS604",
            Some(7),
            "parameter access `noAccess` has no CANopen access type; the entry's access is unknown"
        )]
    );
    assert_eq!(read.device.objects[&0x6009].subs[&1].access, None);
    let validated = edsgen_model::validate::validate(&read.device);
    for d in &validated {
        assert!(
            !d.message.contains("(ro)") && !d.message.contains("into an RPDO"),
            "{d:?}"
        );
    }
    assert!(
        validated.iter().any(|d| d.rule.code == "EDS303"),
        "{validated:#?}"
    );
}
