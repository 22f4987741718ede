//! The Parameter object (class 0x0F), sans-IO: instance N is the EDS's `ParamN`, with the
//! attributes of a full parameter object (CIP Vol. 1 §5A-14: 1 the value, 2–3 the link path,
//! 4 the descriptor, 5 the data type, 6 the data size, 7–9 the name, units and help strings,
//! 10–12 the minimum, maximum and default, 13–16 the scaling, 17–20 the scaling links, 21 the
//! decimal precision) and the class attributes 1 (revision), 2 (max instance), 8 (parameter
//! class descriptor) and 9 (configuration assembly instance). A parameter that is a member of an
//! assembly lives in that assembly's bytes (one storage: what the Parameter object and class-1
//! I/O show is the same value); the others keep their own bytes, starting at their default.
//! Setting the value checks the descriptor's read-only bit (0x0E), the size (0x13/0x15) and the
//! limits (0x09).

use std::collections::BTreeMap;

use edsgen_model::model::cip_value;
use edsgen_model::model::{decode_path, path_bytes, Cip, CipNumber, CipParam, FieldRef};
use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, RequestRepr as Request};

use super::bytes::{response, status_only};
use super::cip::{Call, CipObject};
use super::state::{DeviceState, Event};
pub use super::state::{Parameter, Storage};

/// Services of the Parameter object.
const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;
const SET_ATTRIBUTE_SINGLE: u8 = 0x10;

/// Invalid attribute value: a value outside the parameter's limits.
pub const INVALID_ATTRIBUTE_VALUE: u8 = 0x09;

/// The parameter class descriptor (class attribute 8): bit 0 parameter instances supported,
/// bit 1 full attributes supported.
pub const CLASS_DESCRIPTOR: u16 = 0x0003;

/// The Parameter object's instances for the EDS's `[Params]`: members of an assembly the
/// adapter serves (the first that names them) in its bytes, the others with their default.
pub fn from_cip(cip: &Cip, served: &BTreeMap<u32, super::Assembly>) -> BTreeMap<u32, Parameter> {
    let mut places: BTreeMap<u32, Storage> = BTreeMap::new();
    for assembly in cip.assemblies.values() {
        if !served.contains_key(&assembly.instance()) {
            continue;
        }
        for place in cip_value::layout(cip, assembly) {
            if let FieldRef::Param(n) = place.member.member {
                places.entry(n).or_insert(Storage::Member {
                    instance: assembly.instance(),
                    bit: place.bit as usize,
                    bits: place.bits as usize,
                });
            }
        }
    }
    cip.params
        .values()
        .map(|p| {
            let storage = places
                .remove(&p.number)
                .unwrap_or_else(|| Storage::Own(default_bytes(p)));
            (p.number, parameter(p, storage))
        })
        .collect()
}

fn parameter(p: &CipParam, storage: Storage) -> Parameter {
    let link_path = p
        .link_path
        .as_ref()
        .filter(|l| decode_path(&l.value).is_ok())
        .and_then(|l| path_bytes(&l.value).ok())
        .unwrap_or_default();
    let [mult, div, base, offset] = p.scaling;
    Parameter {
        descriptor: p.descriptor.as_ref().map_or(0, |d| d.value as u16),
        data_type: p.data_type.as_ref().map_or(0, |t| t.value),
        size: p.data_size.as_ref().map_or(0, |s| s.value as usize),
        link_path,
        strings: [p.name.clone(), p.units.clone(), p.help.clone()],
        limits: [&p.min, &p.max, &p.default].map(|n| n.as_ref().map(|n| n.value)),
        scaling: [
            mult.unwrap_or(1),
            div.unwrap_or(1),
            base.unwrap_or(1),
            offset.unwrap_or(0),
        ],
        decimals: p.decimals.unwrap_or(0).min(255) as u8,
        storage,
    }
}

/// `p`'s default as its data type and size, little-endian (zeros when it has none).
pub fn default_bytes(p: &CipParam) -> Vec<u8> {
    number_bytes(p, p.default.as_ref().map(|d| d.value))
}

/// `value` as `p`'s data type and size, little-endian (zeros when absent).
fn number_bytes(p: &CipParam, value: Option<CipNumber>) -> Vec<u8> {
    let size = p.data_size.as_ref().map_or(0, |s| s.value as usize);
    let code = p.data_type.as_ref().map_or(0, |t| t.value);
    encode(code, size, value)
}

