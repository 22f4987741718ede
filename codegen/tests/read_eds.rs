//! The EDS/DCF reader on inline texts: model contents, spans, and exact diagnostics per rule.

use std::path::Path;

use edsgen_codegen::diag::Severity;
use edsgen_codegen::model::*;
use edsgen_codegen::read::{self, Read};

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
    let json = edsgen_codegen::dump::to_json(&read.device);
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
