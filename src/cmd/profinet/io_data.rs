//! `pn io`'s view of a device's IO data and parameters, from its GSDML and the configuration
//! it connects with: each plugged submodule's named input and output items (their byte offsets
//! in the submodule's data), the settings on the command line (`NAME=VALUE`, or
//! `SLOT.SUBSLOT=HEX` for a submodule's whole output data) turned into bytes, the inputs shown
//! in words, and the parameter records to write (their `Const` bytes and `Ref` defaults).

use edsgen_model::model::{DataItem, PnDataType, Profinet, Submodule};
use edsgen_runtime::profinet::wire::connect::ModuleDiffBlock;
use edsgen_sim::profinet::ar::config::DeviceConfig;

/// One named data item of a submodule's input or output data.
#[derive(Debug, Clone)]
pub struct Item {
    /// Its name as printed: the GSDML's text up to a ` (`, or the whole text when that is
    /// not unique in the submodule.
    pub label: String,
    /// The GSDML's whole text.
    pub name: String,
    /// Byte offset in the submodule's data.
    pub offset: usize,
    /// Bytes.
    pub size: usize,
    kind: Option<PnDataType>,
    bits: bool,
}

/// A plugged submodule with its named items.
#[derive(Debug, Clone)]
pub struct SubmoduleData {
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// The input items.
    pub inputs: Vec<Item>,
    /// The output items.
    pub outputs: Vec<Item>,
}

fn items(list: &[DataItem]) -> Vec<Item> {
    let mut offset = 0;
    let mut out: Vec<Item> = Vec::new();
    for (n, item) in list.iter().enumerate() {
        let Some(size) = item.size().and_then(|s| usize::try_from(s).ok()) else {
            break;
        };
        let name = item
            .name
            .clone()
            .unwrap_or_else(|| format!("item {}", n + 1));
        let label = name.split(" (").next().unwrap_or(&name).trim().to_owned();
        out.push(Item {
            label,
            name,
            offset,
            size,
            kind: item.kind,
            bits: item.use_as_bits,
        });
        offset += size;
    }
    let labels: Vec<String> = out.iter().map(|i| i.label.clone()).collect();
    for item in &mut out {
        if labels.iter().filter(|l| **l == item.label).count() > 1 {
            item.label = item.name.clone();
        }
    }
    out
}

/// The GSDML submodule of each submodule of `config`: (slot, the model's submodule), those of
/// the model's configuration ([`Profinet::configuration`]) that `config` has.
pub fn model_submodules<'a>(pn: &'a Profinet, config: &DeviceConfig) -> Vec<(u16, &'a Submodule)> {
    pn.configuration()
        .submodules(pn)
        .into_iter()
        .filter(|(slot, sub)| config.submodule(*slot, sub.subslot).is_some())
        .collect()
}

/// The named data of every submodule of `config` that has IO data.
pub fn submodules(pn: &Profinet, config: &DeviceConfig) -> Vec<SubmoduleData> {
    model_submodules(pn, config)
        .into_iter()
        .filter(|(_, sub)| !sub.inputs.is_empty() || !sub.outputs.is_empty())
        .map(|(slot, sub)| SubmoduleData {
            slot,
            subslot: sub.subslot,
            inputs: items(&sub.inputs),
            outputs: items(&sub.outputs),
        })
        .collect()
}

/// A parameter record to write: slot, subslot, index, content.
pub type RecordWrite = (u16, u16, u16, Vec<u8>);

/// One output setting: slot, subslot, byte offset in the submodule's output data, bytes.
pub type Setting = (u16, u16, usize, Vec<u8>);

