//! Emitter tests on hand-built models (independent of the readers): the checked-in generated
//! module is current and deterministic, and every EDS7xx diagnostic fires where it should.

mod emit_support;

use edsgen_codegen::emit;
use edsgen_model::diag::Severity;
use edsgen_model::model::{AccessType, ObjectType, Value};
use emit_support::*;

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/generated/gd350.rs");

/// The module `emit_runtime.rs` compiles and exercises is exactly what the emitter produces now.
/// Regenerate with `EDSGEN_BLESS=1`.
#[test]
fn checked_in_module_is_current() {
    let generated = emit::generate_module(&goodrive_like(), "gd350").expect("generates");
    if std::env::var_os("EDSGEN_BLESS").is_some() {
        std::fs::write(FIXTURE, &generated.code).unwrap();
    }
    let on_disk = std::fs::read_to_string(FIXTURE).unwrap();
    assert!(
        on_disk == generated.code,
        "tests/generated/gd350.rs is stale; run with EDSGEN_BLESS=1"
    );
    let codes: Vec<_> = generated
        .diagnostics
        .iter()
        .map(|d| (d.code(), d.severity, d.message.clone()))
        .collect();
    assert_eq!(
        codes,
        vec![
            (
                "EDS701",
                Severity::Info,
                "the constant name `STANDARD_ERROR_FIELD` is already used; this one is `STANDARD_ERROR_FIELD_SUB2`".to_owned()
            ),
            (
                "EDS701",
                Severity::Info,
                "the constant name `STATUS_WORD` is already used; this one is `STATUS_WORD_6041`".to_owned()
            ),
        ]
    );
}

#[test]
fn generation_is_deterministic() {
    let a = emit::generate(&goodrive_like(), "gd350").unwrap();
    let b = emit::generate(&goodrive_like(), "gd350").unwrap();
    assert_eq!(a, b);
}

#[test]
fn module_names_are_snake_case_identifiers() {
    assert_eq!(emit::module_name("CP301"), "cp301");
    assert_eq!(emit::module_name("Gen4 drive"), "gen4_drive");
    assert_eq!(emit::module_name("1st"), "n_1st");
    assert_eq!(emit::module_name("mod"), "mod_");
    let code = emit::generate(&goodrive_like(), "My Card").unwrap();
    assert!(code.contains("\npub mod my_card {\n"));
}

#[test]
fn unknown_data_type_is_eds702() {
    let device = device(vec![var(
        0x2000,
        "Mystery",
        0x0123,
        AccessType::Rw,
        Some(Value::Integer(1)),
        false,
    )]);
    let diags = emit::generate_module(&device, "x").unwrap_err();
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code(), "EDS702");
    assert_eq!(diags[0].severity, Severity::Error);
    assert_eq!(
        diags[0].message,
        "2000h sub 0 `Mystery`: data type 0123h is not a basic type; no Rust type can hold it"
    );
    let text = emit::generate(&device, "x").unwrap_err();
    assert_eq!(
        text,
        "line 1: error[EDS702]: 2000h sub 0 `Mystery`: data type 0123h is not a basic type; no Rust type can hold it"
    );
}

#[test]
fn default_out_of_range_is_eds703() {
    let device = device(vec![
        var(
            0x2000,
            "Small",
            0x05,
            AccessType::Rw,
            Some(Value::Integer(300)),
            false,
        ),
        var(
            0x2001,
            "Flag",
            0x01,
            AccessType::Rw,
            Some(Value::Real(0.5)),
            false,
        ),
        var(
            0x2002,
            "Text node",
            0x09,
            AccessType::Rw,
            Some(Value::NodeRelative(1)),
            false,
        ),
    ]);
    let diags = emit::generate_module(&device, "x").unwrap_err();
    let messages: Vec<_> = diags
        .iter()
        .map(|d| (d.code(), d.message.as_str()))
        .collect();
    assert_eq!(
        messages,
        vec![
            (
                "EDS703",
                "2000h sub 0 `Small`: `300` is outside the range of UNSIGNED8"
            ),
            (
                "EDS703",
                "2001h sub 0 `Flag`: `0.5` is not a value of BOOLEAN"
            ),
            (
                "EDS703",
                "2002h sub 0 `Text node`: `$NODEID+1` is not a value of VISIBLE_STRING"
            ),
        ]
    );
}

