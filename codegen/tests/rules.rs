//! One test per validator rule (EDS1xx..EDS5xx): a small inline EDS/DCF, read by the real reader,
//! validated, and the exact (code, severity, line) list asserted. Line 0 means "no span" (a
//! finding about the whole file). Also keeps `docs/rules.md` in step with the rule catalogue.

use std::path::Path;

use edsgen_model::diag::Severity::{self, Error, Info, Warning};
use edsgen_model::{read, rules, validate};

/// A clean device: every rule is quiet on `eds(&[], &[], "")`. Tests add objects in `body` (and
/// list them in `optional`/`manufacturer`) or edit keys with `str::replace`.
const BASE: &str = "\
[FileInfo]
FileName=t.eds
FileVersion=1
FileRevision=0
EDSVersion=4.0
Description=validator test device
CreationTime=09:00AM
CreationDate=01-31-2026
CreatedBy=edsgen
ModificationTime=10:30PM
ModificationDate=02-01-2026
ModifiedBy=edsgen

[DeviceInfo]
VendorName=edsgen
VendorNumber=0x1234
ProductName=test
ProductNumber=0x1
RevisionNumber=0x2
OrderCode=T-1
BaudRate_10=0
BaudRate_20=0
BaudRate_50=0
BaudRate_125=1
BaudRate_250=1
BaudRate_500=1
BaudRate_800=0
BaudRate_1000=1
SimpleBootUpMaster=0
SimpleBootUpSlave=1
Granularity=8
DynamicChannelsSupported=0
GroupMessaging=0
NrOfRXPDO=0
NrOfTXPDO=0
LSS_Supported=0

[DummyUsage]
Dummy0001=0
Dummy0002=1
Dummy0003=1
Dummy0004=1
Dummy0005=1
Dummy0006=1
Dummy0007=1

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00000000
PDOMapping=0

[1001]
ParameterName=Error register
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=0
PDOMapping=1

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=5

[1018sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=4
PDOMapping=0

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x1234
PDOMapping=0

[1018sub2]
ParameterName=Product code
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x1
PDOMapping=0

[1018sub3]
ParameterName=Revision number
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x2
PDOMapping=0

[1018sub4]
ParameterName=Serial number
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0
PDOMapping=0

[1017]
ParameterName=Producer heartbeat time
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0
PDOMapping=0
";

/// An object list section.
fn list(name: &str, indices: &[u16]) -> String {
    let mut s = format!("\n[{name}]\nSupportedObjects={}\n", indices.len());
    for (i, index) in indices.iter().enumerate() {
        s.push_str(&format!("{}=0x{index:04X}\n", i + 1));
    }
    s
}

/// The clean base plus `body`, with 1017h and `optional` in [OptionalObjects] and
/// `manufacturer` in [ManufacturerObjects].
fn eds(optional: &[u16], manufacturer: &[u16], body: &str) -> String {
    let mut opt = vec![0x1017];
    opt.extend_from_slice(optional);
    format!(
        "{BASE}{}{}\n{body}",
        list("OptionalObjects", &opt),
        list("ManufacturerObjects", manufacturer)
    )
}

/// A VAR section.
fn var(
    index: u16,
    name: &str,
    data_type: u16,
    access: &str,
    default: &str,
    mapping: bool,
) -> String {
    format!(
        "\n[{index:X}]\nParameterName={name}\nObjectType=0x7\nDataType=0x{data_type:04X}\nAccessType={access}\nDefaultValue={default}\nPDOMapping={}\n",
        u8::from(mapping)
    )
}

/// A sub-object section.
fn sub(
    index: u16,
    sub: u8,
    name: &str,
    data_type: u16,
    access: &str,
    default: &str,
    mapping: bool,
) -> String {
    format!(
        "\n[{index:X}sub{sub:X}]\nParameterName={name}\nObjectType=0x7\nDataType=0x{data_type:04X}\nAccessType={access}\nDefaultValue={default}\nPDOMapping={}\n",
        u8::from(mapping)
    )
}

/// A RECORD or ARRAY main section.
fn record(index: u16, name: &str, object_type: u8, sub_number: u32) -> String {
    format!("\n[{index:X}]\nParameterName={name}\nObjectType=0x{object_type:X}\nSubNumber={sub_number}\n")
}

/// A PDO communication record (subs 0, 1, 2, and 5 for TPDOs).
fn pdo_comm(index: u16, cob_id: &str, transmission: u8) -> String {
    let tpdo = index >= 0x1800;
    let mut s = record(
        index,
        "PDO communication parameter",
        9,
        if tpdo { 4 } else { 3 },
    );
    s += &sub(
        index,
        0,
        "Highest sub-index supported",
        5,
        "ro",
        if tpdo { "5" } else { "2" },
        false,
    );
    s += &sub(index, 1, "COB-ID used by PDO", 7, "rw", cob_id, false);
    s += &sub(
        index,
        2,
        "Transmission type",
        5,
        "rw",
        &transmission.to_string(),
        false,
    );
    if tpdo {
        s += &sub(index, 5, "Event timer", 6, "rw", "0", false);
    }
    s
}

/// A PDO mapping record with the given entries (mapping sub0 = their count).
fn pdo_map(index: u16, entries: &[&str]) -> String {
    let mut s = record(index, "PDO mapping parameter", 9, entries.len() as u32 + 1);
    s += &sub(
        index,
        0,
        "Number of mapped objects",
        5,
        "rw",
        &entries.len().to_string(),
        false,
    );
    for (i, e) in entries.iter().enumerate() {
        s += &sub(
            index,
            i as u8 + 1,
            &format!("Mapped object {}", i + 1),
            7,
            "rw",
            e,
            false,
        );
    }
    s
}

/// Mappable application objects: 2000h U16 rww, 2001h U32 rwr, 2002h U8 ro (not mappable),
/// 2003h U8 ro (mappable).
fn app_objects() -> String {
    var(0x2000, "Command", 6, "rww", "0", true)
        + &var(0x2001, "Status", 7, "rwr", "0", true)
        + &var(0x2002, "Private", 5, "ro", "0", false)
        + &var(0x2003, "Mode display", 5, "ro", "0", true)
}

const APP: &[u16] = &[0x2000, 0x2001, 0x2002, 0x2003];

type Found = (String, Severity, u32);

/// The validator's diagnostics (reader diagnostics excluded) as (code, severity, line).
fn diags_for(path: &str, text: &str) -> Vec<Found> {
    let read = read::read_bytes(Path::new(path), text.as_bytes());
    validate::validate(&read.device)
        .iter()
        .map(|d| {
            (
                d.code().to_owned(),
                d.severity,
                d.span.map_or(0, |s| s.line),
            )
        })
        .collect()
}

fn diags(text: &str) -> Vec<Found> {
    diags_for("t.eds", text)
}

/// The 1-based line number of the only line equal to `needle` (after trimming).
fn line_of(text: &str, needle: &str) -> u32 {
    let hits: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == needle)
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(
        hits.len(),
        1,
        "`{needle}` should be on exactly one line: {hits:?}"
    );
    hits[0] as u32
}

