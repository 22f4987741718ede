//! The device's real configuration, from its GSDML and the model's chosen configuration
//! ([`PnConfiguration`]): the access point in its slot with its own, interface and port
//! submodules, and each module plugged (the chosen ones, else those the access point fixes or
//! uses) in its slot, each submodule with its IO data lengths (as the GSDML
//! reader counts them) and its parameter records; the send clocks and reduction ratios the
//! interface allows, and the minimum device interval.

use edsgen_model::model::modules::PnConfiguration;
use edsgen_model::model::{Profinet, Submodule};

/// One parameter record of a submodule.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    /// Index.
    pub index: u16,
    /// Its content before any write: the `Const` bytes in place, zero elsewhere.
    pub initial: Vec<u8>,
}

/// One real submodule.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RealSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber.
    pub ident: u32,
    /// Bytes of input data.
    pub input_len: u16,
    /// Bytes of output data.
    pub output_len: u16,
    /// The parameter records.
    pub records: Vec<Record>,
}

/// One real module in its slot.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RealSlot {
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// Its submodules.
    pub submodules: Vec<RealSubmodule>,
}

/// What a Connect is checked against.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceConfig {
    /// The modules in their slots (API 0), in slot order.
    pub slots: Vec<RealSlot>,
    /// The SendClockFactors the interface allows.
    pub send_clocks: Vec<u16>,
    /// The ReductionRatios the interface allows (RT_CLASS_1).
    pub reduction_ratios: Vec<u16>,
    /// MinDeviceInterval (31.25 µs units).
    pub min_device_interval: u32,
}

fn io_len(items: &[edsgen_model::model::DataItem]) -> u16 {
    let sum: u32 = items.iter().filter_map(|i| i.size()).sum();
    u16::try_from(sum).unwrap_or(u16::MAX)
}

fn real(sub: &Submodule) -> RealSubmodule {
    RealSubmodule {
        subslot: sub.subslot,
        ident: sub.submodule_ident.as_ref().map_or(0, |s| s.value),
        input_len: io_len(&sub.inputs),
        output_len: io_len(&sub.outputs),
        records: sub
            .records
            .iter()
            .map(|r| {
                let mut initial = vec![0; usize::try_from(r.length.value).unwrap_or(0).min(4096)];
                for (at, bytes) in &r.consts {
                    let at = *at as usize;
                    if let Some(area) = initial.get_mut(at..at + bytes.len()) {
                        area.copy_from_slice(bytes);
                    }
                }
                Record {
                    index: r.index.value,
                    initial,
                }
            })
            .collect(),
    }
}

impl DeviceConfig {
    /// The configuration the GSDML's device runs with ([`Profinet::configuration`]: the
    /// chosen one, else the first access point with the modules it fixes or uses).
    pub fn from_gsdml(pn: &Profinet) -> DeviceConfig {
        DeviceConfig::configured(pn, &pn.configuration())
    }

    /// The device of `pn` with `configuration`: its access point in its slot with its own,
    /// interface and port submodules, each plugged module in its slot.
    pub fn configured(pn: &Profinet, configuration: &PnConfiguration) -> DeviceConfig {
        let mut slots = Vec::new();
        let Some(dap) = configuration.access_point(pn) else {
            return DeviceConfig {
                slots,
                send_clocks: vec![32],
                reduction_ratios: vec![1, 2, 4, 8, 16, 32, 64, 128, 256, 512],
                min_device_interval: 32,
            };
        };
        let mut own: Vec<RealSubmodule> = dap.submodules.iter().map(real).collect();
        for system in dap.interface.iter().chain(&dap.ports) {
            own.push(RealSubmodule {
                subslot: system.subslot,
                ident: system.submodule_ident.as_ref().map_or(0, |s| s.value),
                input_len: 0,
                output_len: 0,
                records: Vec::new(),
            });
        }
        slots.push(RealSlot {
            slot: dap.fixed_in_slots.first().copied().unwrap_or(0),
            module_ident: dap.module_ident.as_ref().map_or(0, |m| m.value),
            submodules: own,
        });
        for plugged in &configuration.slots {
            let Some(module) = pn.modules.get(plugged.module) else {
                continue;
            };
            slots.push(RealSlot {
                slot: plugged.slot,
                module_ident: module.module_ident.as_ref().map_or(0, |m| m.value),
                submodules: module.submodules.iter().map(real).collect(),
            });
        }
        slots.sort_by_key(|s| s.slot);
        let interface = dap.interface.as_ref();
        let narrow =
            |v: &[u32]| -> Vec<u16> { v.iter().filter_map(|&x| u16::try_from(x).ok()).collect() };
        let send_clocks = interface.map(|i| narrow(&i.send_clock)).unwrap_or_default();
        let reduction_ratios = interface
            .map(|i| narrow(&i.reduction_ratio))
            .unwrap_or_default();
        DeviceConfig {
            slots,
            // GSDML's defaults when the interface says nothing.
            send_clocks: if send_clocks.is_empty() {
                vec![32]
            } else {
                send_clocks
            },
            reduction_ratios: if reduction_ratios.is_empty() {
                vec![1, 2, 4, 8, 16, 32, 64, 128, 256, 512]
            } else {
                reduction_ratios
            },
            min_device_interval: dap.min_device_interval.unwrap_or(32),
        }
    }

    /// The module in `slot`.
    pub fn slot(&self, slot: u16) -> Option<&RealSlot> {
        self.slots.iter().find(|s| s.slot == slot)
    }

    /// The submodule in `slot`, `subslot`.
    pub fn submodule(&self, slot: u16, subslot: u16) -> Option<&RealSubmodule> {
        self.slot(slot)?
            .submodules
            .iter()
            .find(|s| s.subslot == subslot)
    }
}
