//! GSD rules over the model's [`Dp`] part (GSD010–GSD017; the reader owns GSD001–GSD007).
//! Errors are what makes a master's Set_Prm or Chk_Cfg wrong: configuration bytes that cannot
//! be decoded, lengths beyond the slave's limits, parameters placed where there is no room or
//! referring to nothing, defaults a slave would refuse.

use crate::diag::Diagnostic;
use crate::model::{decode_cfg, CfgError, Dp, PrmType, PrmValues, Span};
use crate::rules;

/// Judges the DP part of a device read from a GSD file.
pub fn check(dp: &Dp, out: &mut Vec<Diagnostic>) {
    identity(dp, out);
    baud_rates(dp, out);
    modules(dp, out);
    parameters(dp, out);
}

fn identity(dp: &Dp, out: &mut Vec<Diagnostic>) {
    if dp.ident_number.is_none() {
        out.push(Diagnostic::new(
            &rules::GSD_IDENT,
            None,
            "no Ident_Number: a master cannot send Set_Prm".to_owned(),
        ));
    }
}

/// GSD016: a supported rate without its MaxTsdr. A MaxTsdr for a rate the slave does not
/// support is harmless (vendors fill the whole table; a master never uses it): not reported.
fn baud_rates(dp: &Dp, out: &mut Vec<Diagnostic>) {
    for baud in dp.baud_rates.iter().filter(|b| b.max_tsdr.is_none()) {
        let rate = baud.rate.keyword();
        out.push(
            Diagnostic::new(
                &rules::GSD_TSDR,
                Some(baud.span),
                format!(
                    "{rate}_supp without MaxTsdr_{rate}: a master cannot know how long to wait"
                ),
            )
            .with_help(format!(
                "add `MaxTsdr_{rate} = N`, the slave's longest response time at that rate in bit \
                 times (the table of the slave's manual or ASIC), or remove `{rate}_supp`"
            )),
        );
    }
}

fn modules(dp: &Dp, out: &mut Vec<Diagnostic>) {
    if dp.modules.is_empty() {
        out.push(Diagnostic::new(
            &rules::GSD_NO_MODULE,
            None,
            "no Module: a master has no configuration to send".to_owned(),
        ));
    }
    for module in &dp.modules {
        match decode_cfg(&module.config) {
            Err(CfgError::Truncated(at)) => out.push(Diagnostic::new(
                &rules::GSD_CFG_BYTES,
                Some(module.span),
                format!(
                    "module \"{}\": the identifier at byte {at} ({:#04X}) says more bytes follow \
                     than there are",
                    module.name,
                    module.config.get(at).copied().unwrap_or(0)
                ),
            )),
            Ok(_) => {
                let lengths = module.io_lengths();
                lengths_within(
                    dp,
                    &format!("module \"{}\"", module.name),
                    lengths,
                    module.span,
                    out,
                );
            }
        }
    }
}

fn lengths_within(
    dp: &Dp,
    what: &str,
    (input, output): (u32, u32),
    span: Span,
    out: &mut Vec<Diagnostic>,
) {
    let limits = [
        ("input", input, &dp.max_input_len, "Max_Input_Len"),
        ("output", output, &dp.max_output_len, "Max_Output_Len"),
        ("total", input + output, &dp.max_data_len, "Max_Data_Len"),
    ];
    for (kind, bytes, limit, name) in limits {
        if let Some(limit) = limit {
            if bytes > limit.value {
                out.push(
                    Diagnostic::new(
                        &rules::GSD_IO_LENGTH,
                        Some(span),
                        format!(
                            "{what}: {bytes} {kind} bytes, beyond {name} = {}",
                            limit.value
                        ),
                    )
                    .with_help(format!("{name} is on line {}", limit.span.line)),
                );
            }
        }
    }
}