/// The default value image of generated code: its `DEFAULTS` runs unpacked over `IMAGE_SIZE`
/// zeros, as `Od::new(0)` does (`$NODEID` defaults at their offset).
fn default_image(code: &str) -> Vec<u8> {
    let number_after = |key: &str| {
        let start = code
            .find(key)
            .unwrap_or_else(|| panic!("no `{key}` in {code}"))
            + key.len();
        let digits: String = code[start..]
            .chars()
            .take_while(char::is_ascii_digit)
            .collect();
        digits.parse::<usize>().unwrap()
    };
    let size = number_after("const IMAGE_SIZE: usize = ");
    let start = code.find("const DEFAULTS: [u8; ").unwrap();
    let list = &code[start..];
    let list = &list[list.find("= [").unwrap() + 3..list.find("];").unwrap()];
    let runs: Vec<u8> = list
        .split(',')
        .map(str::trim)
        .filter(|n| !n.is_empty())
        .map(|n| n.parse().unwrap())
        .collect();
    let mut image = vec![0; size];
    edsgen_runtime::od::image::unpack_defaults(&mut image, &runs, 0);
    image
}

#[test]
fn signed_hex_default_is_read_as_twos_complement() {
    let device = device(vec![var(
        0x2000,
        "Offset",
        0x03,
        AccessType::Rw,
        Some(Value::Integer(0xFFFF)),
        false,
    )]);
    let code = emit::generate(&device, "x").unwrap();
    assert_eq!(default_image(&code), [0xFF, 0xFF]);
}

#[test]
fn missing_default_is_eds705_and_zero() {
    let device = device(vec![
        var(0x2000, "Speed", 0x04, AccessType::Rw, None, false),
        var(0x2001, "Name", 0x09, AccessType::Ro, None, false),
    ]);
    let generated = emit::generate_module(&device, "x").unwrap();
    assert_eq!(generated.diagnostics.len(), 2);
    assert!(generated
        .diagnostics
        .iter()
        .all(|d| d.code() == "EDS705" && d.severity == Severity::Info));
    // 4 bytes of INTEGER32 and an empty string's length, all zero.
    assert!(generated.code.contains("const IMAGE_SIZE: usize = 6;"));
    assert!(
        generated.code.contains("const DEFAULTS: [u8; 0] = [];"),
        "{}",
        generated.code
    );
    assert_eq!(default_image(&generated.code), [0; 6]);
    assert!(generated
        .code
        .contains("pub const NAME: Entry<FixedBytes<0>, super::Od, ReadOnly> = Entry::new("));
}

#[test]
fn skipped_infos_leave_the_code_and_every_other_diagnostic() {
    let device = device(vec![
        var(0x2000, "Speed", 0x04, AccessType::Rw, None, false),
        var(0x2001, "Name", 0x09, AccessType::Ro, None, false),
    ]);
    let reported = emit::generate_module(&device, "x").unwrap();
    let skipped = emit::generate_module_reporting(&device, "x", emit::Infos::Skipped).unwrap();
    assert_eq!(reported.diagnostics.len(), 2);
    assert!(skipped.diagnostics.is_empty());
    assert_eq!(skipped.code, reported.code);
}

#[test]
fn untypeable_pdo_mapping_is_eds704_and_skipped() {
    let mut mapping = object(
        0x1A00,
        "TPDO1 mapping",
        ObjectType::Record,
        vec![
            sub(
                0,
                "Count",
                0x05,
                AccessType::Rw,
                Some(Value::Integer(2)),
                false,
            ),
            sub(
                1,
                "Map 1",
                0x07,
                AccessType::Rw,
                Some(Value::Integer(0x2000_0010)),
                false,
            ),
            sub(
                2,
                "Map 2",
                0x07,
                AccessType::Rw,
                Some(Value::Integer(0x3000_0008)),
                false,
            ),
        ],
    );
    mapping.span = edsgen_model::model::Span::new(40, 1, 6);
    let device = device(vec![
        mapping,
        var(
            0x2000,
            "Speed",
            0x06,
            AccessType::Ro,
            Some(Value::Integer(0)),
            true,
        ),
        var(
            0x2001,
            "Wide",
            0x06,
            AccessType::Ro,
            Some(Value::Integer(0)),
            true,
        ),
    ]);
    let generated = emit::generate_module(&device, "x").unwrap();
    let warnings: Vec<_> = generated
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Warning)
        .map(|d| (d.code(), d.span.map(|s| s.line), d.message.as_str()))
        .collect();
    assert_eq!(
        warnings,
        vec![(
            "EDS704",
            Some(40),
            "TPDO 1 (1A00h): mapping sub-index 2 points to 3000h sub 0, which is not in the dictionary"
        )]
    );
    assert!(!generated.code.contains("pub mod pdo"));
}

