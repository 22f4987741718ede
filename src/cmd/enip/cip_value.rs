//! CIP parameter values as a person reads and writes them at the bench, for `enip io` and
//! `enip get|set` alike: an assembly's members named, laid out as the simulated adapter lays them
//! out (`edsgen_model::model::cip_value`: from bit 0 of byte 0, each member least significant
//! bit first), and a parameter's raw bits typed by its `ParamN`
//! ([`Typed`]: signed, unsigned, BOOL, REAL, bit strings), scaled with its units (multiplier,
//! divisor, base, offset, decimal places), named by its `EnumN` texts, and text made raw bits
//! again, typed and checked against the parameter's limits, its type and its width.

use edsgen_model::model::cip_value;
use edsgen_model::model::{data_type_info, data_type_range, Cip, CipAssembly, CipEnum};
use edsgen_model::model::{CipNumber, CipParam, FieldRef};

/// One member of an assembly with its place in the image.
#[derive(Debug, Clone)]
pub struct Member<'a> {
    /// The name shown and matched: the parameter's name (`Param7` when it has none, `Assem3`
    /// for a nested assembly), with `[i]` when the name repeats in the assembly.
    pub name: String,
    /// The parameter, when the member names one the file has.
    pub param: Option<&'a CipParam>,
    /// The first bit in the image.
    pub bit: u64,
    /// The width in bits.
    pub bits: u32,
}

impl Member<'_> {
    /// Whether `wanted` (already [`fold`]ed) names this member: its name, or `ParamN` of the
    /// parameter it carries (as `enip get|set` take them).
    pub fn is_named(&self, wanted: &str) -> bool {
        fold(&self.name) == wanted
            || self
                .param
                .is_some_and(|p| fold(&format!("Param{}", p.number)) == wanted)
    }
}

/// The members of `assembly` that carry data (padding has no name and is left out).
pub fn members<'a>(cip: &'a Cip, assembly: &CipAssembly) -> Vec<Member<'a>> {
    let mut out: Vec<Member<'a>> = Vec::new();
    for place in cip_value::layout(cip, assembly) {
        let (name, param) = match &place.member.member {
            FieldRef::Param(n) => match cip.params.get(n) {
                Some(p) if !p.name.trim().is_empty() => (p.name.trim().to_owned(), Some(p)),
                p => (format!("Param{n}"), p),
            },
            FieldRef::Assem(n) => (format!("Assem{n}"), None),
            _ => continue,
        };
        if place.bits > 0 {
            out.push(Member {
                name,
                param,
                bit: place.bit,
                bits: place.bits,
            });
        }
    }
    // Repeated names get their index among their namesakes.
    let names: Vec<String> = out.iter().map(|m| m.name.clone()).collect();
    for (i, m) in out.iter_mut().enumerate() {
        let same: Vec<usize> = (0..names.len()).filter(|&j| names[j] == names[i]).collect();
        if same.len() > 1 {
            let k = same.iter().position(|&j| j == i).unwrap_or(0);
            m.name = format!("{}[{k}]", names[i]);
        }
    }
    out
}

/// `name` folded for matching: lower case, every run of other characters than letters and
/// digits one `_` (`Received PZD2`, `received_pzd2` and `received-pzd2` match).
pub fn fold(name: &str) -> String {
    let mut out = String::new();
    for c in name.trim().chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.trim_matches('_').to_owned()
}

pub use edsgen_model::model::cip_value::{get_bits, put_bits};

/// How a value's raw bits read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// USINT, UINT, UDINT, ULINT, BOOL.
    Unsigned,
    /// SINT, INT, DINT, LINT.
    Signed,
    /// REAL (32 bits) or LREAL (64 bits).
    Real,
    /// BYTE, WORD, DWORD, LWORD, values of no parameter or of a type without a range (strings,
    /// dates, ...), and values wider than 64 bits: shown in hex.
    BitString,
}

/// A parameter's value type, as wide as the value at hand (its data size on its own, or its
/// member's bits in an assembly): how its raw bits read and how text becomes raw bits.
#[derive(Debug, Clone, Copy)]
pub struct Typed<'a> {
    /// The parameter, if the value has one.
    pub param: Option<&'a CipParam>,
    /// Its `EnumN`, if the file gives one.
    pub enumeration: Option<&'a CipEnum>,
    /// How the bits read.
    pub kind: Kind,
    /// The width in bits.
    pub bits: u32,
}

