//! A parameter of an ODVA EDS's `[Params]` as `edsgen enip get|set` takes it: found by name
//! (exact or unique prefix, case- and space-insensitive, or `ParamN`; suggestions on a miss),
//! where it lives on the device (the attribute its link path names; else the bits of the
//! assembly it is a member of; else attribute 1 of its Parameter object instance, `@0x0F/N/1`),
//! typed as wide as it is there (`cip_value::Typed`).

use edsgen_model::model::{decode_path, path_bytes, Cip, CipParam, FieldRef};

use super::cip_value::Typed;

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
    /// Its value's type, as wide as it is where it is.
    pub typed: Typed<'a>,
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

/// The parameter of `cip` that `text` names.
pub fn resolve<'a>(cip: &'a Cip, text: &str) -> Result<Param<'a>, String> {
    let param = by_name(cip, text)?;
    let access = access(cip, param)?;
    let typed = match access {
        Access::Member { bits, .. } => Typed::of(cip, Some(param), bits as u32),
        Access::Attribute(_) => Typed::param(cip, param),
    };
    Ok(Param {
        param,
        typed,
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
                // In parameter order: the nearest by number first.
                let keyed = params.iter().map(|p| (key(&p.name), *p));
                near = crate::cmd::did_you_mean::closest(&wanted, keyed, true);
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
    let lines: Vec<String> = params
        .iter()
        .map(|p| format!("Param{}  {}", p.number, p.name))
        .collect();
    crate::cmd::did_you_mean::listing(&lines)
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
        let mut bytes = path_bytes(&path.value).map_err(|_| bad())?;
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

impl Param<'_> {
    /// `ParamN name`, as the output names it.
    pub fn label(&self) -> String {
        format!("Param{} {}", self.param.number, self.param.name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn io() -> Cip {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("codegen/tests/odva/io.eds");
        let read = edsgen_model::read::read_file(&path).expect("io.eds reads");
        read.device.cip().cloned().expect("an ODVA EDS")
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
        assert_eq!(speed.typed.raw(&[0xDC, 0x05]), Ok(1500));
        assert_eq!(speed.typed.full(1500), "150.0 rpm (raw 1500)");
        // Engineering values must be whole steps; raw hex is taken as it is.
        assert_eq!(speed.typed.parse("12.3"), Ok(123));
        assert_eq!(
            speed.typed.parse("12.34"),
            Err("not a whole step of the parameter (123.4 raw)".into())
        );
        assert_eq!(speed.typed.parse("0x10"), Ok(16));
        let mode = resolve(&cip, "param2").expect("Mode");
        assert_eq!(
            mode.access,
            Access::Member {
                instance: 100,
                offset: 16,
                bits: 8
            }
        );
        assert_eq!(mode.typed.full(2), "2 (0x02) \"Fast\"");
        assert_eq!(mode.typed.full(7), "7 (0x07)");
        assert_eq!(mode.typed.parse("SLOW"), Ok(1));
        assert_eq!(mode.typed.parse("f"), Ok(2), "a unique prefix");
        assert_eq!(mode.typed.parse("0x2"), Ok(2));
        // RPI: no member, no link path: its Parameter object instance.
        let rpi = resolve(&cip, "rpi").expect("RPI");
        assert_eq!(
            rpi.access,
            Access::Attribute(vec![0x20, 0x0F, 0x24, 0x03, 0x30, 0x01])
        );
        assert_eq!(rpi.typed.raw(&[0x50, 0xC3, 0, 0]), Ok(50_000));
        assert_eq!(rpi.typed.full(50_000), "50000 (0x0000C350) us");
        assert_eq!(rpi.typed.bytes(50_000), [0x50, 0xC3, 0, 0]);
        assert_eq!(
            rpi.typed.parse("9999"),
            Err("9999 is outside 10000 ..= 1000000 us".into())
        );
        assert_eq!(
            rpi.typed.raw(&[1, 2]),
            Err("2 bytes received where the data type has 4".into())
        );
    }

    proptest::proptest! {
        #[test]
        fn any_name_or_value_is_taken_or_refused_without_a_panic(text in "\\PC{0,12}") {
            let cip = io();
            if let Ok(param) = resolve(&cip, &text) {
                let _ = param.typed.parse(&text);
            }
            for name in ["Speed", "Mode", "RPI"] {
                let param = resolve(&cip, name).expect("a parameter");
                let _ = param.typed.parse(&text);
                let _ = param.typed.raw(text.as_bytes());
            }
        }
    }
}
