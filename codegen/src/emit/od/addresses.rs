//! The typed addresses in `od`: a constant per entry, branded with the module's `Od`, with its
//! access marker (`Entry`, `ReadOnly`, `WriteOnly`, ...), in `od` for a VAR and in a module of its
//! own for an ARRAY or RECORD.

use std::fmt::Write as _;

use proc_macro2::TokenStream;
use quote::quote;

use super::super::plan::{EntryPlan, Plan};
use super::super::text::{self, Splices, ITEM_INDENT};
use super::super::types::{Prim, RustType};
use edsgen_model::model::AccessType;

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
    // 340 to 370 bytes an entry on the bundled cards: one allocation for the whole item (each
    // growth of a buffer this size copies megabytes).
    let mut out = String::with_capacity(400 * plan.entries.len());
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
    let mut scratch = Scratch::default();
    let mut rest = &positioned[..];
    while let Some(&(position, e)) = rest.first() {
        let Some(module) = &e.module else {
            constant(
                &mut out,
                &mut scratch,
                at,
                position,
                (e, plan.doc(e)),
                "super::Od",
            );
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
            constant(
                &mut out,
                &mut scratch,
                at + 4,
                position,
                (member, plan.doc(member)),
                "super::super::Od",
            );
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

/// An address's type and constructor arguments, written anew for each entry into the same two
/// buffers (thousands of entries: a string per piece was most of this item's cost).
#[derive(Default)]
struct Scratch {
    ty: String,
    args: String,
}

/// One entry's typed address with its rustdoc, branded with the dictionary at `dict`.
fn constant(
    out: &mut String,
    scratch: &mut Scratch,
    at: usize,
    position: usize,
    (e, doc): (&EntryPlan, &str),
    dict: &str,
) {
    let Scratch { ty, args } = scratch;
    ty.clear();
    match e.ty {
        RustType::Bytes(n) => {
            // A capacity fits the image's 16-bit offsets (EDS707).
            ty.push_str("FixedBytes<");
            text::push_decimal(ty, n as u32);
            ty.push('>');
        }
        RustType::Scalar(prim, _) => ty.push_str(prim.name()),
    }
    // `0xIIII, 0xSS[, WIDTH]`
    args.clear();
    args.push_str("0x");
    text::push_hex4(args, e.index);
    args.push_str(", 0x");
    text::push_hex2(args, e.sub);
    let constructor = match e.ty {
        RustType::Scalar(prim, wire) if (wire as u32) * 8 < prim.bits() && prim != Prim::Bool => {
            args.push_str(", ");
            text::push_decimal(args, wire as u32);
            "Entry::with_width"
        }
        _ => "Entry::new",
    };
    text::docs(out, at, &[doc]);
    text::docs(out, at, &e.notes);
    address(
        out,
        at,
        (&*e.const_name, dict),
        ty,
        access_marker(e.access),
        (constructor, args),
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
/// arguments (`args`, joined by `, `) too when the line up to them does not fit; or, when even
/// the line up to ` = ` does not fit, the type's parameters on lines of their own and the rest on
/// one line.
fn address(
    out: &mut String,
    at: usize,
    (name, dict): (&str, &str),
    ty: &str,
    marker: Option<&str>,
    (constructor, args): (&str, &str),
    position: usize,
) {
    let params = [Some(ty), Some(dict), marker];
    let params = || params.iter().flatten();
    // `pub const NAME: Entry<P1, P2> = ` and `CONSTRUCTOR(ARGS)`.
    let head_len =
        "pub const : Entry<> = ".len() + name.len() + params().map(|p| p.len() + 2).sum::<usize>()
            - 2;
    let call_len = constructor.len() + args.len() + 2;
    let call = |out: &mut String| {
        out.push_str(constructor);
        out.push('(');
        out.push_str(args);
        out.push(')');
    };
    let link = |out: &mut String, link: usize| match link {
        0 => out.push_str(marker.map_or("", access_constructor)),
        1 => {
            // Positions in `ENTRIES` are below 65536, as its offsets are (EDS707).
            out.push_str(".at_position(");
            text::push_decimal(out, position as u32);
            out.push(')');
        }
        _ => out.push_str(".in_dictionary();"),
    };
    text::indent(out, at);
    if at + head_len > text::MARGIN {
        out.push_str("pub const ");
        out.push_str(name);
        out.push_str(": Entry<\n");
        for param in params() {
            text::indent(out, at + 4);
            out.push_str(param);
            out.push_str(",\n");
        }
        text::indent(out, at);
        out.push_str("> = ");
        call(out);
        for n in 0..3 {
            link(out, n);
        }
        out.push('\n');
        return;
    }
    out.push_str("pub const ");
    out.push_str(name);
    out.push_str(": Entry<");
    for (n, param) in params().enumerate() {
        if n > 0 {
            out.push_str(", ");
        }
        out.push_str(param);
    }
    out.push_str("> = ");
    if at + head_len + call_len <= text::MARGIN {
        call(out);
    } else {
        out.push_str(constructor);
        out.push_str("(\n");
        // `args` are joined by `, ` (split at the comma: a `&str` pattern's searcher cost more
        // than the rest of the line).
        for arg in args.split(',').map(str::trim_start) {
            text::indent(out, at + 8);
            out.push_str(arg);
            out.push_str(",\n");
        }
        text::indent(out, at + 4);
        out.push(')');
    }
    out.push('\n');
    for n in usize::from(marker.is_none())..3 {
        text::indent(out, at + 4);
        link(out, n);
        out.push('\n');
    }
}
