//! A modular device's chosen configuration: which module is plugged in which slot. One spelling
//! for the overlay's `[modules]`, `--module` and a machine file ([`parse_choice`]), resolved and
//! checked against the description as a configuration tool would (GSD: [`DpConfiguration`];
//! GSDML: [`PnConfiguration`], with its access point; ESI: [`EcConfiguration`]).

use super::dp::{decode_cfg, Dp, DpModule};

mod ethercat;
mod profinet;

pub use ethercat::{choose_ec, EcConfiguration, EcPlugged};
pub use profinet::{choose_pn, PnConfiguration, PnPlugged};

/// DP's limit on configuration bytes and on each direction's data (EN 50170).
const DP_MAX_BYTES: u32 = 244;

/// One module chosen as written: `SLOT=NAME`, or `NAME` for the slot after the one before.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModuleChoice {
    /// The slot, when written.
    pub slot: Option<u32>,
    /// The module's name (a GSD module's name; a GSDML module's ID or name).
    pub module: String,
}

/// Parses one choice: `SLOT=NAME` (SLOT a decimal number) or `NAME`. A module's name may hold
/// commas and spaces (`4 PKW, 2 PZD (PPO 1)`), so choices are never split on commas: the
/// command line repeats `--module`, a TOML file writes a list.
pub fn parse_choice(text: &str) -> Result<ModuleChoice, String> {
    let (slot, module) = match text.split_once('=') {
        Some((slot, module))
            if !slot.trim().is_empty() && slot.trim().bytes().all(|b| b.is_ascii_digit()) =>
        {
            let slot = slot
                .trim()
                .parse::<u32>()
                .map_err(|_| format!("`{text}`: slot `{}` is too large", slot.trim()))?;
            (Some(slot), module.trim())
        }
        _ => (None, text.trim()),
    };
    if module.is_empty() {
        return Err(format!(
            "`{text}`: no module named (write SLOT=NAME or NAME)"
        ));
    }
    Ok(ModuleChoice {
        slot,
        module: module.to_owned(),
    })
}

/// Parses every choice, in order (see [`parse_choice`]).
pub fn parse_choices<S: AsRef<str>>(texts: &[S]) -> Result<Vec<ModuleChoice>, String> {
    texts.iter().map(|t| parse_choice(t.as_ref())).collect()
}

/// A name compared as a person reads it: case and runs of blanks ignored (GSD names are often
/// padded: `"PPO 1:   4 PKW / 2 PZD        "`).
fn normalized(name: &str) -> String {
    name.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase()
}

/// The index of the candidate named `wanted` (as written, else [`normalized`]), or an error
/// with the nearest names.
fn find_named<'a>(
    wanted: &str,
    names: impl Iterator<Item = &'a str> + Clone,
    what: &str,
) -> Result<usize, String> {
    if let Some(n) = names.clone().position(|n| n == wanted) {
        return Ok(n);
    }
    let key = normalized(wanted);
    if let Some(n) = names.clone().position(|n| normalized(n) == key) {
        return Ok(n);
    }
    let near: Vec<String> = crate::did_you_mean::closest(
        &key,
        names.map(|n| (normalized(n), format!("\"{}\"", n.trim()))),
        false,
    );
    Err(format!(
        "no {what} \"{wanted}\"{}",
        crate::did_you_mean::listing(&near[..near.len().min(3)])
    ))
}

/// A module plugged into a DP slave's slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DpPlugged {
    /// The slot number (the first slot is the GSD's first `SlotDefinition` slot, else 1).
    pub slot: u32,
    /// The module: its index in [`Dp::modules`].
    pub module: usize,
}

/// A DP slave's configuration: its modules in slot order, Chk_Cfg's order. A compact station's
/// is its one module.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DpConfiguration {
    /// The modules, slot by slot, without gaps.
    pub slots: Vec<DpPlugged>,
}