/// A raw value read as a number.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Number {
    Int(i128),
    Real(f64),
}

impl Number {
    fn as_f64(self) -> f64 {
        match self {
            Number::Int(v) => v as f64,
            Number::Real(v) => v,
        }
    }
}

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Number::Int(v) => write!(f, "{v}"),
            Number::Real(v) => write!(f, "{v}"),
        }
    }
}

fn signed(raw: u64, bits: u32) -> i64 {
    if bits == 0 || bits >= 64 {
        return raw as i64;
    }
    let shift = 64 - bits;
    ((raw << shift) as i64) >> shift
}

fn mask(bits: u32) -> u64 {
    if bits >= 64 {
        u64::MAX
    } else {
        (1 << bits) - 1
    }
}

/// Lower case without white space: how enumeration texts compare.
fn key(text: &str) -> String {
    text.chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect()
}

impl<'a> Typed<'a> {
    /// The parameter `p` on its own (an attribute): as wide as its data size (else its type's).
    pub fn param(cip: &'a Cip, p: &'a CipParam) -> Typed<'a> {
        let code = p.data_type.as_ref().map(|t| t.value);
        let bytes = match &p.data_size {
            Some(size) => size.value,
            None => code
                .and_then(data_type_info)
                .and_then(|(_, size)| size)
                .unwrap_or(0),
        };
        Typed::of(cip, Some(p), bytes.saturating_mul(8))
    }

    /// A member of an assembly, as wide as its bits.
    pub fn member(cip: &'a Cip, member: &Member<'a>) -> Typed<'a> {
        Typed::of(cip, member.param, member.bits)
    }

    /// A value `bits` wide of `param` (or of none).
    pub fn of(cip: &'a Cip, param: Option<&'a CipParam>, bits: u32) -> Typed<'a> {
        let code = param.and_then(|p| p.data_type.as_ref()).map(|t| t.value);
        let kind = match code {
            _ if bits > 64 => Kind::BitString,
            Some(0xCA) if bits == 32 => Kind::Real,
            Some(0xCB) if bits == 64 => Kind::Real,
            Some(0xD1..=0xD4) => Kind::BitString,
            Some(c) if data_type_range(c).is_none() => Kind::BitString,
            None => Kind::BitString,
            Some(0xC2..=0xC5) => Kind::Signed,
            Some(_) => Kind::Unsigned,
        };
        Typed {
            param,
            enumeration: param.and_then(|p| cip.enums.get(&p.number)),
            kind,
            bits,
        }
    }

    /// The raw bits of a value's little-endian `bytes` (as many bytes as the value is wide).
    pub fn raw(&self, bytes: &[u8]) -> Result<u64, String> {
        let len = self.bits.div_ceil(8) as usize;
        if bytes.len() != len {
            return Err(format!(
                "{} bytes received where the data type has {len}",
                bytes.len()
            ));
        }
        let mut wide = [0u8; 8];
        wide[..len.min(8)].copy_from_slice(&bytes[..len.min(8)]);
        Ok(u64::from_le_bytes(wide) & mask(self.bits))
    }

    /// The little-endian bytes of `raw`, as many as the value is wide.
    pub fn bytes(&self, raw: u64) -> Vec<u8> {
        let len = (self.bits.div_ceil(8) as usize).min(8);
        raw.to_le_bytes()[..len].to_vec()
    }

    fn number(&self, raw: u64) -> Option<Number> {
        let raw = raw & mask(self.bits);
        match self.kind {
            Kind::BitString => None,
            Kind::Signed => Some(Number::Int(i128::from(signed(raw, self.bits)))),
            Kind::Unsigned => Some(Number::Int(i128::from(raw))),
            Kind::Real if self.bits == 32 => {
                Some(Number::Real(f64::from(f32::from_bits(raw as u32))))
            }
            Kind::Real => Some(Number::Real(f64::from_bits(raw))),
        }
    }

    /// The scaling `(multiplier, divisor, base, offset)` when the EDS gives one that changes
    /// the value, or decimal places; a factor of 0 counts as 1.
    fn scaling(&self) -> Option<(f64, f64, f64, f64)> {
        let p = self.param?;
        let [mult, div, base, offset] = p.scaling;
        let scaled = p.decimals.is_some_and(|d| d > 0)
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

    /// A native value in engineering units, with the parameter's decimal places.
    fn engineering(&self, native: f64) -> Option<String> {
        let (mult, div, base, offset) = self.scaling()?;
        let decimals = self.param.and_then(|p| p.decimals).unwrap_or(0) as usize;
        Some(format!(
            "{:.decimals$}",
            (native + offset) * mult * base / div
        ))
    }

    fn units(&self) -> String {
        match self.param.map_or("", |p| p.units.trim()) {
            "" => String::new(),
            units => format!(" {units}"),
        }
    }

    /// The text of `raw` in the parameter's enumeration.
    fn named(&self, raw: u64) -> Option<&'a str> {
        let value = match self.number(raw) {
            Some(Number::Int(v)) => v,
            Some(Number::Real(_)) => return None,
            None => i128::from(raw & mask(self.bits)),
        };
        let e = self.enumeration?;
        let (_, text) = e.values.iter().find(|(v, _)| i128::from(*v) == value)?;
        Some(text)
    }

    fn hex(&self, raw: u64) -> String {
        format!(
            "0x{:0width$X}",
            raw & mask(self.bits),
            width = self.bits.div_ceil(4) as usize
        )
    }

    /// `raw` in a few characters, as `enip io` lines show values: the enumeration's text, else
    /// scaled with its decimals and units, else the number (bit strings in hex).
    pub fn brief(&self, raw: u64) -> String {
        if let Some(text) = self.named(raw) {
            return text.to_owned();
        }
        let units = self.units();
        match self.number(raw) {
            None => format!("{}{units}", self.hex(raw)),
            Some(n) => match self.engineering(n.as_f64()) {
                Some(value) => format!("{value}{units}"),
                None => format!("{n}{units}"),
            },
        }
    }

    /// `raw` in full, as `enip get` shows values: scaled with units and the raw value
    /// (`150.0 rpm (raw 1500)`), else integers and bit strings with their hex (`16643
    /// (0x4103)`), reals as numbers; then the enumeration's text, quoted.
    pub fn full(&self, raw: u64) -> String {
        let units = self.units();
        let number = self
            .number(raw)
            .unwrap_or(Number::Int(i128::from(raw & mask(self.bits))));
        let mut text = match (self.engineering(number.as_f64()), number) {
            (Some(value), _) => format!("{value}{units} (raw {number})"),
            (None, Number::Int(_)) => format!("{number} ({}){units}", self.hex(raw)),
            (None, Number::Real(_)) => format!("{number}{units}"),
        };
        if let Some(name) = self.named(raw) {
            text.push_str(&format!(" \"{name}\""));
        }
        text
    }

    /// `; it takes 0 "Off", 1 "Slow", ...` when the parameter has an enumeration.
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

    /// The raw bits of `text`: an enumeration's text (any case and spacing, or a unique prefix
    /// of one), `true`/`false` for BOOL, `0x` hex (raw bits), else a number in the parameter's
    /// engineering units when it is scaled (a whole step of it), else a number of its type;
    /// within the parameter's limits, its type's range and its width.
    pub fn parse(&self, text: &str) -> Result<u64, String> {
        let text = text.trim();
        if self.bits > 64 {
            return Err(format!("a value of {} bits is not set by value", self.bits));
        }
        if let Some(v) = self.enum_value(text) {
            return self.checked(text, Number::Int(i128::from(v)), false);
        }
        let boolean = self
            .param
            .and_then(|p| p.data_type.as_ref())
            .is_some_and(|t| t.value == 0xC1);
        match text {
            "true" if boolean => return Ok(1),
            "false" if boolean => return Ok(0),
            _ => {}
        }
        if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
            let raw = u64::from_str_radix(hex, 16).map_err(|_| format!("`{text}` is not hex"))?;
            if raw & !mask(self.bits) != 0 {
                return Err(format!("{text} has more than {} bits", self.bits));
            }
            return match self.number(raw) {
                Some(Number::Real(_)) => Ok(raw),
                Some(n) => self.checked(text, n, true),
                None => self.checked(text, Number::Int(i128::from(raw)), true),
            };
        }
        let not_a_number = || format!("`{text}` is not a number{}", self.enum_hint());
        if let Some((mult, div, base, offset)) = self.scaling() {
            let value: f64 = text.parse().map_err(|_| not_a_number())?;
            let native = value * div / (mult * base) - offset;
            if self.kind == Kind::Real {
                return self.checked(text, Number::Real(native), false);
            }
            return self.checked(text, self.whole(native)?, false);
        }
        if self.kind == Kind::Real {
            let value: f64 = text.parse().map_err(|_| not_a_number())?;
            return self.checked(text, Number::Real(value), false);
        }
        match text.parse::<i128>() {
            Ok(v) => self.checked(text, Number::Int(v), false),
            Err(_) => {
                let value: f64 = text.parse().map_err(|_| not_a_number())?;
                self.checked(text, self.whole(value)?, false)
            }
        }
    }

    /// The value an enumeration text (or a unique prefix of one) names.
    fn enum_value(&self, text: &str) -> Option<i64> {
        let e = self.enumeration?;
        let wanted = key(text);
        if wanted.is_empty() {
            return None;
        }
        if let Some((v, _)) = e.values.iter().find(|(_, name)| key(name) == wanted) {
            return Some(*v);
        }
        let mut prefixed = e
            .values
            .iter()
            .filter(|(_, name)| key(name).starts_with(&wanted));
        match (prefixed.next(), prefixed.next()) {
            (Some((v, _)), None) => Some(*v),
            _ => None,
        }
    }

    /// A native value that must be a whole raw step.
    fn whole(&self, native: f64) -> Result<Number, String> {
        let rounded = native.round();
        if !native.is_finite() || (rounded - native).abs() > 1e-6 * native.abs().max(1.0) {
            return Err(format!("not a whole step of the parameter ({native} raw)"));
        }
        // Beyond every 64-bit range: refused by the range check below, never wrapped.
        Ok(Number::Int(rounded.clamp(-1e20, 1e20) as i128))
    }

    /// `value` (native) checked against the parameter's limits, its type's range and the
    /// width; its raw bits. `hex`: the text was raw bits, so the limits are said raw.
    fn checked(&self, text: &str, value: Number, hex: bool) -> Result<u64, String> {
        let limit = |n: Option<&edsgen_model::model::Spanned<CipNumber>>| {
            n.map(|n| match n.value {
                CipNumber::Int(v) => Number::Int(v),
                CipNumber::Real(v) => Number::Real(v),
            })
        };
        let (mut low, mut high) = (
            limit(self.param.and_then(|p| p.min.as_ref())),
            limit(self.param.and_then(|p| p.max.as_ref())),
        );
        let bits = self.bits.clamp(1, 64);
        if self.kind != Kind::Real {
            let (mut l, mut h) = match self.kind {
                Kind::Signed => (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1),
                _ => (0, (1i128 << bits) - 1),
            };
            let code = self
                .param
                .and_then(|p| p.data_type.as_ref())
                .map(|t| t.value);
            if let Some((tl, th)) = code.and_then(data_type_range) {
                (l, h) = (l.max(tl), h.min(th));
            }
            let (pl, ph) = (
                low.map_or(l as f64, Number::as_f64),
                high.map_or(h as f64, Number::as_f64),
            );
            low = Some(Number::Int(l.max(pl.ceil() as i128)));
            high = Some(Number::Int(h.min(ph.floor() as i128)));
        }
        let v = value.as_f64();
        let outside = !v.is_finite()
            || low.is_some_and(|l| v < l.as_f64())
            || high.is_some_and(|h| v > h.as_f64())
            || matches!((value, low, high), (Number::Int(v), Some(Number::Int(l)), Some(Number::Int(h))) if v < l || v > h);
        if outside {
            let show = |n: Option<Number>| match (n, hex) {
                (Some(n), false) => self
                    .engineering(n.as_f64())
                    .unwrap_or_else(|| n.to_string()),
                (Some(n), true) => n.to_string(),
                (None, _) => "?".to_owned(),
            };
            let range = format!("{} ..= {}", show(low), show(high));
            return Err(if hex {
                format!("{text} ({value} raw) is outside {range} raw")
            } else {
                format!("{text} is outside {range}{}", self.units())
            });
        }
        Ok(match value {
            Number::Real(v) if self.bits == 32 => u64::from((v as f32).to_bits()),
            Number::Real(v) if self.kind == Kind::Real => v.to_bits(),
            Number::Real(v) => (v as i64 as u64) & mask(self.bits),
            Number::Int(v) => (v as i64 as u64) & mask(self.bits),
        })
    }

    /// The raw bits of the parameter's default, if it has one of this kind.
    fn default(&self) -> Option<u64> {
        let default = self.param?.default.as_ref()?.value;
        Some(match (default, self.kind) {
            (CipNumber::Real(v), Kind::Real) if self.bits == 32 => u64::from((v as f32).to_bits()),
            (CipNumber::Real(v), Kind::Real) => v.to_bits(),
            (CipNumber::Int(v), Kind::Real) if self.bits == 32 => u64::from((v as f32).to_bits()),
            (CipNumber::Int(v), Kind::Real) => (v as f64).to_bits(),
            (CipNumber::Int(v), _) => (v as i64 as u64) & mask(self.bits),
            (CipNumber::Real(_), _) => return None,
        })
    }
}

