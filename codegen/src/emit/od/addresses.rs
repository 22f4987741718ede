//! The typed addresses in `od`: a constant per entry, branded with the module's `Od`, with its
//! access marker (`Entry`, `ReadOnly`, `WriteOnly`, ...), in `od` for a VAR and in a module of its
//! own for an ARRAY or RECORD.

use std::fmt::Write as _;

use proc_macro2::TokenStream;
use quote::quote;

use super::super::plan::{EntryPlan, Plan};
use super::super::text::{self, Splices, ITEM_INDENT};
use super::super::types::{Prim, RustType};
use crate::model::AccessType;

/// The typed addresses, branded with the module's `Od`, as text: a VAR's in `od`
/// (`pub mod od { pub const CONTROLWORD: Entry<u16, super::Od> = ...; }`), an ARRAY's or
/// RECORD's in a module of its own (`od::identity_object::VENDOR_ID`).
pub fn addresses(plan: &Plan, splices: &mut Splices) -> TokenStream {
    let doc =
        " Typed addresses of every entry: the (index, sub-index) and the Rust type of its value.";
    if plan.entries.is_empty() {
        return quote! {
            #[doc = #doc]
            pub mod od {}
        };
    }
    let mut out = String::new();
    let modules =
        " A VAR's address is here (`od::CONTROLWORD`), an ARRAY's or RECORD's entries are in a";
    let modules_2 = " module of their own (`od::identity_object::VENDOR_ID`).";
    text::docs(&mut out, ITEM_INDENT, &[doc, "", modules, modules_2]);
    text::indent(&mut out, ITEM_INDENT);
    out.push_str("pub mod od {\n");
    let at = ITEM_INDENT + 4;
    let positioned: Vec<(usize, &EntryPlan)> = plan.entries.iter().enumerate().collect();
    let flat: Vec<(usize, &EntryPlan)> = positioned
        .iter()
        .copied()
        .filter(|(_, e)| e.module.is_none())
        .collect();
    uses(&mut out, at, &flat);
    let mut rest = &positioned[..];
    while let Some(&(position, e)) = rest.first() {
        let Some(module) = &e.module else {
            constant(&mut out, at, position, e, "super::Od");
            rest = &rest[1..];
            continue;
        };
        let len = rest
            .iter()
            .take_while(|(_, m)| m.module.as_ref() == Some(module))
            .count();
        let (members, after) = rest.split_at(len);
        let module_doc = format!(
            " {} ({:04X}h): the typed addresses of its {} entries.",
            e.object_title,
            e.index,
            members.len()
        );
        text::docs(&mut out, at, &[module_doc]);
        text::indent(&mut out, at);
        let _ = writeln!(out, "pub mod {module} {{");
        uses(&mut out, at + 4, members);
        for &(position, member) in members {
            constant(&mut out, at + 4, position, member, "super::super::Od");
        }
        text::indent(&mut out, at);
        out.push_str("}\n");
        rest = after;
    }
    text::indent(&mut out, ITEM_INDENT);
    out.push_str("}\n");
    splices.item(out)
}

/// The `use` lines the typed addresses `entries` need: `Entry`, `FixedBytes` for a string's,
/// and the access markers other than the default `ReadWrite`.
fn uses(out: &mut String, at: usize, entries: &[(usize, &EntryPlan)]) {
    if entries.is_empty() {
        return;
    }
    text::indent(out, at);
    if entries
        .iter()
        .any(|(_, e)| matches!(e.ty, RustType::Bytes(_)))
    {
        out.push_str("use ::edsgen_runtime::{Entry, FixedBytes};\n");
    } else {
        out.push_str("use ::edsgen_runtime::Entry;\n");
    }
    let markers: Vec<&str> = ["Const", "ReadOnly", "WriteOnly"]
        .into_iter()
        .filter(|m| {
            entries
                .iter()
                .any(|(_, e)| access_marker(e.access) == Some(m))
        })
        .collect();
    match markers[..] {
        [] => {}
        [one] => {
            text::indent(out, at);
            let _ = writeln!(out, "use ::edsgen_runtime::od::access::{one};");
        }
        _ => {
            text::indent(out, at);
            let _ = writeln!(
                out,
                "use ::edsgen_runtime::od::access::{{{}}};",
                markers.join(", ")
            );
        }
    }
}

