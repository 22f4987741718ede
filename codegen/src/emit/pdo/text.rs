//! The `pdo` module written as text, formatted as `prettyplease` formats the tokens of
//! [`super::emit_pdo`] (parsing and re-formatting them was a sixth of generating a dictionary).
//! Only the common shapes are written here: a module with a string field, a field narrower than
//! its type (`to_bytes` then checks it), or a line whose length leaves the formatter's choice in
//! doubt, is left whole to the tokens (`None`).

use super::super::text::{self, ITEM_INDENT, MARGIN};
use super::super::types::Prim;
use super::{Direction, FieldType, PdoPlan, Slot};

/// The indentation of the items in `pub mod pdo`.
const AT: usize = ITEM_INDENT + 4;

/// `::edsgen_runtime::support::`, where every helper the PDOs call lives.
const SUPPORT: &str = "::edsgen_runtime::support::";

/// The whole `pdo` module (its rustdoc and `pub mod pdo { ... }`), or `None` when a PDO has a
/// shape this writer leaves to the tokens.
pub(super) fn module(pdos: &[PdoPlan]) -> Option<String> {
    let mut out = String::with_capacity(3000 * pdos.len());
    text::docs(
        &mut out,
        ITEM_INDENT,
        &[" Typed PDOs: one struct per default mapping of the description."],
    );
    text::indent(&mut out, ITEM_INDENT);
    out.push_str("pub mod pdo {\n");
    line(
        &mut out,
        AT,
        "use ::edsgen_runtime::master::pdo::{MappedPdo, PdoKind};",
    );
    for p in pdos {
        pdo(&mut out, p)?;
    }
    text::indent(&mut out, ITEM_INDENT);
    out.push_str("}\n");
    Some(out)
}

/// A field written as text: its name, type, mapped bits and offset in the payload.
struct Field<'a> {
    name: &'a str,
    prim: Prim,
    bits: u32,
    offset: u32,
    doc: &'a str,
}

fn pdo(out: &mut String, p: &PdoPlan) -> Option<()> {
    let (prefix, word, kind) = match p.direction {
        Direction::Rx => ("Rpdo", "RPDO", "Receive"),
        Direction::Tx => ("Tpdo", "TPDO", "Transmit"),
    };
    let name = format!("{prefix}{}", p.number);
    let mut fields = Vec::new();
    let mut eq = true;
    let mut offset = 0u32;
    for slot in &p.slots {
        match slot {
            Slot::Dummy { bits } => offset += bits,
            Slot::Field {
                name,
                ty,
                bits,
                doc,
            } => {
                let FieldType::Scalar(prim) = *ty else {
                    return None;
                };
                if *bits < prim.bits() && matches!(prim, Prim::Unsigned(_) | Prim::Signed(_)) {
                    return None;
                }
                eq &= !matches!(prim, Prim::F32 | Prim::F64);
                fields.push(Field {
                    name,
                    prim,
                    bits: *bits,
                    offset,
                    doc,
                });
                offset += bits;
            }
        }
    }
    if fields.is_empty() {
        return None;
    }
    let len = offset.div_ceil(8);
    text::docs(out, AT, &super::struct_doc(p, word, len));
    let derives = if eq {
        "#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]"
    } else {
        "#[derive(Debug, Clone, Copy, PartialEq, Default)]"
    };
    line(out, AT, derives);
    line(out, AT, &format!("pub struct {name} {{"));
    for f in &fields {
        text::docs(out, AT + 4, &[f.doc]);
        fits_clearly(AT + 4, &format!("pub {}: {}", f.name, f.prim.name()))?;
        line(out, AT + 4, &format!("pub {}: {},", f.name, f.prim.name()));
    }
    line(out, AT, "}");

    line(out, AT, &format!("impl {name} {{"));
    let at = AT + 4;
    text::docs(out, at, &[" The payload length in bytes."]);
    line(out, at, &format!("pub const SIZE: usize = {len};"));
    text::docs(
        out,
        at,
        &[" The image of exactly [`Self::SIZE`] bytes; `WrongLength` for any other length."],
    );
    line(out, at, "pub fn from_slice(");
    line(out, at + 4, "bytes: &[u8],");
    line(
        out,
        at,
        ") -> ::core::result::Result<Self, ::edsgen_runtime::PdoError> {",
    );
    line(out, at + 4, &format!("{SUPPORT}payload::<{len}>(bytes)"));
    line(out, at + 8, ".map(|bytes| Self::from_bytes(&bytes))");
    line(out, at, "}");
    if let Some((ty, body)) = &p.cob_text {
        let node = if p.uses_node_id {
            "node_id"
        } else {
            "_node_id"
        };
        text::docs(
            out,
            at,
            &[
                " The CAN identifier for a node-ID (the COB-ID without its flag bits).",
                "",
                &p.cob_doc,
            ],
        );
        line(
            out,
            at,
            &format!("pub const fn cob_id({node}: u8) -> {ty} {{"),
        );
        fits_clearly(at + 4, body)?;
        line(out, at + 4, body);
        line(out, at, "}");
    }

    text::docs(out, at, &[" The fields of a payload."]);
    line(
        out,
        at,
        &format!("pub fn from_bytes(payload: &[u8; {len}]) -> Self {{"),
    );
    line(out, at + 4, "Self {");
    // One field that fits beside `Self {` would be printed on one line: left to the tokens.
    if fields.len() == 1 && at + 4 + 12 + fields[0].name.len() + 70 <= MARGIN + 8 {
        return None;
    }
    for (n, f) in fields.iter().enumerate() {
        decode(out, at + 8, f, n + 1 == fields.len())?;
    }
    line(out, at + 4, "}");
    line(out, at, "}");

    text::docs(
        out,
        at,
        &[" The payload, bit-exact (little-endian, least significant bit first)."],
    );
    line(out, at, &format!("pub fn to_bytes(self) -> [u8; {len}] {{"));
    line(out, at + 4, &format!("let mut payload = [0u8; {len}];"));
    for f in &fields {
        encode(out, at + 4, f)?;
    }
    line(out, at + 4, "payload");
    line(out, at, "}");
    line(out, AT, "}");

    line(out, AT, &format!("impl MappedPdo for {name} {{"));
    line(out, at, &format!("const KIND: PdoKind = PdoKind::{kind};"));
    line(out, at, &format!("const NUMBER: u16 = {};", p.number));
    let mapping: Vec<String> = p.mapping.iter().map(|m| format!("0x{m:08X}")).collect();
    text::literal_array(out, at, "const MAPPING: &'static [u32] = &", &mapping);
    line(out, AT, "}");
    Some(())
}

