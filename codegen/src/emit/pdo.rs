//! The typed PDOs of one device: one struct per default mapping (16xxh as `RpdoN`, 1Axxh as
//! `TpdoN`), with the image API over the payload (`SIZE`, bit-exact `from_bytes` and `to_bytes`,
//! `from_slice`), and the COB-ID as a function of the node-ID. Written as text (`pdo::text`) when
//! every PDO has a shape it writes, else as tokens for `prettyplease`.
//!
//! Fields follow the mapping order; dummy entries (indices 0001h-0007h) take their bits but no
//! field and encode as zeros. Each struct implements the runtime's `MappedPdo` (its kind, number
//! and mapping entries), from which a master configures a node's PDO to match it. A field mapped
//! with fewer bits than its type is range-checked by `to_bytes`, and sign-extended by
//! `from_bytes` when signed.

mod text;

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::names::Namespace;
use super::plan::{id, Plan};
use super::text::Splices;
use super::types::{hex, pdo_derives, Prim, RustType, TypeTokens};
use edsgen_model::diag::Diagnostic;
use edsgen_model::model::layout::initial_value;
use edsgen_model::model::{Device, Value};
use edsgen_model::rules;

/// Direction of a PDO.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Direction {
    Rx,
    Tx,
}

enum Slot {
    Dummy {
        bits: u32,
    },
    Field {
        name: String,
        ty: FieldType,
        bits: u32,
        doc: String,
    },
}

#[derive(Clone, Copy)]
enum FieldType {
    Scalar(Prim),
    Bytes(usize),
}

