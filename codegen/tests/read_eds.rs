//! The EDS/DCF reader on inline texts: model contents, spans, and exact diagnostics per rule.

use std::path::Path;

use edsgen_model::diag::Severity;
use edsgen_model::model::*;
use edsgen_model::read::{self, Read};

fn read_eds(text: &str) -> Read {
    read::read_bytes(Path::new("test.eds"), text.as_bytes())
}

fn read_as(name: &str, text: &str) -> Read {
    read::read_bytes(Path::new(name), text.as_bytes())
}

/// (code, severity, line) of every diagnostic, in emission order.
fn diags(read: &Read) -> Vec<(&'static str, Severity, u32)> {
    read.diagnostics
        .iter()
        .map(|d| (d.code(), d.severity, d.span.map_or(0, |s| s.line)))
        .collect()
}

fn value_of(source: &Option<ValueSource>) -> Option<Value> {
    source.as_ref().and_then(|s| s.value.clone())
}

const SMALL: &str = "\
[FileInfo]
FileName=small.eds
FileVersion=1
FileRevision=2
EDSVersion=4.0
Description=A small test device
CreationTime=09:15AM
CreationDate=01-02-2026
CreatedBy=edsgen tests

[DeviceInfo]
VendorName=Test Vendor
VendorNumber=0x0000ABCD
ProductName=Small
ProductNumber=0x10
RevisionNumber=0x00010002
OrderCode=SM-1
BaudRate_125=1
BaudRate_250=1
BaudRate_1000=0
SimpleBootUpSlave=1
Granularity=8
NrOfRXPDO=0
NrOfTXPDO=0
LSS_Supported=0

[DummyUsage]
Dummy0001=0
Dummy0005=1

[Comments]
Lines=2
Line1=first
Line2=second

[MandatoryObjects]
SupportedObjects=2
1=0x1000
2=0x1018

[OptionalObjects]
SupportedObjects=1
1=0x1017

[ManufacturerObjects]
SupportedObjects=2
1=0x2000
2=0x2001

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
PDOMapping=0

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=1000

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x0000ABCD

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=2

[1018sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=1

[2000]
ParameterName=Values
ObjectType=0x8
DataType=0x0003
AccessType=rw
DefaultValue=-5
PDOMapping=1
CompactSubObj=3

[2000Name]
NrOfEntries=1
2=Middle value

[2001]
ParameterName=Blob
ObjectType=0x2
DefaultValue=01a2 ff

[2002]
ParameterName=COB-ID
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
HighLimit=0x7FF

[2003]
ParameterName=Label
DataType=0x0009
AccessType=ro
DefaultValue=edsgen

[2004]
ParameterName=Gain
DataType=0x0008
AccessType=rw
DefaultValue=1.25
";

#[test]
fn small_eds_reads_cleanly() {
    let read = read_eds(SMALL);
    assert_eq!(diags(&read), vec![]);
    let d = &read.device;
    assert_eq!(d.source.format, Format::Eds);
    assert_eq!(d.source.encoding, TextEncoding::Ascii);
    assert_eq!(d.file_info.file_name.as_deref(), Some("small.eds"));
    assert_eq!(
        d.file_info.eds_version,
        Some(Spanned::new("4.0".to_owned(), Span::new(5, 12, 3)))
    );
    assert_eq!(
        d.device_info.vendor_number.as_ref().map(|v| v.value),
        Some(0xABCD)
    );
    assert_eq!(
        d.device_info.baud_rates,
        vec![(125, true), (250, true), (1000, false)]
    );
    assert!(d.device_info.simple_boot_up_slave);
    assert_eq!(d.dummy_usage.get(&5), Some(&true));
    assert_eq!(d.comments, vec!["first", "second"]);
    assert_eq!(d.object_lists.len(), 3);
    assert_eq!(
        d.object_lists[0].entries,
        vec![
            (1, Spanned::new(0x1000, Span::new(38, 3, 6))),
            (2, Spanned::new(0x1018, Span::new(39, 3, 6)))
        ]
    );
    let keys: Vec<u16> = d.objects.keys().copied().collect();
    assert_eq!(
        keys,
        vec![0x1000, 0x1017, 0x1018, 0x2000, 0x2001, 0x2002, 0x2003, 0x2004]
    );

    let device_type = d.entry(0x1000, 0).unwrap();
    assert_eq!(device_type.name, "Device type");
    assert_eq!(device_type.data_type, Some(7));
    assert_eq!(device_type.access, Some(AccessType::Ro));
    assert_eq!(
        value_of(&device_type.default),
        Some(Value::Integer(0x20192))
    );
    assert_eq!(
        device_type.default.as_ref().unwrap().span,
        Span::new(55, 14, 10)
    );
    assert_eq!(d.objects[&0x1000].span, Span::new(50, 1, 6));

    // A sub-index section before its parent.
    let identity = &d.objects[&0x1018];
    assert_eq!(identity.object_type, ObjectType::Record);
    assert_eq!(identity.sub_number.as_ref().map(|n| n.value), Some(2));
    assert_eq!(
        identity.subs.keys().copied().collect::<Vec<_>>(),
        vec![0, 1]
    );
    assert_eq!(identity.subs[&1].name, "Vendor-ID");
    assert_eq!(identity.subs[&1].span, Span::new(64, 1, 10));

    // CompactSubObj with a [xxxxName] override.
    let values = &d.objects[&0x2000];
    assert_eq!(values.object_type, ObjectType::Array);
    let names: Vec<&str> = values.subs.values().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        vec!["NrOfObjects", "Values1", "Middle value", "Values3"]
    );
    assert!(values.subs.values().all(|s| s.implicit));
    assert_eq!(values.subs[&0].data_type, Some(5));
    assert_eq!(values.subs[&0].access, Some(AccessType::Ro));
    assert_eq!(value_of(&values.subs[&0].default), Some(Value::Integer(3)));
    assert_eq!(values.subs[&3].data_type, Some(3));
    assert_eq!(values.subs[&3].access, Some(AccessType::Rw));
    assert!(values.subs[&3].pdo_mapping);
    assert_eq!(value_of(&values.subs[&3].default), Some(Value::Integer(-5)));

    let blob = d.entry(0x2001, 0).unwrap();
    assert_eq!(blob.data_type, Some(0x000F));
    assert_eq!(blob.access, Some(AccessType::Rw));
    assert_eq!(
        value_of(&blob.default),
        Some(Value::Bytes(vec![0x01, 0xa2, 0xff]))
    );

    let cob = d.entry(0x2002, 0).unwrap();
    assert_eq!(value_of(&cob.default), Some(Value::NodeRelative(0x180)));
    assert_eq!(value_of(&cob.high_limit), Some(Value::Integer(0x7FF)));
    assert_eq!(
        value_of(&d.entry(0x2003, 0).unwrap().default),
        Some(Value::Text("edsgen".into()))
    );
    assert_eq!(
        value_of(&d.entry(0x2004, 0).unwrap().default),
        Some(Value::Real(1.25))
    );
}

