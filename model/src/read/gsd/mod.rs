//! The GSD reader (PROFIBUS-DP device description, the PNO's GSD specification): a file into a
//! [`Device`](crate::model::Device) whose [`Dp`] part holds what the file says, never failing on content.
//!
//! Lexing is in [`lines`] (Latin-1, `;` comments, `\` continuations); keywords are matched
//! case-insensitively. Blocks (`Module` … `EndModule`, `PrmText`, `ExtUserPrmData`,
//! `SlotDefinition`, `Unit_Diag_Area`) are read line by line; what the model does not interpret
//! is kept in [`Dp::other`] (reported as GSD005 unless it is a keyword of the specification the
//! model leaves aside).

use std::collections::HashMap;
use std::path::Path;

use crate::diag::Diagnostic;
use crate::model::{
    Bus, DeviceInfo, Dp, DpModule, DpSlot, ExtUserPrmData, Format, GsdKeyword, PrmConst, PrmRef,
    PrmText, PrmType, PrmValues, Span, Spanned, TextEncoding, UnitDiag,
};
use crate::rules::{self, Rule};

use super::Read;

pub mod lines;
mod other;
mod values;

use lines::Line;
use values::{call_arg, number, numbers, quoted, split_key};

/// Reads a GSD file's bytes.
pub fn read(path: &Path, bytes: &[u8]) -> Read {
    let (text, encoding) = lines::decode(bytes);
    let mut reader = Reader::default();
    if encoding == TextEncoding::Utf8 {
        let span = crate::read::text::first_non_ascii(&text).map(|(l, c)| Span::new(l, c, 1));
        reader.diag(
            &rules::GSD_UTF8,
            span,
            "the file is UTF-8, where a GSD file is ISO 8859-1: read as UTF-8".to_owned(),
        );
    }
    let lines = lines::logical_lines(&text);
    if !lines
        .iter()
        .any(|l| l.text.eq_ignore_ascii_case("#Profibus_DP"))
    {
        reader.diag(
            &rules::GSD_NOT_GSD,
            lines.first().map(|l| l.span),
            "no `#Profibus_DP` line: this is not a GSD file".to_owned(),
        );
    }
    for line in &lines {
        reader.line(line);
    }
    reader.close_block(None);
    let mut device = super::eds::empty_device(path, Format::Gsd, encoding);
    let dp = reader.dp;
    device.device_info = DeviceInfo {
        vendor_name: dp.vendor_name.clone(),
        product_name: dp.model_name.clone(),
        order_code: dp.order_number.clone(),
        product_number: dp
            .ident_number
            .as_ref()
            .map(|i| Spanned::new(u32::from(i.value), i.span)),
        ..DeviceInfo::default()
    };
    device.bus = Bus::Dp(dp);
    let mut diagnostics = reader.diags;
    crate::diag::sort(&mut diagnostics);
    Read {
        device,
        diagnostics,
        text,
    }
}

/// The block being read.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Block {
    Module(usize),
    PrmText(usize),
    ExtUserPrmData(usize),
    SlotDefinition,
    UnitDiagArea(u32, u32),
}

impl Block {
    fn name(self) -> &'static str {
        match self {
            Block::Module(_) => "Module",
            Block::PrmText(_) => "PrmText",
            Block::ExtUserPrmData(_) => "ExtUserPrmData",
            Block::SlotDefinition => "SlotDefinition",
            Block::UnitDiagArea(..) => "Unit_Diag_Area",
        }
    }

    fn end(self) -> &'static str {
        match self {
            Block::Module(_) => "EndModule",
            Block::PrmText(_) => "EndPrmText",
            Block::ExtUserPrmData(_) => "EndExtUserPrmData",
            Block::SlotDefinition => "EndSlotDefinition",
            Block::UnitDiagArea(..) => "Unit_Diag_Area_End",
        }
    }
}

#[derive(Default)]
struct Reader {
    dp: Dp,
    diags: Vec<Diagnostic>,
    block: Option<(Block, Span)>,
    /// Top-level single-valued keywords seen (lowercase) and where.
    seen: HashMap<String, Span>,
}

impl Reader {
    fn diag(&mut self, rule: &'static Rule, span: Option<Span>, message: String) {
        self.diags.push(Diagnostic::new(rule, span, message));
    }

