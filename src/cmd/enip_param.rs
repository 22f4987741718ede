//! A parameter of an ODVA EDS's `[Params]` as `edsgen enip get|set` takes it: found by name
//! (exact or unique prefix, case- and space-insensitive, or `ParamN`; suggestions on a miss),
//! where it lives on the device (the attribute its link path names; else the bits of the
//! assembly it is a member of; else attribute 1 of its Parameter object instance, `@0x0F/N/1`),
//! and its value shown typed (scaled with its decimals and units, with its `EnumN` text) and
//! taken typed and range-checked.

use edsgen_codegen::model::{
    data_type_range, decode_path, Cip, CipEnum, CipNumber, CipParam, FieldRef,
};

use super::value::{parse_int, Kind};

/// Where a parameter's value is on the device.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Access {
    /// An attribute: the request path's bytes (the link path, or the Parameter object's).
    Attribute(Vec<u8>),
    /// Bits of an assembly (attribute 3 of its instance), from `offset`, `bits` long.
    Member {
        /// The Assembly object instance.
        instance: u32,
        /// The first bit.
        offset: usize,
        /// The number of bits.
        bits: usize,
    },
}

/// A parameter resolved against its EDS.
#[derive(Debug, Clone)]
pub struct Param<'a> {
    /// Its `[Params]` entry.
    pub param: &'a CipParam,
    /// Its `EnumN`, if the file gives one.
    pub enumeration: Option<&'a CipEnum>,
    /// How its bytes read.
    pub kind: Kind,
    /// Where it is.
    pub access: Access,
}

/// Lower case without white space: how names compare.
fn key(name: &str) -> String {
    name.chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect()
}

/// The kind of a CIP data type code: integers and bit strings as integers, REAL/LREAL as reals,
/// anything else as bytes.
fn kind_of(code: u8, size: usize) -> Kind {
    match code {
        0xC1 => Kind::Boolean,
        0xC2..=0xC5 => Kind::Signed(size),
        0xC6..=0xC9 | 0xD1..=0xD4 => Kind::Unsigned(size),
        0xCA => Kind::Real32,
        0xCB => Kind::Real64,
        _ => Kind::Bytes,
    }
}

/// The parameter of `cip` that `text` names.
pub fn resolve<'a>(cip: &'a Cip, text: &str) -> Result<Param<'a>, String> {
    let param = by_name(cip, text)?;
    let code = param.data_type.as_ref().map_or(0, |t| t.value);
    let size = match param.data_size.as_ref() {
        Some(s) => s.value as usize,
        None => edsgen_codegen::model::data_type_info(code)
            .and_then(|(_, size)| size)
            .unwrap_or(0) as usize,
    };
    let kind = kind_of(code, size);
    let access = access(cip, param)?;
    Ok(Param {
        param,
        enumeration: cip.enums.get(&param.number),
        kind,
        access,
    })
}

fn by_name<'a>(cip: &'a Cip, text: &str) -> Result<&'a CipParam, String> {
    let wanted = key(text);
    let params: Vec<&CipParam> = cip.params.values().collect();
    if let Some(p) = params
        .iter()
        .find(|p| key(&format!("Param{}", p.number)) == wanted)
    {
        return Ok(p);
    }
    let exact: Vec<&CipParam> = params
        .iter()
        .copied()
        .filter(|p| key(&p.name) == wanted)
        .collect();
    let prefixed: Vec<&CipParam> = params
        .iter()
        .copied()
        .filter(|p| key(&p.name).starts_with(&wanted))
        .collect();
    let candidates = if exact.is_empty() { prefixed } else { exact };
    match candidates.as_slice() {
        [one] => Ok(one),
        [] => {
            let mut near: Vec<&CipParam> = params
                .iter()
                .copied()
                .filter(|p| !wanted.is_empty() && key(&p.name).contains(&wanted))
                .collect();
            if near.is_empty() {
                let mut scored: Vec<(usize, &CipParam)> = params
                    .iter()
                    .map(|p| (strsim::levenshtein(&wanted, &key(&p.name)), *p))
                    .filter(|(d, _)| *d <= wanted.chars().count().div_ceil(3))
                    .collect();
                scored.sort_by_key(|(d, p)| (*d, p.number));
                near = scored.into_iter().map(|(_, p)| p).collect();
            }
            Err(format!(
                "the EDS has no parameter named `{text}`{}",
                suggestions(&near)
            ))
        }
        many => Err(format!(
            "`{text}` names {} parameters{}",
            many.len(),
            suggestions(many)
        )),
    }
}