/// One field of `from_bytes`'s `Self { ... }` at column `at`: `NAME: EXPR,`. The comma after
/// the `last` field is the formatter's trailing one, which it does not count in the line.
fn decode(out: &mut String, at: usize, f: &Field, last: bool) -> Option<()> {
    let get = format!("{SUPPORT}get_bits(payload, {}, {})", f.offset, f.bits);
    let head = format!("{}: ", f.name);
    match f.prim {
        Prim::Signed(w) => {
            let cast = if w == 64 {
                String::new()
            } else {
                format!(" as {}", f.prim.name())
            };
            // `sign_extend(GET, BITS)` never fits on the field's line: its arguments are broken.
            let whole = format!("{head}{SUPPORT}sign_extend({get}, {}){cast}", f.bits);
            if at + whole.len() <= MARGIN + 8 {
                return None;
            }
            line(out, at, &format!("{head}{SUPPORT}sign_extend("));
            fits_clearly(at + 4, &get)?;
            line(out, at + 4, &format!("{get},"));
            line(out, at + 4, &format!("{},", f.bits));
            line(out, at, &format!("){cast},"));
        }
        Prim::F32 | Prim::F64 => {
            let (float, inner) = match f.prim {
                Prim::F32 => ("f32", format!("{get} as u32")),
                _ => ("f64", get),
            };
            let whole = format!("{head}{float}::from_bits({inner})");
            if at + whole.len() <= MARGIN + 8 {
                return None;
            }
            line(out, at, &format!("{head}{float}::from_bits("));
            fits_clearly(at + 4, &inner)?;
            line(out, at + 4, &format!("{inner},"));
            line(out, at, "),");
        }
        Prim::Bool | Prim::Unsigned(_) => {
            let suffix = match f.prim {
                Prim::Bool => " != 0".to_owned(),
                Prim::Unsigned(64) => String::new(),
                _ => format!(" as {}", f.prim.name()),
            };
            let call = format!("{head}{get}");
            let call_end = at + call.len();
            let comma = usize::from(!last);
            if suffix.is_empty() && !last && call_end == MARGIN {
                // Whether the comma may pass the margin is not certain.
                return None;
            }
            if call_end <= MARGIN {
                // The cast or comparison stays on the line if it ends within the margin (with
                // the comma, but for the last field's), else it goes to the next line.
                if call_end + suffix.len() + comma <= MARGIN {
                    line(out, at, &format!("{call}{suffix},"));
                } else {
                    line(out, at, &call);
                    line(out, at + 4, &format!("{},", suffix.trim_start()));
                }
            } else {
                line(out, at, &format!("{head}{SUPPORT}get_bits("));
                line(out, at + 4, "payload,");
                line(out, at + 4, &format!("{},", f.offset));
                line(out, at + 4, &format!("{},", f.bits));
                line(out, at, &format!("){suffix},"));
            }
        }
    }
    Some(())
}