#[test]
fn dump_of_small_eds() {
    let read = read_eds(SMALL);
    let json = edsgen_model::dump::to_json(&read.device);
    insta::assert_snapshot!(serde_json::to_string_pretty(&json).unwrap());
}

#[test]
fn dcf_values_denotations_and_commissioning() {
    let text = "\
[FileInfo]
LastEDS=small.eds

[DeviceComissioning]
NodeID=5
NodeName=Left drive
Baudrate=500
NetNumber=1
CANopenManager=0
LSS_SerialNumber=0x1234

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=0
ParameterValue=100
Denotation=Heartbeat

[1F22]
ParameterName=Concise DCF
ObjectType=0x8
DataType=0x000F
AccessType=rw
CompactSubObj=2

[1F22Value]
NrOfEntries=1
2=0a0b

[1F22Denotation]
NrOfEntries=1
1=first node
";
    let read = read_as("node5.DCF", text);
    assert_eq!(diags(&read), vec![]);
    let d = &read.device;
    assert_eq!(d.source.format, Format::Dcf);
    assert_eq!(d.file_info.last_eds.as_deref(), Some("small.eds"));
    let c = d.commissioning.as_ref().unwrap();
    assert_eq!(
        c.node_id.as_ref().map(|n| (n.value, n.span)),
        Some((5, Span::new(5, 8, 1)))
    );
    assert_eq!(c.node_name.as_deref(), Some("Left drive"));
    assert_eq!(c.baudrate.as_ref().map(|n| n.value), Some(500));
    assert_eq!(c.net_number, Some(1));
    assert!(!c.canopen_manager);
    assert_eq!(c.lss_serial_number, Some(0x1234));
    let hb = d.entry(0x1017, 0).unwrap();
    assert_eq!(value_of(&hb.default), Some(Value::Integer(0)));
    assert_eq!(value_of(&hb.parameter_value), Some(Value::Integer(100)));
    assert_eq!(hb.denotation.as_deref(), Some("Heartbeat"));
    let dcf = &d.objects[&0x1F22];
    assert_eq!(dcf.subs.len(), 3);
    assert_eq!(value_of(&dcf.subs[&1].parameter_value), None);
    assert_eq!(
        value_of(&dcf.subs[&2].parameter_value),
        Some(Value::Bytes(vec![0x0a, 0x0b]))
    );
    assert_eq!(
        dcf.subs[&2].parameter_value.as_ref().unwrap().span,
        Span::new(29, 3, 4)
    );
    assert_eq!(dcf.subs[&1].denotation.as_deref(), Some("first node"));
}

/// A minimal VAR object, for tests that need one valid object.
const VAR_1000: &str = "[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\n";

#[test]
fn eds001_junk_line_is_an_error_and_ignored() {
    let read = read_eds("[1000]\nParameterName=Device type\nthis is junk\nDataType=0x0007\n");
    assert_eq!(diags(&read), vec![("EDS001", Severity::Error, 3)]);
    assert_eq!(read.device.entry(0x1000, 0).unwrap().data_type, Some(7));
}

#[test]
fn eds027_line_after_a_comment_continues_it() {
    // A Sevcon file breaks a `;SEVCONFIELD PARAMETERNAME=` comment over two lines.
    let read = read_eds(
        "[1000]\n;SEVCONFIELD PARAMETERNAME=\nDirection reference\nmore of it\nParameterName=Device type\nDataType=0x0007\n",
    );
    assert_eq!(
        diags(&read),
        vec![
            ("EDS027", Severity::Warning, 3),
            ("EDS027", Severity::Warning, 4)
        ]
    );
    assert_eq!(
        read.diagnostics[1].message,
        "line continues the comment on line 2"
    );
    assert_eq!(read.diagnostics[0].span, Some(Span::new(3, 1, 19)));
    assert_eq!(read.device.entry(0x1000, 0).unwrap().data_type, Some(7));
}