fn encode(code: u8, size: usize, value: Option<CipNumber>) -> Vec<u8> {
    let wide: [u8; 8] = match (value, code, size) {
        (None, _, _) => [0; 8],
        (Some(n), 0xCA, 4) => u64::from((n.as_f64() as f32).to_bits()).to_le_bytes(),
        (Some(n), 0xCB, 8) => n.as_f64().to_bits().to_le_bytes(),
        (Some(CipNumber::Int(v)), _, _) => (v as i64).to_le_bytes(),
        (Some(CipNumber::Real(v)), _, _) => (v as i64).to_le_bytes(),
    };
    let mut out = wide[..size.min(8)].to_vec();
    out.resize(size, 0);
    out
}

/// A SHORT_STRING: its length, then its bytes (at most 255).
fn short_string(text: &str) -> Vec<u8> {
    let bytes = &text.as_bytes()[..text.len().min(255)];
    let mut out = vec![bytes.len() as u8];
    out.extend_from_slice(bytes);
    out
}

impl Parameter {
    /// Whether the descriptor says read-only (bit 4).
    pub fn read_only(&self) -> bool {
        self.descriptor & 0x10 != 0
    }

    /// The value `bytes` as a number of the parameter's type, for the limits; `None` for types
    /// without an order (strings, ...).
    fn number(&self, bytes: &[u8]) -> Option<f64> {
        let mut wide = [0u8; 8];
        let len = bytes.len().min(8);
        wide[..len].copy_from_slice(&bytes[..len]);
        let raw = u64::from_le_bytes(wide);
        let shift = 64 - 8 * len.max(1) as u32;
        Some(match self.data_type {
            0xC2..=0xC5 => (((raw << shift) as i64) >> shift) as f64,
            0xC1 | 0xC6..=0xC9 | 0xD1..=0xD4 => raw as f64,
            0xCA if len == 4 => f64::from(f32::from_bits(raw as u32)),
            0xCB if len == 8 => f64::from_bits(raw),
            _ => return None,
        })
    }

    /// Whether `bytes` (a value of the right size) is within the minimum and maximum.
    fn within_limits(&self, bytes: &[u8]) -> bool {
        let Some(v) = self.number(bytes) else {
            return true;
        };
        let [min, max, _] = self.limits;
        !(min.is_some_and(|m| v < m.as_f64()) || max.is_some_and(|m| v > m.as_f64()))
    }

    /// Instance attribute `attribute` other than the value.
    fn attribute(&self, attribute: u32) -> Option<Vec<u8>> {
        let limit = |i: usize| encode(self.data_type, self.size, self.limits[i]);
        let uint = |v: i64| (v as u16).to_le_bytes().to_vec();
        Some(match attribute {
            2 => vec![self.link_path.len() as u8],
            3 => self.link_path.clone(),
            4 => self.descriptor.to_le_bytes().to_vec(),
            5 => vec![self.data_type],
            6 => vec![self.size as u8],
            7..=9 => short_string(&self.strings[attribute as usize - 7]),
            10..=12 => limit(attribute as usize - 10),
            13..=16 => uint(self.scaling[attribute as usize - 13]),
            // No scaling links: the EDS gives the scaling as numbers.
            17..=20 => vec![0, 0],
            21 => vec![self.decimals],
            _ => return None,
        })
    }
}

fn status(service: u8, code: u8) -> Vec<u8> {
    status_only(service, code)
}

/// Bits `at..at + len` of `data` as `size` little-endian bytes.
fn cut(data: &[u8], at: usize, len: usize, size: usize) -> Vec<u8> {
    let mut out = cip_value::read_bits(data, at as u64, len as u64, size);
    out.truncate(size.max(1));
    out
}

/// `data` with bits `at..at + len` from the little-endian `value` (bits past `value` zero).
pub fn paste(data: &mut [u8], at: usize, len: usize, value: &[u8]) {
    cip_value::write_bits(data, at as u64, len as u64, value);
}

/// The value of parameter `n` (its data size in bytes), from wherever it is kept.
pub fn value(device: &DeviceState, n: u32) -> Option<Vec<u8>> {
    let p = device.parameters.get(&n)?;
    Some(match &p.storage {
        Storage::Own(bytes) => bytes.clone(),
        &Storage::Member {
            instance,
            bit,
            bits,
        } => cut(&device.assemblies.get(&instance)?.data, bit, bits, p.size),
    })
}