fn d(code: &str, severity: Severity, line: u32) -> Found {
    (code.to_owned(), severity, line)
}

/// Replaces exactly one occurrence.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "`{from}` should occur once");
    text.replacen(from, to, 1)
}

#[test]
fn clean_base_has_no_diagnostics() {
    assert_eq!(diags(&eds(&[], &[], "")), vec![]);
    let with_pdos = eds(
        &[0x1400, 0x1600, 0x1800, 0x1A00],
        APP,
        &(app_objects()
            + &pdo_comm(0x1400, "$NODEID+0x200", 255)
            + &pdo_map(0x1600, &["0x20000010"])
            + &pdo_comm(0x1800, "$NODEID+0x180", 254)
            + &pdo_map(0x1A00, &["0x20010020", "0x20030008"])),
    );
    let with_pdos = edit(&with_pdos, "NrOfRXPDO=0", "NrOfRXPDO=1");
    let with_pdos = edit(&with_pdos, "NrOfTXPDO=0", "NrOfTXPDO=1");
    assert_eq!(diags(&with_pdos), vec![]);
}

// ---- EDS1xx ----

#[test]
fn eds101_file_info_missing() {
    let t = eds(&[], &[], "");
    let end = t.find("[DeviceInfo]").unwrap();
    let t = t[end..].to_owned();
    assert_eq!(diags(&t), vec![d("EDS101", Warning, 0)]);
}

#[test]
fn eds102_eds_version_not_x_y() {
    let t = edit(&eds(&[], &[], ""), "EDSVersion=4.0", "EDSVersion=4");
    assert_eq!(
        diags(&t),
        vec![d("EDS102", Warning, line_of(&t, "EDSVersion=4"))]
    );
}

#[test]
fn eds102_eds_version_missing_points_at_the_section() {
    let t = edit(&eds(&[], &[], ""), "EDSVersion=4.0\n", "");
    assert_eq!(diags(&t), vec![d("EDS102", Warning, 1)]);
}

#[test]
fn eds103_iso_dates_are_info_once_per_file() {
    let t = edit(
        &eds(&[], &[], ""),
        "CreationDate=01-31-2026",
        "CreationDate=2026-01-31",
    );
    let t = edit(&t, "ModificationTime=10:30PM", "ModificationTime=22:30:00");
    // At the first offending key.
    assert_eq!(
        diags(&t),
        vec![d("EDS103", Info, line_of(&t, "CreationDate=2026-01-31"))]
    );
}

#[test]
fn eds104_file_version_not_u8() {
    let t = edit(&eds(&[], &[], ""), "FileVersion=1", "FileVersion=300");
    assert_eq!(
        diags(&t),
        vec![d("EDS104", Warning, line_of(&t, "FileVersion=300"))]
    );
}

#[test]
fn eds104_file_revision_with_a_leading_zero_is_explained_as_octal() {
    let t = edit(&eds(&[], &[], ""), "FileRevision=0", "FileRevision=09");
    assert_eq!(
        diags(&t),
        vec![d("EDS104", Warning, line_of(&t, "FileRevision=09"))]
    );
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    let found = validate::validate(&read.device);
    assert_eq!(
        found[0].message,
        "FileRevision `09` has a leading 0, which CiA 306 reads as octal, and 9 is not an octal digit"
    );
    assert_eq!(found[0].help.as_deref(), Some("write `9`"));
}

#[test]
fn eds105_device_info_missing() {
    let t = eds(&[], &[], "");
    let start = t.find("[DeviceInfo]").unwrap();
    let end = t.find("[DummyUsage]").unwrap();
    let t = format!("{}{}", &t[..start], &t[end..]);
    assert_eq!(diags(&t), vec![d("EDS105", Error, 0)]);
}

#[test]
fn eds106_vendor_number_differs_from_1018() {
    let t = edit(
        &eds(&[], &[], ""),
        "VendorNumber=0x1234",
        "VendorNumber=0x9999",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS106", Warning, line_of(&t, "VendorNumber=0x9999"))]
    );
}

#[test]
fn eds107_no_bit_rate_supported() {
    let mut t = eds(&[], &[], "");
    for rate in [125, 250, 500, 1000] {
        t = edit(
            &t,
            &format!("BaudRate_{rate}=1"),
            &format!("BaudRate_{rate}=0"),
        );
    }
    assert_eq!(
        diags(&t),
        vec![d("EDS107", Warning, line_of(&t, "[DeviceInfo]"))]
    );
}

#[test]
fn eds107_non_standard_bit_rate_key() {
    let t = edit(
        &eds(&[], &[], ""),
        "BaudRate_1000=1",
        "BaudRate_1000=1\nBaudRate_100=1",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS107", Warning, line_of(&t, "[DeviceInfo]"))]
    );
}

#[test]
fn eds108_granularity_above_64() {
    let t = edit(&eds(&[], &[], ""), "Granularity=8", "Granularity=65");
    assert_eq!(
        diags(&t),
        vec![d("EDS108", Error, line_of(&t, "Granularity=65"))]
    );
}

fn one_rpdo(map_entries: &[&str]) -> String {
    let t = eds(
        &[0x1400, 0x1600],
        APP,
        &(app_objects() + &pdo_comm(0x1400, "$NODEID+0x200", 255) + &pdo_map(0x1600, map_entries)),
    );
    edit(&t, "NrOfRXPDO=0", "NrOfRXPDO=1")
}

fn one_tpdo(map_entries: &[&str]) -> String {
    let t = eds(
        &[0x1800, 0x1A00],
        APP,
        &(app_objects() + &pdo_comm(0x1800, "$NODEID+0x180", 254) + &pdo_map(0x1A00, map_entries)),
    );
    edit(&t, "NrOfTXPDO=0", "NrOfTXPDO=1")
}

#[test]
fn eds109_granularity_zero_with_writable_mapping() {
    let t = edit(&one_rpdo(&["0x20000010"]), "Granularity=8", "Granularity=0");
    assert_eq!(
        diags(&t),
        vec![d("EDS109", Warning, line_of(&t, "Granularity=0"))]
    );
}

#[test]
fn eds110_pdo_count_differs_from_objects() {
    let t = edit(&eds(&[], &[], ""), "NrOfRXPDO=0", "NrOfRXPDO=2");
    assert_eq!(
        diags(&t),
        vec![d("EDS110", Warning, line_of(&t, "NrOfRXPDO=2"))]
    );
}

#[test]
fn eds111_pdo_count_above_512() {
    let t = edit(&eds(&[], &[], ""), "NrOfTXPDO=0", "NrOfTXPDO=600");
    assert_eq!(
        diags(&t),
        vec![d("EDS111", Error, line_of(&t, "NrOfTXPDO=600"))]
    );
}

#[test]
fn eds112_compact_pdo_high_bits() {
    let t = edit(
        &eds(&[], &[], ""),
        "LSS_Supported=0",
        "LSS_Supported=0\nCompactPDO=0x40",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS112", Warning, line_of(&t, "CompactPDO=0x40"))]
    );
}