/// One field's statement in `to_bytes` at column `at`: `put_bits(&mut payload, OFFSET, BITS,
/// RAW);`, its arguments broken.
fn encode(out: &mut String, at: usize, f: &Field) -> Option<()> {
    let name = f.name;
    let raw = match f.prim {
        Prim::Bool => format!("u64::from(self.{name})"),
        Prim::F32 => format!("u64::from(self.{name}.to_bits())"),
        Prim::F64 => format!("self.{name}.to_bits()"),
        Prim::Unsigned(64) => format!("self.{name}"),
        Prim::Unsigned(_) => format!("u64::from(self.{name})"),
        Prim::Signed(64) => format!("self.{name} as u64"),
        Prim::Signed(_) => format!("i64::from(self.{name}) as u64"),
    };
    let whole = format!(
        "{SUPPORT}put_bits(&mut payload, {}, {}, {raw});",
        f.offset, f.bits
    );
    if at + whole.len() <= MARGIN + 8 {
        return None;
    }
    line(out, at, &format!("{SUPPORT}put_bits("));
    line(out, at + 4, "&mut payload,");
    line(out, at + 4, &format!("{},", f.offset));
    line(out, at + 4, &format!("{},", f.bits));
    fits_clearly(at + 4, &raw)?;
    line(out, at + 4, &format!("{raw},"));
    line(out, at, ");");
    Some(())
}

/// `Some` when `text` at column `at`, with a comma after it, ends well inside the margin.
fn fits_clearly(at: usize, text: &str) -> Option<()> {
    (at + text.len() + 1 < MARGIN).then_some(())
}

/// Appends `text` at column `at` and a line break.
fn line(out: &mut String, at: usize, text: &str) {
    text::indent(out, at);
    out.push_str(text);
    out.push('\n');
}

#[cfg(test)]
mod tests {
    use super::super::super::plan;
    use super::super::{module_tokens, plan_pdos};
    use super::*;
    use std::path::Path;

    /// The text is what `prettyplease` prints for the tokens, for each bundled card with PDOs:
    /// every shape the cards hold (unsigned, signed, bool, 64-bit fields, dummies, long names
    /// broken over lines) is written as text.
    #[test]
    fn text_is_what_prettyplease_prints_for_the_tokens() {
        let cards = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds");
        for card in ["cp301.eds", "goodrive350.eds", "hd1e.eds", "rd11.eds"] {
            let loaded = edsgen_model::load::load(&cards.join(card), None).unwrap();
            let plan = plan::plan(&loaded.device);
            let pdos = plan_pdos(&loaded.device, &plan, &mut Vec::new());
            assert!(!pdos.is_empty(), "{card}");
            let written = module(&pdos).unwrap_or_else(|| panic!("{card}: left to the tokens"));
            let tokens = module_tokens(&pdos);
            let file = syn::parse2(quote::quote!(pub mod device { #tokens })).unwrap();
            let printed = prettyplease::unparse(&file);
            let inner = printed
                .strip_prefix("pub mod device {\n")
                .and_then(|p| p.strip_suffix("}\n"))
                .unwrap();
            assert_eq!(written, inner, "{card}");
        }
    }

    /// A call that ends on the margin stays on the field's line, a cast after it that passes
    /// the margin goes to the next line; a call that passes the margin has its arguments broken.
    /// (The last field: its comma is not counted.)
    #[test]
    fn fields_near_the_margin() {
        let get = "::edsgen_runtime::support::get_bits(payload, 0, 16)";
        let decoded = |name: &str| {
            let field = Field {
                name,
                prim: Prim::Unsigned(16),
                bits: 16,
                offset: 0,
                doc: " d",
            };
            let mut out = String::new();
            decode(&mut out, 20, &field, true).map(|()| out)
        };
        let pad = " ".repeat(20);
        // `NAME: GET as u16` ends on the margin: one line.
        let name = "x".repeat(MARGIN - 20 - get.len() - 2 - " as u16".len());
        let one_line = format!("{pad}{name}: {get} as u16,\n");
        assert_eq!(decoded(&name), Some(one_line));
        // One more letter: the cast on a line of its own.
        let name = format!("{name}x");
        let cast_below = format!("{pad}{name}: {get}\n{pad}    as u16,\n");
        assert_eq!(decoded(&name), Some(cast_below));
        // `NAME: GET` ends on the margin.
        let name = "x".repeat(MARGIN - 20 - get.len() - 2);
        let cast_below = format!("{pad}{name}: {get}\n{pad}    as u16,\n");
        assert_eq!(decoded(&name), Some(cast_below));
        // One more letter: the arguments broken.
        let name = format!("{name}x");
        let support = "::edsgen_runtime::support::";
        let broken = format!(
            "{pad}{name}: {support}get_bits(\n{pad}    payload,\n{pad}    0,\n{pad}    16,\n{pad}) as u16,\n"
        );
        assert_eq!(decoded(&name), Some(broken));
    }
}