#[test]
fn overlong_mapping_of_a_narrow_type_is_eds704() {
    let device = device(vec![
        object(
            0x1600,
            "RPDO1 mapping",
            ObjectType::Record,
            vec![
                sub(
                    0,
                    "Count",
                    0x05,
                    AccessType::Rw,
                    Some(Value::Integer(1)),
                    false,
                ),
                sub(
                    1,
                    "Map 1",
                    0x07,
                    AccessType::Rw,
                    Some(Value::Integer(0x2000_0020)),
                    false,
                ),
            ],
        ),
        var(
            0x2000,
            "Speed",
            0x06,
            AccessType::Rw,
            Some(Value::Integer(0)),
            true,
        ),
    ]);
    let generated = emit::generate_module(&device, "x").unwrap();
    assert_eq!(generated.diagnostics.len(), 1);
    assert_eq!(
        generated.diagnostics[0].message,
        "RPDO 1 (1600h): 2000h sub 0 is mapped with 32 bits, more than its 16 bits"
    );
}

#[test]
fn unusable_limit_is_eds706() {
    let mut o = var(
        0x2000,
        "Speed",
        0x06,
        AccessType::Rw,
        Some(Value::Integer(0)),
        false,
    );
    if let Some(s) = o.subs.get_mut(&0) {
        s.high_limit = Some(value(Value::NodeRelative(5), "$NODEID+5"));
    }
    let generated = emit::generate_module(&device(vec![o]), "x").unwrap();
    assert_eq!(generated.diagnostics.len(), 1);
    assert_eq!(generated.diagnostics[0].code(), "EDS706");
    assert_eq!(
        generated.diagnostics[0].message,
        "2000h sub 0 `Speed`: the HighLimit `$NODEID+5` is not a constant UNSIGNED16; writes are not checked against it"
    );
}

#[test]
fn parameter_value_overrides_default() {
    let mut o = var(
        0x2000,
        "Speed",
        0x06,
        AccessType::Rw,
        Some(Value::Integer(7)),
        false,
    );
    if let Some(s) = o.subs.get_mut(&0) {
        s.parameter_value = Some(value(Value::Integer(1234), "1234"));
    }
    let code = emit::generate(&device(vec![o]), "x").unwrap();
    assert_eq!(default_image(&code), 1234u16.to_le_bytes());
}

#[test]
fn digit_and_symbol_names_are_escaped() {
    let device = device(vec![
        var(
            0x2000,
            "type",
            0x05,
            AccessType::Rw,
            Some(Value::Integer(0)),
            false,
        ),
        var(
            0x2001,
            "1st gear",
            0x05,
            AccessType::Rw,
            Some(Value::Integer(0)),
            false,
        ),
        var(
            0x2002,
            "°",
            0x05,
            AccessType::Rw,
            Some(Value::Integer(0)),
            false,
        ),
    ]);
    let code = emit::generate(&device, "x").unwrap();
    for needle in [
        "pub const TYPE: Entry<u8, super::Od>",
        "pub const N_1ST_GEAR: Entry<u8, super::Od>",
        "pub const OBJECT_2002: Entry<u8, super::Od>",
    ] {
        assert!(code.contains(needle), "missing {needle}");
    }
}

#[test]
fn time_of_day_days_and_milliseconds() {
    // Lely writes TIME_OF_DAY as "<days> <ms>": ms in bits 0-27, days in bits 32-47.
    let device = device(vec![var(
        0x2000,
        "Stamp",
        0x0C,
        AccessType::Rw,
        Some(Value::Text("365 43200000".into())),
        false,
    )]);
    let code = emit::generate(&device, "x").unwrap();
    assert_eq!(default_image(&code), 0x16D_0293_2E00u64.to_le_bytes()[..6]);
    assert!(code
        .contains("pub const STAMP: Entry<u64, super::Od> = Entry::with_width(0x2000, 0x00, 6)"));
}