#[test]
fn eds001_after_a_blank_line_a_stray_line_is_not_a_comment_continuation() {
    let read = read_eds("[1000]\n; comment\n\nstray\nDataType=0x0007\n");
    assert_eq!(diags(&read), vec![("EDS001", Severity::Error, 4)]);
    let read = read_eds("[1000]\nDataType=0x0007\nstray\n");
    assert_eq!(diags(&read), vec![("EDS001", Severity::Error, 3)]);
}

#[test]
fn eds028_empty_number_key_is_absent_and_reported() {
    let read = read_eds("[DeviceInfo]\nVendorName=x\nVendorNumber=\nProductNumber=0x2\n");
    assert_eq!(diags(&read), vec![("EDS028", Severity::Warning, 3)]);
    assert_eq!(read.diagnostics[0].span, Some(Span::new(3, 1, 12)));
    assert_eq!(read.device.device_info.vendor_number, None);
    assert_eq!(
        read.device.device_info.product_number.map(|n| n.value),
        Some(2)
    );
}

#[test]
fn eds008_is_a_warning_for_keys_python_looks_up_case_sensitively() {
    let read = read_eds("[DummyUsage]\ndummy0001=0\n[1000]\nDataType=0x0007\nPDOMapping=0\n");
    assert_eq!(diags(&read), vec![("EDS008", Severity::Warning, 2)]);
    assert_eq!(read.device.dummy_usage.get(&1), Some(&false));
    let read = read_eds("[1000]\nDataType=0x0007\nparametername=Device type\n");
    assert_eq!(diags(&read), vec![("EDS008", Severity::Info, 3)]);
}

#[test]
fn eds002_windows_1252_and_utf8_are_reported_with_the_first_line() {
    let mut bytes = b"[1000]\nParameterName=Temp \xB0C\nDataType=0x0007\n".to_vec();
    let read = read::read_bytes(Path::new("t.eds"), &bytes);
    assert_eq!(read.device.source.encoding, TextEncoding::Windows1252);
    assert_eq!(diags(&read), vec![("EDS002", Severity::Warning, 2)]);
    assert!(read.diagnostics[0].message.contains("Windows-1252"));
    assert_eq!(read.diagnostics[0].span, Some(Span::new(2, 20, 1)));
    assert_eq!(read.device.entry(0x1000, 0).unwrap().name, "Temp \u{b0}C");
    bytes = "[1000]\nDataType=0x0007\nParameterName=abc\u{2713}\n"
        .as_bytes()
        .to_vec();
    let read = read::read_bytes(Path::new("t.eds"), &bytes);
    assert_eq!(read.device.source.encoding, TextEncoding::Utf8);
    assert_eq!(diags(&read), vec![("EDS002", Severity::Warning, 3)]);
    assert!(read.diagnostics[0].message.contains("UTF-8"));
}

#[test]
fn eds003_long_line_is_kept_whole() {
    let name = "N".repeat(300);
    let read = read_eds(&format!(
        "{VAR_1000}[2000]\nParameterName={name}\nDataType=0x0005\n"
    ));
    assert_eq!(diags(&read), vec![("EDS003", Severity::Warning, 6)]);
    assert_eq!(read.device.objects[&0x2000].name.len(), 300);
}

#[test]
fn eds003_long_lines_are_one_warning_per_file() {
    let long = "N".repeat(300);
    let read = read_eds(&format!(
        "{VAR_1000}[2000]\nParameterName={long}\nDataType=0x0005\nDefaultValue=1\n\
         [2001]\nParameterName={long}x\nDataType=0x0005\n"
    ));
    assert_eq!(diags(&read), vec![("EDS003", Severity::Warning, 6)]);
    assert_eq!(
        read.diagnostics[0].message,
        "line has 314 characters; CiA 306 allows 255; the same on 1 more line(s): 10"
    );
}

#[test]
fn eds004_comments_stripped_from_numbers_kept_in_strings() {
    let text = "\
[1000]
ParameterName=Device type
  ; indented comment
DataType=0x0007 ; UNSIGNED32
AccessType=ro;read only
DefaultValue=0x191 ; DS401
[2000]
ParameterName=Label
DataType=0x0009
AccessType=ro
DefaultValue=a;b
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS004", Severity::Warning, 3),
            ("EDS004", Severity::Warning, 4),
            ("EDS004", Severity::Warning, 5),
            ("EDS004", Severity::Warning, 6),
            ("EDS004", Severity::Warning, 11),
        ]
    );
    let e = read.device.entry(0x1000, 0).unwrap();
    assert_eq!(e.data_type, Some(7));
    assert_eq!(e.access, Some(AccessType::Ro));
    let default = e.default.as_ref().unwrap();
    assert_eq!(default.raw, "0x191");
    assert_eq!(default.span, Span::new(6, 14, 5));
    assert_eq!(default.value, Some(Value::Integer(0x191)));
    assert_eq!(
        value_of(&read.device.entry(0x2000, 0).unwrap().default),
        Some(Value::Text("a;b".into()))
    );
}