#[test]
fn eds113_lss_without_serial_number() {
    let t = edit(&eds(&[], &[], ""), "LSS_Supported=0", "LSS_Supported=1");
    let start = t.find("\n[1018sub4]").unwrap();
    let end = t.find("\n[1017]").unwrap();
    let t = format!("{}{}", &t[..start], &t[end..]);
    let t = edit(&t, "SubNumber=5", "SubNumber=4");
    let t = edit(&t, "DefaultValue=4\n", "DefaultValue=3\n");
    assert_eq!(
        diags(&t),
        vec![d("EDS113", Warning, line_of(&t, "[DeviceInfo]"))]
    );
}

#[test]
fn eds114_dynamic_channels_flag_without_section() {
    let t = edit(
        &eds(&[], &[], ""),
        "DynamicChannelsSupported=0",
        "DynamicChannelsSupported=1",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS114", Warning, line_of(&t, "[DeviceInfo]"))]
    );
}

// ---- EDS2xx ----

#[test]
fn eds201_mandatory_list_missing() {
    let t = edit(
        &eds(&[], &[], ""),
        "[MandatoryObjects]\nSupportedObjects=3\n1=0x1000\n2=0x1001\n3=0x1018\n",
        "",
    );
    assert_eq!(diags(&t), vec![d("EDS201", Error, 0)]);
}

#[test]
fn eds202_manufacturer_list_missing() {
    let t = eds(&[], &[], &var(0x2000, "Speed", 6, "rw", "0", false));
    let t = edit(&t, "[ManufacturerObjects]\nSupportedObjects=0\n", "");
    assert_eq!(diags(&t), vec![d("EDS202", Warning, 0)]);
}

#[test]
fn eds203_supported_objects_count_differs() {
    let t = edit(
        &eds(&[], &[], ""),
        "SupportedObjects=3",
        "SupportedObjects=4",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS203", Warning, line_of(&t, "SupportedObjects=4"))]
    );
}

#[test]
fn eds204_listed_without_section() {
    let t = eds(&[], &[0x2005], "");
    assert_eq!(diags(&t), vec![d("EDS204", Error, line_of(&t, "1=0x2005"))]);
}

#[test]
fn eds204_entry_beyond_supported_objects_is_a_warning() {
    let t = edit(
        &eds(&[], &[0x2005], ""),
        "[ManufacturerObjects]\nSupportedObjects=1",
        "[ManufacturerObjects]\nSupportedObjects=0",
    );
    assert_eq!(
        diags(&t),
        vec![
            d("EDS203", Warning, line_of(&t, "SupportedObjects=0")),
            d("EDS204", Warning, line_of(&t, "1=0x2005")),
        ]
    );
}

