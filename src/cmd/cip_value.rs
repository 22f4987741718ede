//! CIP parameter values as a person reads and writes them at the bench: an assembly's members
//! laid out as CIP packs them (from bit 0 of byte 0, each member least significant bit first),
//! their raw bits shown typed by their `ParamN` (signed, unsigned, REAL, bit strings in hex),
//! scaled with units (multiplier, divisor, base, offset, decimal places), or by their `EnumN`
//! text; and `VALUE` text made raw bits again, typed and range-checked.

use edsgen_codegen::model::{data_type_range, Cip, CipAssembly, CipNumber, CipParam, FieldRef};

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

/// The members of `assembly` that carry data (padding has no name and is left out).
pub fn members<'a>(cip: &'a Cip, assembly: &CipAssembly) -> Vec<Member<'a>> {
    let mut out: Vec<Member<'a>> = Vec::new();
    let mut bit = 0u64;
    for m in &assembly.members {
        let bits = m
            .bits
            .or_else(|| match &m.member {
                FieldRef::Param(n) => cip.params.get(n)?.data_size.as_ref().map(|s| s.value * 8),
                FieldRef::Assem(n) => cip
                    .assemblies
                    .get(n)
                    .and_then(|a| edsgen_codegen::validate::cip_assembly_size(cip, a))
                    .and_then(|s| u32::try_from(s * 8).ok()),
                _ => None,
            })
            .unwrap_or(0);
        let (name, param) = match &m.member {
            FieldRef::Param(n) => match cip.params.get(n) {
                Some(p) if !p.name.trim().is_empty() => (p.name.trim().to_owned(), Some(p)),
                p => (format!("Param{n}"), p),
            },
            FieldRef::Assem(n) => (format!("Assem{n}"), None),
            _ => {
                bit += u64::from(bits);
                continue;
            }
        };
        if bits > 0 {
            out.push(Member {
                name,
                param,
                bit,
                bits,
            });
        }
        bit += u64::from(bits);
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

/// Bits `at..at + len` (at most 64) of `buf`, least significant first; bits past its end are 0.
pub fn get_bits(buf: &[u8], at: u64, len: u32) -> u64 {
    let mut value = 0u64;
    for i in 0..u64::from(len.min(64)) {
        let bit = at + i;
        let on = usize::try_from(bit / 8)
            .ok()
            .and_then(|byte| buf.get(byte))
            .is_some_and(|byte| (byte >> (bit % 8)) & 1 != 0);
        if on {
            value |= 1 << i;
        }
    }
    value
}

/// Writes the low `len` bits (at most 64) of `value` at bit `at` of `buf`.
pub fn put_bits(buf: &mut [u8], at: u64, len: u32, value: u64) {
    for i in 0..u64::from(len.min(64)) {
        let bit = at + i;
        let Some(byte) = usize::try_from(bit / 8).ok().and_then(|b| buf.get_mut(b)) else {
            continue;
        };
        if (value >> i) & 1 != 0 {
            *byte |= 1 << (bit % 8);
        } else {
            *byte &= !(1 << (bit % 8));
        }
    }
}

/// How a member's bits read.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Unsigned,
    Signed,
    Real,
    /// BYTE, WORD, DWORD, LWORD, members without a parameter and members wider than 64 bits.
    BitString,
}

fn kind(member: &Member<'_>) -> Kind {
    let code = member
        .param
        .and_then(|p| p.data_type.as_ref())
        .map(|t| t.value);
    match code {
        _ if member.bits > 64 => Kind::BitString,
        None => Kind::BitString,
        Some(0xC2..=0xC5) => Kind::Signed,
        Some(0xCA) if member.bits == 32 => Kind::Real,
        Some(0xCB) if member.bits == 64 => Kind::Real,
        Some(0xD1..=0xD4) => Kind::BitString,
        Some(_) => Kind::Unsigned,
    }
}

/// The scaling of a parameter, when it has one: multiplier, divisor, base, offset, decimal
/// places. Engineering value = (raw + offset) × multiplier × base / divisor, shown with that
/// many decimal places.
fn scaling(p: &CipParam) -> Option<(f64, f64, f64, f64, usize)> {
    if p.scaling.iter().all(Option::is_none) && p.decimals.is_none() {
        return None;
    }
    let [mult, div, base, offset] = p.scaling;
    let div = div.unwrap_or(1);
    Some((
        mult.unwrap_or(1) as f64,
        if div == 0 { 1.0 } else { div as f64 },
        base.unwrap_or(1) as f64,
        offset.unwrap_or(0) as f64,
        p.decimals.unwrap_or(0) as usize,
    ))
}

