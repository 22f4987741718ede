//! A machine file device's `modules` and `access_point`: refused on a card, then checked against
//! its description as the overlay's `[modules]` is (`choose_dp`, `choose_pn`, `choose_ec`), each
//! refusal its EDS708 message at the key's line, before anything starts.

use edsgen_model::model::modules::{choose_dp, choose_ec, choose_pn, parse_choices};
use edsgen_model::model::Device;

use super::file::{Fields, Reader};
use super::model::{Bus, Source};

impl Reader<'_> {
    /// The device's modules and access point, when its description takes them; `None` after a
    /// problem.
    pub(super) fn modules(
        &mut self,
        bus: Bus,
        source: &Source,
        fields: &Fields,
    ) -> Option<(Vec<String>, Option<String>)> {
        let (modules, modules_at) = fields.modules.clone().unwrap_or_default();
        let access_point = fields.access_point.clone();
        let at = match (&fields.modules, &access_point) {
            (Some(_), _) => modules_at,
            (None, Some((_, at))) => *at,
            (None, None) => return Some((Vec::new(), None)),
        };
        let Source::File(path, pick) = source else {
            self.problem(
                at,
                format!(
                    "`{}` is a bundled card: its modules are its own (`modules` is for a modular device's file)",
                    fields.device
                ),
            );
            return None;
        };
        let choices = match parse_choices(&modules) {
            Ok(choices) => choices,
            Err(message) => {
                self.problem(at, format!("EDS708: {message}"));
                return None;
            }
        };
        let pick = pick.as_deref().map(super::device_choice);
        let device = match crate::cmd::load(path, pick.as_deref()) {
            Ok(loaded) => loaded.device,
            Err(message) => {
                self.problem(at, format!("{}: {message}", path.display()));
                return None;
            }
        };
        let point = access_point.as_ref().map(|(p, _)| p.as_str());
        match judged(bus, &device, point, &choices) {
            Ok(()) => Some((modules, access_point.map(|(p, _)| p))),
            Err(errors) => {
                for error in errors {
                    self.problem(at, format!("EDS708: {error}"));
                }
                None
            }
        }
    }
}

/// The choices checked against the device's description of `bus`'s format.
fn judged(
    bus: Bus,
    device: &Device,
    access_point: Option<&str>,
    choices: &[edsgen_model::model::modules::ModuleChoice],
) -> Result<(), Vec<String>> {
    let wrong = |what: &str| Err(vec![format!("modules are chosen in {what}")]);
    match bus {
        Bus::Profibus => match device.dp() {
            Some(dp) => choose_dp(dp, choices).map(drop),
            None => wrong("a GSD file on [[profibus]]"),
        },
        Bus::Profinet => match device.profinet() {
            Some(pn) => choose_pn(pn, access_point, choices).map(drop),
            None => wrong("a GSDML file on [[profinet]]"),
        },
        Bus::EtherCat => match device.ethercat() {
            Some(ec) => choose_ec(ec, choices).map(drop),
            None => wrong("an ESI file on [[ethercat]]"),
        },
        Bus::CanOpen | Bus::Enip => wrong("[[profibus]], [[profinet]] and [[ethercat]] devices"),
    }
}