impl DpConfiguration {
    /// The modules in slot order, each with its slot.
    pub fn modules<'a>(&'a self, dp: &'a Dp) -> impl Iterator<Item = (u32, &'a DpModule)> + 'a {
        self.slots
            .iter()
            .filter_map(|p| dp.modules.get(p.module).map(|m| (p.slot, m)))
    }

    /// The configuration bytes Chk_Cfg carries: every module's, in slot order.
    pub fn config_bytes(&self, dp: &Dp) -> Vec<u8> {
        self.modules(dp)
            .flat_map(|(_, m)| m.config.iter().copied())
            .collect()
    }

    /// The modules' parameter bytes in Set_Prm, after the slave's own: each module's
    /// ([`DpModule::default_prm_data`]) in slot order, plain (one after the other).
    pub fn module_prm_data(&self, dp: &Dp) -> Vec<u8> {
        self.modules(dp)
            .flat_map(|(_, m)| m.default_prm_data(dp))
            .collect()
    }

    /// Set_Prm's User_Prm_Data for this configuration: the slave's own bytes
    /// ([`Dp::own_prm_data`]), then [`DpConfiguration::module_prm_data`].
    pub fn user_prm_data(&self, dp: &Dp) -> Vec<u8> {
        let mut data = dp.own_prm_data();
        data.extend(self.module_prm_data(dp));
        data
    }

    /// Input and output bytes of Data_Exchange: the modules' images one after the other.
    pub fn io_lengths(&self, dp: &Dp) -> (u32, u32) {
        self.modules(dp).fold((0, 0), |(i, o), (_, m)| {
            let (mi, mo) = m.io_lengths();
            (i + mi, o + mo)
        })
    }
}

/// The number of a DP slave's first slot: its `SlotDefinition`'s first, else 1.
pub fn dp_first_slot(dp: &Dp) -> u32 {
    dp.slots.iter().map(|s| s.number).min().unwrap_or(1)
}

/// How many modules the slave takes: `Max_Module` of a modular station, one for a compact one.
fn dp_max_modules(dp: &Dp) -> u32 {
    if dp.modular_station {
        dp.max_module.unwrap_or(1).max(1)
    } else {
        1
    }
}

/// The configuration of the choices (in order; `NAME` alone takes the slot after the previous
/// one), checked as [`check_dp`] does. A slot left empty before a chosen one takes its
/// `SlotDefinition` default module. Every problem found, each a sentence.
pub fn choose_dp(dp: &Dp, choices: &[ModuleChoice]) -> Result<DpConfiguration, Vec<String>> {
    let first = dp_first_slot(dp);
    let mut errors = Vec::new();
    let mut chosen: Vec<(u32, usize)> = Vec::new();
    let mut next = first;
    for choice in choices {
        let slot = choice.slot.unwrap_or(next);
        next = slot.saturating_add(1);
        if slot < first {
            errors.push(format!("slot {slot}: the first slot is {first}"));
            continue;
        }
        if chosen.iter().any(|(s, _)| *s == slot) {
            errors.push(format!("slot {slot} is chosen twice"));
            continue;
        }
        match find_named(
            &choice.module,
            dp.modules.iter().map(|m| m.name.as_str()),
            "module",
        ) {
            Ok(module) => chosen.push((slot, module)),
            Err(e) => errors.push(format!("slot {slot}: {e}")),
        }
    }
    chosen.sort_by_key(|(slot, _)| *slot);
    let mut slots = Vec::new();
    let mut expected = first;
    for (slot, module) in chosen {
        while expected < slot {
            match dp_default_module(dp, expected) {
                Some(default) => slots.push(DpPlugged {
                    slot: expected,
                    module: default,
                }),
                None => errors.push(format!(
                    "slot {expected} is empty: a DP configuration has no gaps; choose its module"
                )),
            }
            expected += 1;
        }
        slots.push(DpPlugged { slot, module });
        expected = slot + 1;
    }
    if choices.is_empty() {
        errors.push("no module chosen".to_owned());
    }
    let configuration = DpConfiguration { slots };
    errors.extend(check_dp(dp, &configuration));
    if errors.is_empty() {
        Ok(configuration)
    } else {
        Err(errors)
    }
}

/// The `SlotDefinition` default module of `slot`, if the GSD gives one that it has.
fn dp_default_module(dp: &Dp, slot: u32) -> Option<usize> {
    let reference = dp.slots.iter().find(|s| s.number == slot)?.default_module;
    dp.modules
        .iter()
        .position(|m| m.reference == Some(reference))
}