/// Reads `NAME=VALUE` or `SLOT.SUBSLOT=HEX` against the output items of `subs` (each
/// submodule's output length in `output_len`).
pub fn parse_setting(
    text: &str,
    subs: &[SubmoduleData],
    output_len: impl Fn(u16, u16) -> Option<u16>,
) -> Result<Setting, String> {
    let (target, value) = text
        .rsplit_once('=')
        .ok_or_else(|| format!("`{text}` is not NAME=VALUE or SLOT.SUBSLOT=HEX"))?;
    if let Some((slot, subslot)) = target
        .split_once('.')
        .and_then(|(a, b)| Some((a.parse::<u16>().ok()?, b.parse::<u16>().ok()?)))
    {
        let len = output_len(slot, subslot)
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("slot {slot} subslot {subslot} has no output data"))?;
        let bytes = hex(value).ok_or_else(|| format!("`{value}` is not hex bytes"))?;
        if bytes.len() != usize::from(len) {
            return Err(format!(
                "slot {slot} subslot {subslot} takes {len} bytes of output data, `{value}` is {}",
                bytes.len()
            ));
        }
        return Ok((slot, subslot, 0, bytes));
    }
    let wanted = target.trim();
    let matches: Vec<(&SubmoduleData, &Item)> = subs
        .iter()
        .flat_map(|s| s.outputs.iter().map(move |i| (s, i)))
        .filter(|(_, i)| {
            i.label.eq_ignore_ascii_case(wanted) || i.name.eq_ignore_ascii_case(wanted)
        })
        .collect();
    match matches.as_slice() {
        [(sub, item)] => Ok((sub.slot, sub.subslot, item.offset, encode(item, value)?)),
        [] => {
            let known: Vec<&str> = subs
                .iter()
                .flat_map(|s| s.outputs.iter().map(|i| i.label.as_str()))
                .collect();
            Err(format!(
                "no output named `{wanted}` (the outputs: {})",
                if known.is_empty() {
                    "none".to_owned()
                } else {
                    known.join(", ")
                }
            ))
        }
        several => {
            let places: Vec<String> = several
                .iter()
                .map(|(s, _)| format!("{}.{}", s.slot, s.subslot))
                .collect();
            Err(format!(
                "`{wanted}` names outputs of {}: set SLOT.SUBSLOT=HEX instead",
                places.join(" and ")
            ))
        }
    }
}

fn hex(text: &str) -> Option<Vec<u8>> {
    let digits: String = text
        .trim_start_matches("0x")
        .chars()
        .filter(|c| !matches!(c, ' ' | ':' | '_'))
        .collect();
    if digits.is_empty() || !digits.len().is_multiple_of(2) {
        return None;
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(digits.get(i..i + 2)?, 16).ok())
        .collect()
}

fn integer(text: &str) -> Option<i128> {
    let text = text.trim();
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(h) => i128::from_str_radix(h, 16).ok(),
        None => text.parse().ok(),
    }
}