#[test]
fn eds005_eds006_duplicates_merge_and_last_wins() {
    let text = "\
[1000]
ParameterName=First
DataType=0x0007
ParameterName=Second
[1001]
ParameterName=Error register
[1000]
AccessType=ro
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS006", Severity::Error, 4),
            ("EDS005", Severity::Error, 7)
        ]
    );
    let e = read.device.entry(0x1000, 0).unwrap();
    assert_eq!(e.name, "Second");
    assert_eq!(e.data_type, Some(7));
    assert_eq!(e.access, Some(AccessType::Ro));
}

#[test]
fn eds007_spacing_and_odd_key_characters() {
    let text = "[1000]\nParameterName = Device type\nDataType=0x0007\n[ 1001 ]\nParameterName=E\n[OptionalObjects]\nSupported Objects=0\n";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS007", Severity::Warning, 2),
            ("EDS007", Severity::Warning, 4),
            ("EDS007", Severity::Warning, 7),
            ("EDS009", Severity::Info, 7),
        ]
    );
    assert_eq!(read.device.entry(0x1000, 0).unwrap().name, "Device type");
    assert!(read.device.objects.contains_key(&0x1001));
}

#[test]
fn eds007_hash_is_not_a_comment_and_the_help_says_so() {
    let read = read_eds("[1000]\nParameterName=D\nDataType=0x0007\n#ParameterValue=5\n");
    assert_eq!(
        diags(&read),
        vec![
            ("EDS007", Severity::Warning, 4),
            ("EDS009", Severity::Info, 4),
        ]
    );
    assert_eq!(
        read.diagnostics[0].help.as_deref(),
        Some("`#` does not start a comment in CiA 306: write `;` to comment the line out")
    );
    assert_eq!(read.device.entry(0x1000, 0).unwrap().parameter_value, None);
}

#[test]
fn eds008_case_only_matches_are_reported_once_per_name() {
    let text = "\
[fileinfo]
FileName=x.eds
[1000]
parametername=Device type
DataType=0x0007
AccessType=RO
[1001]
parametername=Error register
DataType=0x0005
AccessType=RO
[1018]
ObjectType=0x9
ParameterName=Identity
[1018Sub0]
ParameterName=N
DataType=0x0005
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS008", Severity::Info, 1),
            ("EDS008", Severity::Info, 4),
            ("EDS008", Severity::Info, 6),
            ("EDS008", Severity::Info, 14),
        ]
    );
    assert_eq!(read.device.file_info.file_name.as_deref(), Some("x.eds"));
    assert_eq!(
        read.device.entry(0x1001, 0).unwrap().access,
        Some(AccessType::Ro)
    );
    assert_eq!(read.device.entry(0x1018, 0).unwrap().name, "N");
}

#[test]
fn eds009_unknown_sections_and_keys_are_kept() {
    let text = "\
[1000]
ParameterName=Device type
DataType=0x0007
Unit=mm
[1001]
ParameterName=Error register
DataType=0x0005
Unit=none
[VendorSpecific]
Foo=1
[SupportedModules]
NrOfEntries=1
[M1ModuleInfo]
ProductName=Module
[DynamicChannels]
NrOfSeg=0
[Tools]
Items=1
[Tool1]
Name=Config
[ConnectedModules]
NrOfEntries=0
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![("EDS009", Severity::Info, 4), ("EDS009", Severity::Info, 9)]
    );
    assert_eq!(
        read.device.entry(0x1000, 0).unwrap().custom,
        vec![("Unit".to_owned(), "mm".to_owned())]
    );
    assert_eq!(
        read.device.entry(0x1001, 0).unwrap().custom,
        vec![("Unit".to_owned(), "none".to_owned())]
    );
    let names: Vec<&str> = read
        .device
        .other_sections
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(
        names,
        vec![
            "VendorSpecific",
            "SupportedModules",
            "M1ModuleInfo",
            "DynamicChannels",
            "Tools",
            "Tool1",
            "ConnectedModules"
        ]
    );
    let vendor = &read.device.other_sections[0];
    assert_eq!(vendor.entries[0].key, "Foo");
    assert_eq!(vendor.entries[0].value, "1");
    assert_eq!(vendor.entries[0].span, Span::new(10, 1, 5));
}

#[test]
fn eds010_leading_zeros_in_section_names_and_numbered_keys() {
    let text = "\
[1018]
ParameterName=Identity
ObjectType=0x9
[1018sub01]
ParameterName=Vendor-ID
DataType=0x0007
[MandatoryObjects]
SupportedObjects=1
01=0x1018
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS010", Severity::Warning, 4),
            ("EDS010", Severity::Warning, 9)
        ]
    );
    assert_eq!(read.device.entry(0x1018, 1).unwrap().name, "Vendor-ID");
    assert_eq!(read.device.object_lists[0].entries[0].0, 1);
    assert_eq!(read.device.object_lists[0].entries[0].1.value, 0x1018);
}

#[test]
fn eds011_keys_that_must_be_numbers() {
    let text = "\
[DeviceInfo]
VendorNumber=ACME
NrOfRXPDO=70000
[1000]
ParameterName=Device type
ObjectType=0x3
DataType=UNSIGNED32
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS011", Severity::Error, 2),
            ("EDS011", Severity::Error, 3),
            ("EDS011", Severity::Error, 6),
            ("EDS011", Severity::Error, 7),
        ]
    );
    assert_eq!(read.device.device_info.vendor_number, None);
    let object = &read.device.objects[&0x1000];
    assert_eq!(object.object_type, ObjectType::Var);
    assert_eq!(object.subs[&0].data_type, None);
}

