//! CiA 301 kinds: access types, object types and basic data types, with what each means for
//! sizes, ranges and parsing.

/// An object dictionary access type as written in CiA 306.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum AccessType {
    /// Read only.
    Ro,
    /// Write only.
    Wo,
    /// Read and write.
    Rw,
    /// Read and write, mapped into TPDOs (read on process input).
    Rwr,
    /// Read and write, mapped into RPDOs (write on process output).
    Rww,
    /// Read only, constant value.
    Const,
}

impl AccessType {
    /// The lowercase CiA 306 spelling.
    pub const fn as_str(self) -> &'static str {
        match self {
            AccessType::Ro => "ro",
            AccessType::Wo => "wo",
            AccessType::Rw => "rw",
            AccessType::Rwr => "rwr",
            AccessType::Rww => "rww",
            AccessType::Const => "const",
        }
    }

    /// Parses the CiA 306 spelling, case-insensitively.
    pub fn parse(text: &str) -> Option<Self> {
        let text = text.trim();
        [
            AccessType::Ro,
            AccessType::Wo,
            AccessType::Rw,
            AccessType::Rwr,
            AccessType::Rww,
            AccessType::Const,
        ]
        .into_iter()
        .find(|access| access.as_str().eq_ignore_ascii_case(text))
    }

    /// Whether an SDO client may read this entry.
    pub const fn readable(self) -> bool {
        !matches!(self, AccessType::Wo)
    }

    /// Whether an SDO client may write this entry.
    pub const fn writable(self) -> bool {
        matches!(
            self,
            AccessType::Wo | AccessType::Rw | AccessType::Rwr | AccessType::Rww
        )
    }
}

/// The object code of an object (CiA 301 table 42).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ObjectType {
    /// 0x0: no data fields.
    Null,
    /// 0x2: large variable amount of data.
    Domain,
    /// 0x5: a type definition (BOOLEAN, UNSIGNED8, ...).
    DefType,
    /// 0x6: a record type definition.
    DefStruct,
    /// 0x7: a single value.
    Var,
    /// 0x8: several values of one type, sub-index 0 is the count.
    Array,
    /// 0x9: several values of possibly different types.
    Record,
}

impl ObjectType {
    /// The object code as a number.
    pub const fn code(self) -> u8 {
        match self {
            ObjectType::Null => 0x0,
            ObjectType::Domain => 0x2,
            ObjectType::DefType => 0x5,
            ObjectType::DefStruct => 0x6,
            ObjectType::Var => 0x7,
            ObjectType::Array => 0x8,
            ObjectType::Record => 0x9,
        }
    }

    /// The object type for an object code, if it is one CiA 301 defines.
    pub const fn from_code(code: u32) -> Option<Self> {
        Some(match code {
            0x0 => ObjectType::Null,
            0x2 => ObjectType::Domain,
            0x5 => ObjectType::DefType,
            0x6 => ObjectType::DefStruct,
            0x7 => ObjectType::Var,
            0x8 => ObjectType::Array,
            0x9 => ObjectType::Record,
            _ => return None,
        })
    }

    /// Whether objects of this type hold sub-indices 0..n (ARRAY, RECORD, DEFSTRUCT).
    pub const fn has_subs(self) -> bool {
        matches!(
            self,
            ObjectType::Array | ObjectType::Record | ObjectType::DefStruct
        )
    }
}

/// The CiA 301 basic data types (OD indices 0x0001-0x001B).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BasicType {
    /// 0x0001
    Boolean,
    /// 0x0002
    Integer8,
    /// 0x0003
    Integer16,
    /// 0x0004
    Integer32,
    /// 0x0005
    Unsigned8,
    /// 0x0006
    Unsigned16,
    /// 0x0007
    Unsigned32,
    /// 0x0008
    Real32,
    /// 0x0009
    VisibleString,
    /// 0x000A
    OctetString,
    /// 0x000B
    UnicodeString,
    /// 0x000C
    TimeOfDay,
    /// 0x000D
    TimeDifference,
    /// 0x000F
    Domain,
    /// 0x0010
    Integer24,
    /// 0x0011
    Real64,
    /// 0x0012
    Integer40,
    /// 0x0013
    Integer48,
    /// 0x0014
    Integer56,
    /// 0x0015
    Integer64,
    /// 0x0016
    Unsigned24,
    /// 0x0018
    Unsigned40,
    /// 0x0019
    Unsigned48,
    /// 0x001A
    Unsigned56,
    /// 0x001B
    Unsigned64,
}

impl BasicType {
    /// The basic type that an OD data type index names, if any.
    pub const fn from_index(index: u16) -> Option<Self> {
        Some(match index {
            0x01 => BasicType::Boolean,
            0x02 => BasicType::Integer8,
            0x03 => BasicType::Integer16,
            0x04 => BasicType::Integer32,
            0x05 => BasicType::Unsigned8,
            0x06 => BasicType::Unsigned16,
            0x07 => BasicType::Unsigned32,
            0x08 => BasicType::Real32,
            0x09 => BasicType::VisibleString,
            0x0A => BasicType::OctetString,
            0x0B => BasicType::UnicodeString,
            0x0C => BasicType::TimeOfDay,
            0x0D => BasicType::TimeDifference,
            0x0F => BasicType::Domain,
            0x10 => BasicType::Integer24,
            0x11 => BasicType::Real64,
            0x12 => BasicType::Integer40,
            0x13 => BasicType::Integer48,
            0x14 => BasicType::Integer56,
            0x15 => BasicType::Integer64,
            0x16 => BasicType::Unsigned24,
            0x18 => BasicType::Unsigned40,
            0x19 => BasicType::Unsigned48,
            0x1A => BasicType::Unsigned56,
            0x1B => BasicType::Unsigned64,
            _ => return None,
        })
    }

