//! The values of stored CiA 301 entries as numbers: which primitive holds each basic type and how
//! many bytes it travels as, and constant values read into that primitive's range. The emitter
//! writes them as Rust; the simulator's dictionary stores them.
//!
//! Odd-width integers (24, 40, 48, 56 bits, and TIME_OF_DAY/TIME_DIFFERENCE as 48-bit unsigned)
//! live in the smallest fitting Rust integer; the OD write reads exactly their wire width and sign
//! extends, so a stored value is always in range. Strings, octet strings and domains are bytes
//! with a capacity (see [`capacity`](super::capacity)).

use crate::model::{BasicType, Value};

/// A Rust primitive holding a fixed-size CiA 301 value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Prim {
    /// `bool`
    Bool,
    /// `u8`..`u64`
    Unsigned(u32),
    /// `i8`..`i64`
    Signed(u32),
    /// `f32`
    F32,
    /// `f64`
    F64,
}

/// The Rust type of one entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RustType {
    /// A fixed-size value: the primitive and its wire width in bytes (3 for a 24-bit integer in an
    /// `i32`).
    Scalar(Prim, usize),
    /// `FixedBytes<N>` with capacity `N`.
    Bytes(usize),
}

impl Prim {
    /// The primitive's width in bits.
    pub fn bits(self) -> u32 {
        match self {
            Prim::Bool => 8,
            Prim::Unsigned(b) | Prim::Signed(b) => b,
            Prim::F32 => 32,
            Prim::F64 => 64,
        }
    }

    /// The type's name (`u16`).
    pub fn name(self) -> &'static str {
        match self {
            Prim::Bool => "bool",
            Prim::Unsigned(8) => "u8",
            Prim::Unsigned(16) => "u16",
            Prim::Unsigned(32) => "u32",
            Prim::Unsigned(_) => "u64",
            Prim::Signed(8) => "i8",
            Prim::Signed(16) => "i16",
            Prim::Signed(32) => "i32",
            Prim::Signed(_) => "i64",
            Prim::F32 => "f32",
            Prim::F64 => "f64",
        }
    }
}

impl RustType {
    /// The bytes a value of this type takes in the value image: its wire size, or a string's
    /// 2-byte length and its capacity.
    pub fn image_size(self) -> usize {
        match self {
            RustType::Scalar(_, wire) => wire,
            RustType::Bytes(capacity) => 2 + capacity,
        }
    }

    /// The Rust type of a basic type; `capacity` is used for strings and domains only.
    pub fn of(basic: BasicType, capacity: usize) -> RustType {
        use BasicType as B;
        let wire = basic.bits().map_or(0, |b| (b as usize).div_ceil(8));
        let prim = match basic {
            B::Boolean => Prim::Bool,
            B::Integer8 => Prim::Signed(8),
            B::Integer16 => Prim::Signed(16),
            B::Integer24 | B::Integer32 => Prim::Signed(32),
            B::Integer40 | B::Integer48 | B::Integer56 | B::Integer64 => Prim::Signed(64),
            B::Unsigned8 => Prim::Unsigned(8),
            B::Unsigned16 => Prim::Unsigned(16),
            B::Unsigned24 | B::Unsigned32 => Prim::Unsigned(32),
            B::Unsigned40
            | B::Unsigned48
            | B::Unsigned56
            | B::Unsigned64
            | B::TimeOfDay
            | B::TimeDifference => Prim::Unsigned(64),
            B::Real32 => Prim::F32,
            B::Real64 => Prim::F64,
            B::VisibleString | B::OctetString | B::UnicodeString | B::Domain => {
                return RustType::Bytes(capacity)
            }
        };
        RustType::Scalar(prim, wire)
    }
}

/// Why a value cannot initialise or bound an entry.
#[derive(Debug, Clone, PartialEq)]
pub enum ValueProblem {
    /// The value is outside the type's range.
    OutOfRange,
    /// The value is of another kind (text for an integer, `$NODEID` on a REAL, ...).
    WrongKind,
}