#[test]
fn value_diagnostics_point_at_the_value() {
    let text = "\
[2000]
ParameterName=Bad
DataType=0x0005
DefaultValue=300
LowLimit=-1
HighLimit=0x180+$NODEID
[2001]
ParameterName=Signed
DataType=0x0003
DefaultValue=0xFFFF
[2002]
ParameterName=Real
DataType=0x0008
DefaultValue=0x3F800000
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS013", Severity::Error, 4),
            ("EDS013", Severity::Warning, 5),
            ("EDS016", Severity::Warning, 6),
            ("EDS014", Severity::Info, 10),
            ("EDS019", Severity::Warning, 14),
        ]
    );
    assert_eq!(read.diagnostics[0].span, Some(Span::new(4, 14, 3)));
    let bad = read.device.entry(0x2000, 0).unwrap();
    assert_eq!(bad.default.as_ref().unwrap().raw, "300");
    assert_eq!(value_of(&bad.default), None);
    assert_eq!(value_of(&bad.high_limit), Some(Value::NodeRelative(0x180)));
    assert_eq!(
        value_of(&read.device.entry(0x2001, 0).unwrap().default),
        Some(Value::Integer(-1))
    );
    assert_eq!(
        value_of(&read.device.entry(0x2002, 0).unwrap().default),
        Some(Value::Real(1.0))
    );
}

#[test]
fn eds021_booleans_other_than_0_and_1() {
    let text = "[DeviceInfo]\nSimpleBootUpSlave=true\nLSS_Supported=0x1\nGroupMessaging=maybe\n";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS021", Severity::Warning, 2),
            ("EDS021", Severity::Warning, 4)
        ]
    );
    assert!(read.device.device_info.simple_boot_up_slave);
    assert!(read.device.device_info.lss_supported);
    assert!(!read.device.device_info.group_messaging);
}

#[test]
fn eds022_empty_file() {
    let read = read_eds("; only a comment\n\n");
    assert_eq!(diags(&read), vec![("EDS022", Severity::Error, 0)]);
    assert!(read.device.objects.is_empty());
}

#[test]
fn eds023_device_commissioning_with_two_m() {
    let read = read_as("x.dcf", "[DeviceCommissioning]\nNodeID=0x10\n");
    assert_eq!(diags(&read), vec![("EDS023", Severity::Info, 1)]);
    assert_eq!(
        read.device
            .commissioning
            .as_ref()
            .and_then(|c| c.node_id.as_ref())
            .map(|n| n.value),
        Some(16)
    );
}

#[test]
fn eds024_sections_for_missing_objects_and_subs_are_kept() {
    let text = "\
[2000sub1]
ParameterName=Orphan
[1000]
ParameterName=Device type
DataType=0x0007
[1000sub0]
ParameterName=Sub of a VAR
[2001]
ParameterName=Arr
ObjectType=0x8
CompactSubObj=1
DataType=0x0005
[2001Name]
NrOfEntries=1
5=Nope
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS024", Severity::Warning, 1),
            ("EDS024", Severity::Warning, 6),
            ("EDS024", Severity::Warning, 15),
        ]
    );
    assert!(!read.device.objects.contains_key(&0x2000));
    assert_eq!(read.device.objects[&0x1000].subs.len(), 1);
    let kept: Vec<&str> = read
        .device
        .other_sections
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(kept, vec!["2000sub1", "1000sub0"]);
}

#[test]
fn line_endings_crlf_cr_and_no_final_newline() {
    for text in [
        "[1000]\r\nParameterName=Device type\r\nDataType=0x0007\r\nDefaultValue=5",
        "[1000]\rParameterName=Device type\rDataType=0x0007\rDefaultValue=5\r",
    ] {
        let read = read_eds(text);
        assert_eq!(diags(&read), vec![]);
        let e = read.device.entry(0x1000, 0).unwrap();
        assert_eq!(e.name, "Device type");
        assert_eq!(e.default.as_ref().unwrap().span, Span::new(4, 14, 1));
        assert_eq!(value_of(&e.default), Some(Value::Integer(5)));
    }
}

#[test]
fn utf8_bom_is_accepted_and_reported() {
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend_from_slice(VAR_1000.as_bytes());
    let read = read::read_bytes(Path::new("t.eds"), &bytes);
    assert_eq!(read.device.source.encoding, TextEncoding::Utf8Bom);
    assert_eq!(diags(&read), vec![("EDS002", Severity::Warning, 1)]);
    assert_eq!(read.device.objects[&0x1000].span, Span::new(1, 1, 6));
}

#[test]
fn comments_keep_every_line_even_when_lines_is_wrong() {
    let read = read_eds("[Comments]\nLines=1\nLine1=one\nLine3=three\nline2=two\n");
    assert_eq!(diags(&read), vec![("EDS008", Severity::Warning, 5)]);
    assert_eq!(read.device.comments, vec!["one", "two", "three"]);
}

#[test]
fn object_links_and_obj_flags() {
    let text = "\
[2000]
ParameterName=Rec
ObjectType=0x9
ObjFlags=0x1
[2000sub0]
ParameterName=N
DataType=0x0005
ObjFlags=2
[2000ObjectLinks]
ObjectLinks=2
2=0x6041
1=0x6040
";
    let read = read_eds(text);
    assert_eq!(diags(&read), vec![]);
    let o = &read.device.objects[&0x2000];
    assert_eq!(o.obj_flags, 1);
    assert_eq!(o.subs[&0].obj_flags, 2);
    assert_eq!(o.object_links, vec![0x6040, 0x6041]);
}