/// `; did you mean:` and up to eight parameters as `ParamN  name`, or nothing.
fn suggestions(params: &[&CipParam]) -> String {
    const SHOWN: usize = 8;
    if params.is_empty() {
        return String::new();
    }
    let mut list: Vec<String> = params
        .iter()
        .take(SHOWN)
        .map(|p| format!("  Param{}  {}", p.number, p.name))
        .collect();
    if params.len() > SHOWN {
        list.push(format!("  ... and {} more", params.len() - SHOWN));
    }
    format!("; did you mean:\n{}", list.join("\n"))
}

/// Where `param` lives: its link path, else the first assembly that has it as a member, else its
/// Parameter object instance.
fn access(cip: &Cip, param: &CipParam) -> Result<Access, String> {
    if let Some(path) = param
        .link_path
        .as_ref()
        .filter(|p| !p.value.trim().is_empty())
    {
        let bad = || {
            format!(
                "Param{}'s link path `{}` is no EPATH",
                param.number, path.value
            )
        };
        decode_path(&path.value).map_err(|_| bad())?;
        let mut bytes: Vec<u8> = path
            .value
            .split_whitespace()
            .map(|t| u8::from_str_radix(t, 16))
            .collect::<Result<_, _>>()
            .map_err(|_| bad())?;
        if bytes.len() % 2 == 1 {
            bytes.push(0);
        }
        return Ok(Access::Attribute(bytes));
    }
    for assembly in cip.assemblies.values() {
        let mut offset = 0usize;
        for member in &assembly.members {
            let bits = match (member.bits, &member.member) {
                (Some(bits), _) => bits as usize,
                (None, &FieldRef::Param(n)) => cip
                    .params
                    .get(&n)
                    .and_then(|p| p.data_size.as_ref())
                    .map_or(0, |s| 8 * s.value as usize),
                (None, _) => 0,
            };
            if member.member == FieldRef::Param(param.number) {
                return Ok(Access::Member {
                    instance: assembly.instance(),
                    offset,
                    bits,
                });
            }
            offset += bits;
        }
    }
    let mut path = vec![0x20, 0x0F];
    match u8::try_from(param.number) {
        Ok(n) => path.extend_from_slice(&[0x24, n]),
        Err(_) => {
            let n = u16::try_from(param.number)
                .map_err(|_| format!("Param{} has no instance path", param.number))?;
            path.extend_from_slice(&[0x25, 0]);
            path.extend_from_slice(&n.to_le_bytes());
        }
    }
    path.extend_from_slice(&[0x30, 0x01]);
    Ok(Access::Attribute(path))
}

/// The bits `offset..offset + bits` of `data` (little-endian, as CIP packs assemblies) as the
/// bytes of a value `len` bytes long; `None` when they run past `data`.
pub fn extract(data: &[u8], offset: usize, bits: usize, len: usize) -> Option<Vec<u8>> {
    if offset + bits > 8 * data.len() {
        return None;
    }
    let mut out = vec![0u8; len.max(bits.div_ceil(8))];
    for i in 0..bits {
        if data[(offset + i) / 8] >> ((offset + i) % 8) & 1 != 0 {
            out[i / 8] |= 1 << (i % 8);
        }
    }
    Some(out)
}