    fn bad(&mut self, span: Span, what: &str, value: &str) {
        self.diag(
            &rules::GSD_BAD_VALUE,
            Some(span),
            format!("`{value}` is not {what}"),
        );
    }

    fn close_block(&mut self, end: Option<(&str, Span)>) {
        match (self.block.take(), end) {
            (Some((block, _)), Some((word, _))) if block.end().eq_ignore_ascii_case(word) => {}
            (Some((block, span)), _) => {
                self.diag(
                    &rules::GSD_BLOCK,
                    Some(span),
                    format!("`{}` without `{}`", block.name(), block.end()),
                );
                if let Some((word, at)) = end {
                    self.diag(
                        &rules::GSD_BLOCK,
                        Some(at),
                        format!("`{word}` without its block"),
                    );
                }
            }
            (None, Some((word, at))) => self.diag(
                &rules::GSD_BLOCK,
                Some(at),
                format!("`{word}` without its block"),
            ),
            (None, None) => {}
        }
    }

    fn line(&mut self, line: &Line) {
        let text = line.text.as_str();
        let span = line.span;
        if text.eq_ignore_ascii_case("#Profibus_DP") {
            return;
        }
        let (key, value) = split_key(text);
        let lower = key.to_ascii_lowercase();
        const ENDS: [&str; 6] = [
            "endmodule",
            "endprmtext",
            "endextuserprmdata",
            "endslotdefinition",
            "unit_diag_area_end",
            "end_unit_diag_area",
        ];
        if value.is_none() && ENDS.contains(&lower.as_str()) {
            let word = if lower == "end_unit_diag_area" {
                "Unit_Diag_Area_End"
            } else {
                key
            };
            self.close_block(Some((word, span)));
            return;
        }
        if let Some((block, _)) = self.block {
            if self.block_line(block, &lower, key, value, span) {
                return;
            }
        }
        self.top_line(&lower, key, value, span);
    }

    /// A line inside a block; `false` if it is not one of the block's (then it is read as a
    /// top-level keyword, and a block opening there closes this one with a report).
    fn block_line(
        &mut self,
        block: Block,
        lower: &str,
        key: &str,
        value: Option<&str>,
        span: Span,
    ) -> bool {
        match block {
            Block::Module(i) => {
                if value.is_none() {
                    if let Some(n) = number(key) {
                        self.dp.modules[i].reference = u32::try_from(n).ok();
                        return true;
                    }
                }
                let value = value.unwrap_or("");
                if lower == "ext_module_prm_data_len" {
                    self.dp.modules[i].prm_data_len = self.u32(value, span);
                    return true;
                }
                if let Some(c) = self.prm_const(lower, value, span) {
                    self.dp.modules[i].prm_consts.push(c);
                    return true;
                }
                if let Some(r) = self.prm_ref(lower, value, span) {
                    self.dp.modules[i].prm_refs.push(r);
                    return true;
                }
                if lower == "module" || lower == "prmtext" || lower == "extuserprmdata" {
                    self.close_block(None);
                    return false;
                }
                self.dp.other.push(GsdKeyword {
                    key: key.to_owned(),
                    value: value.to_owned(),
                    span,
                });
                true
            }
            Block::PrmText(i) => {
                let Some(arg) = call_arg(lower, "text") else {
                    return false;
                };
                match (number(arg), value.and_then(quoted)) {
                    (Some(v), Some(text)) => self.dp.prm_texts[i].texts.push((v, text)),
                    _ => self.bad(span, "`Text(n) = \"text\"`", key),
                }
                true
            }
            Block::ExtUserPrmData(i) => {
                if lower == "prm_text_ref" {
                    let n = value.and_then(number).and_then(|n| u32::try_from(n).ok());
                    match n {
                        Some(n) => self.dp.prm_definitions[i].text_ref = Some(n),
                        None => self.bad(span, "a PrmText reference", value.unwrap_or("")),
                    }
                    return true;
                }
                if value.is_none() {
                    if let Some((data_type, default, values)) = values::prm_type_line(key) {
                        let def = &mut self.dp.prm_definitions[i];
                        def.data_type = data_type;
                        def.default = default;
                        def.values = values;
                        def.type_span = span;
                        return true;
                    }
                    self.bad(span, "a parameter type line (`Unsigned8 0 0-255`)", key);
                    return true;
                }
                if matches!(lower, "changeable" | "visible") {
                    return true;
                }
                false
            }
            Block::SlotDefinition => {
                let Some(arg) = call_arg(lower, "slot") else {
                    return false;
                };
                match (number(arg), value.and_then(values::slot_value)) {
                    (Some(n), Some((name, default, allowed))) => self.dp.slots.push(DpSlot {
                        number: u32::try_from(n).unwrap_or(0),
                        name,
                        default_module: default,
                        allowed,
                        span,
                    }),
                    _ => self.bad(span, "`Slot(n) = \"name\" default allowed`", key),
                }
                true
            }
            Block::UnitDiagArea(first, last) => {
                let Some(arg) = call_arg(lower, "value") else {
                    return false;
                };
                match (number(arg), value.and_then(quoted)) {
                    (Some(v), Some(text)) => self.dp.unit_diag.push(UnitDiag {
                        bits: (first, last),
                        value: Some(v),
                        not: false,
                        text,
                        span,
                    }),
                    _ => self.bad(span, "`Value(n) = \"text\"`", key),
                }
                true
            }
        }
    }