#[test]
fn eds205_sections_not_listed_are_one_warning_per_list() {
    let body =
        var(0x2000, "Speed", 6, "rw", "0", false) + &var(0x2001, "Torque", 6, "rw", "0", false);
    let t = eds(&[], &[], &body);
    assert_eq!(diags(&t), vec![d("EDS205", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds206_manufacturer_index_in_optional_list() {
    let t = eds(&[0x2000], &[], &var(0x2000, "Speed", 6, "rw", "0", false));
    assert_eq!(
        diags(&t),
        vec![d("EDS206", Warning, line_of(&t, "2=0x2000"))]
    );
}

#[test]
fn eds207_index_listed_twice() {
    let t = eds(&[0x1017], &[], "");
    assert_eq!(
        diags(&t),
        vec![d("EDS207", Warning, line_of(&t, "2=0x1017"))]
    );
}

#[test]
fn eds208_identity_missing() {
    let t = eds(&[], &[], "");
    let start = t.find("\n[1018]").unwrap();
    let end = t.find("\n[1017]").unwrap();
    let t = format!("{}{}", &t[..start], &t[end..]);
    let t = edit(
        &t,
        "SupportedObjects=3\n1=0x1000\n2=0x1001\n3=0x1018",
        "SupportedObjects=2\n1=0x1000\n2=0x1001",
    );
    assert_eq!(diags(&t), vec![d("EDS208", Error, 0)]);
}

#[test]
fn eds209_no_error_control() {
    let t = eds(&[], &[], "");
    let start = t.find("\n[1017]").unwrap();
    let end = t.find("\n[OptionalObjects]").unwrap();
    let t = format!("{}{}", &t[..start], &t[end..]);
    let t = edit(&t, "SupportedObjects=1\n1=0x1017", "SupportedObjects=0");
    assert_eq!(diags(&t), vec![d("EDS209", Warning, 0)]);
}

// ---- EDS3xx ----

#[test]
fn eds301_missing_parameter_name() {
    let t = eds(&[], &[0x2000], &var(0x2000, "Speed", 6, "rw", "0", false));
    let t = edit(&t, "ParameterName=Speed\n", "");
    assert_eq!(diags(&t), vec![d("EDS301", Error, line_of(&t, "[2000]"))]);
}

#[test]
fn eds301_unnamed_array_elements_are_one_warning_per_object() {
    let body = record(0x2000, "Arr", 8, 3)
        + &sub(0x2000, 0, "Count", 5, "ro", "2", false)
        + &sub(0x2000, 1, "", 6, "rw", "0", false)
        + &sub(0x2000, 2, "", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS301", Warning, line_of(&t, "[2000sub1]"))]
    );
}

#[test]
fn eds301_unnamed_record_field_is_an_error() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 5, "ro", "1", false)
        + &sub(0x2000, 1, "", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS301", Error, line_of(&t, "[2000sub1]"))]
    );
}

#[test]
fn eds302_long_parameter_name() {
    let name = "N".repeat(242);
    let t = eds(&[], &[0x2000], &var(0x2000, &name, 6, "rw", "0", false));
    assert_eq!(diags(&t), vec![d("EDS302", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds303_var_without_data_type() {
    let t = eds(&[], &[0x2000], &var(0x2000, "Speed", 6, "rw", "0", false));
    let t = edit(
        &t,
        "ParameterName=Speed\nObjectType=0x7\nDataType=0x0006\n",
        "ParameterName=Speed\nObjectType=0x7\n",
    );
    assert_eq!(diags(&t), vec![d("EDS303", Error, line_of(&t, "[2000]"))]);
}

#[test]
fn eds303_record_without_sub_number() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 5, "ro", "1", false)
        + &sub(0x2000, 1, "A", 6, "rw", "0", false);
    let t = edit(&eds(&[], &[0x2000], &body), "SubNumber=2\n", "");
    assert_eq!(diags(&t), vec![d("EDS303", Error, line_of(&t, "[2000]"))]);
}

#[test]
fn eds303_compact_array_without_data_type() {
    let body = "\n[2000]\nParameterName=Arr\nObjectType=0x8\nCompactSubObj=3\nAccessType=rw\nDefaultValue=0\nPDOMapping=0\n";
    let t = eds(&[], &[0x2000], body);
    assert_eq!(
        diags(&t),
        vec![d("EDS303", Error, line_of(&t, "CompactSubObj=3"))]
    );
}

#[test]
fn eds304_sub_number_on_a_var() {
    let t = eds(&[], &[0x2000], &var(0x2000, "Speed", 6, "rw", "0", false));
    let t = edit(
        &t,
        "ParameterName=Speed\nObjectType=0x7\n",
        "ParameterName=Speed\nObjectType=0x7\nSubNumber=1\n",
    );
    assert_eq!(diags(&t), vec![d("EDS304", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds304_data_type_on_record_mains_is_one_info_per_file() {
    let rec = |index: u16| {
        record(index, "Rec", 9, 2)
            + "DataType=0x0007\nAccessType=rw\n"
            + &sub(index, 0, "Count", 5, "ro", "1", false)
            + &sub(index, 1, "A", 6, "rw", "0", false)
    };
    let t = eds(&[], &[0x2000, 0x2001], &(rec(0x2000) + &rec(0x2001)));
    assert_eq!(diags(&t), vec![d("EDS304", Info, line_of(&t, "[2000]"))]);
}

#[test]
fn eds305_sub_number_and_compact_sub_obj() {
    let body = "\n[2000]\nParameterName=Arr\nObjectType=0x8\nSubNumber=2\nCompactSubObj=3\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nPDOMapping=0\n";
    let t = eds(&[], &[0x2000], body);
    assert_eq!(
        diags(&t),
        vec![d("EDS305", Error, line_of(&t, "SubNumber=2"))]
    );
}

#[test]
fn eds306_sub_number_differs_from_subs() {
    let body = record(0x2000, "Rec", 9, 3)
        + &sub(0x2000, 0, "Count", 5, "ro", "1", false)
        + &sub(0x2000, 1, "A", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS306", Warning, line_of(&t, "SubNumber=3"))]
    );
}

#[test]
fn eds307_sub_index_ff() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 5, "ro", "1", false)
        + &sub(0x2000, 1, "A", 6, "rw", "0", false)
        + &sub(0x2000, 0xFF, "Structure", 7, "ro", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS307", Error, line_of(&t, "[2000subFF]"))]
    );
}

#[test]
fn eds308_record_without_sub0() {
    let body = record(0x2000, "Rec", 9, 1) + &sub(0x2000, 1, "A", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS308", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds308_sub0_not_unsigned8() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 6, "ro", "1", false)
        + &sub(0x2000, 1, "A", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        // At the DataType key: three lines below the header.
        vec![d("EDS308", Warning, line_of(&t, "[2000sub0]") + 3)]
    );
}

#[test]
fn eds308_array_without_sub0_is_an_error() {
    let body = record(0x2000, "Arr", 8, 1) + &sub(0x2000, 1, "Arr1", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS308", Error, line_of(&t, "[2000]"))]);
}

#[test]
fn eds309_writable_sub0() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 5, "rw", "1", false)
        + &sub(0x2000, 1, "A", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        // At the AccessType key.
        vec![d("EDS309", Warning, line_of(&t, "[2000sub0]") + 4)]
    );
}

#[test]
fn eds310_sub0_value_not_highest_sub_index() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 5, "ro", "3", false)
        + &sub(0x2000, 1, "A", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS310", Warning, line_of(&t, "DefaultValue=3"))]
    );
}

fn array2(t1: u16, a1: &str, t2: u16, a2: &str) -> String {
    record(0x2000, "Arr", 8, 3)
        + &sub(0x2000, 0, "Count", 5, "ro", "2", false)
        + &sub(0x2000, 1, "Arr1", t1, a1, "0", false)
        + &sub(0x2000, 2, "Arr2", t2, a2, "0", false)
}

#[test]
fn eds311_array_of_mixed_types() {
    let t = eds(&[], &[0x2000], &array2(6, "rw", 7, "rw"));
    assert_eq!(
        diags(&t),
        vec![d("EDS311", Error, line_of(&t, "[2000sub2]") + 3)]
    );
}

#[test]
fn eds312_array_of_mixed_access() {
    let t = eds(&[], &[0x2000], &array2(6, "rw", 6, "ro"));
    assert_eq!(
        diags(&t),
        vec![d("EDS312", Warning, line_of(&t, "[2000sub2]") + 4)]
    );
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    assert_eq!(
        validate::validate(&read.device)[0].message,
        "2000h sub 2 differs from 2000h sub 1 in AccessType ro vs rw"
    );
}

#[test]
fn eds313_record_gap_is_info() {
    let body = record(0x2000, "Rec", 9, 2)
        + &sub(0x2000, 0, "Count", 5, "ro", "2", false)
        + &sub(0x2000, 2, "B", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS313", Info, line_of(&t, "[2000]"))]);
}

#[test]
fn eds313_array_gap_is_a_warning() {
    let body = record(0x2000, "Arr", 8, 2)
        + &sub(0x2000, 0, "Count", 5, "ro", "2", false)
        + &sub(0x2000, 2, "Arr2", 6, "rw", "0", false);
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS313", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds314_unknown_data_type() {
    let t = eds(
        &[],
        &[0x2000],
        &var(0x2000, "Speed", 0x99, "rw", "0", false),
    );
    let found = diags(&t);
    assert_eq!(
        found,
        vec![d("EDS314", Error, line_of(&t, "DataType=0x0099"))]
    );
}

#[test]
fn eds314_standard_record_type_on_a_var_is_named() {
    let t = eds(&[], &[0x2000], &var(0x2000, "Pdo", 0x20, "rw", "", false));
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    let found = validate::validate(&read.device);
    assert_eq!(found.len(), 1);
    assert_eq!(
        found[0].span.map(|s| s.line),
        Some(line_of(&t, "DataType=0x0020"))
    );
    assert_eq!(
        found[0].message,
        "2000h has DataType 0020h, the CiA 301 record type PDO_COMMUNICATION_PARAMETER, \
         which this file does not describe as a DEFSTRUCT"
    );
}

#[test]
fn eds315_domain_with_a_data_type() {
    let body = "\n[2000]\nParameterName=Blob\nObjectType=0x2\nDataType=0x0007\nAccessType=rw\n";
    let t = eds(&[], &[0x2000], body);
    assert_eq!(
        diags(&t),
        vec![d("EDS315", Error, line_of(&t, "ParameterName=Blob") + 2)]
    );
}

#[test]
fn eds316_low_limit_above_high_limit() {
    let body = var(0x2000, "Speed", 6, "rw", "7", false) + "LowLimit=10\nHighLimit=5\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS316", Error, line_of(&t, "LowLimit=10"))]
    );
}

#[test]
fn eds317_default_above_high_limit() {
    let body = var(0x2000, "Speed", 6, "rw", "20", false) + "LowLimit=0\nHighLimit=10\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS317", Warning, line_of(&t, "DefaultValue=20"))]
    );
}

#[test]
fn eds317_nodeid_default_checked_for_node_127() {
    let body =
        var(0x2000, "Id", 7, "rw", "$NODEID+0x10", false) + "LowLimit=0x11\nHighLimit=0x80\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d(
            "EDS317",
            Warning,
            line_of(&t, "DefaultValue=$NODEID+0x10")
        )]
    );
}

#[test]
fn eds318_limits_on_a_string() {
    let body = var(0x2000, "Label", 9, "rw", "abc", false) + "LowLimit=0\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS318", Warning, line_of(&t, "LowLimit=0"))]
    );
}

