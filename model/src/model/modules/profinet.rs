//! A GSDML device's chosen configuration: its access point (slot 0's `DeviceAccessPointItem`)
//! and the modules in its slots, checked against the access point's `UseableModules`
//! (`AllowedInSlots`, `FixedInSlots`, `UsedInSlots`), its `PhysicalSlots` and its
//! `MaxInputLength` / `MaxOutputLength`.

use super::{find_named, ModuleChoice};
use crate::model::{AccessPoint, Profinet, Submodule};

/// A module plugged into a slot of a PROFINET device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PnPlugged {
    /// The slot number.
    pub slot: u16,
    /// The module: its index in [`Profinet::modules`].
    pub module: usize,
}

/// A PROFINET device's configuration: its access point and its modules by slot.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PnConfiguration {
    /// The access point: its index in [`Profinet::access_points`].
    pub access_point: usize,
    /// The modules in slot order.
    pub slots: Vec<PnPlugged>,
}

impl PnConfiguration {
    /// The access point.
    pub fn access_point<'a>(&self, pn: &'a Profinet) -> Option<&'a AccessPoint> {
        pn.access_points.get(self.access_point)
    }

    /// Every submodule with its slot, the access point's first (in its own slots, 0 when it
    /// gives none), then the modules' in slot order.
    pub fn submodules<'a>(&self, pn: &'a Profinet) -> Vec<(u16, &'a Submodule)> {
        let mut out = Vec::new();
        if let Some(dap) = self.access_point(pn) {
            let slot = dap.fixed_in_slots.first().copied().unwrap_or(0);
            out.extend(dap.submodules.iter().map(|s| (slot, s)));
        }
        for plugged in &self.slots {
            if let Some(module) = pn.modules.get(plugged.module) {
                out.extend(module.submodules.iter().map(|s| (plugged.slot, s)));
            }
        }
        out
    }

    /// Input and output data bytes of every submodule (IOPS bytes not counted).
    pub fn io_lengths(&self, pn: &Profinet) -> (u32, u32) {
        let size = |items: &[crate::model::DataItem]| -> u32 {
            items.iter().filter_map(|i| i.size()).sum()
        };
        self.submodules(pn).iter().fold((0, 0), |(i, o), (_, s)| {
            (i + size(&s.inputs), o + size(&s.outputs))
        })
    }
}

/// The slots `module` (by `ID`) may take under `dap`: `AllowedInSlots`, else `FixedInSlots`,
/// else `UsedInSlots` (the reader already fills `allowed_in_slots` so).
fn allowed_slots(dap: &AccessPoint, module_id: &str) -> Vec<u16> {
    dap.useable_modules
        .iter()
        .filter(|r| r.target.value == module_id)
        .flat_map(|r| {
            r.allowed_in_slots
                .iter()
                .chain(&r.fixed_in_slots)
                .chain(&r.used_in_slots)
                .copied()
        })
        .collect()
}

