//! Hand-built device models for the emitter tests (independent of the readers), and the typed
//! addresses of generated code.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::PathBuf;

use edsgen_model::model::*;

pub fn value(v: Value, raw: &str) -> ValueSource {
    ValueSource {
        value: Some(v),
        raw: raw.to_owned(),
        span: Span::new(1, 1, 0),
    }
}

pub fn sub(
    index_sub: u8,
    name: &str,
    dt: u16,
    access: AccessType,
    default: Option<Value>,
    pdo: bool,
) -> SubObject {
    let raw = match &default {
        Some(Value::Integer(v)) => format!("{v}"),
        Some(Value::NodeRelative(o)) => format!("$NODEID+{o}"),
        Some(Value::Real(r)) => format!("{r}"),
        Some(Value::Text(t)) => t.clone(),
        Some(Value::Bytes(b)) => b.iter().map(|x| format!("{x:02x}")).collect(),
        None => String::new(),
    };
    SubObject {
        sub_index: index_sub,
        name: name.to_owned(),
        data_type: Some(dt),
        access: Some(access),
        pdo_mapping: pdo,
        default: default.map(|v| value(v, &raw)),
        parameter_value: None,
        low_limit: None,
        high_limit: None,
        obj_flags: 0,
        denotation: None,
        upload_file: None,
        download_file: None,
        span: Span::new(u32::from(index_sub) + 1, 1, 0),
        custom: Vec::new(),
        implicit: false,
        key_spans: Default::default(),
        capacity: None,
    }
}

pub fn object(index: u16, name: &str, object_type: ObjectType, subs: Vec<SubObject>) -> Object {
    Object {
        index,
        name: name.to_owned(),
        object_type,
        subs: subs.into_iter().map(|s| (s.sub_index, s)).collect(),
        sub_number: None,
        compact_sub_obj: None,
        obj_flags: 0,
        span: Span::new(u32::from(index), 1, 0),
        custom: Vec::new(),
        object_links: Vec::new(),
        implicit: false,
    }
}

pub fn var(
    index: u16,
    name: &str,
    dt: u16,
    access: AccessType,
    default: Option<Value>,
    pdo: bool,
) -> Object {
    object(
        index,
        name,
        ObjectType::Var,
        vec![sub(0, name, dt, access, default, pdo)],
    )
}

pub fn device(objects: Vec<Object>) -> Device {
    Device {
        source: Source {
            path: PathBuf::from("hand.eds"),
            format: Format::Eds,
            encoding: TextEncoding::Ascii,
        },
        file_info: FileInfo::default(),
        device_info: DeviceInfo {
            product_name: Some("Hand-built test device".into()),
            vendor_name: Some("edsgen tests".into()),
            ..DeviceInfo::default()
        },
        dummy_usage: BTreeMap::new(),
        dummy_usage_span: None,
        comments: Vec::new(),
        comment_lines: None,
        objects: objects.into_iter().map(|o| (o.index, o)).collect(),
        object_lists: Vec::new(),
        commissioning: None,
        other_sections: Vec::new(),
        naming: Default::default(),
        bus: Bus::CanOpen,
    }
}

use AccessType::*;
use Value::*;

pub fn mapping(index: u16, name: &str, entries: &[u32]) -> Object {
    let mut subs = vec![sub(
        0,
        "Number of mapped objects",
        0x05,
        Rw,
        Some(Integer(entries.len() as i128)),
        false,
    )];
    for (i, e) in entries.iter().enumerate() {
        subs.push(sub(
            i as u8 + 1,
            &format!("Mapped object {}", i + 1),
            0x07,
            Rw,
            Some(Integer(i128::from(*e))),
            false,
        ));
    }
    object(index, name, ObjectType::Record, subs)
}

pub fn comm(index: u16, name: &str, cob: Value) -> Object {
    object(
        index,
        name,
        ObjectType::Record,
        vec![
            sub(
                0,
                "Highest sub-index supported",
                0x05,
                Const,
                Some(Integer(2)),
                false,
            ),
            sub(1, "COB-ID", 0x07, Rw, Some(cob), false),
            sub(2, "Transmission type", 0x05, Rw, Some(Integer(255)), false),
        ],
    )
}

