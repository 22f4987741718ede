//! Each stored CANopen entry's value as the generated `Od` and the simulator's dictionary hold
//! it: its type, access, initial value and limits, from the model's layout (`model::layout`);
//! what cannot be held gets an EDS702-EDS706 diagnostic. Used by the emitter and the simulator.

use crate::diag::Diagnostic;
use crate::model::layout::{
    capacity, initial_value, node_relative_offset, scalar_number, stored_entries, value_bytes,
    Number, Prim, RustType, ValueProblem,
};
use crate::model::{AccessType, BasicType, Device, Object, SubObject, Value, ValueSource};
use crate::rules;

/// An entry's initial value.
#[derive(Debug, Clone, PartialEq)]
pub enum Initial {
    /// A constant scalar: the bits the value image stores (see [`Number::raw`]).
    Raw(u64),
    /// A `$NODEID + offset` value: the offset's bits, to which `Od::new` adds the node-ID.
    NodeRelative(u64),
    /// A string's, octet string's or domain's bytes.
    Bytes(Vec<u8>),
}

/// What one stored entry holds and what a write to it must respect.
#[derive(Debug, Clone, PartialEq)]
pub struct EntryValue {
    /// OD index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The basic data type.
    pub basic: BasicType,
    /// The Rust type.
    pub ty: RustType,
    /// The access type (`ro` when the file gives none; the reader has reported that).
    pub access: AccessType,
    /// PDOMapping.
    pub pdo_mappable: bool,
    /// The initial value.
    pub init: Initial,
    /// LowLimit and HighLimit, when the entry has at least one usable limit (the type's range,
    /// or an infinity for a REAL, stands in for the missing one).
    pub limits: Option<(Number, Number)>,
}

/// The values of every stored object of `device` (from 1000h on) in (index, sub) order. An
/// object with an entry that cannot be held is left out whole, as the generator leaves it out;
/// [`entry_value`] says why.
pub fn stored_values(device: &Device) -> Vec<EntryValue> {
    let mut ignored = Vec::new();
    let mut values = Vec::new();
    for object in device.objects.values() {
        let entries: Option<Vec<EntryValue>> = stored_entries(object)
            .into_iter()
            .map(|sub| entry_value_without_infos(device, object, sub, &mut ignored))
            .collect();
        values.extend(entries.unwrap_or_default());
    }
    values
}

/// The value of one stored entry of `object`, or `None` (with its diagnostics pushed onto
/// `diagnostics`) when no Rust type can hold it or its initial value.
pub fn entry_value(
    device: &Device,
    object: &Object,
    sub: &SubObject,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<EntryValue> {
    let mut values = Values {
        diagnostics,
        infos: true,
    };
    values.entry(device, object, sub)
}

/// [`entry_value`] for a caller that shows no infos: the errors and warnings alone. A file
/// without defaults has an EDS705 info for every entry (thousands), not worth making unseen.
pub fn entry_value_without_infos(
    device: &Device,
    object: &Object,
    sub: &SubObject,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<EntryValue> {
    let mut values = Values {
        diagnostics,
        infos: false,
    };
    values.entry(device, object, sub)
}

/// An entry's place in diagnostics, `1018h sub 1`: written only when a diagnostic is.
#[derive(Debug, Clone, Copy)]
struct Where(u16, u8);

impl std::fmt::Display for Where {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:04X}h sub {}", self.0, self.1)
    }
}

impl Where {
    /// `1018h sub 1 `NAME` ` followed by `rest`, written by hand into one string: a file
    /// without defaults gets this message for every entry (thousands), where `format!` was a
    /// tenth of generating such a file.
    fn message(self, name: &str, rest: &str) -> String {
        const HEX: &[u8; 16] = b"0123456789ABCDEF";
        let mut out = String::with_capacity(16 + name.len() + rest.len());
        for shift in [12, 8, 4, 0] {
            out.push(char::from(HEX[usize::from((self.0 >> shift) & 0xF)]));
        }
        out.push_str("h sub ");
        let sub = self.1;
        if sub >= 100 {
            out.push(char::from(b'0' + sub / 100));
        }
        if sub >= 10 {
            out.push(char::from(b'0' + sub / 10 % 10));
        }
        out.push(char::from(b'0' + sub % 10));
        out.push_str(" `");
        out.push_str(name);
        out.push('`');
        out.push_str(rest);
        out
    }
}

struct Values<'a> {
    diagnostics: &'a mut Vec<Diagnostic>,
    /// Whether infos (EDS705) are made, or only errors and warnings.
    infos: bool,
}