#[test]
fn keys_of_the_wrong_object_type_stay_visible() {
    let text = "[2000]\nParameterName=Arr\nObjectType=0x8\nDataType=0x0007\nAccessType=rw\nSubNumber=1\n[2000sub0]\nParameterName=N\nDataType=0x0005\nObjectType=0x7\n";
    let read = read_eds(text);
    assert_eq!(diags(&read), vec![]);
    let o = &read.device.objects[&0x2000];
    assert_eq!(
        o.custom,
        vec![
            ("AccessType".to_owned(), "rw".to_owned()),
            ("DataType".to_owned(), "0x0007".to_owned())
        ]
    );
    assert_eq!(o.sub_number.as_ref().map(|n| n.value), Some(1));
    assert!(o.subs[&0].custom.is_empty());
}

#[test]
fn data_type_through_a_deftype_object() {
    let text = "\
[2000]
ParameterName=Typed
DataType=0x0040
DefaultValue=0xFFFFFFFF
[40]
ParameterName=MY_INT32
ObjectType=0x5
DataType=0x0007
DefaultValue=0x0004
";
    let read = read_eds(text);
    assert_eq!(diags(&read), vec![("EDS014", Severity::Info, 4)]);
    assert_eq!(
        value_of(&read.device.entry(0x2000, 0).unwrap().default),
        Some(Value::Integer(-1))
    );
}

#[test]
fn compact_sub_obj_value_reported_once() {
    let text = "[2000]\nParameterName=A\nObjectType=0x8\nDataType=0x0005\nAccessType=rw\nDefaultValue=256\nCompactSubObj=4\n";
    let read = read_eds(text);
    assert_eq!(diags(&read), vec![("EDS013", Severity::Error, 6)]);
    assert_eq!(read.device.objects[&0x2000].subs.len(), 5);
}

#[test]
fn compact_pdo_synthesises_the_missing_pdos() {
    let text = "\
[DeviceInfo]
NrOfRXPDO=3
NrOfTXPDO=1
CompactPDO=0x13
[1401]
ParameterName=RPDO2 communication parameter
ObjectType=0x9
[1401sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
";
    let read = read_eds(text);
    assert_eq!(diags(&read), vec![]);
    let d = &read.device;
    let keys: Vec<u16> = d.objects.keys().copied().collect();
    assert_eq!(
        keys,
        vec![0x1400, 0x1401, 0x1402, 0x1600, 0x1602, 0x1800, 0x1A00]
    );
    assert!(!d.objects[&0x1401].implicit);
    let rpdo1 = &d.objects[&0x1400];
    assert!(rpdo1.implicit);
    assert_eq!(rpdo1.object_type, ObjectType::Record);
    assert_eq!(rpdo1.span, Span::new(4, 12, 4));
    assert_eq!(
        rpdo1.subs.keys().copied().collect::<Vec<_>>(),
        vec![0, 1, 2, 5]
    );
    assert_eq!(value_of(&rpdo1.subs[&0].default), Some(Value::Integer(5)));
    assert_eq!(
        value_of(&rpdo1.subs[&1].default),
        Some(Value::NodeRelative(0x200))
    );
    assert_eq!(rpdo1.subs[&1].data_type, Some(7));
    assert_eq!(rpdo1.subs[&5].data_type, Some(6));
    assert_eq!(value_of(&rpdo1.subs[&2].default), None);
    assert!(rpdo1.subs.values().all(|s| s.implicit));
    assert_eq!(
        value_of(&d.objects[&0x1402].subs[&1].default),
        Some(Value::NodeRelative(0x400))
    );
    assert_eq!(
        value_of(&d.objects[&0x1800].subs[&1].default),
        Some(Value::NodeRelative(0x180))
    );
    let map = &d.objects[&0x1A00];
    assert_eq!(map.subs.len(), 9);
    assert_eq!(map.subs[&0].access, Some(AccessType::Rw));
    assert_eq!(value_of(&map.subs[&0].default), Some(Value::Integer(0)));
    assert_eq!(map.subs[&8].data_type, Some(7));
    assert!(map.implicit);
}

#[test]
fn compact_pdo_in_a_dcf_disables_the_unwritten_pdos() {
    let text = "[DeviceInfo]\nNrOfRXPDO=0\nNrOfTXPDO=5\nCompactPDO=0x01\n";
    let read = read_as("n.dcf", text);
    assert_eq!(diags(&read), vec![]);
    let d = &read.device;
    assert_eq!(
        value_of(&d.objects[&0x1801].subs[&1].default),
        Some(Value::NodeRelative(0x8000_0280))
    );
    assert_eq!(
        value_of(&d.objects[&0x1804].subs[&1].default),
        Some(Value::Integer(0x8000_0000))
    );
    assert!(!d.objects.contains_key(&0x1400));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]
    #[test]
    fn never_panics_on_ini_like_text(text in "[\\[\\]=;$a-zA-Z0-9 x+\\-.\"\r\n\t\u{e9}]{0,300}") {
        let _ = read_eds(&text);
        let _ = read_as("x.dcf", &format!("[DeviceInfo]\nCompactPDO=0x3F\nNrOfRXPDO=600\n{text}"));
    }

    #[test]
    fn never_panics_on_bytes(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..200)) {
        let _ = read::read_bytes(Path::new("x.eds"), &bytes);
    }
}