#[test]
fn colliding_constant_names_take_the_index() {
    let rec = |index: u16| {
        object(
            index,
            "Remote mapping",
            ObjectType::Record,
            vec![sub(
                0,
                "Count",
                0x05,
                AccessType::Ro,
                Some(Value::Integer(0)),
                false,
            )],
        )
    };
    let code = emit::generate(&device(vec![rec(0x5E11), rec(0x5E12)]), "x").unwrap();
    // Another object holds the module's name: the index tells them apart.
    assert_eq!(
        addresses(&code),
        ["remote_mapping::COUNT", "remote_mapping_5e12::COUNT"]
    );
    assert!(
        code.contains("pub const COUNT: Entry<u8, super::super::Od, ReadOnly>"),
        "{code}"
    );
    // The same object: the sub-index does.
    let twice = object(
        0x5E20,
        "Pair",
        ObjectType::Record,
        vec![
            sub(
                0,
                "Count",
                0x05,
                AccessType::Ro,
                Some(Value::Integer(2)),
                false,
            ),
            sub(
                1,
                "Value",
                0x05,
                AccessType::Rw,
                Some(Value::Integer(0)),
                false,
            ),
            sub(
                2,
                "Value",
                0x05,
                AccessType::Rw,
                Some(Value::Integer(0)),
                false,
            ),
        ],
    );
    let code = emit::generate(&device(vec![twice]), "x").unwrap();
    assert_eq!(
        addresses(&code),
        ["pair::COUNT", "pair::VALUE", "pair::VALUE_SUB2"]
    );
}

#[test]
fn time_of_day_as_a_48_bit_integer() {
    let device = device(vec![var(
        0x2000,
        "Stamp",
        0x0D,
        AccessType::Rw,
        Some(Value::Integer(1_567_706_263_040)),
        false,
    )]);
    let code = emit::generate(&device, "x").unwrap();
    assert_eq!(default_image(&code), 0x16D_0293_2E00u64.to_le_bytes()[..6]);
    let too_big = device_with(0x0C, Value::Integer(1 << 48));
    assert_eq!(
        emit::generate_module(&too_big, "x").unwrap_err()[0].code(),
        "EDS703"
    );
}

fn device_with(data_type: u16, default: Value) -> edsgen_model::model::Device {
    device(vec![var(
        0x2000,
        "Stamp",
        data_type,
        AccessType::Rw,
        Some(default),
        false,
    )])
}

#[test]
fn string_longer_than_an_entry_can_hold_is_eds707() {
    let device = device_with(0x0009, Value::Text("x".repeat(70_000)));
    let diags = emit::generate_module(&device, "x").unwrap_err();
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code(), "EDS707");
    assert_eq!(diags[0].severity, Severity::Error);
    assert_eq!(
        diags[0].message,
        "2000h sub 0 `Stamp`: needs 70000 bytes; an entry holds at most 65535"
    );
}

#[test]
fn values_needing_more_than_65535_bytes_in_all_are_eds707() {
    // Two domains of 40,000 bytes each: each fits an entry, together they do not fit the image.
    let domain = |index: u16| {
        let mut o = var(index, "Blob", 0x0F, AccessType::Rw, None, false);
        if let Some(s) = o.subs.get_mut(&0) {
            s.capacity = Some(40_000);
        }
        o
    };
    let diags =
        emit::generate_module(&device(vec![domain(0x2000), domain(0x2001)]), "x").unwrap_err();
    let errors: Vec<_> = diags
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| (d.code(), d.message.as_str()))
        .collect();
    assert_eq!(
        errors,
        vec![(
            "EDS707",
            "2001h `Blob`: with this object the device's values need more than 65535 bytes in all"
        )]
    );
    assert!(emit::generate_module(&device(vec![domain(0x2000)]), "x").is_ok());
}

#[test]
fn cob_id_is_the_can_identifier_and_to_bytes_is_fallible_only_for_narrow_fields() {
    let speed = var(
        0x2000,
        "Speed",
        0x06,
        AccessType::Rw,
        Some(Value::Integer(0)),
        true,
    );
    let wide = var(
        0x2001,
        "Wide",
        0x10,
        AccessType::Rw,
        Some(Value::Integer(0)),
        true,
    );
    let dev = device(vec![
        comm(0x1400, "RPDO1 communication", Value::Integer(0x8000_0201)),
        comm(
            0x1401,
            "RPDO2 communication",
            Value::NodeRelative(0x2000_0300),
        ),
        comm(0x1402, "RPDO3 communication", Value::NodeRelative(0x400)),
        mapping(0x1600, "RPDO1 mapping", &[0x2000_0010]),
        mapping(0x1601, "RPDO2 mapping", &[0x2000_0010]),
        mapping(0x1602, "RPDO3 mapping", &[0x2001_0018]),
        speed,
        wide,
    ]);
    let code = emit::generate(&dev, "x").unwrap();
    let squeezed: String = code.split_whitespace().collect::<Vec<_>>().join(" ");
    // A fixed COB-ID: the CAN identifier without bit 31 (and the doc says it is disabled).
    assert!(
        squeezed.contains("Bit 31 is set: the PDO is disabled until a configuration tool enables it. pub const fn cob_id(_node_id: u8) -> u16 { 0x201 }"),
        "{code}"
    );
    // Bit 29: a 29-bit identifier, as u32.
    assert!(
        squeezed.contains(
            "pub const fn cob_id(node_id: u8) -> u32 { (node_id as u32).wrapping_add(0x300) }"
        ),
        "{code}"
    );
    // 16 bits in 16: nothing can overflow; an INTEGER24 in an i32 can.
    assert!(
        squeezed.contains("pub fn to_bytes(self) -> [u8; 2] {"),
        "{code}"
    );
    assert!(
        squeezed.contains("pub fn to_bytes(self) -> Result<[u8; 3], ::edsgen_runtime::PdoError> {"),
        "{code}"
    );
}