/// `data` with the bits `offset..offset + bits` replaced by the low bits of `value`; `None` when
/// they run past `data`.
pub fn patch(data: &[u8], offset: usize, bits: usize, value: &[u8]) -> Option<Vec<u8>> {
    if offset + bits > 8 * data.len() {
        return None;
    }
    let mut out = data.to_vec();
    for i in 0..bits {
        let on = value.get(i / 8).is_some_and(|b| b >> (i % 8) & 1 != 0);
        let (byte, bit) = ((offset + i) / 8, (offset + i) % 8);
        if on {
            out[byte] |= 1 << bit;
        } else {
            out[byte] &= !(1 << bit);
        }
    }
    Some(out)
}

impl Param<'_> {
    /// `ParamN name`, as the output names it.
    pub fn label(&self) -> String {
        format!("Param{} {}", self.param.number, self.param.name)
    }

    /// The scaling `(multiplier, divisor, base, offset)` when the EDS gives one that changes the
    /// value, or decimal places.
    fn scaling(&self) -> Option<(f64, f64, f64, f64)> {
        let [mult, div, base, offset] = self.param.scaling;
        let scaled = self.param.decimals.is_some_and(|d| d > 0)
            || [mult, div, base].iter().any(|v| v.is_some_and(|v| v != 1))
            || offset.is_some_and(|v| v != 0);
        let factor = |v: Option<i64>| v.filter(|v| *v != 0).unwrap_or(1) as f64;
        scaled.then(|| {
            (
                factor(mult),
                factor(div),
                factor(base),
                offset.unwrap_or(0) as f64,
            )
        })
    }

    /// An integer as the engineering value, with its decimals.
    fn engineering(&self, raw: i128) -> Option<String> {
        let (mult, div, base, offset) = self.scaling()?;
        let value = (raw as f64 + offset) * mult * base / div;
        let decimals = self.param.decimals.unwrap_or(0) as usize;
        Some(format!("{value:.decimals$}"))
    }

    fn units(&self) -> String {
        match self.param.units.trim() {
            "" => String::new(),
            units => format!(" {units}"),
        }
    }

    /// The raw integer in `bytes` (a value of this parameter's kind), if it is an integer.
    fn integer(&self, bytes: &[u8]) -> Option<i128> {
        let n = match self.kind {
            Kind::Unsigned(n) | Kind::Signed(n) => n,
            Kind::Boolean => 1,
            _ => return None,
        };
        let mut wide = [0u8; 8];
        let len = bytes.len().min(n).min(8);
        wide[..len].copy_from_slice(&bytes[..len]);
        let raw = u64::from_le_bytes(wide);
        Some(match self.kind {
            Kind::Signed(n) => {
                let shift = 64 - 8 * n.min(8) as u32;
                i128::from(((raw << shift) as i64) >> shift)
            }
            _ => i128::from(raw),
        })
    }

    /// The value in `bytes` as text: scaled with units (and the raw value), or the kind's own
    /// text; then the enumeration's text for it, quoted.
    pub fn show(&self, bytes: &[u8]) -> Result<String, String> {
        let raw = self.integer(bytes);
        let mut text = match raw.and_then(|r| Some((r, self.engineering(r)?))) {
            Some((raw, value)) => format!("{value}{} (raw {raw})", self.units()),
            None => format!("{}{}", self.kind.show(bytes)?, self.units()),
        };
        let named = self
            .enumeration
            .zip(raw)
            .and_then(|(e, raw)| e.values.iter().find(|(v, _)| i128::from(*v) == raw));
        if let Some((_, name)) = named {
            text.push_str(&format!(" \"{name}\""));
        }
        Ok(text)
    }

    /// The limits as the EDS gives them (else the data type's), as text in engineering units.
    fn range_text(&self, min: i128, max: i128) -> String {
        let show = |v: i128| self.engineering(v).unwrap_or_else(|| v.to_string());
        format!("{} ..= {}{}", show(min), show(max), self.units())
    }

    /// The bytes of the value `text`: an enumeration's text (or a unique prefix of one), an
    /// engineering value when the parameter is scaled, else a number of its type; within its
    /// limits.
    pub fn encode(&self, text: &str) -> Result<Vec<u8>, String> {
        let label = self.label();
        let code = self.param.data_type.as_ref().map_or(0, |t| t.value);
        let Some((type_min, type_max)) = data_type_range(code) else {
            if let (Kind::Real32 | Kind::Real64, Ok(v)) = (self.kind, text.parse::<f64>()) {
                let number = |n: &Option<edsgen_codegen::model::Spanned<CipNumber>>| {
                    n.as_ref().map(|n| n.value.as_f64())
                };
                let (min, max) = (number(&self.param.min), number(&self.param.max));
                if min.is_some_and(|m| v < m) || max.is_some_and(|m| v > m) {
                    return Err(format!(
                        "{label}: {text} is outside {} ..= {}{}",
                        min.map_or("-inf".into(), |m| m.to_string()),
                        max.map_or("inf".into(), |m| m.to_string()),
                        self.units()
                    ));
                }
            }
            return self.kind.encode(text).map_err(|m| format!("{label}: {m}"));
        };
        let limit = |n: &Option<edsgen_codegen::model::Spanned<CipNumber>>, or: i128| match n
            .as_ref()
            .map(|n| n.value)
        {
            Some(CipNumber::Int(v)) => v,
            _ => or,
        };
        let (min, max) = (
            limit(&self.param.min, type_min),
            limit(&self.param.max, type_max),
        );
        let named = self.enumeration.and_then(|e| {
            let wanted = key(text);
            let exact = e.values.iter().find(|(_, name)| key(name) == wanted);
            let mut prefixed = e
                .values
                .iter()
                .filter(|(_, name)| !wanted.is_empty() && key(name).starts_with(&wanted));
            let unique = match (prefixed.next(), prefixed.next()) {
                (Some(one), None) => Some(one),
                _ => None,
            };
            exact.or(unique).map(|(v, _)| i128::from(*v))
        });
        let raw = match (named, self.scaling()) {
            (Some(v), _) => v,
            (None, Some((mult, div, base, offset))) => {
                let value: f64 = text.trim().parse().map_err(|_| {
                    format!("{label}: `{text}` is not a number{}", self.enum_hint())
                })?;
                let raw = (value * div / (mult * base) - offset).round();
                if !raw.is_finite() || raw.abs() > 1e30 {
                    return Err(format!(
                        "{label}: {text} is outside {}",
                        self.range_text(min, max)
                    ));
                }
                raw as i128
            }
            (None, None) => parse_int(text.trim()).ok_or_else(|| {
                format!(
                    "{label}: `{text}` is not a value of type {}{}",
                    self.kind.name(),
                    self.enum_hint()
                )
            })?,
        };
        if !(min..=max).contains(&raw) {
            return Err(format!(
                "{label}: {text} is outside {}",
                self.range_text(min, max)
            ));
        }
        let len = self.kind.len().unwrap_or(8).min(8);
        Ok((raw as i64).to_le_bytes()[..len].to_vec())
    }

    /// `; it takes: 0 "Off", ...` when the parameter has an enumeration.
    fn enum_hint(&self) -> String {
        match self.enumeration {
            Some(e) => {
                let values: Vec<String> = e
                    .values
                    .iter()
                    .map(|(v, name)| format!("{v} \"{name}\""))
                    .collect();
                format!("; it takes {}", values.join(", "))
            }
            None => String::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn members_cut_from_and_written_into_their_assembly() {
        // Bits 4..16 of 34 12 ..: 0x123 (as CIP packs members, little-endian from bit 0).
        let data = [0x34, 0x12, 0xFF];
        assert_eq!(extract(&data, 4, 12, 2), Some(vec![0x23, 0x01]));
        assert_eq!(extract(&data, 16, 8, 1), Some(vec![0xFF]));
        assert_eq!(extract(&data, 16, 16, 2), None);
        assert_eq!(
            patch(&data, 4, 12, &[0xCD, 0x0A]),
            Some(vec![0xD4, 0xAC, 0xFF])
        );
        assert_eq!(patch(&data, 8, 8, &[0]), Some(vec![0x34, 0x00, 0xFF]));
        assert_eq!(patch(&data, 20, 8, &[0]), None);
    }

    fn io() -> Cip {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("codegen/tests/odva/io.eds");
        let read = edsgen_codegen::read::read_file(&path).expect("io.eds reads");
        read.device.cip.expect("an ODVA EDS")
    }

    #[test]
    fn where_parameters_are_and_how_their_values_read() {
        let cip = io();
        let speed = resolve(&cip, "SPEED").expect("Speed");
        assert_eq!(
            speed.access,
            Access::Member {
                instance: 100,
                offset: 0,
                bits: 16
            }
        );
        assert_eq!(speed.kind, Kind::Unsigned(2));
        assert_eq!(
            speed.show(&[0xDC, 0x05]).as_deref(),
            Ok("150.0 rpm (raw 1500)")
        );
        // Engineering values round to the nearest raw value.
        assert_eq!(speed.encode("12.34"), Ok(vec![123, 0]));
        assert_eq!(
            speed.encode("0x10"),
            Err("Param1 Speed: `0x10` is not a number".into())
        );
        let mode = resolve(&cip, "param2").expect("Mode");
        assert_eq!(
            mode.access,
            Access::Member {
                instance: 100,
                offset: 16,
                bits: 8
            }
        );
        assert_eq!(mode.show(&[2]).as_deref(), Ok("2 (0x02) \"Fast\""));
        assert_eq!(mode.show(&[7]).as_deref(), Ok("7 (0x07)"));
        assert_eq!(mode.encode("SLOW"), Ok(vec![1]));
        assert_eq!(mode.encode("0x2"), Ok(vec![2]));
        // RPI: no member, no link path: its Parameter object instance.
        let rpi = resolve(&cip, "rpi").expect("RPI");
        assert_eq!(
            rpi.access,
            Access::Attribute(vec![0x20, 0x0F, 0x24, 0x03, 0x30, 0x01])
        );
        assert_eq!(
            rpi.show(&[0x50, 0xC3, 0, 0]).as_deref(),
            Ok("50000 (0x0000C350) us")
        );
        assert_eq!(
            rpi.encode("9999"),
            Err("Param3 RPI: 9999 is outside 10000 ..= 1000000 us".into())
        );
        assert_eq!(
            rpi.show(&[1, 2]),
            Err("2 bytes received where the data type has 4".into())
        );
    }

    proptest::proptest! {
        #[test]
        fn any_name_or_value_is_taken_or_refused_without_a_panic(text in "\\PC{0,12}") {
            let cip = io();
            if let Ok(param) = resolve(&cip, &text) {
                let _ = param.encode(&text);
            }
            for name in ["Speed", "Mode", "RPI"] {
                let param = resolve(&cip, name).expect("a parameter");
                let _ = param.encode(&text);
                let _ = param.show(text.as_bytes());
            }
        }

        #[test]
        fn a_member_reads_back_what_was_written(
            data in proptest::collection::vec(proptest::prelude::any::<u8>(), 1..8),
            offset in 0usize..64,
            bits in 1usize..=16,
            value: u16,
        ) {
            let patched = patch(&data, offset, bits, &value.to_le_bytes());
            if offset + bits <= 8 * data.len() {
                let patched = patched.expect("fits");
                let read = extract(&patched, offset, bits, 2).expect("fits");
                let mask = if bits == 16 { u16::MAX } else { (1 << bits) - 1 };
                proptest::prop_assert_eq!(read, (value & mask).to_le_bytes().to_vec());
            } else {
                proptest::prop_assert_eq!(patched, None);
            }
        }
    }
}