fn signed(raw: u64, bits: u32) -> i64 {
    if bits == 0 || bits >= 64 {
        return raw as i64;
    }
    let shift = 64 - bits;
    ((raw << shift) as i64) >> shift
}

/// The member's value in `image`, as text: its enumeration's text, else scaled with units, else
/// the number (bit strings in hex).
pub fn show(cip: &Cip, member: &Member<'_>, image: &[u8]) -> String {
    if member.bits > 64 {
        let bytes = (0..u64::from(member.bits).div_ceil(8))
            .map(|i| get_bits(image, member.bit + 8 * i, 8) as u8);
        return format!(
            "0x{}",
            bytes.rev().map(|b| format!("{b:02X}")).collect::<String>()
        );
    }
    let raw = get_bits(image, member.bit, member.bits);
    let Some(p) = member.param else {
        return format!("0x{raw:0width$X}", width = member.bits.div_ceil(4) as usize);
    };
    let k = kind(member);
    let integer = match k {
        Kind::Signed => i128::from(signed(raw, member.bits)),
        _ => i128::from(raw),
    };
    if let Some(e) = cip.enums.get(&p.number) {
        if let Some((_, text)) = e.values.iter().find(|(v, _)| i128::from(*v) == integer) {
            return text.clone();
        }
    }
    let units = if p.units.trim().is_empty() {
        String::new()
    } else {
        format!(" {}", p.units.trim())
    };
    let number = match k {
        Kind::Real if member.bits == 32 => f64::from(f32::from_bits(raw as u32)),
        Kind::Real => f64::from_bits(raw),
        Kind::BitString => {
            return format!(
                "0x{raw:0width$X}{units}",
                width = member.bits.div_ceil(4) as usize
            )
        }
        _ => integer as f64,
    };
    match scaling(p) {
        Some((mult, div, base, offset, places)) => {
            let value = (number + offset) * mult * base / div;
            format!("{value:.places$}{units}")
        }
        None if k == Kind::Real => format!("{number}{units}"),
        None => format!("{integer}{units}"),
    }
}

/// `text` as the member's raw bits: an enumeration text (any case), `0x` hex (raw), or a
/// number in the parameter's engineering units (scaled back when it has a scaling); checked
/// against the parameter's limits and the member's width.
pub fn parse(cip: &Cip, member: &Member<'_>, text: &str) -> Result<u64, String> {
    let text = text.trim();
    let what = format!("`{}={text}`", member.name);
    if member.bits > 64 {
        return Err(format!(
            "{what}: a member of {} bits cannot be set by value",
            member.bits
        ));
    }
    let k = kind(member);
    let param = member.param;
    if let Some(e) = param.and_then(|p| cip.enums.get(&p.number)) {
        if let Some((v, _)) = e.values.iter().find(|(_, t)| t.eq_ignore_ascii_case(text)) {
            return range_checked(&what, member, k, i128::from(*v));
        }
    }
    if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        let raw = u64::from_str_radix(hex, 16).map_err(|_| format!("{what}: not hex"))?;
        if member.bits < 64 && raw >> member.bits != 0 {
            return Err(format!("{what}: more than {} bits", member.bits));
        }
        return match k {
            Kind::Real | Kind::BitString => Ok(raw),
            Kind::Signed => range_checked(&what, member, k, i128::from(signed(raw, member.bits))),
            Kind::Unsigned => range_checked(&what, member, k, i128::from(raw)),
        };
    }
    let choices = || {
        param
            .and_then(|p| cip.enums.get(&p.number))
            .map(|e| {
                let texts: Vec<String> = e.values.iter().map(|(_, t)| format!("`{t}`")).collect();
                format!(" (or one of {})", texts.join(", "))
            })
            .unwrap_or_default()
    };
    let number: f64 = text
        .parse()
        .map_err(|_| format!("{what}: not a number{}", choices()))?;
    if !number.is_finite() {
        return Err(format!("{what}: not a finite number"));
    }
    let native = match param.and_then(scaling) {
        Some((mult, div, base, offset, _)) if mult * base != 0.0 => {
            number * div / (mult * base) - offset
        }
        _ => number,
    };
    match k {
        Kind::Real => {
            let limits = param.map(|p| (p.min.as_ref(), p.max.as_ref()));
            if let Some((min, max)) = limits {
                let low = min.map(|m| m.value.as_f64());
                let high = max.map(|m| m.value.as_f64());
                if low.is_some_and(|l| native < l) || high.is_some_and(|h| native > h) {
                    return Err(format!("{what}: outside {}", limits_text(param)));
                }
            }
            Ok(if member.bits == 32 {
                u64::from((native as f32).to_bits())
            } else {
                native.to_bits()
            })
        }
        _ => {
            let rounded = native.round();
            if (rounded - native).abs() > 1e-6 * native.abs().max(1.0) {
                return Err(format!(
                    "{what}: not a whole step of the parameter ({native} raw)"
                ));
            }
            if rounded.abs() > 1.8e19 {
                return Err(format!("{what}: outside {}", limits_text(param)));
            }
            range_checked(&what, member, k, rounded as i128)
        }
    }
}