/// The member's value in `image` as `enip io` shows it ([`Typed::brief`]; a member wider than
/// 64 bits in hex, most significant byte first).
pub fn show(cip: &Cip, member: &Member<'_>, image: &[u8]) -> String {
    if member.bits > 64 {
        let bytes = (0..u64::from(member.bits).div_ceil(8))
            .map(|i| get_bits(image, member.bit + 8 * i, 8) as u8);
        return format!(
            "0x{}",
            bytes.rev().map(|b| format!("{b:02X}")).collect::<String>()
        );
    }
    Typed::member(cip, member).brief(get_bits(image, member.bit, member.bits))
}

/// The assembly's bytes with every member at its parameter's default (members without one,
/// and padding, zero).
pub fn defaults(cip: &Cip, members: &[Member<'_>], size: usize) -> Vec<u8> {
    let mut image = vec![0u8; size];
    for m in members {
        if let Some(raw) = Typed::member(cip, m).default() {
            put_bits(&mut image, m.bit, m.bits, raw);
        }
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Cip {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/enip/io.eds");
        let read = edsgen_model::read::read_file(&path).expect("tests/enip/io.eds");
        read.device.cip().cloned().expect("an ODVA EDS")
    }

    #[test]
    fn members_are_laid_out_as_cip_packs_them() {
        let cip = model();
        let outputs = members(&cip, &cip.assemblies[&150]);
        let layout: Vec<(&str, u64, u32)> = outputs
            .iter()
            .map(|m| (m.name.as_str(), m.bit, m.bits))
            .collect();
        // Seven bits of padding between Enable and Gain have no member.
        assert_eq!(
            layout,
            [
                ("Mode", 0, 8),
                ("Setpoint", 8, 16),
                ("Enable", 24, 1),
                ("Gain", 32, 32)
            ]
        );
        let named = |wanted: &str| {
            let wanted = fold(wanted);
            outputs.iter().position(|m| m.is_named(&wanted))
        };
        assert_eq!(
            [
                named("gain"),
                named("Param3"),
                named("PARAM4"),
                named("Param5")
            ],
            [Some(3), Some(3), Some(2), None]
        );
        assert_eq!(
            defaults(&cip, &outputs, 8),
            [0x00, 0xE7, 0xFF, 0x00, 0x00, 0x00, 0xC0, 0x3F]
        );
    }

    #[test]
    fn values_shown_and_parsed_back() {
        let cip = model();
        let outputs = members(&cip, &cip.assemblies[&150]);
        let inputs = members(&cip, &cip.assemblies[&100]);
        let image = [0x02, 0x83, 0xFF, 0x01, 0x00, 0x00, 0x10, 0x40];
        let shown: Vec<String> = outputs.iter().map(|m| show(&cip, m, &image)).collect();
        assert_eq!(shown, ["Fast", "-12.5 bar", "1", "2.25"]);
        let typed: Vec<Typed<'_>> = outputs.iter().map(|m| Typed::member(&cip, m)).collect();
        for ((m, t), text) in outputs.iter().zip(&typed).zip(&shown) {
            let value = text.strip_suffix(" bar").unwrap_or(text);
            assert_eq!(
                t.parse(value),
                Ok(get_bits(&image, m.bit, m.bits)),
                "{}",
                m.name
            );
        }
        // In full: scaled with the raw value, enumerations quoted, REALs as numbers.
        let full: Vec<String> = outputs
            .iter()
            .zip(&typed)
            .map(|(m, t)| t.full(get_bits(&image, m.bit, m.bits)))
            .collect();
        assert_eq!(
            full,
            [
                "2 (0x02) \"Fast\"",
                "-12.5 bar (raw -125)",
                "1 (0x1)",
                "2.25"
            ]
        );
        // An enumeration value without a text is its number; a WORD is hex; signed with units.
        let image = [0x03, 0x41, 0x9C, 0xFF, 0x07];
        let brief: Vec<String> = inputs.iter().map(|m| show(&cip, m, &image)).collect();
        assert_eq!(brief, ["0x4103", "-100 degC", "7"]);
        assert_eq!(
            Typed::member(&cip, &inputs[0]).full(0x4103),
            "16643 (0x4103)"
        );
        let [mode, setpoint, enable, gain] = &typed[..] else {
            panic!("four outputs");
        };
        assert_eq!(mode.parse("SLOW"), Ok(1));
        assert_eq!(mode.parse("s"), Ok(1), "a unique prefix");
        assert_eq!(setpoint.parse("0xFFE7"), Ok(0xFFE7));
        assert_eq!(setpoint.parse("-2.5"), Ok(0xFFE7));
        assert_eq!(enable.parse("true"), Ok(1));
        assert_eq!(gain.parse("11"), Err("11 is outside 0 ..= 10".to_owned()));
        assert_eq!(gain.parse("0.5"), Ok(u64::from(0.5f32.to_bits())));
        assert_eq!(enable.parse("2"), Err("2 is outside 0 ..= 1".to_owned()));
        assert_eq!(
            setpoint.parse("100.1"),
            Err("100.1 is outside -100.0 ..= 100.0 bar".to_owned())
        );
        assert_eq!(
            setpoint.parse("0x8000"),
            Err("0x8000 (-32768 raw) is outside -1000 ..= 1000 raw".to_owned())
        );
        assert_eq!(
            mode.parse("0x100"),
            Err("0x100 has more than 8 bits".to_owned())
        );
        assert_eq!(
            mode.parse("Medium"),
            Err("`Medium` is not a number; it takes 0 \"Off\", 1 \"Slow\", 2 \"Fast\"".to_owned())
        );
        assert_eq!(
            setpoint.parse("1e300"),
            Err("1e300 is outside -100.0 ..= 100.0 bar".to_owned())
        );
    }

    #[test]
    fn names_fold_and_bits_round_trip() {
        assert_eq!(fold("  Received PZD2 "), "received_pzd2");
        assert_eq!(fold("received-pzd2"), "received_pzd2");
        assert_eq!(fold("PKW1 (task)"), "pkw1_task");
        let mut buf = [0u8; 3];
        put_bits(&mut buf, 4, 12, 0xABC);
        assert_eq!(buf, [0xC0, 0xAB, 0x00]);
        assert_eq!(get_bits(&buf, 4, 12), 0xABC);
        assert_eq!(get_bits(&buf, 20, 12), 0, "bits past the end read as zero");
    }

    proptest::proptest! {
        #[test]
        fn any_text_is_taken_or_refused_without_a_panic(text in "\\PC{0,16}") {
            let cip = model();
            for assembly in [100, 150] {
                for m in members(&cip, &cip.assemblies[&assembly]) {
                    let typed = Typed::member(&cip, &m);
                    if let Ok(raw) = typed.parse(&text) {
                        proptest::prop_assert_eq!(raw & !mask(m.bits.min(64)), 0);
                    }
                }
            }
        }
    }
}