/// `value` as `item`'s bytes (big-endian, as PROFINET carries them).
fn encode(item: &Item, value: &str) -> Result<Vec<u8>, String> {
    use PnDataType::*;
    let bad = |what: &str| format!("`{value}` is not {what} for `{}`", item.label);
    let signed = matches!(
        item.kind,
        Some(Integer8 | Integer16 | Integer32 | Integer64)
    );
    match item.kind {
        Some(Float32) => value
            .trim()
            .parse::<f32>()
            .map(|v| v.to_be_bytes().to_vec())
            .map_err(|_| bad("a number")),
        Some(Float64) => value
            .trim()
            .parse::<f64>()
            .map(|v| v.to_be_bytes().to_vec())
            .map_err(|_| bad("a number")),
        Some(Boolean) => match value.trim() {
            "1" | "true" => Ok(vec![1]),
            "0" | "false" => Ok(vec![0]),
            _ => Err(bad("0, 1, true or false")),
        },
        Some(
            Unsigned8 | Unsigned16 | Unsigned32 | Unsigned64 | Integer8 | Integer16 | Integer32
            | Integer64,
        ) => {
            let v = integer(value).ok_or_else(|| bad("an integer"))?;
            let bits = 8 * item.size as u32;
            let (min, max) = if signed {
                (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
            } else {
                (0, (1i128 << bits) - 1)
            };
            if v < min || v > max {
                return Err(format!(
                    "{value} is out of range for `{}` ({min} to {max})",
                    item.label
                ));
            }
            Ok(v.to_be_bytes()[16 - item.size..].to_vec())
        }
        _ => match hex(value) {
            Some(bytes) if bytes.len() == item.size => Ok(bytes),
            _ => Err(bad(&format!("{} hex bytes", item.size))),
        },
    }
}

/// `item`'s value in `data` (the submodule's input data), in words: integers in decimal (bit
/// fields in hex), floats, other types as hex bytes; `?` when the data is short.
pub fn show(item: &Item, data: &[u8]) -> String {
    use PnDataType::*;
    let Some(bytes) = data.get(item.offset..item.offset + item.size) else {
        return "?".to_owned();
    };
    let unsigned = || bytes.iter().fold(0u128, |v, b| (v << 8) | u128::from(*b));
    match item.kind {
        _ if item.bits => format!("0x{:0width$x}", unsigned(), width = 2 * item.size),
        Some(Unsigned8 | Unsigned16 | Unsigned32 | Unsigned64 | Boolean) => unsigned().to_string(),
        Some(Integer8 | Integer16 | Integer32 | Integer64) => {
            let shift = 128 - 8 * item.size as u32;
            (((unsigned() << shift) as i128) >> shift).to_string()
        }
        Some(Float32) => {
            <[u8; 4]>::try_from(bytes).map_or("?".into(), |b| f32::from_be_bytes(b).to_string())
        }
        Some(Float64) => {
            <[u8; 8]>::try_from(bytes).map_or("?".into(), |b| f64::from_be_bytes(b).to_string())
        }
        _ => bytes.iter().map(|b| format!("{b:02x}")).collect(),
    }
}

/// The parameter records to write at connection, in order: slot, subslot, index, content
/// (the `Const` bytes, and each `Ref`'s integer `DefaultValue` in place).
pub fn records(pn: &Profinet, config: &DeviceConfig) -> Vec<RecordWrite> {
    let mut out = Vec::new();
    for (slot, sub) in model_submodules(pn, config) {
        for record in &sub.records {
            let len = usize::try_from(record.length.value).unwrap_or(0).min(4096);
            let mut data = vec![0u8; len];
            for (at, bytes) in &record.consts {
                let at = *at as usize;
                if let Some(area) = data.get_mut(at..at + bytes.len()) {
                    area.copy_from_slice(bytes);
                }
            }
            for field in &record.fields {
                let Some(default) = field.default.as_ref().and_then(|d| integer(&d.value)) else {
                    continue;
                };
                put_default(&mut data, field, default);
            }
            out.push((slot, sub.subslot, record.index.value, data));
        }
    }
    out
}

/// [`records`], with the contents `SLOT.SUBSLOT.INDEX=HEX` in `given` in place of theirs.
pub fn records_with(
    pn: &Profinet,
    config: &DeviceConfig,
    given: &[String],
) -> Result<Vec<RecordWrite>, String> {
    let mut all = records(pn, config);
    for text in given {
        let bad = || format!("--record `{text}` is not SLOT.SUBSLOT.INDEX=HEX");
        let (place, value) = text.split_once('=').ok_or_else(bad)?;
        let numbers: Vec<u16> = place
            .split('.')
            .map(|n| n.parse().ok())
            .collect::<Option<_>>()
            .ok_or_else(bad)?;
        let [slot, subslot, index] = numbers[..] else {
            return Err(bad());
        };
        let bytes = hex(value).ok_or_else(bad)?;
        let record = all
            .iter_mut()
            .find(|r| (r.0, r.1, r.2) == (slot, subslot, index))
            .ok_or_else(|| {
                format!("the GSDML has no record {index} in slot {slot} subslot {subslot}")
            })?;
        if bytes.len() != record.3.len() {
            return Err(format!(
                "record {index} of slot {slot} subslot {subslot} is {} bytes, `{value}` is {}",
                record.3.len(),
                bytes.len()
            ));
        }
        record.3 = bytes;
    }
    Ok(all)
}

/// Writes `value` into `data` where `field` is: whole bytes big-endian, or bits.
fn put_default(data: &mut [u8], field: &edsgen_model::model::RecordField, value: i128) {
    let at = field.byte_offset as usize;
    match field.kind {
        Some(PnDataType::Bit | PnDataType::BitArea) => {
            let width = field.bit_length.unwrap_or(1).min(8);
            let shift = field.bit_offset.unwrap_or(0).min(7);
            if let Some(byte) = data.get_mut(at) {
                let mask = (((1u16 << width) - 1) << shift) as u8;
                *byte = (*byte & !mask) | (((value as u16) << shift) as u8 & mask);
            }
        }
        Some(kind) => {
            let Some(size) = kind.size().map(|s| s as usize).filter(|s| *s <= 8) else {
                return;
            };
            if matches!(kind, PnDataType::Float32 | PnDataType::Float64) {
                return;
            }
            if let Some(area) = data.get_mut(at..at + size) {
                area.copy_from_slice(&value.to_be_bytes()[16 - size..]);
            }
        }
        None => {}
    }
}

/// One line per module of a ModuleDiffBlock, then one per submodule under it, with the
/// states' meanings (IEC 61158-6-10: ModuleState, SubmoduleState's IdentInfo).
pub fn module_diff_lines(diff: &ModuleDiffBlock) -> Vec<String> {
    let module_state = |state| match state {
        0 => "no module",
        1 => "wrong module",
        2 => "proper module",
        3 => "substitute",
        _ => "reserved",
    };
    let ident_info = |state: u16| match (state >> 11) & 0x0F {
        0 => "ok",
        1 => "substitute",
        2 => "wrong",
        3 => "no submodule",
        _ => "reserved",
    };
    let mut lines = Vec::new();
    for api in &diff.apis {
        for module in &api.modules {
            lines.push(format!(
                "API {} slot {}: ModuleIdentNumber {:#010x}, ModuleState {} ({})",
                api.api,
                module.slot,
                module.module_ident,
                module.state,
                module_state(module.state)
            ));
            for &(subslot, ident, state) in &module.submodules {
                lines.push(format!(
                    "  subslot {subslot:#06x}: SubmoduleIdentNumber {ident:#010x}, SubmoduleState {state:#06x} ({})",
                    ident_info(state)
                ));
            }
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use edsgen_model::model::PnDataType::*;

    fn item(kind: PnDataType, size: usize, bits: bool) -> Item {
        Item {
            label: "x".into(),
            name: "x (y)".into(),
            offset: 1,
            size,
            kind: Some(kind),
            bits,
        }
    }

    #[test]
    fn values_are_written_big_endian_in_range() {
        assert_eq!(
            encode(&item(Unsigned16, 2, false), "0x1234"),
            Ok(vec![0x12, 0x34])
        );
        assert_eq!(
            encode(&item(Integer16, 2, false), "-2"),
            Ok(vec![0xFF, 0xFE])
        );
        assert_eq!(
            encode(&item(Integer8, 1, false), "128"),
            Err("128 is out of range for `x` (-128 to 127)".to_owned())
        );
        assert_eq!(
            encode(&item(Float32, 4, false), "1.5"),
            Ok(vec![0x3F, 0xC0, 0, 0])
        );
        assert_eq!(encode(&item(Boolean, 1, false), "true"), Ok(vec![1]));
        assert_eq!(
            encode(&item(OctetString, 2, false), "0a0b"),
            Ok(vec![0x0A, 0x0B])
        );
        assert_eq!(
            encode(&item(OctetString, 2, false), "0a"),
            Err("`0a` is not 2 hex bytes for `x`".to_owned())
        );
    }

    #[test]
    fn inputs_are_shown_in_words() {
        let data = [0x00, 0xFF, 0xFE, 0x00];
        assert_eq!(show(&item(Unsigned16, 2, false), &data), "65534");
        assert_eq!(show(&item(Integer16, 2, false), &data), "-2");
        assert_eq!(show(&item(Unsigned16, 2, true), &data), "0xfffe");
        assert_eq!(show(&item(Unsigned32, 4, false), &data), "?");
        let float = [0, 0x40, 0x90, 0, 0];
        assert_eq!(show(&item(Float32, 4, false), &float), "4.5");
    }

    #[test]
    fn hex_takes_separators_and_refuses_odd_digits() {
        assert_eq!(hex("0x01 02:03_04"), Some(vec![1, 2, 3, 4]));
        assert_eq!(hex("123"), None);
        assert_eq!(hex(""), None);
        assert_eq!(hex("zz"), None);
    }
}