fn limits_text(param: Option<&CipParam>) -> String {
    let show = |n: Option<CipNumber>| match n {
        Some(CipNumber::Int(v)) => v.to_string(),
        Some(CipNumber::Real(v)) => v.to_string(),
        None => "?".to_owned(),
    };
    match param {
        Some(p) => format!(
            "{}..{} (Param{}, raw)",
            show(p.min.as_ref().map(|m| m.value)),
            show(p.max.as_ref().map(|m| m.value)),
            p.number
        ),
        None => "the member's range".to_owned(),
    }
}

/// `value` (raw, as an integer) within the parameter's limits, its type's range and the
/// member's width; its bits.
fn range_checked(what: &str, member: &Member<'_>, k: Kind, value: i128) -> Result<u64, String> {
    let bits = member.bits.min(64);
    let (mut low, mut high) = match k {
        Kind::Signed => (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1),
        _ => (0, (1i128 << bits) - 1),
    };
    if let Some((l, h)) = member
        .param
        .and_then(|p| p.data_type.as_ref())
        .and_then(|t| data_type_range(t.value))
    {
        (low, high) = (low.max(l), high.min(h));
    }
    let out = |v: i128| v < low || v > high;
    let limit = |n: Option<&edsgen_codegen::model::Spanned<CipNumber>>| n.map(|n| n.value.as_f64());
    let below = member
        .param
        .and_then(|p| limit(p.min.as_ref()))
        .is_some_and(|m| (value as f64) < m);
    let above = member
        .param
        .and_then(|p| limit(p.max.as_ref()))
        .is_some_and(|m| (value as f64) > m);
    if out(value) {
        return Err(format!(
            "{what}: {value} does not fit {bits} bits ({low}..{high})"
        ));
    }
    if below || above {
        return Err(format!(
            "{what}: {value} is outside {}",
            limits_text(member.param)
        ));
    }
    Ok(match k {
        Kind::Signed => (value as i64 as u64) & mask(bits),
        _ => value as u64,
    })
}

fn mask(bits: u32) -> u64 {
    if bits >= 64 {
        u64::MAX
    } else {
        (1 << bits) - 1
    }
}

/// The assembly's bytes with every member at its parameter's default (members without one,
/// and padding, zero).
pub fn defaults(members: &[Member<'_>], size: usize) -> Vec<u8> {
    let mut image = vec![0u8; size];
    for m in members {
        let Some(default) = m.param.and_then(|p| p.default.as_ref()) else {
            continue;
        };
        let raw = match (default.value, kind(m)) {
            (CipNumber::Real(v), Kind::Real) if m.bits == 32 => u64::from((v as f32).to_bits()),
            (CipNumber::Real(v), Kind::Real) => v.to_bits(),
            (CipNumber::Int(v), Kind::Real) if m.bits == 32 => u64::from((v as f32).to_bits()),
            (CipNumber::Int(v), Kind::Real) => (v as f64).to_bits(),
            (CipNumber::Int(v), _) => (v as i64 as u64) & mask(m.bits),
            (CipNumber::Real(_), _) => continue,
        };
        put_bits(&mut image, m.bit, m.bits, raw);
    }
    image
}