struct PdoPlan {
    direction: Direction,
    number: u16,
    mapping_index: u16,
    /// The mapping entries (index << 16 | sub << 8 | bits), in payload order.
    mapping: Vec<u32>,
    slots: Vec<Slot>,
    /// The body and return type of `cob_id`, or `None` when the PDO has no COB-ID to give.
    cob_id: Option<(TokenStream, TokenStream)>,
    /// The same as text: the return type and the body.
    cob_text: Option<(&'static str, String)>,
    cob_doc: String,
    uses_node_id: bool,
    transmission: Option<i128>,
}

/// The `pdo` module: as text in `splices` when `text::module` can write it, else as tokens.
pub fn pdos(
    device: &Device,
    plan: &Plan,
    diagnostics: &mut Vec<Diagnostic>,
    splices: &mut Splices,
) -> TokenStream {
    let pdos = plan_pdos(device, plan, diagnostics);
    if pdos.is_empty() {
        return quote!();
    }
    match text::module(&pdos) {
        Some(module) => splices.item(module),
        None => module_tokens(&pdos),
    }
}

/// The PDOs to generate, in index order; a diagnostic for each mapping that cannot be typed.
fn plan_pdos(device: &Device, plan: &Plan, diagnostics: &mut Vec<Diagnostic>) -> Vec<PdoPlan> {
    let mut pdos = Vec::new();
    for object in device.objects.values() {
        let (direction, base) = match object.index {
            0x1600..=0x17FF => (Direction::Rx, 0x1600),
            0x1A00..=0x1BFF => (Direction::Tx, 0x1A00),
            _ => continue,
        };
        let number = object.index - base + 1;
        match plan_pdo(device, plan, object.index, direction, number) {
            Ok(Some(p)) => pdos.push(p),
            Ok(None) => {}
            Err(why) => diagnostics.push(
                Diagnostic::new(
                    &rules::UNTYPED_PDO,
                    Some(object.span),
                    format!(
                        "{}PDO {number} ({:04X}h): {why}",
                        if direction == Direction::Rx { "R" } else { "T" },
                        object.index
                    ),
                )
                .with_label("no PDO struct is generated for this mapping"),
            ),
        }
    }
    pdos
}

/// The `pdo` module as tokens.
fn module_tokens(pdos: &[PdoPlan]) -> TokenStream {
    let structs = pdos.iter().map(emit_pdo);
    quote! {
        /// Typed PDOs: one struct per default mapping of the description.
        pub mod pdo {
            use ::edsgen_runtime::master::pdo::{MappedPdo, PdoKind};

            #(#structs)*
        }
    }
}

fn integer(value: Option<&Value>) -> Option<i128> {
    match value {
        Some(Value::Integer(v)) => Some(*v),
        _ => None,
    }
}

fn plan_pdo(
    device: &Device,
    plan: &Plan,
    mapping_index: u16,
    direction: Direction,
    number: u16,
) -> Result<Option<PdoPlan>, String> {
    let Some(object) = device.objects.get(&mapping_index) else {
        return Ok(None);
    };
    let count = match object.subs.get(&0).map(|s| integer(initial_value(s))) {
        Some(Some(n)) => n,
        _ => {
            return Err("sub-index 0 has no integer default (the number of mapped objects)".into())
        }
    };
    if count == 0 {
        return Ok(None);
    }
    if !(1..=64).contains(&count) {
        return Err(format!("{count} mapped objects; at most 64 are allowed"));
    }
    let mut names = Namespace::default();
    let mut slots = Vec::new();
    let mut mapping = Vec::new();
    let mut offset = 0u32;
    for k in 1..=count as u8 {
        let Some(sub) = object.subs.get(&k) else {
            return Err(format!("mapping sub-index {k} is missing"));
        };
        let Some(raw) = integer(initial_value(sub)) else {
            return Err(format!("mapping sub-index {k} has no integer default"));
        };
        let raw = raw as u32;
        let (index, sub_index, bits) = ((raw >> 16) as u16, ((raw >> 8) & 0xFF) as u8, raw & 0xFF);
        if bits == 0 {
            return Err(format!("mapping sub-index {k} ({raw:08X}h) has length 0"));
        }
        mapping.push(raw);
        if (0x0001..=0x0007).contains(&index) {
            slots.push(Slot::Dummy { bits });
            offset += bits;
            continue;
        }
        let Some(entry) = plan.entry(index, sub_index) else {
            return Err(format!(
                "mapping sub-index {k} points to {index:04X}h sub {sub_index}, which is not in the dictionary"
            ));
        };
        let ty = match entry.ty {
            RustType::Scalar(prim @ (Prim::F32 | Prim::F64), _) => {
                if bits != prim.bits() {
                    return Err(format!(
                        "{index:04X}h sub {sub_index} is a REAL mapped with {bits} bits"
                    ));
                }
                FieldType::Scalar(prim)
            }
            RustType::Scalar(prim, wire) => {
                if bits > (wire as u32) * 8 {
                    return Err(format!(
                        "{index:04X}h sub {sub_index} is mapped with {bits} bits, more than its {} bits",
                        wire * 8
                    ));
                }
                FieldType::Scalar(prim)
            }
            RustType::Bytes(_) => {
                if bits % 8 != 0 {
                    return Err(format!(
                        "{index:04X}h sub {sub_index} is a string mapped with {bits} bits (not whole bytes)"
                    ));
                }
                FieldType::Bytes((bits / 8) as usize)
            }
        };
        let (name, _) = names.claim(
            &entry.pdo_name(),
            index,
            &[format!("{index:04x}_{sub_index}")],
        );
        let title = entry.title();
        let title = title.trim();
        let doc = format!(
            " {title} ({index:04X}h sub {sub_index}, {}): bits {offset} to {} of the payload.",
            entry.basic.name(),
            offset + bits - 1
        );
        slots.push(Slot::Field {
            name,
            ty,
            bits,
            doc,
        });
        offset += bits;
    }
    let comm_index = mapping_index - 0x200;
    let comm_cob = device
        .entry(comm_index, 1)
        .and_then(|s| initial_value(s).cloned());
    let predefined = if number <= 4 {
        Some(match direction {
            Direction::Rx => 0x200 + 0x100 * u32::from(number - 1),
            Direction::Tx => 0x180 + 0x100 * u32::from(number - 1),
        })
    } else {
        None
    };
    let (cob_id, cob_text, cob_doc, uses_node_id) = cob_id_fn(comm_index, comm_cob, predefined);
    let transmission = device
        .entry(comm_index, 2)
        .and_then(|s| integer(initial_value(s)));
    Ok(Some(PdoPlan {
        direction,
        number,
        mapping_index,
        mapping,
        slots,
        cob_id,
        cob_text,
        cob_doc,
        uses_node_id,
        transmission,
    }))
}

/// COB-ID bit 29: the PDO uses a 29-bit CAN identifier.
const COB_EXTENDED: u32 = 1 << 29;
/// COB-ID bit 31: the PDO is not valid (disabled).
const COB_INVALID: u32 = 1 << 31;

/// `cob_id`'s body and return type and its doc line, and whether it uses the node-ID. The
/// function gives the CAN identifier as `CanFrame::new` takes it (`u16`, 11 bits), the COB-ID's
/// flag bits stripped; a 29-bit one as `u32` (for `CanFrame::new_extended`); none at all when the
/// description gives no COB-ID and there is no predefined one.
fn cob_id_fn(comm_index: u16, comm_cob: Option<Value>, predefined: Option<u32>) -> CobId {
    let (cob, relative, doc) = match comm_cob {
        Some(Value::Integer(v)) => (
            v as u32,
            false,
            format!(" The COB-ID of {comm_index:04X}h sub 1: `0x{:X}`, whatever the node-ID.", v as u32),
        ),
        Some(Value::NodeRelative(off)) => (
            off as u32,
            true,
            format!(" The COB-ID of {comm_index:04X}h sub 1: `$NODEID + 0x{:X}`.", off as u32),
        ),
        _ => match predefined {
            Some(base) => (
                base,
                true,
                format!(" {comm_index:04X}h sub 1 gives no COB-ID; this is the predefined connection set's `0x{base:X} + node-ID`."),
            ),
            None => return (None, None, String::new(), false),
        },
    };
    let mut doc = doc;
    if cob & COB_INVALID != 0 {
        doc.push_str(" Bit 31 is set: the PDO is disabled until a configuration tool enables it.");
    }
    let (ty, ty_name, id) = if cob & COB_EXTENDED != 0 {
        doc.push_str(" A 29-bit identifier: use `CanFrame::new_extended`.");
        (quote!(u32), "u32", cob & 0x1FFF_FFFF)
    } else {
        (quote!(u16), "u16", cob & 0x7FF)
    };
    let (id, id_text) = (hex(u128::from(id), 1), format!("0x{id:X}"));
    let (body, body_text) = if relative {
        (
            quote!((node_id as #ty).wrapping_add(#id)),
            format!("(node_id as {ty_name}).wrapping_add({id_text})"),
        )
    } else {
        (quote!(#id), id_text)
    };
    (Some((body, ty)), Some((ty_name, body_text)), doc, relative)
}

/// `cob_id`'s body and return type as tokens and as text, its doc line, and whether it uses the
/// node-ID.
type CobId = (
    Option<(TokenStream, TokenStream)>,
    Option<(&'static str, String)>,
    String,
    bool,
);

/// A PDO struct's rustdoc lines: its mapping, each field's or dummy's bits, its transmission
/// type (the same for the token and the text writer).
fn struct_doc(p: &PdoPlan, word: &str, len: impl std::fmt::Display) -> Vec<String> {
    let mut doc = vec![
        format!(
            " {word} {} with its default mapping ({:04X}h), {len} bytes:",
            p.number, p.mapping_index
        ),
        String::new(),
    ];
    let mut offset = 0u32;
    for slot in &p.slots {
        let (bits, what) = match slot {
            Slot::Dummy { bits } => (*bits, "dummy".to_owned()),
            Slot::Field { name, bits, .. } => (*bits, format!("`{name}`")),
        };
        doc.push(format!(" - bits {offset} to {}: {what}", offset + bits - 1));
        offset += bits;
    }
    if let Some(t) = p.transmission {
        doc.push(String::new());
        doc.push(format!(" Default transmission type {t}."));
    }
    doc
}

fn emit_pdo(p: &PdoPlan) -> TokenStream {
    let (prefix, word, kind) = match p.direction {
        Direction::Rx => ("Rpdo", "RPDO", quote!(Receive)),
        Direction::Tx => ("Tpdo", "TPDO", quote!(Transmit)),
    };
    let name = id(&format!("{prefix}{}", p.number));
    let total_bits: u32 = p
        .slots
        .iter()
        .map(|s| match s {
            Slot::Dummy { bits } | Slot::Field { bits, .. } => *bits,
        })
        .sum();
    let len = total_bits.div_ceil(8) as usize;
    let len_lit = Literal::usize_unsuffixed(len);
    let number = Literal::u16_unsuffixed(p.number);
    let mapping = p.mapping.iter().map(|&raw| hex(u128::from(raw), 8));
    let mut fields = Vec::new();
    let mut encodes = Vec::new();
    let mut decodes = Vec::new();
    let mut eq = true;
    let mut default = true;
    let mut fallible = false;
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
                let field = id(name);
                let off = Literal::u32_unsuffixed(offset);
                let nbits = Literal::u32_unsuffixed(*bits);
                match ty {
                    FieldType::Scalar(prim) => {
                        let t = prim.tokens();
                        fields.push(quote!(#[doc = #doc] pub #field: #t,));
                        let narrow = *bits < prim.bits();
                        let (raw, check, decode) = match prim {
                            Prim::Bool => (
                                quote!(u64::from(self.#field)),
                                None,
                                quote!(::edsgen_runtime::support::get_bits(payload, #off, #nbits) != 0),
                            ),
                            Prim::F32 => {
                                eq = false;
                                (
                                    quote!(u64::from(self.#field.to_bits())),
                                    None,
                                    quote!(f32::from_bits(::edsgen_runtime::support::get_bits(payload, #off, #nbits) as u32)),
                                )
                            }
                            Prim::F64 => {
                                eq = false;
                                (
                                    quote!(self.#field.to_bits()),
                                    None,
                                    quote!(f64::from_bits(::edsgen_runtime::support::get_bits(payload, #off, #nbits))),
                                )
                            }
                            Prim::Unsigned(w) => {
                                let raw = if *w == 64 {
                                    quote!(self.#field)
                                } else {
                                    quote!(u64::from(self.#field))
                                };
                                let check = narrow.then(
                                    || quote!(::edsgen_runtime::support::fits_unsigned(#raw, #nbits)),
                                );
                                let get = quote!(::edsgen_runtime::support::get_bits(payload, #off, #nbits));
                                let decode = if *w == 64 { get } else { quote!(#get as #t) };
                                (raw, check, decode)
                            }
                            Prim::Signed(w) => {
                                let wide = if *w == 64 {
                                    quote!(self.#field)
                                } else {
                                    quote!(i64::from(self.#field))
                                };
                                let check = narrow.then(
                                    || quote!(::edsgen_runtime::support::fits_signed(#wide, #nbits)),
                                );
                                let get = quote!(::edsgen_runtime::support::sign_extend(::edsgen_runtime::support::get_bits(payload, #off, #nbits), #nbits));
                                let decode = if *w == 64 { get } else { quote!(#get as #t) };
                                (quote!(#wide as u64), check, decode)
                            }
                        };
                        if let Some(check) = check {
                            fallible = true;
                            encodes.push(quote! {
                                if !#check {
                                    return Err(::edsgen_runtime::PdoError::OutOfRange { field: #name });
                                }
                            });
                        }
                        encodes.push(quote!(::edsgen_runtime::support::put_bits(&mut payload, #off, #nbits, #raw);));
                        decodes.push(quote!(#field: #decode,));
                    }
                    FieldType::Bytes(n) => {
                        if *n > 32 {
                            default = false;
                        }
                        let n_lit = Literal::usize_unsuffixed(*n);
                        let at = if offset == 0 {
                            quote!(8 * i)
                        } else {
                            quote!(#off + 8 * i)
                        };
                        fields.push(quote!(#[doc = #doc] pub #field: [u8; #n_lit],));
                        encodes.push(quote! {
                            for (i, byte) in self.#field.iter().enumerate() {
                                ::edsgen_runtime::support::put_bits(&mut payload, #at, 8, u64::from(*byte));
                            }
                        });
                        decodes.push(quote!(#field: {
                            let mut bytes = [0u8; #n_lit];
                            for (i, byte) in bytes.iter_mut().enumerate() {
                                *byte = ::edsgen_runtime::support::get_bits(payload, #at, 8) as u8;
                            }
                            bytes
                        },));
                    }
                }
                offset += bits;
            }
        }
    }
    let doc = struct_doc(p, word, len);
    let doc_attrs = doc.iter().map(|l| quote!(#[doc = #l]));
    let derives = pdo_derives(eq, default);
    let node_param = if p.uses_node_id {
        quote!(node_id)
    } else {
        quote!(_node_id)
    };
    let cob_doc = &p.cob_doc;
    let cob_id_fn = match &p.cob_id {
        Some((body, ty)) => quote! {
            /// The CAN identifier for a node-ID (the COB-ID without its flag bits).
            #[doc = ""]
            #[doc = #cob_doc]
            pub const fn cob_id(#node_param: u8) -> #ty {
                #body
            }
        },
        None => TokenStream::new(),
    };
    let size_and_from_slice =
        super::image_api::size_and_from_slice(len, "The payload length in bytes.");
    let payload_binding = if decodes.is_empty() {
        quote!(_payload)
    } else {
        quote!(payload)
    };
    let encode_binding = if encodes.is_empty() {
        quote!(let payload = [0u8; #len_lit];)
    } else {
        quote!(let mut payload = [0u8; #len_lit];)
    };
    // Only a field narrower than its Rust type can overflow its bits: without one, encoding
    // cannot fail.
    let encode_fn = if fallible {
        quote! {
            /// The payload, bit-exact (little-endian, least significant bit first); an error if a
            /// field does not fit its mapped length.
            pub fn to_bytes(self) -> Result<[u8; #len_lit], ::edsgen_runtime::PdoError> {
                #encode_binding
                #(#encodes)*
                Ok(payload)
            }
        }
    } else {
        quote! {
            /// The payload, bit-exact (little-endian, least significant bit first).
            pub fn to_bytes(self) -> [u8; #len_lit] {
                #encode_binding
                #(#encodes)*
                payload
            }
        }
    };
    quote! {
        #(#doc_attrs)*
        #[derive(#(#derives),*)]
        pub struct #name {
            #(#fields)*
        }

        impl #name {
            #size_and_from_slice

            #cob_id_fn

            /// The fields of a payload.
            pub fn from_bytes(#payload_binding: &[u8; #len_lit]) -> Self {
                Self { #(#decodes)* }
            }

            #encode_fn
        }

        impl MappedPdo for #name {
            const KIND: PdoKind = PdoKind::#kind;
            const NUMBER: u16 = #number;
            const MAPPING: &'static [u32] = &[#(#mapping),*];
        }
    }
}