/// A Goodrive350-like card: identity, error field array, CW/SW and PZD settings/returns mapped
/// into PDO2, a 24-bit and a string entry, a sparse record.
pub fn goodrive_like() -> Device {
    let mut limited = var(
        0x2100,
        "Setting limited",
        0x06,
        Rw,
        Some(Integer(100)),
        true,
    );
    if let Some(s) = limited.subs.get_mut(&0) {
        s.low_limit = Some(value(Integer(10), "10"));
        s.high_limit = Some(value(Integer(5000), "5000"));
    }
    device(vec![
        var(
            0x1000,
            "Device type",
            0x07,
            Ro,
            Some(Integer(0x0001_0192)),
            false,
        ),
        var(
            0x1008,
            "Manufacturer device name",
            0x09,
            Const,
            Some(Text("GD350".into())),
            false,
        ),
        var(
            0x1009,
            "Manufacturer hardware version",
            0x09,
            Rw,
            Some(Text("1.0".into())),
            false,
        ),
        object(
            0x1003,
            "Pre-defined error field",
            ObjectType::Array,
            vec![
                sub(0, "Number of errors", 0x05, Rw, Some(Integer(0)), false),
                sub(1, "Standard error field", 0x07, Ro, Some(Integer(0)), false),
                sub(2, "Standard error field", 0x07, Ro, Some(Integer(0)), false),
            ],
        ),
        var(
            0x1014,
            "COB-ID EMCY",
            0x07,
            Ro,
            Some(NodeRelative(0x80)),
            false,
        ),
        object(
            0x1018,
            "Identity object",
            ObjectType::Record,
            vec![
                sub(0, "Number of entries", 0x05, Const, Some(Integer(3)), false),
                sub(1, "Vendor-ID", 0x07, Ro, Some(Integer(0x4D8)), false),
                sub(2, "Product code", 0x07, Ro, Some(Integer(0x9252)), false),
                sub(
                    3,
                    "Revision number",
                    0x07,
                    Ro,
                    Some(Integer(0x10001)),
                    false,
                ),
            ],
        ),
        comm(0x1401, "RPDO2 communication parameter", NodeRelative(0x300)),
        mapping(
            0x1601,
            "RPDO2 mapping parameter",
            &[0x2101_0010, 0x2100_0110, 0x2100_0210, 0x2100_0310],
        ),
        comm(0x1801, "TPDO2 communication parameter", NodeRelative(0x280)),
        mapping(
            0x1A01,
            "TPDO2 mapping parameter",
            &[0x2001_0010, 0x2000_0110, 0x2000_0210, 0x2000_0310],
        ),
        mapping(
            0x1A02,
            "TPDO3 mapping parameter",
            &[
                0x2002_0004,
                0x0005_0004,
                0x2003_0118,
                0x2003_0208,
                0x2004_0001,
            ],
        ),
        mapping(
            0x1A03,
            "TPDO4 mapping parameter",
            &[0x2004_0001, 0x2006_0020, 0x2003_0208],
        ),
        object(
            0x2000,
            "Returned values",
            ObjectType::Array,
            vec![
                sub(0, "Number of entries", 0x05, Const, Some(Integer(4)), false),
                sub(1, "Returned value 1", 0x06, Ro, Some(Integer(0)), true),
                sub(2, "Returned value 2", 0x06, Ro, Some(Integer(0)), true),
                sub(3, "Returned value 3", 0x06, Ro, Some(Integer(0)), true),
                sub(4, "Returned value 4", 0x06, Ro, Some(Integer(0)), true),
            ],
        ),
        var(0x2001, "Status word", 0x06, Ro, Some(Integer(0)), true),
        var(0x2002, "Nibble", 0x05, Ro, Some(Integer(0)), true),
        object(
            0x2003,
            "Sparse record",
            ObjectType::Record,
            vec![
                sub(
                    0,
                    "Highest sub-index supported",
                    0x05,
                    Const,
                    Some(Integer(5)),
                    false,
                ),
                sub(1, "Signed 24", 0x10, Rw, Some(Integer(-5)), true),
                sub(2, "type", 0x02, Rw, Some(Integer(-1)), true),
                sub(5, "Big", 0x1B, Rw, Some(Integer(0xFFFF_FFFF_FFFF)), false),
            ],
        ),
        var(0x2004, "Flag", 0x01, Rw, Some(Integer(1)), true),
        var(0x2005, "Gain", 0x08, Rw, Some(Real(1.5)), false),
        var(0x2006, "Tag", 0x0A, Rw, Some(Bytes(vec![1, 2, 3, 4])), true),
        object(
            0x2100,
            "Settings",
            ObjectType::Array,
            vec![
                sub(0, "Number of entries", 0x05, Const, Some(Integer(4)), false),
                sub(1, "Setting 1", 0x06, Rw, Some(Integer(0)), true),
                sub(2, "Setting 2", 0x06, Rw, Some(Integer(0)), true),
                sub(3, "Setting 3", 0x06, Rw, Some(Integer(0)), true),
                sub(4, "Setting 4", 0x06, Rw, Some(Integer(0)), true),
            ],
        ),
        var(0x2101, "Control word", 0x06, Rw, Some(Integer(0)), true),
        limited_renamed(limited),
        var(0x6040, "Controlword", 0x06, Rw, Some(Integer(0)), true),
        var(0x6041, "Status word", 0x06, Ro, Some(Integer(0)), true),
    ])
}