#[test]
fn eds319_nodeid_overflow_for_high_node_ids_is_a_warning() {
    let t = eds(
        &[],
        &[0x2000],
        &var(0x2000, "Id", 5, "rw", "$NODEID+0x90", false),
    );
    assert_eq!(
        diags(&t),
        vec![d(
            "EDS319",
            Warning,
            line_of(&t, "DefaultValue=$NODEID+0x90")
        )]
    );
}

#[test]
fn eds319_nodeid_overflow_for_every_node_id_is_an_error() {
    let t = eds(
        &[],
        &[0x2000],
        &var(0x2000, "Id", 5, "rw", "$NODEID+0x100", false),
    );
    assert_eq!(
        diags(&t),
        vec![d(
            "EDS319",
            Error,
            line_of(&t, "DefaultValue=$NODEID+0x100")
        )]
    );
}

#[test]
fn eds320_fixed_emcy_cob_id() {
    let t = eds(
        &[0x1014],
        &[],
        &var(0x1014, "COB-ID EMCY", 7, "rw", "0x81", false),
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS320", Warning, line_of(&t, "DefaultValue=0x81"))]
    );
}

#[test]
fn eds321_reserved_obj_flags() {
    let body = var(0x2000, "Speed", 6, "rw", "0", false) + "ObjFlags=0x4\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS321", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds322_compact_sub_obj_on_a_var() {
    let body = var(0x2000, "Speed", 6, "rw", "0", false) + "CompactSubObj=2\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS322", Error, line_of(&t, "[2000]"))]);
}

#[test]
fn eds322_compact_sub_obj_255_is_one_error_not_also_eds307() {
    let body = "\n[2000]\nParameterName=Errors\nObjectType=0x8\nCompactSubObj=255\nDataType=0x0007\nAccessType=ro\nPDOMapping=0\n";
    let t = eds(&[], &[0x2000], body);
    assert_eq!(
        diags(&t),
        vec![d("EDS322", Error, line_of(&t, "CompactSubObj=255"))]
    );
}

// ---- EDS4xx ----

#[test]
fn eds401_mapping_without_communication_object() {
    let t = eds(
        &[0x1600],
        APP,
        &(app_objects() + &pdo_map(0x1600, &["0x20000010"])),
    );
    assert_eq!(diags(&t), vec![d("EDS401", Error, line_of(&t, "[1600]"))]);
}

#[test]
fn eds402_transmission_type_not_u8() {
    let t = one_tpdo(&["0x20010020"]);
    let t = edit(
        &t,
        "ParameterName=Transmission type\nObjectType=0x7\nDataType=0x0005",
        "ParameterName=Transmission type\nObjectType=0x7\nDataType=0x0006",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS402", Error, line_of(&t, "[1800sub2]"))]
    );
}

#[test]
fn eds403_reserved_sub4_is_one_info() {
    let t = one_tpdo(&["0x20010020"]);
    let t = edit(&t, "SubNumber=4\n", "SubNumber=5\n");
    let t = t + &sub(0x1800, 4, "Compatibility entry", 5, "rw", "0", false);
    assert_eq!(
        diags(&t),
        vec![d("EDS403", Info, line_of(&t, "[1800sub4]"))]
    );
}

#[test]
fn eds404_inhibit_time_on_an_rpdo() {
    let t = one_rpdo(&["0x20000010"]);
    let t = edit(&t, "SubNumber=3\n", "SubNumber=4\n");
    let t = edit(&t, "ParameterName=Highest sub-index supported\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=2\n", "ParameterName=Highest sub-index supported\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=3\n");
    let t = t + &sub(0x1400, 3, "Inhibit time", 6, "rw", "0", false);
    assert_eq!(
        diags(&t),
        vec![d("EDS404", Info, line_of(&t, "[1400sub3]"))]
    );
}

#[test]
fn eds405_cob_id_in_heartbeat_range() {
    let t = eds(
        &[0x1404, 0x1604],
        APP,
        &(app_objects() + &pdo_comm(0x1404, "0x701", 255) + &pdo_map(0x1604, &["0x20000010"])),
    );
    let t = edit(&t, "NrOfRXPDO=0", "NrOfRXPDO=1");
    assert_eq!(
        diags(&t),
        vec![d("EDS405", Warning, line_of(&t, "DefaultValue=0x701"))]
    );
}

#[test]
fn eds406_reserved_transmission_type() {
    let t = eds(
        &[0x1800, 0x1A00],
        APP,
        &(app_objects()
            + &pdo_comm(0x1800, "$NODEID+0x180", 245)
            + &pdo_map(0x1A00, &["0x20010020"])),
    );
    let t = edit(&t, "NrOfTXPDO=0", "NrOfTXPDO=1");
    assert_eq!(
        diags(&t),
        vec![d("EDS406", Warning, line_of(&t, "DefaultValue=245"))]
    );
}

#[test]
fn eds407_more_mapped_than_entries() {
    let t = one_rpdo(&["0x20000010"]);
    let t = edit(&t, "ParameterName=Number of mapped objects\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=1", "ParameterName=Number of mapped objects\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=2");
    let line = line_of(&t, "[1600sub0]") + 5;
    assert_eq!(diags(&t), vec![d("EDS407", Error, line)]);
}

#[test]
fn eds407_mpdo_modes_are_not_counts() {
    for mode in ["0xFE", "0xFF", "65"] {
        let t = one_rpdo(&["0x20000010"]);
        let t = edit(&t, "ParameterName=Number of mapped objects\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=1", &format!("ParameterName=Number of mapped objects\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue={mode}"));
        let line = line_of(&t, "[1600sub0]") + 5;
        let want = if mode == "65" {
            vec![d("EDS407", Error, line)]
        } else {
            vec![]
        };
        assert_eq!(diags(&t), want, "sub 0 = {mode}");
    }
}

#[test]
fn eds408_mapping_to_a_missing_entry() {
    let t = one_rpdo(&["0x20050010"]);
    assert_eq!(
        diags(&t),
        vec![d("EDS408", Error, line_of(&t, "DefaultValue=0x20050010"))]
    );
}

#[test]
fn eds409_mapping_to_a_non_mappable_entry() {
    let t = one_tpdo(&["0x20020008"]);
    assert_eq!(
        diags(&t),
        vec![d("EDS409", Error, line_of(&t, "DefaultValue=0x20020008"))]
    );
}

#[test]
fn eds410_rpdo_mapping_a_read_only_entry() {
    let t = one_rpdo(&["0x20030008"]);
    assert_eq!(
        diags(&t),
        vec![d("EDS410", Error, line_of(&t, "DefaultValue=0x20030008"))]
    );
}

#[test]
fn eds411_dummy_not_enabled() {
    let t = one_rpdo(&["0x00010001", "0x20000010"]);
    let t = edit(&t, "Granularity=8", "Granularity=1");
    assert_eq!(
        diags(&t),
        vec![d("EDS411", Error, line_of(&t, "DefaultValue=0x00010001"))]
    );
}

