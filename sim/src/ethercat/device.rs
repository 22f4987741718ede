//! A SubDevice's application built from an ESI device: its CoE dictionary as a
//! [`RuntimeDictionary`] (the one `edsgen simulate` serves for EDS files) answering SDO in the
//! mailbox, its SII image ([`edsgen_model::sii`], where the core finds its layout), and its process
//! images laid out by the PDO assignment in force: 1C12h/1C13h (1C10h + SyncManager) and the
//! mapping objects when the dictionary has them, else the ESI's default `Sm` assignment and
//! `Entry` lists. Outputs from the master are written into the mapped objects in Op; inputs are
//! read from the mapped objects. A [`Behaviour`] (a card's drive) runs each cycle on the
//! dictionary.
//!
//! Write rules: 1C10h–1C2Fh only in Pre-Op and only when the ESI's `PdoAssign` allows, and
//! only with PDO indices the device has (1600h–17FFh for outputs, 1A00h–1BFFh for inputs); the
//! mapping objects only in Pre-Op, only when `PdoConfig` allows and the PDO is not `Fixed`, and
//! only with objects the dictionary has and may map (0 for padding). Otherwise 0800 0022
//! (device state), 0601 0002 (read only), 0609 0030 (invalid value) or 0604 0041 (not mappable).
//! An entry whose `Access` has `WriteRestrictions` (`PreOP`, `SafeOP`, `OP`, joined by `_`:
//! the states a write is allowed in) is written only in those states, else 0800 0022.

use std::cell::OnceCell;
use std::collections::{HashMap, HashSet};

use edsgen_model::model::{Device, EcPdo, SmKind};
use edsgen_runtime::{Instant, ObjectDictionary, SdoAbort};

use super::image::{image_len, pack, place, unpack, Placed};
use super::{AlState, Application, SubDevice};
use crate::canopen::RuntimeDictionary;
use edsgen_runtime::ethercat::sdo::CoeSdoServer;

/// What runs on the dictionary each cycle, as a device's firmware does behind its objects.
pub trait Behaviour: std::fmt::Debug + Send {
    /// One cycle at `now` (the outputs of the last cycle are in the mapped objects).
    fn cycle(&mut self, now: Instant, od: &mut RuntimeDictionary);
}

/// One mapped entry: index (0 for padding), sub-index, bit length.
pub type Mapped = (u16, u8, u16);

/// The application of an ESI device (see the module comment).
#[derive(Debug)]
pub struct EsiDevice {
    od: RuntimeDictionary,
    sdo: CoeSdoServer,
    rx_pdos: Vec<EcPdo>,
    tx_pdos: Vec<EcPdo>,
    outputs_sm: Option<u8>,
    inputs_sm: Option<u8>,
    rules: Rules,
    behaviour: Option<Box<dyn Behaviour>>,
    /// The process images' layout, worked out when first needed after the dictionary or the
    /// state last changed outside a cycle (a mailbox message, [`EsiDevice::dictionary_mut`], a
    /// state change): a cycle's outputs and behaviour change values, not the PDO assignment.
    images: OnceCell<Images>,
}

/// The outputs and inputs images' entries, in order, and their sizes in bytes.
#[derive(Debug)]
struct Images {
    outputs: Vec<Placed>,
    inputs: Vec<Placed>,
    sizes: (usize, usize),
}

/// What the write rules need (see the module comment).
#[derive(Debug)]
struct Rules {
    state: AlState,
    pdo_assign: bool,
    pdo_config: bool,
    outputs_sm: Option<u8>,
    /// PDOs the device has: the ESI's and the dictionary's mapping objects.
    pdos: HashSet<u16>,
    fixed: HashSet<u16>,
    mappable: HashSet<(u16, u8)>,
    /// The states each entry with `WriteRestrictions` may be written in.
    write_states: HashMap<(u16, u8), Vec<AlState>>,
}