    fn open(&mut self, block: Block, span: Span) {
        if self.block.is_some() {
            self.close_block(None);
        }
        self.block = Some((block, span));
    }

    fn u32(&mut self, value: &str, span: Span) -> Option<u32> {
        let n = number(value).and_then(|n| u32::try_from(n).ok());
        if n.is_none() {
            self.bad(span, "a number", value);
        }
        n
    }

    fn flag(&mut self, value: &str, span: Span) -> bool {
        self.u32(value, span).is_some_and(|n| n != 0)
    }

    fn string(&mut self, value: &str, span: Span) -> Option<String> {
        let s = quoted(value);
        if s.is_none() {
            self.bad(span, "a quoted string", value);
        }
        s
    }

    fn prm_const(&mut self, lower: &str, value: &str, span: Span) -> Option<PrmConst> {
        let arg = call_arg(lower, "ext_user_prm_data_const")?;
        let offset = number(arg).and_then(|n| u32::try_from(n).ok());
        let bytes =
            numbers(value).and_then(|v| v.into_iter().map(|n| u8::try_from(n).ok()).collect());
        match (offset, bytes) {
            (Some(offset), Some(bytes)) => Some(PrmConst {
                offset,
                bytes,
                span,
            }),
            _ => {
                self.bad(span, "`Ext_User_Prm_Data_Const(offset) = bytes`", value);
                None
            }
        }
    }

    fn prm_ref(&mut self, lower: &str, value: &str, span: Span) -> Option<PrmRef> {
        let arg = call_arg(lower, "ext_user_prm_data_ref")?;
        let offset = number(arg).and_then(|n| u32::try_from(n).ok());
        let reference = number(value).and_then(|n| u32::try_from(n).ok());
        match (offset, reference) {
            (Some(offset), Some(reference)) => Some(PrmRef {
                offset,
                reference,
                span,
            }),
            _ => {
                self.bad(span, "`Ext_User_Prm_Data_Ref(offset) = reference`", value);
                None
            }
        }
    }