#[test]
fn eds005_same_object_under_two_spellings() {
    let text = "[1000]\nParameterName=A\n[01000]\nParameterName=B\n[1018]\nObjectType=0x9\n[1018sub1]\nParameterName=X\n[1018sub01]\nParameterName=Y\n";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS005", Severity::Error, 3),
            ("EDS010", Severity::Warning, 3),
            ("EDS005", Severity::Error, 9),
            ("EDS010", Severity::Warning, 9),
        ]
    );
    assert_eq!(read.device.objects[&0x1000].name, "B");
    assert_eq!(read.device.entry(0x1018, 1).unwrap().name, "Y");
    let kept: Vec<&str> = read
        .device
        .other_sections
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(kept, vec!["1000", "1018sub1"]);
}

#[test]
fn dcf_domain_upload_and_download_files() {
    let text = "[1F50]\nParameterName=Program\nObjectType=0x2\nUploadFile=up.bin\nDownloadFile=down.bin\nParameterValue=00ff\n";
    let read = read_as("x.dcf", text);
    assert_eq!(diags(&read), vec![]);
    let e = read.device.entry(0x1F50, 0).unwrap();
    assert_eq!(e.upload_file.as_deref(), Some("up.bin"));
    assert_eq!(e.download_file.as_deref(), Some("down.bin"));
    assert_eq!(
        value_of(&e.parameter_value),
        Some(Value::Bytes(vec![0, 0xff]))
    );
}

#[test]
fn canopen_editor_storage_location_comments_are_kept() {
    let text = "\
[1017]
ParameterName=Producer heartbeat time
;StorageLocation=PERSIST_COMM
DataType=0x0006
[1018]
ParameterName=Identity
ObjectType=0x9
;StorageLocation=ROM
[1018sub0]
ParameterName=N
DataType=0x0005
";
    let read = read_eds(text);
    assert_eq!(diags(&read), vec![]);
    assert_eq!(
        read.device.entry(0x1017, 0).unwrap().custom,
        vec![("StorageLocation".to_owned(), "PERSIST_COMM".to_owned())]
    );
    assert_eq!(
        read.device.objects[&0x1018].custom,
        vec![("StorageLocation".to_owned(), "ROM".to_owned())]
    );
    assert!(read.device.entry(0x1018, 0).unwrap().custom.is_empty());
}

#[test]
fn eds013_limits_beyond_the_type_are_warnings_and_ignored() {
    let text = "\
[2000]
ParameterName=Signed
DataType=0x0003
LowLimit=-40000
HighLimit=65535
[2001]
ParameterName=Unsigned
DataType=0x0006
LowLimit=70000
HighLimit=0xffffffff
[2002]
ParameterName=Sevcon
DataType=0x0006
LowLimit=-2
HighLimit=-1
[2003]
ParameterName=Hex on signed
DataType=0x0003
LowLimit=0
HighLimit=0xFFFF
[2004]
ParameterName=Hex on signed, not inverting
DataType=0x0003
LowLimit=0x8000
HighLimit=0x7FFF
";
    let read = read_eds(text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS013", Severity::Warning, 4),
            ("EDS013", Severity::Warning, 5),
            ("EDS013", Severity::Error, 9),
            ("EDS013", Severity::Warning, 10),
            ("EDS013", Severity::Warning, 14),
            ("EDS013", Severity::Warning, 15),
            ("EDS013", Severity::Warning, 20),
            ("EDS014", Severity::Info, 24),
        ]
    );
    assert_eq!(
        read.diagnostics[6].message,
        "HighLimit `0xFFFF` read as two's complement (-1) is below the LowLimit; as the unsigned \
         number meant, it is above the maximum 32767 of INTEGER16: it restricts nothing and is ignored"
    );
    let hex = read.device.entry(0x2003, 0).unwrap();
    assert_eq!(value_of(&hex.low_limit), Some(Value::Integer(0)));
    assert_eq!(value_of(&hex.high_limit), None);
    let kept = read.device.entry(0x2004, 0).unwrap();
    assert_eq!(value_of(&kept.low_limit), Some(Value::Integer(-0x8000)));
    assert_eq!(value_of(&kept.high_limit), Some(Value::Integer(0x7FFF)));
    assert_eq!(
        read.diagnostics[5].message,
        "HighLimit `-1` is all ones, the maximum 65535 of UNSIGNED16; it restricts nothing and is ignored"
    );
    assert_eq!(
        read.diagnostics[1].message,
        "HighLimit `65535` is above the maximum 32767 of INTEGER16; it restricts nothing and is ignored"
    );
    assert_eq!(
        read.diagnostics[1].help.as_deref(),
        Some("remove the HighLimit, or write 32767")
    );
    let signed = read.device.entry(0x2000, 0).unwrap();
    assert_eq!(value_of(&signed.low_limit), None);
    assert_eq!(value_of(&signed.high_limit), None);
    assert_eq!(signed.high_limit.as_ref().unwrap().raw, "65535");
}

