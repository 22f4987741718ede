//! `[pkw_pzd]` of an ODVA EDS's overlay: which assemblies carry the Goodrive350's 16-word PKW/PZD
//! images, and their byte order. The emitter then gives those assemblies' images conversions to
//! and from `edsgen_runtime::pkw_pzd::{OutputImage, InputImage}`.

use toml::de::{DeTable, DeValue};

use crate::diag::Diagnostic;
use crate::model::{Device, PkwPzdImages, Span};
use crate::read::text::LineIndex;
use crate::rules;
use crate::validate::cip_assembly_size;

/// Checks `[pkw_pzd]` and sets [`crate::model::Cip::pkw_pzd`].
pub fn apply(
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
            "[pkw_pzd] is for an ODVA EDS (EtherNet/IP); this description is not one".to_owned(),
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