    /// The OD index of this data type.
    pub const fn index(self) -> u16 {
        match self {
            BasicType::Boolean => 0x01,
            BasicType::Integer8 => 0x02,
            BasicType::Integer16 => 0x03,
            BasicType::Integer32 => 0x04,
            BasicType::Unsigned8 => 0x05,
            BasicType::Unsigned16 => 0x06,
            BasicType::Unsigned32 => 0x07,
            BasicType::Real32 => 0x08,
            BasicType::VisibleString => 0x09,
            BasicType::OctetString => 0x0A,
            BasicType::UnicodeString => 0x0B,
            BasicType::TimeOfDay => 0x0C,
            BasicType::TimeDifference => 0x0D,
            BasicType::Domain => 0x0F,
            BasicType::Integer24 => 0x10,
            BasicType::Real64 => 0x11,
            BasicType::Integer40 => 0x12,
            BasicType::Integer48 => 0x13,
            BasicType::Integer56 => 0x14,
            BasicType::Integer64 => 0x15,
            BasicType::Unsigned24 => 0x16,
            BasicType::Unsigned40 => 0x18,
            BasicType::Unsigned48 => 0x19,
            BasicType::Unsigned56 => 0x1A,
            BasicType::Unsigned64 => 0x1B,
        }
    }

    /// The CiA 301 name, e.g. `UNSIGNED16`.
    pub const fn name(self) -> &'static str {
        match self {
            BasicType::Boolean => "BOOLEAN",
            BasicType::Integer8 => "INTEGER8",
            BasicType::Integer16 => "INTEGER16",
            BasicType::Integer32 => "INTEGER32",
            BasicType::Unsigned8 => "UNSIGNED8",
            BasicType::Unsigned16 => "UNSIGNED16",
            BasicType::Unsigned32 => "UNSIGNED32",
            BasicType::Real32 => "REAL32",
            BasicType::VisibleString => "VISIBLE_STRING",
            BasicType::OctetString => "OCTET_STRING",
            BasicType::UnicodeString => "UNICODE_STRING",
            BasicType::TimeOfDay => "TIME_OF_DAY",
            BasicType::TimeDifference => "TIME_DIFFERENCE",
            BasicType::Domain => "DOMAIN",
            BasicType::Integer24 => "INTEGER24",
            BasicType::Real64 => "REAL64",
            BasicType::Integer40 => "INTEGER40",
            BasicType::Integer48 => "INTEGER48",
            BasicType::Integer56 => "INTEGER56",
            BasicType::Integer64 => "INTEGER64",
            BasicType::Unsigned24 => "UNSIGNED24",
            BasicType::Unsigned40 => "UNSIGNED40",
            BasicType::Unsigned48 => "UNSIGNED48",
            BasicType::Unsigned56 => "UNSIGNED56",
            BasicType::Unsigned64 => "UNSIGNED64",
        }
    }

    /// Width in bits of a fixed-size type; `None` for strings and DOMAIN.
    pub const fn bits(self) -> Option<u32> {
        Some(match self {
            BasicType::Boolean => 1,
            BasicType::Integer8 | BasicType::Unsigned8 => 8,
            BasicType::Integer16 | BasicType::Unsigned16 => 16,
            BasicType::Integer24 | BasicType::Unsigned24 => 24,
            BasicType::Integer32 | BasicType::Unsigned32 | BasicType::Real32 => 32,
            BasicType::Integer40 | BasicType::Unsigned40 => 40,
            BasicType::Integer48
            | BasicType::Unsigned48
            | BasicType::TimeOfDay
            | BasicType::TimeDifference => 48,
            BasicType::Integer56 | BasicType::Unsigned56 => 56,
            BasicType::Integer64 | BasicType::Unsigned64 | BasicType::Real64 => 64,
            BasicType::VisibleString
            | BasicType::OctetString
            | BasicType::UnicodeString
            | BasicType::Domain => return None,
        })
    }

    /// Whether this is a signed integer type.
    pub const fn is_signed_integer(self) -> bool {
        matches!(
            self,
            BasicType::Integer8
                | BasicType::Integer16
                | BasicType::Integer24
                | BasicType::Integer32
                | BasicType::Integer40
                | BasicType::Integer48
                | BasicType::Integer56
                | BasicType::Integer64
        )
    }

    /// Whether this is an unsigned integer type (BOOLEAN excluded).
    pub const fn is_unsigned_integer(self) -> bool {
        matches!(
            self,
            BasicType::Unsigned8
                | BasicType::Unsigned16
                | BasicType::Unsigned24
                | BasicType::Unsigned32
                | BasicType::Unsigned40
                | BasicType::Unsigned48
                | BasicType::Unsigned56
                | BasicType::Unsigned64
        )
    }

    /// Whether this is an integer type (BOOLEAN excluded).
    pub const fn is_integer(self) -> bool {
        self.is_signed_integer() || self.is_unsigned_integer()
    }

    /// Whether this is REAL32 or REAL64.
    pub const fn is_real(self) -> bool {
        matches!(self, BasicType::Real32 | BasicType::Real64)
    }

    /// The inclusive integer range of an integer or BOOLEAN type.
    pub const fn integer_range(self) -> Option<(i128, i128)> {
        if matches!(self, BasicType::Boolean) {
            return Some((0, 1));
        }
        let bits = match self.bits() {
            Some(b) => b,
            None => return None,
        };
        if self.is_signed_integer() {
            Some((-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1))
        } else if self.is_unsigned_integer() {
            Some((0, (1i128 << bits) - 1))
        } else {
            None
        }
    }
}