impl Values<'_> {
    fn entry(&mut self, device: &Device, object: &Object, sub: &SubObject) -> Option<EntryValue> {
        let where_ = Where(object.index, sub.sub_index);
        let Some(basic) = sub.data_type.and_then(|t| device.basic_type(t)) else {
            let what = match sub.data_type {
                Some(t) => format!("data type {t:04X}h is not a basic type"),
                None => "no data type".to_owned(),
            };
            self.diagnostics.push(
                Diagnostic::new(
                    &rules::UNREPRESENTABLE_TYPE,
                    Some(sub.span),
                    format!("{where_} `{}`: {what}; no Rust type can hold it", sub.name),
                )
                .with_help("give the entry a CiA 301 basic data type (0001h-001Bh)"),
            );
            return None;
        };
        let cap = capacity(basic, sub);
        if matches!(RustType::of(basic, 0), RustType::Bytes(_)) && cap > usize::from(u16::MAX) {
            return None; // reported by `size_errors`
        }
        let ty = RustType::of(basic, cap);
        let init = self.initial(sub, basic, ty, where_)?;
        let limits = match ty {
            RustType::Scalar(prim, _) if prim != Prim::Bool => {
                self.limits(sub, basic, prim, where_)
            }
            _ => None,
        };
        Some(EntryValue {
            index: object.index,
            sub: sub.sub_index,
            basic,
            ty,
            access: sub.access.unwrap_or(AccessType::Ro),
            pdo_mappable: sub.pdo_mapping,
            init,
            limits,
        })
    }

    fn initial(
        &mut self,
        sub: &SubObject,
        basic: BasicType,
        ty: RustType,
        where_: Where,
    ) -> Option<Initial> {
        let value = initial_value(sub);
        let source_span = sub
            .parameter_value
            .as_ref()
            .filter(|v| v.value.is_some())
            .or(sub.default.as_ref())
            .map_or(sub.span, |v| v.span);
        let Some(value) = value else {
            if sub
                .default
                .as_ref()
                .is_some_and(|d| d.value.is_none() && !d.raw.is_empty())
            {
                // The reader reported the unparseable value; generation cannot invent one.
                self.diagnostics.push(Diagnostic::new(
                    &rules::UNREPRESENTABLE_VALUE,
                    Some(source_span),
                    format!(
                        "{where_} `{}`: the default `{}` could not be read",
                        sub.name,
                        sub.default.as_ref().map_or("", |d| d.raw.as_str())
                    ),
                ));
                return None;
            }
            if self.infos {
                self.diagnostics.push(Diagnostic::new(
                    &rules::NO_DEFAULT,
                    Some(sub.span),
                    where_.message(
                        &sub.name,
                        " has no default value; it starts at zero or empty",
                    ),
                ));
            }
            return Some(match ty {
                RustType::Scalar(..) => Initial::Raw(0),
                RustType::Bytes(_) => Initial::Bytes(Vec::new()),
            });
        };
        let result = match (ty, value) {
            (RustType::Bytes(_), v) => value_bytes(basic, v)
                .map(Initial::Bytes)
                .ok_or(ValueProblem::WrongKind),
            (RustType::Scalar(..), Value::NodeRelative(offset)) => {
                node_relative_offset(*offset, basic).map(Initial::NodeRelative)
            }
            (RustType::Scalar(prim, _), v) => {
                scalar_number(v, basic, prim).map(|n| Initial::Raw(n.raw(prim)))
            }
        };
        match result {
            Ok(init) => Some(init),
            Err(problem) => {
                let why = match problem {
                    ValueProblem::OutOfRange => "is outside the range of",
                    ValueProblem::WrongKind => "is not a value of",
                };
                let raw = sub
                    .parameter_value
                    .as_ref()
                    .filter(|v| v.value.is_some())
                    .or(sub.default.as_ref())
                    .map_or("", |v| v.raw.as_str());
                self.diagnostics.push(Diagnostic::new(
                    &rules::UNREPRESENTABLE_VALUE,
                    Some(source_span),
                    format!("{where_} `{}`: `{raw}` {why} {}", sub.name, basic.name()),
                ));
                None
            }
        }
    }

    fn limits(
        &mut self,
        sub: &SubObject,
        basic: BasicType,
        prim: Prim,
        where_: Where,
    ) -> Option<(Number, Number)> {
        if sub.low_limit.is_none() && sub.high_limit.is_none() {
            return None;
        }
        let mut bound = |source: &Option<ValueSource>, is_low: bool| -> Option<Number> {
            let default = match (prim, is_low) {
                (Prim::F32 | Prim::F64, true) => Number::Real(f64::NEG_INFINITY),
                (Prim::F32 | Prim::F64, false) => Number::Real(f64::INFINITY),
                _ => {
                    let (min, max) = basic.integer_range().unwrap_or((0, 0));
                    Number::Integer(if is_low { min } else { max })
                }
            };
            let Some(source) = source else {
                return Some(default);
            };
            let parsed = match &source.value {
                Some(Value::NodeRelative(_)) | None => Err(ValueProblem::WrongKind),
                Some(v) => scalar_number(v, basic, prim),
            };
            match parsed {
                Ok(t) => Some(t),
                Err(_) => {
                    self.diagnostics.push(Diagnostic::new(
                        &rules::UNUSABLE_LIMIT,
                        Some(source.span),
                        format!(
                            "{where_} `{}`: the {} `{}` is not a constant {}; writes are not checked against it",
                            sub.name,
                            if is_low { "LowLimit" } else { "HighLimit" },
                            source.raw,
                            basic.name()
                        ),
                    ));
                    Some(default)
                }
            }
        };
        let low = bound(&sub.low_limit, true)?;
        let high = bound(&sub.high_limit, false)?;
        Some((low, high))
    }
}

#[cfg(test)]
mod tests {
    use super::Where;

    #[test]
    fn a_message_written_by_hand_reads_as_formatted() {
        for (index, sub) in [
            (0x1018, 1),
            (0x0000, 0),
            (0xABCD, 10),
            (0x2000, 99),
            (0xFFFF, 255),
        ] {
            let at = Where(index, sub);
            assert_eq!(
                at.message("Name", ": rest"),
                format!("{at} `Name`: rest"),
                "{index:04X}h sub {sub}"
            );
        }
        assert_eq!(Where(0x1018, 7).message("x", ""), "1018h sub 7 `x`");
    }
}