/// An integer value normalised into `basic`'s range (two's complement read back for signed types
/// written as unsigned hex).
pub fn normalise_integer(value: i128, basic: BasicType) -> Result<i128, ValueProblem> {
    let (min, max) = match basic {
        // 48-bit values: milliseconds in bits 0-27, days in bits 32-47.
        BasicType::TimeOfDay | BasicType::TimeDifference => (0, (1i128 << 48) - 1),
        _ => basic.integer_range().ok_or(ValueProblem::WrongKind)?,
    };
    if (min..=max).contains(&value) {
        return Ok(value);
    }
    let bits = basic.bits().unwrap_or(0);
    if basic.is_signed_integer() && value > max && value < (1i128 << bits) {
        return Ok(value - (1i128 << bits));
    }
    Err(ValueProblem::OutOfRange)
}

/// A constant scalar value (not `$NODEID`) as a number: an integer (in the type's range, signed
/// ones written as unsigned hex read back as two's complement) or a REAL (rounded to `f32` for
/// REAL32, exactly representable as `f64`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    /// An integer, BOOLEAN (0 or 1), TIME_OF_DAY or TIME_DIFFERENCE value.
    Integer(i128),
    /// A REAL32 or REAL64 value.
    Real(f64),
}

impl Number {
    /// The bits the value image stores (its low wire-width bytes are the value's wire form):
    /// two's complement for integers, IEEE 754 for REAL32/REAL64.
    pub fn raw(self, prim: Prim) -> u64 {
        match self {
            Number::Integer(v) => v as u64,
            Number::Real(f) if prim == Prim::F32 => u64::from((f as f32).to_bits()),
            Number::Real(f) => f.to_bits(),
        }
    }
}

/// A constant value (not `$NODEID`) of a scalar type, as a number.
pub fn scalar_number(value: &Value, basic: BasicType, prim: Prim) -> Result<Number, ValueProblem> {
    let real = |f: f64| {
        Number::Real(if prim == Prim::F32 {
            f64::from(f as f32)
        } else {
            f
        })
    };
    match (prim, value) {
        (Prim::Bool, Value::Integer(v)) => match v {
            0 | 1 => Ok(Number::Integer(*v)),
            _ => Err(ValueProblem::OutOfRange),
        },
        (Prim::F32 | Prim::F64, Value::Real(f)) => Ok(real(*f)),
        (Prim::F32 | Prim::F64, Value::Integer(i)) => Ok(real(*i as f64)),
        (Prim::Unsigned(_) | Prim::Signed(_), Value::Integer(v)) => {
            Ok(Number::Integer(normalise_integer(*v, basic)?))
        }
        (Prim::Unsigned(_), Value::Text(text))
            if matches!(basic, BasicType::TimeOfDay | BasicType::TimeDifference) =>
        {
            Ok(Number::Integer(time_of_day(text)?))
        }
        _ => Err(ValueProblem::WrongKind),
    }
}

/// A TIME_OF_DAY / TIME_DIFFERENCE written as `<days> <milliseconds>` (the form Lely's tools
/// use): milliseconds in bits 0-27, days in bits 32-47 (CiA 301).
fn time_of_day(text: &str) -> Result<i128, ValueProblem> {
    let mut parts = text.split_whitespace();
    let (Some(days), Some(ms), None) = (parts.next(), parts.next(), parts.next()) else {
        return Err(ValueProblem::WrongKind);
    };
    let days: u64 = days.parse().map_err(|_| ValueProblem::WrongKind)?;
    let ms: u64 = ms.parse().map_err(|_| ValueProblem::WrongKind)?;
    if days > 0xFFFF || ms >= 1 << 28 {
        return Err(ValueProblem::OutOfRange);
    }
    Ok(i128::from(ms | (days << 32)))
}

/// The offset of a `$NODEID + offset` value of an integer type, as the bits the value image
/// stores before `Od::new` adds the node-ID (see [`Number::raw`]).
pub fn node_relative_offset(offset: i64, basic: BasicType) -> Result<u64, ValueProblem> {
    if !basic.is_integer() {
        return Err(ValueProblem::WrongKind);
    }
    let (min, max) = basic.integer_range().ok_or(ValueProblem::WrongKind)?;
    if i128::from(offset) < min || i128::from(offset) > max {
        return Err(ValueProblem::OutOfRange);
    }
    Ok(offset as u64)
}