fn parameters(dp: &Dp, out: &mut Vec<Diagnostic>) {
    let length = dp
        .user_prm_data_len
        .as_ref()
        .or(dp.max_user_prm_data_len.as_ref())
        .map(|l| l.value);
    if let (Some(declared), false) = (&dp.user_prm_data_len, dp.user_prm_data.is_empty()) {
        if dp.user_prm_data.len() as u32 > declared.value {
            out.push(Diagnostic::new(
                &rules::GSD_PRM_LENGTH,
                Some(declared.span),
                format!(
                    "User_Prm_Data has {} bytes, User_Prm_Data_Len says {}",
                    dp.user_prm_data.len(),
                    declared.value
                ),
            ));
        }
    }
    for c in &dp.prm_consts {
        let end = c.offset + c.bytes.len() as u32;
        if let Some(length) = length.filter(|&l| end > l) {
            out.push(Diagnostic::new(
                &rules::GSD_PRM_LENGTH,
                Some(c.span),
                format!("Ext_User_Prm_Data_Const({}) ends at byte {end}, beyond the {length} parameter bytes", c.offset),
            ));
        }
    }
    for r in &dp.prm_refs {
        let Some(def) = dp
            .prm_definitions
            .iter()
            .find(|d| d.reference == r.reference)
        else {
            out.push(Diagnostic::new(
                &rules::GSD_PRM_REF,
                Some(r.span),
                format!(
                    "Ext_User_Prm_Data_Ref({}) = {}: no ExtUserPrmData {}",
                    r.offset, r.reference, r.reference
                ),
            ));
            continue;
        };
        let end = r.offset + def.data_type.size();
        if let Some(length) = length.filter(|&l| end > l) {
            out.push(Diagnostic::new(
                &rules::GSD_PRM_LENGTH,
                Some(r.span),
                format!(
                    "Ext_User_Prm_Data_Ref({}) places \"{}\" up to byte {end}, beyond the {length} parameter bytes",
                    r.offset, def.name
                ),
            ));
        }
    }
    for module in &dp.modules {
        for r in &module.prm_refs {
            if !dp
                .prm_definitions
                .iter()
                .any(|d| d.reference == r.reference)
            {
                out.push(Diagnostic::new(
                    &rules::GSD_PRM_REF,
                    Some(r.span),
                    format!(
                        "module \"{}\": Ext_User_Prm_Data_Ref({}) = {}: no ExtUserPrmData {}",
                        module.name, r.offset, r.reference, r.reference
                    ),
                ));
            }
        }
    }
    for def in &dp.prm_definitions {
        if let Some(text) = def.text_ref {
            if !dp.prm_texts.iter().any(|t| t.reference == text) {
                out.push(Diagnostic::new(
                    &rules::GSD_PRM_REF,
                    Some(def.span),
                    format!(
                        "ExtUserPrmData {} \"{}\": Prm_Text_Ref = {text}, no PrmText {text}",
                        def.reference, def.name
                    ),
                ));
            }
        }
        let (low, high) = def.data_type.bounds();
        let (allowed, within_type) = match &def.values {
            PrmValues::Range(a, b) => (
                (*a..=*b).contains(&def.default),
                (low..=high).contains(a) && (low..=high).contains(b),
            ),
            PrmValues::List(list) => (
                list.contains(&def.default),
                list.iter().all(|v| (low..=high).contains(v)),
            ),
            PrmValues::Any => ((low..=high).contains(&def.default), true),
        };
        if !allowed || !within_type {
            let kind = match def.data_type {
                PrmType::Bit(_) => "Bit".to_owned(),
                PrmType::BitArea(a, b) => format!("BitArea({a}-{b})"),
                PrmType::Unsigned(n) => format!("Unsigned{}", 8 * n),
                PrmType::Signed(n) => format!("Signed{}", 8 * n),
            };
            let message = if !allowed {
                format!(
                    "ExtUserPrmData {} \"{}\": default {} outside its allowed values",
                    def.reference, def.name, def.default
                )
            } else {
                format!(
                    "ExtUserPrmData {} \"{}\": allowed values outside {kind} ({low} to {high})",
                    def.reference, def.name
                )
            };
            out.push(Diagnostic::new(
                &rules::GSD_PRM_DEFAULT,
                Some(def.type_span),
                message,
            ));
        }
    }
}