#[test]
fn eds412_mapping_length_differs_from_type_width() {
    let t = one_rpdo(&["0x20000008"]);
    assert_eq!(
        diags(&t),
        vec![d("EDS412", Error, line_of(&t, "DefaultValue=0x20000008"))]
    );
}

#[test]
fn eds413_more_than_64_bits() {
    let t = one_tpdo(&["0x20010020", "0x20010020", "0x20030008"]);
    let line = line_of(&t, "[1A00sub0]") + 5;
    assert_eq!(diags(&t), vec![d("EDS413", Error, line)]);
}

#[test]
fn eds414_length_not_a_multiple_of_granularity() {
    let t = edit(
        &one_tpdo(&["0x20030008"]),
        "Granularity=8",
        "Granularity=16",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS414", Warning, line_of(&t, "DefaultValue=0x20030008"))]
    );
}

#[test]
fn eds414_more_than_8_entries_with_granularity_8() {
    let entries = ["0x00050008"; 9];
    let t = one_rpdo(&entries);
    let line = line_of(&t, "[1600sub0]") + 5;
    assert_eq!(
        diags(&t),
        vec![d("EDS413", Error, line), d("EDS414", Warning, line)]
    );
}

#[test]
fn eds415_two_tpdos_with_one_cob_id() {
    let t = eds(
        &[0x1800, 0x1801, 0x1A00, 0x1A01],
        APP,
        &(app_objects()
            + &pdo_comm(0x1800, "$NODEID+0x180", 254)
            + &pdo_map(0x1A00, &["0x20010020"])
            + &pdo_comm(0x1801, "$NODEID+0x180", 254)
            + &pdo_map(0x1A01, &["0x20030008"])),
    );
    let t = edit(&t, "NrOfTXPDO=0", "NrOfTXPDO=2");
    let found = diags(&t);
    let second = line_of(&t, "[1801sub1]") + 5;
    assert!(found.contains(&d("EDS415", Warning, second)), "{found:?}");
    assert_eq!(found.len(), 2, "{found:?}"); // and EDS320 for 1801h's default.
    assert!(found.contains(&d("EDS320", Warning, second)), "{found:?}");
}

#[test]
fn eds416_dummy_usage_key_out_of_range() {
    let t = edit(
        &eds(&[], &[], ""),
        "Dummy0007=1",
        "Dummy0007=1\nDummy0010=1",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS416", Info, line_of(&t, "[DummyUsage]"))]
    );
}

#[test]
fn eds417_dummy_usage_without_dummy0001() {
    // lely's DCFs list only the dummies they use; python canopen 2.4.1 raises on the first absent.
    let t = edit(&eds(&[], &[], ""), "Dummy0001=0\n", "");
    assert_eq!(
        diags(&t),
        vec![d("EDS417", Warning, line_of(&t, "[DummyUsage]"))]
    );
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    let found = validate::validate(&read.device);
    assert_eq!(found[0].message, "[DummyUsage] has no Dummy0001");
}

// ---- EDS5xx ----

const COMMISSIONING: &str = "\n[DeviceComissioning]\nNodeID=5\nNodeName=drive\nBaudrate=250\nNetNumber=1\nNetworkName=net\nCANopenManager=0\nLSS_SerialNumber=0\n";

fn dcf(body: &str) -> String {
    eds(&[], &[], &format!("{COMMISSIONING}{body}"))
}

#[test]
fn dcf_base_is_clean() {
    assert_eq!(diags_for("t.dcf", &dcf("")), vec![]);
}

#[test]
fn eds501_node_id_out_of_range() {
    let t = edit(&dcf(""), "NodeID=5", "NodeID=128");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS501", Error, line_of(&t, "NodeID=128"))]
    );
}

#[test]
fn eds501_eds502_zero_means_not_commissioned_and_is_a_warning() {
    let t = edit(&dcf(""), "NodeID=5", "NodeID=0");
    let t = edit(&t, "Baudrate=250", "Baudrate=0");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![
            d("EDS501", Warning, line_of(&t, "NodeID=0")),
            d("EDS502", Warning, line_of(&t, "Baudrate=0")),
        ]
    );
}

#[test]
fn eds502_baudrate_not_standard() {
    let t = edit(&dcf(""), "Baudrate=250", "Baudrate=100");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS502", Error, line_of(&t, "Baudrate=100"))]
    );
}

#[test]
fn eds502_baudrate_not_enabled() {
    let t = edit(&dcf(""), "Baudrate=250", "Baudrate=20");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS502", Error, line_of(&t, "Baudrate=20"))]
    );
}

#[test]
fn eds503_lss_serial_differs_from_1018() {
    let t = edit(&dcf(""), "LSS_SerialNumber=0", "LSS_SerialNumber=5");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS503", Warning, line_of(&t, "[DeviceComissioning]"))]
    );
}

#[test]
fn eds504_node_name_too_long() {
    let t = edit(
        &dcf(""),
        "NodeName=drive",
        &format!("NodeName={}", "n".repeat(247)),
    );
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS504", Warning, line_of(&t, "[DeviceComissioning]"))]
    );
}

#[test]
fn eds505_parameter_value_in_an_eds() {
    let t = eds(
        &[],
        &[0x2000],
        &(var(0x2000, "Speed", 6, "rw", "0", false) + "ParameterValue=5\n"),
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS505", Warning, line_of(&t, "ParameterValue=5"))]
    );
}

#[test]
fn eds506_dcf_without_commissioning() {
    assert_eq!(
        diags_for("t.dcf", &eds(&[], &[], "")),
        vec![d("EDS506", Warning, 0)]
    );
}

#[test]
fn eds507_upload_file_on_a_var() {
    let t = dcf(&(var(0x2000, "Speed", 6, "rw", "0", false) + "UploadFile=speed.bin\n"));
    let t = edit(
        &t,
        "[ManufacturerObjects]\nSupportedObjects=0",
        "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2000",
    );
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS507", Warning, line_of(&t, "UploadFile=speed.bin"))]
    );
}

#[test]
fn eds508_parameter_value_on_a_read_only_entry() {
    let t = dcf(&(var(0x2000, "Version", 7, "ro", "1", false) + "ParameterValue=2\n"));
    let t = edit(
        &t,
        "[ManufacturerObjects]\nSupportedObjects=0",
        "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2000",
    );
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS508", Warning, line_of(&t, "ParameterValue=2"))]
    );
}

#[test]
fn eds509_connected_module_not_supported() {
    let body = "\n[SupportedModules]\nNrOfEntries=2\n\n[ConnectedModules]\nNrOfEntries=1\n1=3\n";
    let t = dcf(body);
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS509", Warning, line_of(&t, "1=3"))]
    );
}

#[test]
fn eds510_comments_lines_mismatch() {
    let t = eds(&[], &[], "\n[Comments]\nLines=2\nLine1=only one\n");
    assert_eq!(
        diags(&t),
        vec![d("EDS510", Warning, line_of(&t, "Lines=2"))]
    );
}

#[test]
fn eds511_object_link_to_a_missing_object() {
    let body = var(0x2000, "Speed", 6, "rw", "0", false)
        + "\n[2000ObjectLinks]\nObjectLinks=1\n1=0x2100\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![d("EDS511", Warning, line_of(&t, "[2000]"))]);
}