impl EsiDevice {
    /// The application of `device` (an ESI model), with an optional behaviour.
    pub fn new(device: &Device, behaviour: Option<Box<dyn Behaviour>>) -> Result<Self, String> {
        let ec = device
            .ethercat()
            .ok_or("not an EtherCAT device: the simulator serves ESI files")?;
        let od = RuntimeDictionary::new(device, 0);
        let position = |kind: SmKind| {
            ec.sync_managers
                .iter()
                .position(|sm| sm.kind == kind)
                .and_then(|n| u8::try_from(n).ok())
        };
        let mappable = od
            .entries()
            .iter()
            .filter(|e| e.pdo_mappable())
            .map(|e| (e.index(), e.sub()))
            .collect();
        let esi_pdos = || ec.rx_pdos.iter().chain(&ec.tx_pdos);
        let pdos = esi_pdos()
            .map(|p| p.index)
            .chain(
                od.entries()
                    .iter()
                    .map(|e| e.index())
                    .filter(|i| matches!(i, 0x1600..=0x17FF | 0x1A00..=0x1BFF)),
            )
            .collect();
        let rules = Rules {
            state: AlState::Init,
            pdo_assign: ec.coe.as_ref().is_some_and(|c| c.pdo_assign),
            pdo_config: ec.coe.as_ref().is_some_and(|c| c.pdo_config),
            outputs_sm: position(SmKind::Outputs),
            pdos,
            fixed: esi_pdos().filter(|p| p.fixed).map(|p| p.index).collect(),
            mappable,
            write_states: write_states(device),
        };
        let mut od = od;
        seed_defaults(
            &mut od,
            ec,
            position(SmKind::Outputs),
            position(SmKind::Inputs),
        );
        Ok(EsiDevice {
            od,
            sdo: CoeSdoServer::new(),
            rx_pdos: ec.rx_pdos.clone(),
            tx_pdos: ec.tx_pdos.clone(),
            outputs_sm: position(SmKind::Outputs),
            inputs_sm: position(SmKind::Inputs),
            rules,
            behaviour,
            images: OnceCell::new(),
        })
    }

    /// The SubDevice serving `device`: its SII image (from which the core reads its layout)
    /// and this application.
    pub fn subdevice(
        device: &Device,
        behaviour: Option<Box<dyn Behaviour>>,
    ) -> Result<SubDevice<EsiDevice>, String> {
        let sii = edsgen_model::sii::build(device)?;
        let app = EsiDevice::new(device, behaviour)?;
        Ok(SubDevice::new(sii, app))
    }

    /// The dictionary.
    pub fn dictionary(&self) -> &RuntimeDictionary {
        &self.od
    }

    /// The dictionary, to change values as the device's firmware would.
    pub fn dictionary_mut(&mut self) -> &mut RuntimeDictionary {
        self.images.take();
        &mut self.od
    }

    /// The PDOs assigned to SyncManager `sm` now.
    pub fn assigned(&self, sm: u8, outputs: bool) -> Vec<u16> {
        let assign = 0x1C10 + u16::from(sm);
        if let Some(n) = u8_value(&self.od, assign, 0) {
            return (1..=n)
                .filter_map(|s| {
                    let mut b = [0u8; 2];
                    self.od.read(assign, s, 0, &mut b).ok()?;
                    Some(u16::from_le_bytes(b))
                })
                .collect();
        }
        let pdos = if outputs {
            &self.rx_pdos
        } else {
            &self.tx_pdos
        };
        pdos.iter()
            .filter(|p| p.sm == Some(sm))
            .map(|p| p.index)
            .collect()
    }