/// What is wrong with `configuration` for the slave: more modules than `Max_Module`, a module
/// its slot's `SlotDefinition` does not allow, configuration bytes that do not decode, and
/// lengths over `Max_Input_Len`, `Max_Output_Len`, `Max_Data_Len` or DP's 244 bytes. Empty
/// when a real slave would accept it.
pub fn check_dp(dp: &Dp, configuration: &DpConfiguration) -> Vec<String> {
    let mut errors = Vec::new();
    let max = dp_max_modules(dp);
    let count = configuration.slots.len() as u32;
    if count > max {
        let kind = if dp.modular_station {
            "Max_Module is"
        } else {
            "a compact station (Modular_Station = 0) takes"
        };
        errors.push(format!("{count} modules: {kind} {max}"));
    }
    for (slot, module) in configuration.modules(dp) {
        if decode_cfg(&module.config).is_err() {
            errors.push(format!(
                "slot {slot}: module \"{}\" has configuration bytes that do not decode",
                module.name.trim()
            ));
        }
        let Some(definition) = dp.slots.iter().find(|s| s.number == slot) else {
            continue;
        };
        let allowed = match module.reference {
            Some(r) => r == definition.default_module || definition.allowed.contains(&r),
            None => true,
        };
        if !allowed {
            errors.push(format!(
                "slot {slot} (\"{}\") does not take module \"{}\"",
                definition.name.trim(),
                module.name.trim()
            ));
        }
    }
    let (inputs, outputs) = configuration.io_lengths(dp);
    let limit =
        |len: u32, max: Option<u32>, what: &str, key: &str, errors: &mut Vec<String>| match max {
            Some(max) if len > max => errors.push(format!("{len} {what}: {key} is {max}")),
            _ if len > DP_MAX_BYTES => {
                errors.push(format!("{len} {what}: DP carries at most {DP_MAX_BYTES}"))
            }
            _ => {}
        };
    let value = |v: &Option<super::Spanned<u32>>| v.as_ref().map(|v| v.value);
    limit(
        inputs,
        value(&dp.max_input_len),
        "input bytes",
        "Max_Input_Len",
        &mut errors,
    );
    limit(
        outputs,
        value(&dp.max_output_len),
        "output bytes",
        "Max_Output_Len",
        &mut errors,
    );
    if let Some(max) = value(&dp.max_data_len).filter(|max| inputs + outputs > *max) {
        errors.push(format!(
            "{} bytes of inputs and outputs: Max_Data_Len is {max}",
            inputs + outputs
        ));
    }
    let config_len = configuration.config_bytes(dp).len() as u32;
    if config_len > DP_MAX_BYTES {
        errors.push(format!(
            "{config_len} configuration bytes: DP carries at most {DP_MAX_BYTES}"
        ));
    }
    errors
}

/// How many partial configurations [`match_dp_cfg`] tries before it gives up (Chk_Cfg comes
/// from the line: bounded work for any bytes).
const MATCH_BUDGET: usize = 4096;

/// The configuration whose Chk_Cfg bytes are `bytes`, as a modular slave recognises its modules
/// in them, if one passes [`check_dp`]; `None` for bytes no allowed combination gives (the
/// slave's Cfg_Fault).
pub fn match_dp_cfg(dp: &Dp, bytes: &[u8]) -> Option<DpConfiguration> {
    let mut budget = MATCH_BUDGET;
    let mut slots = Vec::new();
    let first = dp_first_slot(dp);
    search(dp, bytes, first, &mut slots, &mut budget)
}

fn search(
    dp: &Dp,
    rest: &[u8],
    slot: u32,
    slots: &mut Vec<DpPlugged>,
    budget: &mut usize,
) -> Option<DpConfiguration> {
    if rest.is_empty() {
        let configuration = DpConfiguration {
            slots: slots.clone(),
        };
        return (!slots.is_empty() && check_dp(dp, &configuration).is_empty())
            .then_some(configuration);
    }
    if slots.len() as u32 >= dp_max_modules(dp) {
        return None;
    }
    for (n, module) in dp.modules.iter().enumerate() {
        if module.config.is_empty() || !rest.starts_with(&module.config) {
            continue;
        }
        *budget = budget.checked_sub(1)?;
        slots.push(DpPlugged { slot, module: n });
        if let Some(found) = search(dp, &rest[module.config.len()..], slot + 1, slots, budget) {
            return Some(found);
        }
        slots.pop();
    }
    None
}

#[cfg(test)]
mod tests;
