//! The overlay beside a description (`NAME.toml`): capacities applied to the model, and every
//! refusal (EDS708) with its exact line and message in the TOML text.

mod emit_support;

use std::path::Path;

use edsgen_codegen::emit;
use edsgen_model::diag::Severity;
use edsgen_model::{overlay, read};
use emit_support::addresses;

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

fn device() -> edsgen_model::model::Device {
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
    assert!(
        code.contains("pub const LABEL: Entry<FixedBytes<256>, super::Od>"),
        "{code}"
    );
    // Each array item is an entry of its own, with its own capacity.
    // Compared without whitespace and trailing commas: a longer type moves line breaks.
    let squeezed = code
        .split_whitespace()
        .collect::<String>()
        .replace(",)", ")");
    assert!(squeezed.contains("Entry<FixedBytes<1000>,super::super::Od>=Entry::new(0x2100,0x01)"));
    assert!(squeezed.contains("Entry<FixedBytes<32>,super::super::Od>=Entry::new(0x2100,0x02)"));
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

mod no_panic {
    use super::*;
    use proptest::prelude::*;

    /// Lines near the overlay's grammar: tables, entry keys, numbers, junk.
    fn line() -> impl Strategy<Value = String> {
        let keys = prop::sample::select(vec![
            "2000",
            "2001",
            "2100sub1",
            "2100SUB2",
            "2100sub",
            "sub1",
            "1F50sub1FF",
            "FFFFF",
            "",
            "\"2000\"",
            "capacity",
            "x.y",
        ]);
        let values = prop::sample::select(vec![
            "0",
            "1",
            "5",
            "65535",
            "65536",
            "-1",
            "0x10",
            "1_000",
            "\"7\"",
            "1.5",
            "true",
            "[1, 2]",
            "{ a = 1 }",
            "9223372036854775807",
            "",
        ]);
        prop_oneof![
            Just("[capacity]".to_owned()),
            Just("[other]".to_owned()),
            Just("[capacity.2000]".to_owned()),
            (keys, values).prop_map(|(k, v)| format!("{k} = {v}")),
            "[ -~]{0,24}",
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn any_overlay_text_gives_diagnostics_not_panics(lines in prop::collection::vec(line(), 0..12)) {
            let text = lines.join("\n");
            let mut device = device();
            for d in overlay::apply(&text, &mut device) {
                prop_assert_eq!(d.code(), "EDS708");
                let line = d.span.map_or(1, |s| s.line) as usize;
                prop_assert!(line >= 1 && line <= text.lines().count().max(1) + 1);
            }
            // Whatever was applied fits the entry: 2000h holds "drive" (5 bytes), 2100h's
            // strings have no default; 2001h is a number and 2100h sub 0 a count.
            for (index, object) in &device.objects {
                for (sub, entry) in &object.subs {
                    let Some(capacity) = entry.capacity else { continue };
                    let least = match (*index, *sub) {
                        (0x2000, 0) => 5,
                        (0x2100, 1 | 2) => 1,
                        other => return Err(TestCaseError::fail(format!("capacity on {other:?}"))),
                    };
                    prop_assert!((least..=65_535).contains(&capacity), "{}", capacity);
                }
            }
        }

        #[test]
        fn arbitrary_bytes_as_text_do_not_panic(text in "\\PC{0,200}") {
            let mut device = device();
            let _ = overlay::apply(&text, &mut device);
        }
    }
}

#[test]
fn names_and_numbering_rename_entries_and_errors_point_at_their_line() {
    let mut device = device();
    let diags = overlay::apply(
        "[names]\n2100 = \"Tags\"\n2000 = \"Device label\"\n[numbering]\n2100 = 0\n",
        &mut device,
    );
    assert_eq!(diags, vec![]);
    let code = emit::generate(&device, "t").unwrap();
    let names: Vec<String> = addresses(&code)
        .into_iter()
        .filter(|n| n.starts_with("tags") || n.starts_with("DEVICE_LABEL"))
        .collect();
    // The object's name names its module, and its numbered elements.
    assert_eq!(
        names,
        [
            "DEVICE_LABEL",
            "tags::COUNT",
            "tags::TAGS_0",
            "tags::TAGS_1"
        ]
    );

    let text = "[names]\n2999 = \"X\"\n2000 = 5\n[numbering]\n2000 = 0\n\"20-10\" = 1\n";
    let lines: Vec<(u32, String)> = overlay::apply(text, &mut device)
        .into_iter()
        .map(|d| (d.span.map_or(0, |s| s.line), d.message))
        .collect();
    assert_eq!(
        lines,
        [
            (
                2,
                "`2999` names no object or entry of the description".to_owned()
            ),
            (
                3,
                "the name of `2000` must be a string with a letter or digit in it".to_owned()
            ),
            (5, "`2000` holds no ARRAY of the description".to_owned()),
            (
                6,
                "`20-10` is not an index or a range of indices".to_owned()
            ),
        ]
    );
}

#[test]
fn a_device_without_default_pdos_says_so_and_the_overlay_declares_mappings() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/ms300.eds");
    let mut device = read::read_file(&path).unwrap().device;
    let plain = emit::generate_module(&device, "ms300").unwrap();
    assert!(!plain.code.contains("pub mod pdo"));
    let said: Vec<_> = edsgen_model::validate::validate(&device)
        .iter()
        .filter(|d| d.code() == "EDS709")
        .map(|d| (d.severity, d.message.clone()))
        .collect();
    assert_eq!(
        said,
        [(
            Severity::Info,
            "no PDO struct is generated: the mapping objects (1600h, 1601h, 1602h, 1603h, and 4 more) map no objects by default".to_owned()
        )]
    );

    let diags = overlay::apply(
        "[pdo_mapping]\n1600 = [\"6040\", \"6042\"]\n1A00 = [\"6041\", \"6043\"]\n",
        &mut device,
    );
    assert_eq!(diags, vec![]);
    let mapped = emit::generate_module(&device, "ms300").unwrap();
    let squeezed: String = mapped.code.split_whitespace().collect();
    assert!(squeezed.contains("pubstructRpdo1{"), "{}", mapped.code);
    assert!(squeezed.contains("pubstructTpdo1{"));
    assert!(!squeezed.contains("pubstructRpdo2{"));
    let validated = edsgen_model::validate::validate(&device);
    assert!(validated.iter().all(|d| d.code() != "EDS709"));
    // The mapping objects hold the declared mapping as their defaults.
    let default = |sub: u8| {
        device
            .entry(0x1600, sub)
            .unwrap()
            .default
            .as_ref()
            .unwrap()
            .value
            .clone()
    };
    assert_eq!(default(0), Some(edsgen_model::model::Value::Integer(2)));
    assert_eq!(
        default(1),
        Some(edsgen_model::model::Value::Integer(0x6040_0010))
    );

    let text = "[pdo_mapping]\n2000 = [\"6040\"]\n1601 = [\"2999\"]\n1602 = \"6040\"\n";
    let lines: Vec<(u32, String)> = overlay::apply(text, &mut device)
        .into_iter()
        .map(|d| (d.span.map_or(0, |s| s.line), d.message))
        .collect();
    assert_eq!(
        lines,
        [
            (
                2,
                "`2000` is not a PDO mapping object of the description (1600h-17FFh, 1A00h-1BFFh)"
                    .to_owned()
            ),
            (
                3,
                "`2999` is not an entry of the description with a fixed-size type".to_owned()
            ),
            (
                4,
                "the mapping of `1602` must be a list of entries: [\"6040\", \"2000sub1\"]"
                    .to_owned()
            ),
        ]
    );
}