    /// The entries a PDO maps now: its mapping object's, else the ESI's.
    pub fn mapping(&self, pdo: u16) -> Vec<Mapped> {
        if let Some(n) = u8_value(&self.od, pdo, 0) {
            return (1..=n)
                .filter_map(|s| {
                    let mut b = [0u8; 4];
                    self.od.read(pdo, s, 0, &mut b).ok()?;
                    let v = u32::from_le_bytes(b);
                    Some(((v >> 16) as u16, (v >> 8) as u8, (v & 0xFF) as u16))
                })
                .collect();
        }
        self.rx_pdos
            .iter()
            .chain(&self.tx_pdos)
            .find(|p| p.index == pdo)
            .map(|p| {
                p.entries
                    .iter()
                    .map(|e| (e.index, e.sub, e.bit_len))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The outputs (`true`) or inputs image's entries, in order.
    pub fn image(&self, outputs: bool) -> Vec<Mapped> {
        let sm = if outputs {
            self.outputs_sm
        } else {
            self.inputs_sm
        };
        sm.map(|sm| {
            self.assigned(sm, outputs)
                .into_iter()
                .flat_map(|pdo| self.mapping(pdo))
                .collect()
        })
        .unwrap_or_default()
    }
}

impl EsiDevice {
    /// The process images' layout, worked out again after a change (see the `images` field).
    fn images(&self) -> &Images {
        self.images.get_or_init(|| Images::of(self))
    }
}

impl Images {
    fn of(device: &EsiDevice) -> Self {
        let outputs = place(&device.od, &device.image(true));
        let inputs = place(&device.od, &device.image(false));
        let sizes = (image_len(&outputs), image_len(&inputs));
        Images {
            outputs,
            inputs,
            sizes,
        }
    }
}

impl Rules {
    /// Whether a write of `data` to `index`:`sub` is allowed now.
    fn check(&self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        let value = |n: usize| {
            let mut b = [0u8; 4];
            b[..n.min(data.len())].copy_from_slice(&data[..n.min(data.len())]);
            u32::from_le_bytes(b)
        };
        if let Some(states) = self.write_states.get(&(index, sub)) {
            if !states.contains(&self.state) {
                return Err(SdoAbort::DeviceState);
            }
        }
        match index {
            0x1C10..=0x1C2F => {
                if self.state != AlState::PreOp {
                    return Err(SdoAbort::DeviceState);
                }
                if !self.pdo_assign {
                    return Err(SdoAbort::ReadOnly);
                }
                if sub > 0 {
                    let pdo = value(2) as u16;
                    let range = if Some((index - 0x1C10) as u8) == self.outputs_sm {
                        0x1600..=0x17FF
                    } else {
                        0x1A00..=0x1BFF
                    };
                    if !range.contains(&pdo) || !self.pdos.contains(&pdo) {
                        return Err(SdoAbort::InvalidValue);
                    }
                }
                Ok(())
            }
            0x1600..=0x17FF | 0x1A00..=0x1BFF => {
                if self.state != AlState::PreOp {
                    return Err(SdoAbort::DeviceState);
                }
                if !self.pdo_config || self.fixed.contains(&index) {
                    return Err(SdoAbort::ReadOnly);
                }
                if sub > 0 {
                    let v = value(4);
                    let (i, s) = ((v >> 16) as u16, (v >> 8) as u8);
                    if i != 0 && !self.mappable.contains(&(i, s)) {
                        return Err(SdoAbort::NotMappable);
                    }
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

/// The states each entry of `device` with `WriteRestrictions` may be written in: its parts
/// (`PreOP_SafeOP`) as AL states; a text with a part that names no state restricts nothing.
fn write_states(device: &Device) -> HashMap<(u16, u8), Vec<AlState>> {
    let mut restricted = HashMap::new();
    for object in device.objects.values() {
        for sub in object.subs.values() {
            let Some((_, text)) = sub.custom.iter().find(|(k, _)| k == "WriteRestrictions") else {
                continue;
            };
            let states: Option<Vec<AlState>> = text
                .split('_')
                .map(|part| match part.trim().to_ascii_lowercase().as_str() {
                    "preop" => Some(AlState::PreOp),
                    "safeop" => Some(AlState::SafeOp),
                    "op" => Some(AlState::Op),
                    _ => None,
                })
                .collect();
            if let Some(states) = states {
                restricted.insert((object.index, sub.sub_index), states);
            }
        }
    }
    restricted
}

/// Fills assignment (1C1xh) and mapping objects the dictionary has but leaves empty (sub-index
/// 0 is 0, or every entry 0) from the ESI's default assignment (`Sm`) and `Entry` lists, as the
/// device's firmware would at power-up; where sub-index 0 counts entries that are 0 (a "max
/// sub-index" default with a zero-terminated list), it is cut to the entries before the first
/// 0. Values the dictionary refuses are left as they are.
fn seed_defaults(
    od: &mut RuntimeDictionary,
    ec: &edsgen_model::model::EtherCat,
    outputs_sm: Option<u8>,
    inputs_sm: Option<u8>,
) {
    let empty = |od: &RuntimeDictionary, index: u16, width: usize| {
        let Some(n) = u8_value(od, index, 0) else {
            return false;
        };
        (1..=n).all(|s| {
            let mut b = vec![0u8; width];
            od.read(index, s, 0, &mut b).is_err() || b.iter().all(|&x| x == 0)
        })
    };
    let fill = |od: &mut RuntimeDictionary, index: u16, values: &[Vec<u8>]| {
        let _ = od.write(index, 0, &[0]);
        for (s, value) in values.iter().enumerate() {
            let _ = od.write(index, s as u8 + 1, value);
        }
        let _ = od.write(index, 0, &[values.len() as u8]);
    };
    let compact = |od: &mut RuntimeDictionary, index: u16, width: usize| {
        let Some(n) = u8_value(od, index, 0) else {
            return;
        };
        let used = (1..=n)
            .take_while(|&s| {
                let mut b = vec![0u8; width];
                od.read(index, s, 0, &mut b).is_ok() && b.iter().any(|&x| x != 0)
            })
            .count();
        if used > 0 && used < usize::from(n) {
            let _ = od.write(index, 0, &[used as u8]);
        }
    };
    for (sm, pdos) in [(outputs_sm, &ec.rx_pdos), (inputs_sm, &ec.tx_pdos)] {
        let Some(sm) = sm else { continue };
        compact(od, 0x1C10 + u16::from(sm), 2);
        let index = 0x1C10 + u16::from(sm);
        let assigned: Vec<Vec<u8>> = pdos
            .iter()
            .filter(|p| p.sm == Some(sm))
            .map(|p| p.index.to_le_bytes().to_vec())
            .collect();
        if !assigned.is_empty() && empty(od, index, 2) {
            fill(od, index, &assigned);
        }
    }
    for pdo in ec.rx_pdos.iter().chain(&ec.tx_pdos) {
        compact(od, pdo.index, 4);
        if !pdo.entries.is_empty() && empty(od, pdo.index, 4) {
            let entries: Vec<Vec<u8>> = pdo
                .entries
                .iter()
                .map(|e| {
                    let v = u32::from(e.index) << 16
                        | u32::from(e.sub) << 8
                        | u32::from(e.bit_len & 0xFF);
                    v.to_le_bytes().to_vec()
                })
                .collect();
            fill(od, pdo.index, &entries);
        }
    }
}

/// A one-byte entry's value (sub-index 0 of an array or record), if the entry exists.
fn u8_value(od: &RuntimeDictionary, index: u16, sub: u8) -> Option<u8> {
    let mut b = [0u8; 1];
    (od.value_len(index, sub).ok()? == 1).then_some(())?;
    od.read(index, sub, 0, &mut b).ok()?;
    Some(b[0])
}

impl Application for EsiDevice {
    fn mailbox(&mut self, _state: AlState, request: &[u8], answer: &mut [u8]) -> usize {
        let rules = &self.rules;
        let guard = |index: u16, sub: u8, data: &[u8]| rules.check(index, sub, data);
        // An SDO write may change the PDO assignment or mapping.
        self.images.take();
        self.sdo.mailbox(&mut self.od, &guard, request, answer)
    }

    fn image_sizes(&self) -> (usize, usize) {
        self.images().sizes
    }

    fn outputs(&mut self, _now: Instant, outputs: &[u8]) {
        let images = self.images.get_or_init(|| Images::of(self));
        unpack(&mut self.od, &images.outputs, outputs);
    }

    fn inputs(&mut self, now: Instant, inputs: &mut [u8]) {
        if let Some(behaviour) = self.behaviour.as_mut() {
            behaviour.cycle(now, &mut self.od);
        }
        let images = self.images.get_or_init(|| Images::of(self));
        pack(&self.od, &images.inputs, inputs);
    }

    fn state_changed(&mut self, _now: Instant, _from: AlState, to: AlState) {
        self.images.take();
        self.rules.state = to;
    }
}
