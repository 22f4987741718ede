//! `[pkw_pzd]` of an overlay: which assemblies of an ODVA EDS (and their byte order), which
//! module of a GSD file, or which submodule of a GSDML file carry the Goodrive350's 16-word
//! PKW/PZD images. The emitter then gives those images conversions to and from
//! `edsgen_runtime::pkw_pzd::{OutputImage, InputImage}`.

use toml::de::{DeTable, DeValue};

use crate::diag::Diagnostic;
use crate::model::{Bus, Device, PkwPzdImages, Profinet, Span, Submodule};
use crate::read::text::LineIndex;
use crate::rules;

/// Checks `[pkw_pzd]` and sets [`crate::model::Cip::pkw_pzd`] (ODVA EDS),
/// [`crate::model::Dp::pkw_pzd_module`] (GSD) or [`Submodule::pkw_pzd`] (GSDML).
pub fn apply(
    table: &DeTable<'_>,
    key_span: Span,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    match device.bus {
        Bus::Dp(_) => apply_dp(table, key_span, device, text, lines, diags),
        Bus::Profinet(ref mut pn) => apply_pn(table, key_span, pn, text, lines, diags),
        Bus::Cip(_) | Bus::CanOpen | Bus::EtherCat(_) => {
            apply_cip(table, key_span, device, text, lines, diags)
        }
    }
}

/// A refusal of the table: the overlay's rule at `span`, the table ignored.
fn ignored(span: Span, message: String) -> Diagnostic {
    Diagnostic::new(&rules::OVERLAY, Some(span), message).with_label("[pkw_pzd] ignored")
}

/// `[pkw_pzd] output = N, input = N, byte_order = "little"|"big"` (ODVA EDS): the assemblies.
fn apply_cip(
    table: &DeTable<'_>,
    key_span: Span,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let Some(cip) = device.cip_mut() else {
        diags.push(ignored(
            key_span,
            "[pkw_pzd] is for an ODVA EDS (EtherNet/IP), a GSD or a GSDML file; this description is \
             none of them"
                .to_owned(),
        ));
        return;
    };
    let before = diags.len();
    let mut output = None;
    let mut input = None;
    let mut little_endian = None;
    for (key, value) in table {
        let span = lines.span(text, value.span());
        match (key.get_ref().as_ref(), value.get_ref()) {
            (which @ ("output" | "input"), DeValue::Integer(n)) => {
                let number = n.as_str().parse::<u32>().ok();
                let size = number
                    .and_then(|n| cip.assemblies.get(&n))
                    .and_then(|a| cip.assembly_size(a));
                match (number, size) {
                    (Some(n), Some(32)) if which == "output" => output = Some(n),
                    (Some(n), Some(32)) => input = Some(n),
                    (Some(n), Some(size)) => diags.push(ignored(
                        span,
                        format!("Assem{n} is {size} bytes; a PKW/PZD image is 32 (16 words)"),
                    )),
                    _ => diags.push(ignored(
                        span,
                        format!("`{which}` names no assembly of the file"),
                    )),
                }
            }
            ("byte_order", DeValue::String(order)) => match order.as_ref() {
                "little" => little_endian = Some(true),
                "big" => little_endian = Some(false),
                other => diags.push(ignored(
                    span,
                    format!("byte_order is `little` or `big`, not `{other}`"),
                )),
            },
            (other, _) => diags.push(ignored(
                lines.span(text, key.span()),
                format!(
                    "`{other}` is not a key of [pkw_pzd] (output = N, input = N, byte_order = \"little\")"
                ),
            )),
        }
    }
    match (output, input, little_endian) {
        (Some(output), Some(input), Some(little_endian)) => {
            cip.pkw_pzd = Some(PkwPzdImages {
                output,
                input,
                little_endian,
            })
        }
        _ if diags.len() == before => diags.push(ignored(
            key_span,
            "[pkw_pzd] needs output, input and byte_order".to_owned(),
        )),
        _ => {}
    }
}

/// `[pkw_pzd] module = "NAME"` (GSD): the module whose images are INVT's PKW/PZD layout, 16
/// words each way with the 4 PKW words as the first identifier.
fn apply_dp(
    table: &DeTable<'_>,
    table_span: Span,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let Some(dp) = device.dp_mut() else {
        diags.push(Diagnostic::new(
            &rules::OVERLAY,
            Some(table_span),
            "[pkw_pzd] is for a GSD file's module".to_owned(),
        ));
        return;
    };
    for (key, value) in table {
        let span = lines.span(text, key.span());
        let name = match (key.get_ref().as_ref(), value.get_ref()) {
            ("module", DeValue::String(name)) => name.to_string(),
            _ => {
                diags.push(Diagnostic::new(
                    &rules::OVERLAY,
                    Some(span),
                    "[pkw_pzd] takes `module = \"NAME\"`".to_owned(),
                ));
                continue;
            }
        };
        let fits = dp.modules.iter().find(|m| m.name == name).is_some_and(|m| {
            let ids = m.identifiers();
            m.io_lengths() == (32, 32)
                && ids
                    .first()
                    .is_some_and(|i| (i.input_bytes, i.output_bytes, i.words) == (8, 8, true))
        });
        if fits {
            dp.pkw_pzd_module = Some(name);
        } else {
            diags.push(Diagnostic::new(
                &rules::OVERLAY,
                Some(span),
                format!(
                    "no module \"{name}\" of 32 bytes each way whose first identifier is 4 words \
                     (PKW1-PKW4)"
                ),
            ));
        }
    }
}

