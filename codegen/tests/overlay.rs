//! The overlay beside a description (`NAME.toml`): capacities applied to the model, and every
//! refusal (EDS708) with its exact line and message in the TOML text.

use std::path::Path;

use edsgen_codegen::diag::Severity;
use edsgen_codegen::{emit, overlay, read};

/// 2000h a writable VISIBLE_STRING, 2001h an UNSIGNED16, 2100h an ARRAY of two OCTET_STRINGs.
const EDS: &str = "\
[2000]
ParameterName=Label
ObjectType=0x7
DataType=0x0009
AccessType=rw
DefaultValue=drive

[2001]
ParameterName=Speed
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0

[2100]
ParameterName=Keys
ObjectType=0x8
SubNumber=3

[2100sub0]
ParameterName=Count
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2

[2100sub1]
ParameterName=Key1
ObjectType=0x7
DataType=0x000A
AccessType=rw

[2100sub2]
ParameterName=Key2
ObjectType=0x7
DataType=0x000A
AccessType=rw
";

fn device() -> edsgen_codegen::model::Device {
    read::read_bytes(Path::new("t.eds"), EDS.as_bytes()).device
}

/// (line, column, message) of each EDS708 error.
fn refusals(toml: &str) -> Vec<(u32, u32, String)> {
    let mut device = device();
    overlay::apply(toml, &mut device)
        .into_iter()
        .map(|d| {
            assert_eq!((d.code(), d.severity), ("EDS708", Severity::Error));
            let span = d.span.unwrap_or_else(|| panic!("no span: {}", d.message));
            (span.line, span.column, d.message)
        })
        .collect()
}

#[test]
fn capacities_are_set_on_the_named_entries() {
    let mut device = device();
    let diags = overlay::apply(
        "# capacities in bytes\n[capacity]\n2000 = 0x100\n\"2100sub1\" = 1_000\n",
        &mut device,
    );
    assert_eq!(diags, vec![]);
    assert_eq!(device.objects[&0x2000].subs[&0].capacity, Some(256));
    assert_eq!(device.objects[&0x2100].subs[&1].capacity, Some(1000));
    assert_eq!(device.objects[&0x2100].subs[&2].capacity, None);
    let code = emit::generate(&device, "t").unwrap();
    assert!(code.contains("pub label: ::edsgen_runtime::FixedBytes<256>,"));
    // The items of an array share one type: the largest capacity.
    assert!(code.contains("pub items: [::edsgen_runtime::FixedBytes<1000>; 2],"));
}

#[test]
fn bare_and_quoted_keys_in_any_case_name_the_same_entry() {
    let mut device = device();
    assert_eq!(
        overlay::apply("[capacity]\n2100SUB2 = 64\n", &mut device),
        vec![]
    );
    assert_eq!(device.objects[&0x2100].subs[&2].capacity, Some(64));
}

#[test]
fn not_toml_is_one_error_and_nothing_applies() {
    let mut device = device();
    let diags = overlay::apply("[capacity]\n2000 = = 4\n", &mut device);
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code(), "EDS708");
    assert_eq!(diags[0].span.map(|s| s.line), Some(2));
    assert!(diags[0].message.starts_with("the overlay is not TOML: "));
    assert_eq!(device.objects[&0x2000].subs[&0].capacity, None);
}

#[test]
fn unknown_table_is_refused() {
    assert_eq!(
        refusals("[capacity]\n2000 = 64\n\n[persistence]\n2000 = true\n"),
        vec![(4, 2, "unknown overlay table `persistence`".to_owned())]
    );
    assert_eq!(
        refusals("capacity = 5\n"),
        vec![(1, 1, "`capacity` must be a table: `[capacity]`".to_owned())]
    );
}

#[test]
fn keys_that_name_no_entry_are_refused() {
    assert_eq!(
        refusals("[capacity]\nlabel = 64\n3000 = 64\n12345 = 8\n"),
        vec![
            (2, 1, "`label` does not name an entry".to_owned()),
            (3, 1, "3000h sub 0 is not in the description".to_owned()),
            (4, 1, "`12345` does not name an entry".to_owned()),
        ]
    );
}

#[test]
fn capacity_on_a_number_or_out_of_range_is_refused() {
    assert_eq!(
        refusals("[capacity]\n2001 = 8\n2000 = 0\n2100sub1 = 70000\n2100sub2 = \"big\"\n"),
        vec![
            (
                2,
                1,
                "2001h sub 0 `Speed` is not a string, octet string or domain".to_owned()
            ),
            (
                3,
                8,
                "the capacity of `2000` must be a number of bytes in 1..=65535".to_owned()
            ),
            (
                4,
                12,
                "the capacity of `2100sub1` must be a number of bytes in 1..=65535".to_owned()
            ),
            (
                5,
                12,
                "the capacity of `2100sub2` must be a number of bytes in 1..=65535".to_owned()
            ),
        ]
    );
}

#[test]
fn capacity_below_the_default_is_refused() {
    assert_eq!(
        refusals("[capacity]\n2000 = 4\n"),
        vec![(
            2,
            8,
            "2000h sub 0 `Label` holds 5 bytes by default, more than the capacity 4".to_owned()
        )]
    );
}

#[test]
fn the_overlay_lives_beside_the_description() {
    assert_eq!(
        overlay::path_for(Path::new("eds/cp301.eds")),
        Path::new("eds/cp301.toml")
    );
}