    fn top_line(&mut self, lower: &str, key: &str, value: Option<&str>, span: Span) {
        let Some(value) = value else {
            if lower == "slotdefinition" {
                self.open(Block::SlotDefinition, span);
            } else if lower.starts_with("x_") || lower == "endunitdiagtype" {
                // A vendor extension's bare line (`X_Unit_Diag_Area_End`), or the end of a
                // revision 5 `UnitDiagType` block (whose lines are kept one by one): kept.
                self.dp.other.push(GsdKeyword {
                    key: key.to_owned(),
                    value: String::new(),
                    span,
                });
            } else {
                self.diag(
                    &rules::GSD_UNPARSEABLE,
                    Some(span),
                    format!("`{key}` is neither `Keyword = value` nor a block's line"),
                );
            }
            return;
        };
        // Keywords that repeat by design: blocks, indexed ones, vendor extensions (`X_`).
        let single = !lower.contains('(')
            && !lower.starts_with("x_")
            && !matches!(
                lower,
                "module" | "prmtext" | "extuserprmdata" | "unit_diag_area" | "unitdiagtype"
            );
        if single {
            if let Some(first) = self.seen.insert(lower.to_owned(), span) {
                self.diags.push(
                    Diagnostic::new(
                        &rules::GSD_DUPLICATE,
                        Some(span),
                        format!("`{key}` appears twice; the last one wins"),
                    )
                    .with_help(format!("first on line {}", first.line)),
                );
            }
        }
        match lower {
            "gsd_revision" => self.dp.gsd_revision = self.u32(value, span),
            "vendor_name" => self.dp.vendor_name = self.string(value, span),
            "model_name" => self.dp.model_name = self.string(value, span),
            "revision" => self.dp.revision = self.string(value, span),
            "ordernumber" => self.dp.order_number = self.string(value, span),
            "hardware_release" => self.dp.hardware_release = self.string(value, span),
            "software_release" => self.dp.software_release = self.string(value, span),
            "ident_number" => match number(value).and_then(|n| u16::try_from(n).ok()) {
                Some(n) => self.dp.ident_number = Some(Spanned::new(n, span)),
                None => self.bad(span, "a 16-bit number", value),
            },
            "protocol_ident" => self.dp.protocol_ident = self.u32(value, span),
            "station_type" => self.dp.station_type = self.u32(value, span),
            "auto_baud_supp" => self.dp.auto_baud = self.flag(value, span),
            "freeze_mode_supp" => self.dp.freeze = self.flag(value, span),
            "sync_mode_supp" => self.dp.sync = self.flag(value, span),
            "fail_safe" => self.dp.fail_safe = self.flag(value, span),
            "set_slave_add_supp" => self.dp.set_slave_add = self.flag(value, span),
            "dpv1_slave" => self.dp.dpv1 = self.flag(value, span),
            "min_slave_intervall" => self.dp.min_slave_interval = self.u32(value, span),
            "max_diag_data_len" => self.dp.max_diag_data_len = self.u32(value, span),
            "modular_station" => self.dp.modular_station = self.flag(value, span),
            "max_module" => self.dp.max_module = self.u32(value, span),
            "max_input_len" => self.dp.max_input_len = self.spanned(value, span),
            "max_output_len" => self.dp.max_output_len = self.spanned(value, span),
            "max_data_len" => self.dp.max_data_len = self.spanned(value, span),
            "user_prm_data_len" => self.dp.user_prm_data_len = self.spanned(value, span),
            "max_user_prm_data_len" => self.dp.max_user_prm_data_len = self.spanned(value, span),
            "user_prm_data" => {
                match numbers(value)
                    .and_then(|v| v.into_iter().map(|n| u8::try_from(n).ok()).collect())
                {
                    Some(bytes) => self.dp.user_prm_data = bytes,
                    None => self.bad(span, "a list of bytes", value),
                }
            }
            "module" => match values::module_header(value) {
                Some((name, config)) => {
                    self.dp.modules.push(DpModule {
                        name,
                        config,
                        reference: None,
                        prm_data_len: None,
                        prm_consts: Vec::new(),
                        prm_refs: Vec::new(),
                        span,
                    });
                    self.open(Block::Module(self.dp.modules.len() - 1), span);
                }
                None => self.bad(span, "`\"name\" configuration bytes`", value),
            },
            "prmtext" => {
                if let Some(reference) = self.u32(value, span) {
                    self.dp.prm_texts.push(PrmText {
                        reference,
                        texts: Vec::new(),
                        span,
                    });
                    self.open(Block::PrmText(self.dp.prm_texts.len() - 1), span);
                }
            }
            "extuserprmdata" => match values::number_and_name(value) {
                Some((reference, name)) => {
                    self.dp.prm_definitions.push(ExtUserPrmData {
                        reference,
                        name,
                        data_type: PrmType::Unsigned(1),
                        default: 0,
                        values: PrmValues::Any,
                        text_ref: None,
                        span,
                        type_span: span,
                    });
                    self.open(
                        Block::ExtUserPrmData(self.dp.prm_definitions.len() - 1),
                        span,
                    );
                }
                None => self.bad(span, "`reference \"name\"`", value),
            },
            "unit_diag_area" => match values::range(value) {
                Some((first, last)) => self.open(Block::UnitDiagArea(first, last), span),
                None => self.bad(span, "a bit range `first-last`", value),
            },
            _ => self.other_keyword(lower, key, value, span),
        }
    }

    fn spanned(&mut self, value: &str, span: Span) -> Option<Spanned<u32>> {
        self.u32(value, span).map(|n| Spanned::new(n, span))
    }
}
