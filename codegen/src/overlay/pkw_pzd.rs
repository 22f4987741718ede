//! `[pkw_pzd]` of an overlay: which assemblies of an ODVA EDS (and their byte order), or which
//! module of a GSD file, carry the Goodrive350's 16-word PKW/PZD images. The emitter then gives
//! those images conversions to and from `edsgen_runtime::pkw_pzd::{OutputImage, InputImage}`.

use toml::de::{DeTable, DeValue};

use crate::diag::Diagnostic;
use crate::model::{Device, PkwPzdImages, Span};
use crate::read::text::LineIndex;
use crate::rules;
use crate::validate::cip_assembly_size;

/// Checks `[pkw_pzd]` and sets [`crate::model::Cip::pkw_pzd`] (ODVA EDS) or
/// [`crate::model::Dp::pkw_pzd_module`] (GSD).
pub fn apply(
    table: &DeTable<'_>,
    key_span: Span,
    device: &mut Device,
    text: &str,
    lines: &LineIndex,
    diags: &mut Vec<Diagnostic>,
) {
    if device.dp.is_some() {
        apply_dp(table, key_span, device, text, lines, diags);
    } else {
        apply_cip(table, key_span, device, text, lines, diags);
    }
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
    let error = |span: Span, message: String| {
        Diagnostic::new(&rules::OVERLAY, Some(span), message).with_label("[pkw_pzd] ignored")
    };
    let Some(cip) = device.cip.as_mut() else {
        diags.push(error(
            key_span,
            "[pkw_pzd] is for an ODVA EDS (EtherNet/IP) or a GSD file; this description is neither"
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
                    .and_then(|a| cip_assembly_size(cip, a));
                match (number, size) {
                    (Some(n), Some(32)) if which == "output" => output = Some(n),
                    (Some(n), Some(32)) => input = Some(n),
                    (Some(n), Some(size)) => diags.push(error(
                        span,
                        format!("Assem{n} is {size} bytes; a PKW/PZD image is 32 (16 words)"),
                    )),
                    _ => diags.push(error(
                        span,
                        format!("`{which}` names no assembly of the file"),
                    )),
                }
            }
            ("byte_order", DeValue::String(order)) => match order.as_ref() {
                "little" => little_endian = Some(true),
                "big" => little_endian = Some(false),
                other => diags.push(error(
                    span,
                    format!("byte_order is `little` or `big`, not `{other}`"),
                )),
            },
            (other, _) => diags.push(error(
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
        _ if diags.len() == before => diags.push(error(
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
    let Some(dp) = device.dp.as_mut() else {
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