#[test]
fn eds025_eds026_c_suffixes_and_prefixed_bytes_are_read() {
    let text = "\
[2000]
ParameterName=Big
DataType=0x0015
DefaultValue=0x1234567890ABCDEFLL
[2001]
ParameterName=Float
DataType=0x0008
DefaultValue=2.5f
[2002]
ParameterName=Blob
ObjectType=0x2
DataType=0x000F
DefaultValue=0x0004a0ff
ParameterValue=0
";
    let read = read_as("t.dcf", text);
    assert_eq!(
        diags(&read),
        vec![
            ("EDS025", Severity::Warning, 4),
            ("EDS025", Severity::Warning, 8),
            ("EDS026", Severity::Warning, 13),
            ("EDS026", Severity::Warning, 14),
        ]
    );
    assert_eq!(
        read.diagnostics[0].message,
        "INTEGER64 value `0x1234567890ABCDEFLL` has a C literal suffix; read as `0x1234567890ABCDEF`"
    );
    let value = |index| value_of(&read.device.entry(index, 0).unwrap().default);
    assert_eq!(value(0x2000), Some(Value::Integer(0x1234_5678_90AB_CDEF)));
    assert_eq!(value(0x2001), Some(Value::Real(2.5)));
    assert_eq!(
        value(0x2002),
        Some(Value::Bytes(vec![0x00, 0x04, 0xa0, 0xff]))
    );
    assert_eq!(
        value_of(&read.device.entry(0x2002, 0).unwrap().parameter_value),
        Some(Value::Bytes(vec![]))
    );
}

/// A record 2000h with sub-index sections `subs` (each with a ParameterName and a value).
fn record_with_subs(subs: &[&str]) -> String {
    let mut text = String::from(
        "[2000]\nParameterName=Cells\nObjectType=0x9\nSubNumber=3\n\n[2000sub0]\nParameterName=Count\n\
         ObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=2\n",
    );
    for sub in subs {
        text.push_str(&format!(
            "\n[2000sub{sub}]\nParameterName=Cell {sub}\nObjectType=0x7\nDataType=0x0006\n\
             AccessType=ro\nDefaultValue=0\n"
        ));
    }
    text
}

#[test]
fn eds030_a_sub_index_above_ff_is_an_error_at_its_header() {
    // A vendor counting sub-indices in decimal: sub99 is read as 0x99, sub100 cannot exist.
    let read = read_eds(&record_with_subs(&["99", "100", "1G"]));
    assert_eq!(
        diags(&read),
        vec![
            ("EDS030", Severity::Error, 20),
            ("EDS030", Severity::Error, 27)
        ]
    );
    let first = &read.diagnostics[0];
    assert_eq!(
        first.message,
        "section [2000sub100] names sub-index 0x100 of 2000h: beyond 0xFF; the section is kept \
         but not read"
    );
    assert_eq!(
        first.help.as_deref(),
        Some(
            "sub-index sections are hex: `sub100` is 0x100 = 256, beyond 0xFF; if the file counts \
             in decimal, write `sub64` (and its other sub-index sections in hex too: `sub10` is \
             0x10 = 16)"
        )
    );
    assert_eq!(
        read.diagnostics[1].message,
        "section [2000sub1G] names sub-index `1G` of 2000h: not a hex number; the section is kept \
         but not read"
    );
    // Nothing dropped quietly: both sections are kept, the record has sub 0 and 0x99.
    let kept: Vec<_> = read
        .device
        .other_sections
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(kept, vec!["2000sub100", "2000sub1G"]);
    let subs: Vec<u8> = read.device.objects[&0x2000].subs.keys().copied().collect();
    assert_eq!(subs, vec![0, 0x99]);
    // A hex sub-index above FF that is no decimal number either: the help says only hex.
    let read = read_eds(&record_with_subs(&["1A0"]));
    assert_eq!(
        read.diagnostics[0].help.as_deref(),
        Some("sub-index sections are hex, 0..FF: `sub1A0` is 0x1A0 = 416")
    );
}

#[test]
fn a_leading_zero_with_digit_9_is_explained_as_octal() {
    // [2000] ObjectType=09: CiA 306 reads a leading 0 as octal.
    let text = record_with_subs(&["1"]).replace("ObjectType=0x9", "ObjectType=09");
    let read = read_eds(&text);
    assert_eq!(diags(&read), vec![("EDS011", Severity::Error, 3)]);
    assert_eq!(
        read.diagnostics[0].message,
        "ObjectType `09` has a leading 0, which CiA 306 reads as octal, and 9 is not an octal \
         digit; read as RECORD (0x9)"
    );
    assert_eq!(read.diagnostics[0].help.as_deref(), Some("write `9`"));
    // A value of an integer entry: read as decimal, with a warning that says why.
    let text = record_with_subs(&["1"]).replace("DefaultValue=2", "DefaultValue=018");
    let read = read_eds(&text);
    assert_eq!(diags(&read), vec![("EDS017", Severity::Warning, 11)]);
    assert_eq!(
        read.diagnostics[0].message,
        "`018` has a leading 0, which CiA 306 reads as octal, and 8 is not an octal digit; read \
         as decimal 18"
    );
    assert_eq!(read.diagnostics[0].help.as_deref(), Some("write `18`"));
}

#[test]
fn eds030_a_name_key_above_255_is_an_error_at_its_key() {
    let text = SMALL.replace("2=Middle value\n", "2=Middle value\n300=Far value\n");
    let read = read_eds(&text);
    let line = text.lines().position(|l| l == "300=Far value").unwrap() as u32 + 1;
    assert_eq!(diags(&read), vec![("EDS030", Severity::Error, line)]);
    assert_eq!(
        read.diagnostics[0].message,
        "[2000Name] names sub-index 300 of 2000h, beyond 255; the key is not read"
    );
}