#[test]
fn eds512_dynamic_channels_segment_count() {
    let body = "\n[DynamicChannels]\nNrOfSeg=2\nType1=0x0007\nDir1=rww\nRange1=0xA000-0xA0FF\nPPOffset1=0\n";
    let t = edit(
        &eds(&[], &[], body),
        "DynamicChannelsSupported=0",
        "DynamicChannelsSupported=1",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS512", Warning, line_of(&t, "NrOfSeg=2"))]
    );
}

#[test]
fn eds512_malformed_segment_keys_say_why() {
    let body =
        "\n[DynamicChannels]\nNrOfSeg=1\nType1=0x0000\nDir1=RX\nRange1=0xA000\nPPOffset1=0\n";
    let t = edit(
        &eds(&[], &[], body),
        "DynamicChannelsSupported=0",
        "DynamicChannelsSupported=1",
    );
    assert_eq!(
        diags(&t),
        vec![
            d("EDS512", Warning, line_of(&t, "Type1=0x0000")),
            d("EDS512", Warning, line_of(&t, "Dir1=RX")),
            d("EDS512", Warning, line_of(&t, "Range1=0xA000")),
        ]
    );
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    let messages: Vec<String> = validate::validate(&read.device)
        .into_iter()
        .map(|d| d.message)
        .collect();
    assert_eq!(
        messages,
        vec![
            "[DynamicChannels] Type1=`0x0000` is not a CiA 301 basic data type index",
            "[DynamicChannels] Dir1=`RX` is not an access type",
            "[DynamicChannels] Range1=`0xA000` is not an index range `0xLLLL-0xHHHH`",
        ]
    );
}

#[test]
fn eds513_object_inside_a_dynamic_channel_range() {
    let body = "\n[DynamicChannels]\nNrOfSeg=1\nType1=0x0007\nDir1=rww\nRange1=0xA000-0xA0FF\nPPOffset1=0\n".to_owned()
        + &var(0xA000, "Net var", 7, "rww", "0", true);
    let t = edit(
        &eds(&[0xA000], &[], &body),
        "DynamicChannelsSupported=0",
        "DynamicChannelsSupported=1",
    );
    assert_eq!(
        diags(&t),
        vec![d("EDS513", Info, line_of(&t, "Range1=0xA000-0xA0FF"))]
    );
}

#[test]
fn eds316_hex_limit_on_a_signed_type_is_a_warning() {
    // 0x81 on INTEGER8 reads as -127, above -128 only because of two's complement.
    let body = var(0x2000, "Mode", 2, "rw", "-128", false) + "LowLimit=0x81\nHighLimit=-128\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS316", Warning, line_of(&t, "LowLimit=0x81"))]
    );
}

#[test]
fn eds316_narrow_hex_pattern_on_a_wider_signed_type_is_a_warning() {
    let body = var(0x2000, "Offset", 4, "rw", "0", false) + "LowLimit=0xEC78\nHighLimit=0x1388\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS316", Warning, line_of(&t, "LowLimit=0xEC78"))]
    );
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    assert_eq!(
        validate::validate(&read.device)[0].help.as_deref(),
        Some(
            "`0xEC78` is 60536 in INTEGER32, though as a 16-bit two's complement it would be \
             -5000; write the limits in decimal"
        )
    );
}

#[test]
fn eds316_hex_limits_inverted_under_any_reading_are_an_error() {
    let body = var(0x2000, "Mode", 2, "rw", "0", false) + "LowLimit=0x7F\nHighLimit=100\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(
        diags(&t),
        vec![d("EDS316", Error, line_of(&t, "LowLimit=0x7F"))]
    );
}

#[test]
fn eds316_hex_high_limit_inverted_by_twos_complement_is_dropped_by_the_reader() {
    // 0xFF on INTEGER8 reads as -1, below LowLimit 0: the reader drops that HighLimit (EDS013
    // warning), so nothing is inverted here.
    let body = var(0x2000, "Mode", 2, "rw", "0", false) + "LowLimit=0x00\nHighLimit=0xFF\n";
    let t = eds(&[], &[0x2000], &body);
    assert_eq!(diags(&t), vec![]);
    let read = read::read_bytes(Path::new("t.eds"), t.as_bytes());
    assert_eq!(
        read.device
            .entry(0x2000, 0)
            .unwrap()
            .high_limit
            .as_ref()
            .unwrap()
            .value,
        None
    );
}

#[test]
fn eds317_dcf_checks_nodeid_values_at_its_node_id() {
    let body = var(0x2000, "Id", 7, "rw", "$NODEID+0x10", false)
        + "ParameterValue=0x15\nLowLimit=$NODEID+0x10\nHighLimit=$NODEID+0x20\n";
    let t = edit(
        &dcf(&body),
        "[ManufacturerObjects]\nSupportedObjects=0",
        "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2000",
    );
    assert_eq!(diags_for("t.dcf", &t), vec![]);
    let t = edit(&t, "ParameterValue=0x15", "ParameterValue=0x14");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS317", Warning, line_of(&t, "ParameterValue=0x14"))]
    );
}

#[test]
fn eds320_not_checked_for_a_master() {
    let t = eds(
        &[0x1014],
        &[],
        &var(0x1014, "COB-ID EMCY", 7, "rw", "0x81", false),
    );
    let t = edit(&t, "SimpleBootUpMaster=0", "SimpleBootUpMaster=1");
    assert_eq!(diags(&t), vec![]);
}

#[test]
fn eds408_empty_entries_within_the_count_are_one_warning() {
    let t = one_rpdo(&["0", "0"]);
    let line = line_of(&t, "[1600sub1]") + 5;
    assert_eq!(diags(&t), vec![d("EDS408", Warning, line)]);
}

#[test]
fn eds501_node_id_255_is_a_warning() {
    let t = edit(&dcf(""), "NodeID=5", "NodeID=255");
    assert_eq!(
        diags_for("t.dcf", &t),
        vec![d("EDS501", Warning, line_of(&t, "NodeID=255"))]
    );
}

#[test]
fn eds321_reserved_obj_flags_are_one_warning_per_file() {
    let body = var(0x2000, "Speed", 6, "rw", "0", false)
        + "ObjFlags=0x4\n"
        + &var(0x2001, "Torque", 6, "rw", "0", false)
        + "ObjFlags=0x10000\n";
    let t = eds(&[], &[0x2000, 0x2001], &body);
    assert_eq!(diags(&t), vec![d("EDS321", Warning, line_of(&t, "[2000]"))]);
}

// ---- the rule table ----

#[test]
fn every_validator_rule_has_a_test_here() {
    let source = include_str!("rules.rs");
    for rule in rules::ALL {
        let n: u32 = rule.code[3..].parse().unwrap();
        if (100..600).contains(&n) {
            let name = format!("fn eds{n}_");
            assert!(source.contains(&name), "no test for {}", rule.code);
        }
    }
}

