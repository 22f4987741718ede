//! `[modules]` of an overlay: the modules a modular device is built with, as a configuration
//! tool plugs them (`slots = ["4 PKW, 2 PZD (PPO 1)", "3=8 DI"]`, each `NAME` or `SLOT=NAME`, as
//! `--module` writes them; an ESI's `SLOT` is the number of its `Slots/Slot`, 1 first), and a
//! GSDML device's access point (`access_point = "DAP 2"`, its ID
//! or name). Checked against the description by [`crate::model::modules`]; the generator then
//! emits the chosen configuration's images.

use toml::de::{DeTable, DeValue};

use crate::diag::Diagnostic;
use crate::model::modules::{choose_dp, choose_ec, choose_pn, parse_choice};
use crate::model::{Device, Span};
use crate::read::text::LineIndex;
use crate::rules;

/// A refusal: the overlay's rule at `span`, the table ignored.
fn ignored(span: Span, message: String) -> Diagnostic {
    Diagnostic::new(&rules::OVERLAY, Some(span), message).with_label("[modules] ignored")
}

/// Checks `[modules]` and sets [`crate::model::Dp::chosen`] (GSD),
/// [`crate::model::Profinet::chosen`] (GSDML) or [`crate::model::EtherCat::chosen`] (ESI).
pub fn apply(
    table: &DeTable<'_>,
    key_span: Span,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let before = diags.len();
    let mut slots = None;
    let mut access_point = None;
    for (key, value) in table {
        let span = lines.span(text, value.span());
        match (key.get_ref().as_ref(), value.get_ref()) {
            ("slots", DeValue::Array(items)) => {
                let mut choices = Vec::new();
                for item in items.iter() {
                    let item_span = lines.span(text, item.span());
                    let parsed = match item.get_ref() {
                        DeValue::String(choice) => parse_choice(choice),
                        _ => {
                            Err("a module is written as a string: \"NAME\" or \"SLOT=NAME\"".into())
                        }
                    };
                    match parsed {
                        Ok(choice) => choices.push(choice),
                        Err(message) => diags.push(ignored(item_span, message)),
                    }
                }
                slots = Some((choices, span));
            }
            ("access_point", DeValue::String(id)) => access_point = Some((id.to_string(), span)),
            ("access_point", _) => diags.push(ignored(
                span,
                "`access_point` is the ID or name of a DeviceAccessPointItem".to_owned(),
            )),
            ("slots", _) => diags.push(ignored(
                span,
                "`slots` is a list: slots = [\"NAME\", \"SLOT=NAME\"]".to_owned(),
            )),
            (other, _) => diags.push(ignored(
                lines.span(text, key.span()),
                format!(
                    "`{other}` is not a key of [modules] (slots = [\"NAME\", ...], access_point = \"ID\")"
                ),
            )),
        }
    }
    if diags.len() > before {
        return;
    }
    if let Some(pn) = device.profinet_mut() {
        let span = slots
            .as_ref()
            .map(|(_, span)| *span)
            .or(access_point.as_ref().map(|(_, span)| *span))
            .unwrap_or(key_span);
        let choices = slots.map(|(choices, _)| choices).unwrap_or_default();
        let access_point = access_point.as_ref().map(|(id, _)| id.as_str());
        match choose_pn(pn, access_point, &choices) {
            Ok(configuration) => pn.chosen = Some(configuration),
            Err(errors) => diags.extend(errors.into_iter().map(|e| ignored(span, e))),
        }
        return;
    }
    if let Some((_, span)) = access_point {
        return diags.push(ignored(
            span,
            "`access_point` is for a GSDML file".to_owned(),
        ));
    }
    let Some((choices, span)) = slots else {
        return diags.push(ignored(
            key_span,
            "[modules] needs `slots = [\"NAME\", \"SLOT=NAME\", ...]`".to_owned(),
        ));
    };
    if let Some(ec) = device.ethercat_mut() {
        match choose_ec(ec, &choices) {
            Ok(configuration) => ec.chosen = Some(configuration),
            Err(errors) => diags.extend(errors.into_iter().map(|e| ignored(span, e))),
        }
        return;
    }
    let Some(dp) = device.dp_mut() else {
        return diags.push(ignored(
            key_span,
            "[modules] is for a modular device: a GSD, GSDML or ESI file".to_owned(),
        ));
    };
    match choose_dp(dp, &choices) {
        Ok(configuration) => dp.chosen = Some(configuration),
        Err(errors) => diags.extend(errors.into_iter().map(|e| ignored(span, e))),
    }
}