/// One entry's typed address with its rustdoc, branded with the dictionary at `dict`.
fn constant(out: &mut String, at: usize, position: usize, e: &EntryPlan, dict: &str) {
    let ty = match e.ty {
        RustType::Bytes(n) => format!("FixedBytes<{n}>"),
        RustType::Scalar(prim, _) => prim.name().to_owned(),
    };
    let (index, sub) = (text::hex(e.index.into(), 4), text::hex(e.sub.into(), 2));
    let (constructor, args) = match e.ty {
        RustType::Scalar(prim, wire) if (wire as u32) * 8 < prim.bits() && prim != Prim::Bool => {
            ("Entry::with_width", vec![index, sub, wire.to_string()])
        }
        _ => ("Entry::new", vec![index, sub]),
    };
    text::docs(out, at, &e.short_doc);
    address(
        out,
        at,
        (&e.const_name.to_string(), dict),
        &ty,
        access_marker(e.access),
        (constructor, &args),
        position,
    );
}

/// The access marker of an address (`od::access`), or `None` for the default `ReadWrite`.
fn access_marker(access: AccessType) -> Option<&'static str> {
    match access {
        AccessType::Rw | AccessType::Rwr | AccessType::Rww => None,
        AccessType::Ro => Some("ReadOnly"),
        AccessType::Const => Some("Const"),
        AccessType::Wo => Some("WriteOnly"),
    }
}

/// The constructor that narrows an address built by `Entry::new` to `marker`.
fn access_constructor(marker: &str) -> &'static str {
    match marker {
        "ReadOnly" => ".read_only()",
        "Const" => ".constant()",
        _ => ".write_only()",
    }
}

/// One typed address, `pub const NAME: Entry<TY, super::Od[, MARKER]> =
/// CONSTRUCTOR(ARGS)[.read_only()].at_position(POSITION).in_dictionary();`, broken as
/// `prettyplease` breaks it: the method calls on lines of their own, and the constructor's
/// arguments too when the line up to them does not fit; or, when even the line up to ` = ` does
/// not fit, the type's parameters on lines of their own and the rest on one line.
fn address(
    out: &mut String,
    at: usize,
    (name, dict): (&str, &str),
    ty: &str,
    marker: Option<&str>,
    (constructor, args): (&str, &[String]),
    position: usize,
) {
    let mut params = vec![ty, dict];
    params.extend(marker);
    let head = format!("pub const {name}: Entry<{}> = ", params.join(", "));
    let call = format!("{constructor}({})", args.join(", "));
    let mut chain: Vec<String> = marker
        .map(|m| access_constructor(m).to_owned())
        .into_iter()
        .collect();
    chain.push(format!(".at_position({position})"));
    chain.push(".in_dictionary();".to_owned());
    text::indent(out, at);
    if at + head.len() > text::MARGIN {
        let _ = writeln!(out, "pub const {name}: Entry<");
        for param in &params {
            text::indent(out, at + 4);
            let _ = writeln!(out, "{param},");
        }
        text::indent(out, at);
        let _ = writeln!(out, "> = {call}{}", chain.concat());
        return;
    }
    out.push_str(&head);
    if at + head.len() + call.len() <= text::MARGIN {
        out.push_str(&call);
    } else {
        let _ = writeln!(out, "{constructor}(");
        for arg in args {
            text::indent(out, at + 8);
            let _ = writeln!(out, "{arg},");
        }
        text::indent(out, at + 4);
        out.push(')');
    }
    out.push('\n');
    for link in &chain {
        text::indent(out, at + 4);
        out.push_str(link);
        out.push('\n');
    }
}
