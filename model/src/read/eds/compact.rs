//! CompactSubObj and CompactPDO: the sub-objects and PDO objects a file leaves implicit.

use std::collections::BTreeMap;

use crate::model::*;

/// Expands `CompactSubObj=N` into implicit sub-objects 0..N (CiA 306 4.6.3.4): sub 0
/// `NrOfObjects` (UNSIGNED8, ro, default N), subs 1..N named `<ParameterName><n>` (decimal) with
/// the data type, access type, default value, PDO mapping and limits of the main section
/// (`template`).
pub fn expand_compact_sub_obj(object: &mut Object, template: &SubObject, count: Spanned<u32>) {
    let span = count.span;
    object.subs.insert(
        0,
        SubObject {
            // Written in decimal, as the count was.
            default: Some(ValueSource {
                value: Some(Value::Integer(i128::from(count.value))),
                raw: count.value.to_string(),
                span,
            }),
            ..implicit_entry(
                0,
                "NrOfObjects".to_owned(),
                BasicType::Unsigned8,
                AccessType::Ro,
                None,
                span,
            )
        },
    );
    for n in 1..=count.value.min(255) {
        let Ok(sub_index) = u8::try_from(n) else {
            break;
        };
        object.subs.insert(
            sub_index,
            SubObject {
                sub_index,
                name: numbered_name(&object.name, n),
                data_type: template.data_type,
                access: template.access,
                pdo_mapping: template.pdo_mapping,
                default: template.default.clone(),
                parameter_value: None,
                low_limit: template.low_limit.clone(),
                high_limit: template.high_limit.clone(),
                obj_flags: 0,
                denotation: None,
                upload_file: None,
                download_file: None,
                span,
                custom: Vec::new(),
                implicit: true,
                key_spans: template.key_spans,
                capacity: None,
            },
        );
    }
}

/// `<name><n>` (decimal), without the formatting machinery: it runs once per compact sub-object.
fn numbered_name(name: &str, n: u32) -> String {
    let mut digits = [0u8; 10];
    let mut at = digits.len();
    let mut rest = n;
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            break;
        }
    }
    let mut out = String::with_capacity(name.len() + digits.len() - at);
    out.push_str(name);
    out.extend(digits[at..].iter().map(|d| char::from(*d)));
    out
}

/// The entry layout of the PDO communication sub-indices 1..6 (CiA 301): name, data type.
const PDO_COMM_SUBS: [(&str, BasicType); 6] = [
    ("COB-ID used by {}PDO", BasicType::Unsigned32),
    ("Transmission type", BasicType::Unsigned8),
    ("Inhibit time", BasicType::Unsigned16),
    ("Compatibility entry", BasicType::Unsigned8),
    ("Event timer", BasicType::Unsigned16),
    ("SYNC start value", BasicType::Unsigned8),
];

/// How many mapping entries an implicit PDO mapping object gets: 8, enough for a classic CAN
/// frame at granularity 8 (eight one-byte objects). CAN FD devices describe their mapping
/// objects explicitly.
pub const IMPLICIT_MAPPING_ENTRIES: u8 = 8;

/// The highest PDO number (1-based) CiA 301 allows per direction.
const MAX_PDOS: u32 = 512;

/// An implicit entry: no value unless given, access rw unless said otherwise.
fn implicit_entry(
    sub_index: u8,
    name: String,
    data_type: BasicType,
    access: AccessType,
    default: Option<Value>,
    span: Span,
) -> SubObject {
    SubObject {
        sub_index,
        name,
        data_type: Some(data_type.index()),
        access: Some(access),
        pdo_mapping: false,
        default: default.map(|value| ValueSource {
            raw: match &value {
                Value::NodeRelative(offset) => format!("$NODEID+0x{offset:X}"),
                Value::Integer(v) if *v > 9 => format!("0x{v:X}"),
                Value::Integer(v) => v.to_string(),
                other => format!("{other:?}"),
            },
            value: Some(value),
            span,
        }),
        parameter_value: None,
        low_limit: None,
        high_limit: None,
        obj_flags: 0,
        denotation: None,
        upload_file: None,
        download_file: None,
        span,
        custom: Vec::new(),
        implicit: true,
        key_spans: KeySpans::default(),
        capacity: None,
    }
}