/// `[pkw_pzd] module = "ID or name", subslot = N` (GSDML): the submodule whose images are INVT's
/// PKW/PZD layout, 32 bytes each way. `module` names a `ModuleItem` or a
/// `DeviceAccessPointItem` (a compact device's own submodules) by its `ID`, else by its name;
/// `subslot` may be left out when the module has one submodule.
fn apply_pn(
    table: &DeTable<'_>,
    key_span: Span,
    pn: &mut Profinet,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    let before = diags.len();
    let mut module = None;
    let mut subslot = None;
    for (key, value) in table {
        let span = lines.span(text, value.span());
        match (key.get_ref().as_ref(), value.get_ref()) {
            ("module", DeValue::String(name)) => module = Some((name.to_string(), span)),
            ("module", _) => diags.push(ignored(
                span,
                "`module` is the ID or name of a ModuleItem or DeviceAccessPointItem: \
                 module = \"MOD_1\""
                    .to_owned(),
            )),
            ("subslot", DeValue::Integer(n)) => match n.as_str().parse::<u16>() {
                Ok(n) => subslot = Some((n, span)),
                Err(_) => diags.push(ignored(
                    span,
                    format!(
                        "`subslot` is a subslot number (0..=65535), not {}",
                        n.as_str()
                    ),
                )),
            },
            ("subslot", _) => diags.push(ignored(
                span,
                "`subslot` is a subslot number: subslot = 1".to_owned(),
            )),
            (other, _) => diags.push(ignored(
                lines.span(text, key.span()),
                format!(
                    "`{other}` is not a key of [pkw_pzd] for a GSDML file (module = \"ID or \
                     name\", subslot = N)"
                ),
            )),
        }
    }
    if diags.len() != before {
        return;
    }
    let Some((name, module_span)) = module else {
        diags.push(ignored(
            key_span,
            "[pkw_pzd] needs `module = \"ID or name\"` (and `subslot = N` when the module has \
             several submodules)"
                .to_owned(),
        ));
        return;
    };
    let submodules = match module_submodules(pn, &name) {
        Ok(submodules) => submodules,
        Err(message) => return diags.push(ignored(module_span, message)),
    };
    if submodules.is_empty() {
        return diags.push(ignored(module_span, format!("\"{name}\" has no submodule")));
    }
    let subslots = submodules
        .iter()
        .map(|s| s.subslot.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let chosen = match subslot {
        Some((n, span)) => match submodules.iter_mut().find(|s| s.subslot == n) {
            Some(sub) => (sub, span),
            None => {
                return diags.push(ignored(
                    span,
                    format!(
                        "\"{name}\" has no submodule in subslot {n} (its subslots: {subslots})"
                    ),
                ))
            }
        },
        None if submodules.len() == 1 => (&mut submodules[0], module_span),
        None => {
            return diags.push(ignored(
                module_span,
                format!(
                    "\"{name}\" has {} submodules (subslots {subslots}): say which with \
                     `subslot = N`",
                    submodules.len()
                ),
            ))
        }
    };
    let (sub, span) = chosen;
    let bytes = |items: &[crate::model::DataItem]| -> Option<u32> {
        items.iter().map(|i| i.size()).sum::<Option<u32>>()
    };
    match (bytes(&sub.inputs), bytes(&sub.outputs)) {
        (Some(32), Some(32)) => sub.pkw_pzd = true,
        (inputs, outputs) => {
            let shown =
                |n: Option<u32>| n.map_or("an unknown number of".to_owned(), |n| n.to_string());
            diags.push(ignored(
                span,
                format!(
                    "submodule `{}` in subslot {} has {} input bytes and {} output bytes; a \
                     PKW/PZD image is 32 each way (16 words)",
                    sub.id,
                    sub.subslot,
                    shown(inputs),
                    shown(outputs)
                ),
            ))
        }
    }
}

/// The submodules of the module or access point `name` names (its `ID`, else its one name).
fn module_submodules<'a>(
    pn: &'a mut Profinet,
    name: &str,
) -> Result<&'a mut Vec<Submodule>, String> {
    let by_id = pn.modules.iter().position(|m| m.id == name);
    let dap_by_id = pn.access_points.iter().position(|d| d.id == name);
    let by_name: Vec<usize> = pn
        .modules
        .iter()
        .enumerate()
        .filter(|(_, m)| m.name.as_deref() == Some(name))
        .map(|(n, _)| n)
        .collect();
    let dap_by_name: Vec<usize> = pn
        .access_points
        .iter()
        .enumerate()
        .filter(|(_, d)| d.name.as_deref() == Some(name))
        .map(|(n, _)| n)
        .collect();
    match (by_id, dap_by_id) {
        (Some(n), _) => return Ok(&mut pn.modules[n].submodules),
        (None, Some(n)) => return Ok(&mut pn.access_points[n].submodules),
        (None, None) => {}
    }
    match (by_name.as_slice(), dap_by_name.as_slice()) {
        ([n], []) => Ok(&mut pn.modules[*n].submodules),
        ([], [n]) => Ok(&mut pn.access_points[*n].submodules),
        ([], []) => Err(format!(
            "no ModuleItem or DeviceAccessPointItem has the ID or name \"{name}\""
        )),
        (modules, daps) => Err(format!(
            "\"{name}\" is the name of {} items: give the ID",
            modules.len() + daps.len()
        )),
    }
}