#[test]
fn a_sub_object_does_not_repeat_its_object_name_and_acronyms_survive() {
    let sub_named = |s: u8, name: &str| {
        sub(
            s,
            name,
            0x07,
            AccessType::Rw,
            Some(Value::Integer(0)),
            false,
        )
    };
    let heartbeat = object(
        0x1016,
        "Consumer heartbeat time",
        ObjectType::Array,
        vec![
            sub(
                0,
                "Number of entries",
                0x05,
                AccessType::Ro,
                Some(Value::Integer(2)),
                false,
            ),
            sub_named(1, "Consumer heartbeat time 1"),
            sub_named(2, "Consumer heartbeat time"),
        ],
    );
    let speed = object(
        0x2000,
        "CANopen speed",
        ObjectType::Record,
        vec![
            sub(
                0,
                "Highest sub-index",
                0x05,
                AccessType::Ro,
                Some(Value::Integer(1)),
                false,
            ),
            sub_named(1, "CANopen speedometer"),
        ],
    );
    let code = emit::generate(&device(vec![heartbeat, speed]), "x").unwrap();
    // The module names the object; a member adds what its name adds (a number alone follows
    // the object's last word), and a whole word of the object's name is not cut off a longer one.
    assert_eq!(
        addresses(&code),
        [
            "consumer_heartbeat_time::NUMBER_OF_ENTRIES",
            "consumer_heartbeat_time::TIME_1",
            "consumer_heartbeat_time::SUB2",
            "canopen_speed::HIGHEST_SUB_INDEX",
            "canopen_speed::CANOPEN_SPEEDOMETER",
        ]
    );
}

#[test]
fn addresses_carry_the_access_rights_of_their_entries() {
    let device = device(vec![
        var(0x2000, "Speed", 0x04, AccessType::Rw, None, false),
        var(0x2001, "Status", 0x06, AccessType::Ro, None, false),
        var(0x2002, "Limit", 0x06, AccessType::Const, None, false),
        var(0x2003, "Command", 0x05, AccessType::Wo, None, false),
        var(0x2004, "Setpoint", 0x06, AccessType::Rww, None, false),
    ]);
    let code = emit::generate(&device, "x").unwrap();
    let start = code.find("    pub mod od {").unwrap();
    let end = start + code[start..].find("\n    }\n").unwrap();
    let od = &code[start..end];
    assert_eq!(
        od,
        "    pub mod od {
        use ::edsgen_runtime::Entry;
        use ::edsgen_runtime::od::access::{Const, ReadOnly, WriteOnly};
        /// Speed (2000h sub 0: INTEGER32, rw, not PDO-mappable).
        pub const SPEED: Entry<i32, super::Od> = Entry::new(0x2000, 0x00)
            .at_position(0)
            .in_dictionary();
        /// Status (2001h sub 0: UNSIGNED16, ro, not PDO-mappable).
        pub const STATUS: Entry<u16, super::Od, ReadOnly> = Entry::new(0x2001, 0x00)
            .read_only()
            .at_position(1)
            .in_dictionary();
        /// Limit (2002h sub 0: UNSIGNED16, const, not PDO-mappable).
        pub const LIMIT: Entry<u16, super::Od, Const> = Entry::new(0x2002, 0x00)
            .constant()
            .at_position(2)
            .in_dictionary();
        /// Command (2003h sub 0: UNSIGNED8, wo, not PDO-mappable).
        pub const COMMAND: Entry<u8, super::Od, WriteOnly> = Entry::new(0x2003, 0x00)
            .write_only()
            .at_position(3)
            .in_dictionary();
        /// Setpoint (2004h sub 0: UNSIGNED16, rww, not PDO-mappable).
        pub const SETPOINT: Entry<u16, super::Od> = Entry::new(0x2004, 0x00)
            .at_position(4)
            .in_dictionary();",
        "{code}"
    );
}