/// Synthesises the PDO communication (1400h+/1800h+) and mapping (1600h+/1A00h+) objects that
/// `CompactPDO` in `[DeviceInfo]` leaves out (CiA 306 4.6.3.4.1 / 5.3.3).
///
/// For each direction, the implicit count is NrOfRXPDO/NrOfTXPDO minus the PDOs described
/// explicitly (a PDO counts as explicit when its communication or its mapping object is
/// present), placed at the lowest free PDO numbers. A communication object gets sub 0 (UNSIGNED8,
/// ro, the highest sub-index of the bitmask) and the sub-indices whose bit is set (bit 0 = sub 1
/// ... bit 5 = sub 6), rw, without default values except the COB-ID: for PDOs 1-4 the predefined
/// connection set (`$NODEID+0x200/0x300/0x400/0x500` for RPDOs, `$NODEID+0x180/0x280/0x380/0x480`
/// for TPDOs), for the others `0x80000000` (not valid). In a DCF, where CompactPDO means "the PDOs
/// not written are disabled", bit 31 is set on the first four too. A mapping object gets sub 0
/// "Number of mapped application objects in PDO" (UNSIGNED8, rw, 0) and
/// [`IMPLICIT_MAPPING_ENTRIES`] UNSIGNED32 entries (rw, 0). Every synthesised object and entry is
/// marked `implicit`, with the span of the `CompactPDO` key.
pub fn expand_compact_pdo(device: &mut Device) {
    let Some(mask) = device.device_info.compact_pdo.clone() else {
        return;
    };
    let comm_bits = mask.value & 0x3F;
    if comm_bits == 0 {
        return;
    }
    let span = mask.span;
    let dcf = device.source.format.is_configuration();
    let highest_sub = 32 - comm_bits.leading_zeros();
    for (kind, count, comm_base, map_base, cob_base) in [
        (
            "R",
            device.device_info.nr_of_rx_pdo.clone(),
            0x1400u16,
            0x1600u16,
            0x200i64,
        ),
        (
            "T",
            device.device_info.nr_of_tx_pdo.clone(),
            0x1800,
            0x1A00,
            0x180,
        ),
    ] {
        let Some(count) = count else { continue };
        let wanted = count.value.min(MAX_PDOS);
        let present = |objects: &BTreeMap<u16, Object>, n: u16| {
            objects.contains_key(&(comm_base + n)) || objects.contains_key(&(map_base + n))
        };
        let explicit = (0..MAX_PDOS as u16)
            .filter(|n| present(&device.objects, *n))
            .count();
        let mut missing = wanted.saturating_sub(u32::try_from(explicit).unwrap_or(u32::MAX));
        for n in 0..MAX_PDOS as u16 {
            if missing == 0 {
                break;
            }
            if present(&device.objects, n) {
                continue;
            }
            missing -= 1;
            let number = n + 1;
            let mut comm = Object {
                implicit: true,
                ..Object::new(
                    comm_base + n,
                    format!("{kind}PDO{number} communication parameter"),
                    ObjectType::Record,
                    span,
                )
            };
            comm.subs.insert(
                0,
                implicit_entry(
                    0,
                    "Highest sub-index supported".to_owned(),
                    BasicType::Unsigned8,
                    AccessType::Ro,
                    Some(Value::Integer(i128::from(highest_sub))),
                    span,
                ),
            );
            for (bit, (name, data_type)) in PDO_COMM_SUBS.iter().enumerate() {
                if comm_bits & (1 << bit) == 0 {
                    continue;
                }
                let sub = u8::try_from(bit + 1).unwrap_or(u8::MAX);
                let default = (sub == 1).then(|| {
                    let disabled = 0x8000_0000i64;
                    if n < 4 {
                        let cob = cob_base + 0x100 * i64::from(n);
                        Value::NodeRelative(if dcf { disabled + cob } else { cob })
                    } else {
                        Value::Integer(i128::from(disabled))
                    }
                });
                comm.subs.insert(
                    sub,
                    implicit_entry(
                        sub,
                        name.replace("{}", kind),
                        *data_type,
                        AccessType::Rw,
                        default,
                        span,
                    ),
                );
            }
            let mut mapping = Object {
                index: map_base + n,
                name: format!("{kind}PDO{number} mapping parameter"),
                subs: Subs::new(),
                ..comm.clone()
            };
            mapping.subs.insert(
                0,
                implicit_entry(
                    0,
                    "Number of mapped application objects in PDO".to_owned(),
                    BasicType::Unsigned8,
                    AccessType::Rw,
                    Some(Value::Integer(0)),
                    span,
                ),
            );
            for sub in 1..=IMPLICIT_MAPPING_ENTRIES {
                mapping.subs.insert(
                    sub,
                    implicit_entry(
                        sub,
                        format!("Application object {sub}"),
                        BasicType::Unsigned32,
                        AccessType::Rw,
                        Some(Value::Integer(0)),
                        span,
                    ),
                );
            }
            device.objects.insert(comm.index, comm);
            device.objects.insert(mapping.index, mapping);
        }
    }
}