#[test]
fn rules_doc_is_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/rules.md");
    let want = rules::markdown();
    if std::env::var_os("EDSGEN_UPDATE_DOCS").is_some() {
        std::fs::write(path, &want).unwrap();
    }
    let have = std::fs::read_to_string(path).unwrap_or_default();
    assert!(have == want, "docs/rules.md is stale: run `EDSGEN_UPDATE_DOCS=1 cargo test -p edsgen-codegen --test rules rules_doc_is_current`");
}

// ---- robustness ----

mod no_panic {
    use super::*;
    use proptest::prelude::*;

    /// Lines that stress the validator: odd numbers, `$NODEID`, PDO entries, list entries.
    fn line() -> impl Strategy<Value = String> {
        let sections = prop::sample::select(vec![
            "[1000]",
            "[1018]",
            "[1018sub0]",
            "[1400]",
            "[1400sub1]",
            "[1600]",
            "[1600sub0]",
            "[1600sub1]",
            "[1A00]",
            "[1A00sub1]",
            "[1800sub2]",
            "[2000]",
            "[2000sub0]",
            "[2000subFF]",
            "[MandatoryObjects]",
            "[OptionalObjects]",
            "[DeviceInfo]",
            "[DeviceComissioning]",
            "[DynamicChannels]",
            "[ConnectedModules]",
            "[M1SubExt2000]",
            "[Comments]",
            "[2000ObjectLinks]",
            "[FileInfo]",
            "[DummyUsage]",
        ]);
        let keys = prop::sample::select(vec![
            "ParameterName",
            "ObjectType",
            "DataType",
            "AccessType",
            "DefaultValue",
            "PDOMapping",
            "SubNumber",
            "CompactSubObj",
            "LowLimit",
            "HighLimit",
            "ObjFlags",
            "ParameterValue",
            "SupportedObjects",
            "1",
            "2",
            "NrOfRXPDO",
            "Granularity",
            "NodeID",
            "Baudrate",
            "Lines",
            "NrOfSeg",
            "Range1",
            "Type1",
            "Count",
            "NrOfEntries",
            "ObjectLinks",
            "Dummy0010",
            "LSS_SerialNumber",
            "CompactPDO",
            "EDSVersion",
            "CreationDate",
        ]);
        let values = prop::sample::select(vec![
            "0",
            "1",
            "0x7",
            "0x9",
            "0x8",
            "0xFF",
            "255",
            "256",
            "-1",
            "0x80000000",
            "$NODEID+0x180",
            "$NODEID+0x7FFFFFFF",
            "0x20000010",
            "0x00010008",
            "0xFFFFFFFF",
            "rw",
            "ro",
            "wo",
            "rww",
            "0xA000-0xA0FF",
            "0;2",
            "x",
            "",
            "0x1018",
            "1.5",
            "99999999999999999999999",
        ]);
        prop_oneof![
            sections.prop_map(str::to_owned),
            (keys, values).prop_map(|(k, v)| format!("{k}={v}")),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        #[test]
        fn validator_never_panics(lines in prop::collection::vec(line(), 0..80), dcf in any::<bool>()) {
            let text = lines.join("\n");
            let path = if dcf { "p.dcf" } else { "p.eds" };
            let read = read::read_bytes(Path::new(path), text.as_bytes());
            let diags = validate::validate(&read.device);
            let rendered = edsgen_model::render::human(path, &read.text, &diags, false);
            prop_assert_eq!(diags.is_empty(), rendered.is_empty());
        }
    }
}

#[test]
fn eds408_a_missing_object_is_one_error_per_mapping_that_names_it() {
    let t = one_rpdo(&["0x20050010", "0x20050110", "0x20060008"]);
    let found = diags(&t);
    assert_eq!(
        found,
        vec![
            d("EDS408", Error, line_of(&t, "DefaultValue=0x20050010")),
            d("EDS408", Error, line_of(&t, "DefaultValue=0x20060008")),
        ]
    );
    let read = edsgen_model::read::read_bytes(std::path::Path::new("t.eds"), t.as_bytes());
    let messages: Vec<String> = edsgen_model::validate::validate(&read.device)
        .into_iter()
        .map(|d| d.message)
        .collect();
    assert_eq!(
        messages,
        [
            "1600h sub 1, 2 map 2005h sub 0, 1, which do not exist",
            "1600h sub 3 maps 2006h sub 0, which does not exist",
        ]
    );
}

#[test]
fn eds317_values_outside_their_limits_fold_into_one_finding_naming_the_lines() {
    let body = [0x2000u16, 0x2001, 0x2002]
        .iter()
        .map(|&i| {
            var(i, "Speed", 6, "rw", "9", true).replace("PDOMapping=1", "PDOMapping=1\nHighLimit=5")
        })
        .collect::<String>();
    let t = eds(&[], &[0x2000, 0x2001, 0x2002], &body);
    let read = edsgen_model::read::read_bytes(std::path::Path::new("t.eds"), t.as_bytes());
    let found = edsgen_model::validate::validate(&read.device);
    assert_eq!(found.len(), 1, "{found:?}");
    let lines: Vec<usize> = t
        .lines()
        .enumerate()
        .filter(|(_, l)| *l == "DefaultValue=9")
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(
        found[0].message,
        format!(
            "DefaultValue 9 of 2000h is above HighLimit 5; likewise on 2 more line(s): {}, {}",
            lines[1], lines[2]
        )
    );
}

#[test]
fn eds310_advice_names_the_key_that_holds_the_value_and_refuse_read_on_scan_is_respected() {
    let body = |flags: &str| {
        record(0x2000, "Rec", 9, 2)
            + &sub(0x2000, 0, "Count", 5, "ro", "1", false).replace(
                "DefaultValue=1",
                &format!("DefaultValue=1\nParameterValue=0{flags}"),
            )
            + &sub(0x2000, 1, "A", 6, "rw", "0", false)
    };
    let t = edsgen_model::read::read_bytes(
        Path::new("t.dcf"),
        dcf(&body(""))
            .replace(
                "[ManufacturerObjects]\nSupportedObjects=0",
                "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2000",
            )
            .as_bytes(),
    );
    let found: Vec<_> = validate::validate(&t.device)
        .into_iter()
        .filter(|d| d.code() == "EDS310" || d.code() == "EDS508")
        .map(|d| (d.code(), d.help.unwrap_or_default()))
        .collect();
    let read_only = "a configuration tool cannot write ro/const entries; drop these values or make the entries writable";
    assert_eq!(
        found,
        [
            ("EDS310", "set ParameterValue=1".to_owned()),
            ("EDS508", read_only.to_owned())
        ]
    );
    // ObjFlags bit 1: the tool did not read the entry back; the default (1) is the value.
    let t = edsgen_model::read::read_bytes(
        Path::new("t.dcf"),
        dcf(&body("\nObjFlags=2"))
            .replace(
                "[ManufacturerObjects]\nSupportedObjects=0",
                "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2000",
            )
            .as_bytes(),
    );
    let found: Vec<_> = validate::validate(&t.device)
        .into_iter()
        .filter(|d| d.code() == "EDS310" || d.code() == "EDS508")
        .collect();
    assert_eq!(found, vec![]);
}
