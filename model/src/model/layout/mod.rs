//! The value image's layout, as the generated `Od` and the simulator's dictionary store it: which
//! entries are stored, the bytes a value takes, a string's capacity. The validator reports what
//! does not fit; the emitter and the simulator lay values out with it.

mod number;

pub use number::{
    node_relative_offset, normalise_integer, scalar_number, Number, Prim, RustType, ValueProblem,
};

use super::{AccessType, BasicType, Object, SubObject, Value, ValueSource};

/// Writable strings and domains get at least this many bytes of capacity.
pub const MIN_WRITABLE_CAPACITY: usize = 32;

/// The most bytes all values of one device may take (see `Od`'s value image).
pub const MAX_IMAGE_SIZE: usize = u16::MAX as usize;

/// The stored entries of an object, as the generator stores them: a VAR's one entry, or every
/// sub-object of an ARRAY or RECORD.
pub fn stored_entries(object: &Object) -> Vec<&SubObject> {
    if object.index < 0x1000 {
        return Vec::new();
    }
    if object.object_type.has_subs() {
        object.subs.values().collect()
    } else {
        object
            .subs
            .get(&0)
            .or_else(|| object.subs.values().next())
            .into_iter()
            .collect()
    }
}

/// The bytes a value of `basic` takes in the value image: its wire size (a BOOLEAN one byte), or
/// a string's, octet string's or domain's 2-byte length and its `capacity`.
pub fn image_size(basic: BasicType, capacity: usize) -> usize {
    if is_bytes(basic) {
        2 + capacity
    } else {
        basic.bits().map_or(0, |b| (b as usize).div_ceil(8))
    }
}

/// Whether values of `basic` are bytes with a capacity (strings, octet strings, domains) rather
/// than fixed-size scalars.
pub fn is_bytes(basic: BasicType) -> bool {
    matches!(
        basic,
        BasicType::VisibleString
            | BasicType::OctetString
            | BasicType::UnicodeString
            | BasicType::Domain
    )
}

/// The bytes a string, octet string or domain value holds (UNICODE_STRING text as UTF-16LE).
pub fn value_bytes(basic: BasicType, value: &Value) -> Option<Vec<u8>> {
    match value {
        Value::Text(text) if basic == BasicType::UnicodeString => {
            Some(text.encode_utf16().flat_map(u16::to_le_bytes).collect())
        }
        Value::Text(text) => Some(text.as_bytes().to_vec()),
        Value::Bytes(bytes) => Some(bytes.clone()),
        _ => None,
    }
}

/// The configured value of an entry: the DCF ParameterValue when it parsed, else the default.
pub fn initial_value(sub: &SubObject) -> Option<&Value> {
    sub.parameter_value
        .as_ref()
        .and_then(|v| v.value.as_ref())
        .or_else(|| sub.default.as_ref().and_then(|v| v.value.as_ref()))
}

/// The capacity of a string, octet string or domain entry: the overlay's, else the longest of
/// its DefaultValue and ParameterValue, and at least [`MIN_WRITABLE_CAPACITY`] when it is writable.
pub fn capacity(basic: BasicType, sub: &SubObject) -> usize {
    if let Some(capacity) = sub.capacity {
        return capacity;
    }
    let len_of = |v: Option<&ValueSource>| {
        v.and_then(|v| v.value.as_ref())
            .and_then(|v| value_bytes(basic, v))
            .map_or(0, |b| b.len())
    };
    let longest = len_of(sub.default.as_ref()).max(len_of(sub.parameter_value.as_ref()));
    if sub.access.is_some_and(AccessType::writable) {
        longest.max(MIN_WRITABLE_CAPACITY)
    } else {
        longest
    }
}