/// The configuration of `access_point` (its `ID` or name; `None`: the first) with the modules
/// it fixes or uses by default, then the choices (a module by `ID` or name, `SLOT=` or the
/// first free slot it may take) in their slots. Every problem found, each a sentence.
pub fn choose_pn(
    pn: &Profinet,
    access_point: Option<&str>,
    choices: &[ModuleChoice],
) -> Result<PnConfiguration, Vec<String>> {
    let mut errors = Vec::new();
    let index = match access_point {
        None if pn.access_points.is_empty() => Err("the GSDML has no access point".to_owned()),
        None => Ok(0),
        Some(wanted) => find_named(
            wanted,
            pn.access_points.iter().map(|a| a.id.as_str()),
            "access point",
        )
        .or_else(|e| {
            pn.access_points
                .iter()
                .position(|a| a.name.as_deref() == Some(wanted))
                .ok_or(e)
        }),
    };
    let index = index.map_err(|e| vec![e])?;
    let dap = &pn.access_points[index];
    let dap_slots: Vec<u16> = if dap.fixed_in_slots.is_empty() {
        vec![0]
    } else {
        dap.fixed_in_slots.clone()
    };
    let module_index = |id: &str| pn.modules.iter().position(|m| m.id == id);
    // The modules the access point fixes or plugs by default.
    let mut slots: Vec<(u16, usize, bool)> = Vec::new();
    for r in &dap.useable_modules {
        let Some(module) = module_index(&r.target.value) else {
            continue;
        };
        for &slot in &r.fixed_in_slots {
            slots.push((slot, module, true));
        }
        for &slot in r
            .used_in_slots
            .iter()
            .filter(|s| !r.fixed_in_slots.contains(s))
        {
            slots.push((slot, module, false));
        }
    }
    let useable: Vec<usize> = dap
        .useable_modules
        .iter()
        .filter_map(|r| module_index(&r.target.value))
        .collect();
    for choice in choices {
        let names = useable.iter().map(|&n| pn.modules[n].id.as_str());
        let by_id = find_named(&choice.module, names, "module");
        let by_name = useable
            .iter()
            .copied()
            .find(|&n| pn.modules[n].name.as_deref() == Some(choice.module.as_str()));
        let module = match (by_id, by_name) {
            (Ok(n), _) => useable[n],
            (Err(_), Some(n)) => n,
            (Err(e), None) => {
                errors.push(format!("{e} among access point {}'s modules", dap.id));
                continue;
            }
        };
        let id = &pn.modules[module].id;
        let allowed = allowed_slots(dap, id);
        let taken = |slot: u16, slots: &[(u16, usize, bool)]| {
            slots.iter().any(|(s, _, fixed)| *s == slot && *fixed)
        };
        let slot = match choice.slot {
            Some(slot) => match u16::try_from(slot) {
                Ok(slot) => slot,
                Err(_) => {
                    errors.push(format!("slot {slot} is not a PROFINET slot (0..=65535)"));
                    continue;
                }
            },
            None => match allowed.iter().copied().find(|s| {
                !taken(*s, &slots) && !slots.iter().any(|(t, m, _)| t == s && *m != module)
            }) {
                Some(slot) => slot,
                None => {
                    errors.push(format!("module {id}: no free slot it may take"));
                    continue;
                }
            },
        };
        if dap_slots.contains(&slot) {
            errors.push(format!("slot {slot} is the access point's"));
        } else if taken(slot, &slots) {
            errors.push(format!(
                "slot {slot} holds a module the access point fixes there"
            ));
        } else if !allowed.contains(&slot) {
            errors.push(format!(
                "module {id} is not allowed in slot {slot} (it may take {})",
                slot_list(&allowed)
            ));
        } else if !dap.physical_slots.is_empty() && !dap.physical_slots.contains(&slot) {
            errors.push(format!(
                "slot {slot} is not one of the access point's PhysicalSlots"
            ));
        } else {
            slots.retain(|(s, _, _)| *s != slot);
            slots.push((slot, module, false));
        }
    }
    slots.sort_by_key(|(slot, _, _)| *slot);
    let configuration = PnConfiguration {
        access_point: index,
        slots: slots
            .into_iter()
            .map(|(slot, module, _)| PnPlugged { slot, module })
            .collect(),
    };
    let (inputs, outputs) = configuration.io_lengths(pn);
    for (len, max, what, key) in [
        (inputs, &dap.max_input_length, "input", "MaxInputLength"),
        (outputs, &dap.max_output_length, "output", "MaxOutputLength"),
    ] {
        if let Some(max) = max.as_ref().map(|m| m.value).filter(|max| len > *max) {
            errors.push(format!(
                "{len} bytes of {what} data: the access point's {key} is {max}"
            ));
        }
    }
    if errors.is_empty() {
        Ok(configuration)
    } else {
        Err(errors)
    }
}

/// `1, 2, 5..8` for a list of slots.
fn slot_list(slots: &[u16]) -> String {
    let mut sorted = slots.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut parts: Vec<String> = Vec::new();
    let mut n = 0;
    while n < sorted.len() {
        let start = sorted[n];
        while n + 1 < sorted.len() && sorted[n + 1] == sorted[n] + 1 {
            n += 1;
        }
        let end = sorted[n];
        parts.push(if end > start {
            format!("{start}..{end}")
        } else {
            start.to_string()
        });
        n += 1;
    }
    if parts.is_empty() {
        "none".to_owned()
    } else {
        parts.join(", ")
    }
}