/// The Parameter object.
#[derive(Debug)]
pub struct ParameterObject;

impl CipObject for ParameterObject {
    fn class_id(&self) -> u32 {
        0x0F
    }

    /// Get_Attribute_Single and Set_Attribute_Single on the class (instance 0) and instances.
    fn serve(
        &self,
        device: &mut DeviceState,
        _call: &Call,
        request: &Request<'_>,
        path: &Path,
    ) -> Vec<u8> {
        let service = request.service;
        let instance = path.instance.unwrap_or(0);
        let attribute = path.attribute.unwrap_or(0);
        if instance == 0 {
            let value = match attribute {
                1 => Some(1u16.to_le_bytes()),
                2 => Some(
                    (device.parameters.keys().last().copied().unwrap_or(0) as u16).to_le_bytes(),
                ),
                8 => Some(CLASS_DESCRIPTOR.to_le_bytes()),
                9 => Some(0u16.to_le_bytes()),
                _ => None,
            };
            return match (service, value) {
                (GET_ATTRIBUTE_SINGLE, Some(v)) => response(service, general::SUCCESS, &[], &v),
                (GET_ATTRIBUTE_SINGLE, None) => status(service, general::ATTRIBUTE_NOT_SUPPORTED),
                (SET_ATTRIBUTE_SINGLE, _) => status(service, general::ATTRIBUTE_NOT_SETTABLE),
                _ => status(service, general::SERVICE_NOT_SUPPORTED),
            };
        }
        let Some(p) = device.parameters.get(&instance) else {
            return status(service, general::OBJECT_DOES_NOT_EXIST);
        };
        match (service, attribute) {
            (GET_ATTRIBUTE_SINGLE, 1) => match value(device, instance) {
                Some(v) => response(service, general::SUCCESS, &[], &v),
                None => status(service, general::OBJECT_DOES_NOT_EXIST),
            },
            (GET_ATTRIBUTE_SINGLE, a) => match p.attribute(a) {
                Some(v) => response(service, general::SUCCESS, &[], &v),
                None => status(service, general::ATTRIBUTE_NOT_SUPPORTED),
            },
            (SET_ATTRIBUTE_SINGLE, 1) => {
                let code = set_parameter(device, instance, request.data);
                status(service, code)
            }
            (SET_ATTRIBUTE_SINGLE, a) if p.attribute(a).is_some() => {
                status(service, general::ATTRIBUTE_NOT_SETTABLE)
            }
            (SET_ATTRIBUTE_SINGLE, _) => status(service, general::ATTRIBUTE_NOT_SUPPORTED),
            _ => status(service, general::SERVICE_NOT_SUPPORTED),
        }
    }
}

/// Set_Attribute_Single of parameter `n`'s value: its general status.
fn set_parameter(device: &mut DeviceState, n: u32, data: &[u8]) -> u8 {
    let Some(p) = device.parameters.get(&n) else {
        return general::OBJECT_DOES_NOT_EXIST;
    };
    if p.read_only() {
        return general::ATTRIBUTE_NOT_SETTABLE;
    }
    match data.len().cmp(&p.size) {
        std::cmp::Ordering::Less => return general::NOT_ENOUGH_DATA,
        std::cmp::Ordering::Greater => return general::TOO_MUCH_DATA,
        std::cmp::Ordering::Equal => {}
    }
    if !p.within_limits(data) {
        return INVALID_ATTRIBUTE_VALUE;
    }
    let (instance, bit, bits) = match p.storage {
        Storage::Own(_) => {
            if let Some(Storage::Own(bytes)) = device.parameters.get_mut(&n).map(|p| &mut p.storage)
            {
                bytes.copy_from_slice(data);
            }
            return general::SUCCESS;
        }
        Storage::Member {
            instance,
            bit,
            bits,
        } => (instance, bit, bits),
    };
    // The member's assembly, as Set_Attribute_Single on it: not while a connection writes it.
    if device.written_by_connection(instance) {
        return general::DEVICE_STATE_CONFLICT;
    }
    let Some(assembly) = device.assemblies.get_mut(&instance) else {
        return general::OBJECT_DOES_NOT_EXIST;
    };
    paste(&mut assembly.data, bit, bits, data);
    if assembly.consumed {
        device.events.push_back(Event::Consumed(instance));
    }
    general::SUCCESS
}