fn limited_renamed(mut o: Object) -> Object {
    o.index = 0x2102;
    o
}

fn ec_entry(index: u16, sub: u8, bit_len: u16, name: &str, data_type: &str) -> EcPdoEntry {
    EcPdoEntry {
        index,
        sub,
        bit_len,
        name: name.to_owned(),
        data_type: (!data_type.is_empty()).then(|| data_type.to_owned()),
        span: Span::new(1, 1, 0),
    }
}

fn ec_pdo(index: u16, name: &str, sm: Option<u8>, entries: Vec<EcPdoEntry>) -> EcPdo {
    EcPdo {
        index,
        name: name.to_owned(),
        sm,
        fixed: false,
        mandatory: false,
        exclude: Vec::new(),
        entries,
        span: Span::new(1, 1, 0),
    }
}

fn sm(
    kind: SmKind,
    start_address: u16,
    default_size: Option<u16>,
    control_byte: u8,
) -> SyncManager {
    SyncManager {
        kind,
        start_address,
        default_size,
        control_byte,
        enable: true,
        span: Span::new(1, 1, 0),
    }
}

/// An EtherCAT device as an ESI reader would give it: a CoE dictionary and PDOs with odd widths
/// and offsets, padding, entries the dictionary lacks (typed by DataType), one wider than 64
/// bits, two RxPDOs on SM2 and a third that excludes one of them, an empty TxPDO.
pub fn ethercat_like() -> Device {
    let mut dev = device(vec![
        var(0x1000, "Device type", 0x07, Ro, Some(Integer(0x192)), false),
        object(
            0x1018,
            "Identity",
            ObjectType::Record,
            vec![
                sub(0, "Number of entries", 0x05, Ro, Some(Integer(3)), false),
                sub(1, "Vendor ID", 0x07, Ro, Some(Integer(0x4D8)), false),
                sub(2, "Product code", 0x07, Ro, Some(Integer(0x9252)), false),
                sub(3, "Revision", 0x07, Ro, Some(Integer(1)), false),
            ],
        ),
        var(0x2001, "Offset", 0x10, Rw, Some(Integer(0)), true),
        var(0x2002, "Gain", 0x08, Ro, Some(Real(0.0)), true),
        var(0x2003, "Enable", 0x01, Rw, Some(Integer(0)), true),
        var(0x2004, "Tag", 0x09, Ro, Some(Text("ABCDEFGH".into())), true),
        var(0x2005, "Counter", 0x1B, Rw, Some(Integer(0)), true),
        var(0x6040, "Control word", 0x06, Rw, Some(Integer(0)), true),
        var(0x6041, "Status word", 0x06, Ro, Some(Integer(0)), true),
        var(
            0x6060,
            "Mode of operation",
            0x02,
            Rw,
            Some(Integer(0)),
            true,
        ),
        var(0x607A, "Target position", 0x04, Rw, Some(Integer(0)), true),
    ]);
    dev.source.path = PathBuf::from("hand.xml");
    dev.source.format = Format::Esi;
    let mut excluding = ec_pdo(
        0x1602,
        "Alternative",
        Some(2),
        vec![ec_entry(0x6040, 0, 16, "Control word", "UINT")],
    );
    excluding.exclude = vec![Spanned::new(0x1601, Span::new(1, 1, 0))];
    dev.bus = Bus::EtherCat(EtherCat {
        type_name: "HAND-1".into(),
        profiles: vec![402],
        sync_managers: vec![
            sm(SmKind::MailboxOut, 0x1000, Some(128), 0x26),
            sm(SmKind::MailboxIn, 0x1080, Some(128), 0x22),
            sm(SmKind::Outputs, 0x1100, None, 0x64),
            sm(SmKind::Inputs, 0x1180, None, 0x20),
        ],
        rx_pdos: vec![
            ec_pdo(
                0x1600,
                "Outputs A",
                Some(2),
                vec![
                    ec_entry(0x6040, 0, 16, "Control word", "UINT"),
                    ec_entry(0, 0, 3, "", ""),
                    ec_entry(0x2003, 0, 1, "Enable", "BOOL"),
                    ec_entry(0x2001, 0, 12, "Offset", "INT24"),
                    ec_entry(0x607A, 0, 32, "Target position", "DINT"),
                    ec_entry(0x6060, 0, 8, "Mode of operation", "SINT"),
                    ec_entry(0x7000, 1, 2, "Select", "BIT2"),
                    ec_entry(0x2005, 0, 64, "Counter", "ULINT"),
                ],
            ),
            ec_pdo(
                0x1601,
                "Outputs B",
                Some(2),
                vec![
                    ec_entry(0x7010, 1, 100, "Blob", "ARRAY [0..12] OF BYTE"),
                    ec_entry(0x7011, 0, 5, "Small", "SINT"),
                ],
            ),
            excluding,
        ],
        tx_pdos: vec![
            ec_pdo(
                0x1A00,
                "Inputs A",
                Some(3),
                vec![
                    ec_entry(0x6041, 0, 16, "Status word", "UINT"),
                    ec_entry(0x2002, 0, 32, "Gain", "REAL"),
                    ec_entry(0x2004, 0, 64, "Tag", "STRING(8)"),
                ],
            ),
            ec_pdo(0x1A01, "Nothing", None, Vec::new()),
        ],
        coe: Some(CoeMailbox {
            sdo_info: true,
            pdo_assign: true,
            pdo_config: false,
            complete_access: false,
            segmented_sdo: true,
            init_cmds: Vec::new(),
        }),
        op_modes: vec![
            DcOpMode {
                name: "FreeRun".into(),
                description: "Free run".into(),
                assign_activate: 0,
                cycle_time_sync0: 0,
            },
            DcOpMode {
                name: "DC".into(),
                description: "DC SYNC0".into(),
                assign_activate: 0x300,
                cycle_time_sync0: 1_000_000,
            },
        ],
        alternative_mappings: Vec::new(),
        modules: Vec::new(),
        slots: Vec::new(),
        other_devices: Vec::new(),
        span: Span::new(1, 1, 0),
        chosen: None,
    });
    dev
}

/// The typed addresses of generated code by their path from `od` (`pair::VALUE`, `SPEED`), in
/// order.
pub fn addresses(code: &str) -> Vec<String> {
    let od = code.find("    pub mod od {").unwrap_or(0);
    let mut module = None;
    let mut out = Vec::new();
    for line in code[od..].lines().skip(1).take_while(|l| *l != "    }") {
        if let Some(name) = line.strip_prefix("        pub mod ") {
            module = name.strip_suffix(" {").map(str::to_owned);
        } else if line == "        }" {
            module = None;
        } else if let Some(rest) = line.trim().strip_prefix("pub const ") {
            let name = rest.split(':').next().unwrap_or_default();
            if line.starts_with("            pub const ") || line.starts_with("        pub const ")
            {
                out.push(match &module {
                    Some(m) => format!("{m}::{name}"),
                    None => name.to_owned(),
                });
            }
        }
    }
    out
}
