//! One struct per `RxPdo`/`TxPdo`: each field's type and bit offset, and the struct with its
//! `ProcessData` encoding and decoding.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::emit::names::{ident, Case, Namespace};
use crate::emit::plan::{code_span, doc_text, id, Plan};
use crate::emit::types::{pdo_derives, Prim, RustType, TypeTokens};
use edsgen_model::model::EcPdo;

use super::{Field, FieldType, PdoPlan};

/// The struct name of a PDO: `RxPdo1600`, `TxPdo1A00`.
fn pdo_struct_name(pdo: &EcPdo, rx: bool) -> String {
    format!("{}Pdo{:04X}", if rx { "Rx" } else { "Tx" }, pdo.index)
}

/// A field's type from its entry's ESI `DataType` and bit length, for entries the dictionary
/// does not hold (or holds with another width).
fn type_by_name(data_type: Option<&str>, bits: u32) -> FieldType {
    let width = |bits: u32| match bits {
        0..=8 => 8,
        9..=16 => 16,
        17..=32 => 32,
        _ => 64,
    };
    if bits > 64 {
        return FieldType::Bytes(bits.div_ceil(8) as usize);
    }
    match data_type.map(str::trim).unwrap_or("") {
        "BOOL" | "BIT" | "BIT1" if bits == 1 => FieldType::Scalar(Prim::Bool),
        "SINT" | "INT" | "INT24" | "DINT" | "INT40" | "INT48" | "INT56" | "LINT" => {
            FieldType::Scalar(Prim::Signed(width(bits)))
        }
        "REAL" | "FLOAT" if bits == 32 => FieldType::Scalar(Prim::F32),
        "LREAL" | "DOUBLE" if bits == 64 => FieldType::Scalar(Prim::F64),
        _ => FieldType::Scalar(Prim::Unsigned(width(bits))),
    }
}

pub(super) fn plan_pdo(pdo: &EcPdo, rx: bool, plan: &Plan) -> PdoPlan {
    let mut names = Namespace::default();
    let mut fields = Vec::new();
    let mut layout = Vec::new();
    let mut offset = 0u32;
    for entry in &pdo.entries {
        let bits = u32::from(entry.bit_len);
        if bits == 0 {
            continue;
        }
        if entry.index == 0 {
            layout.push(format!(
                " - bits {offset} to {}: padding",
                offset + bits - 1
            ));
            offset += bits;
            continue;
        }
        let known = plan.entry(entry.index, entry.sub);
        let ty = match known.map(|e| e.ty) {
            Some(RustType::Scalar(prim @ (Prim::F32 | Prim::F64), _)) if bits == prim.bits() => {
                FieldType::Scalar(prim)
            }
            Some(RustType::Scalar(Prim::Bool, _)) => FieldType::Scalar(Prim::Bool),
            Some(RustType::Scalar(prim @ (Prim::Unsigned(_) | Prim::Signed(_)), wire))
                if bits <= wire as u32 * 8 =>
            {
                FieldType::Scalar(prim)
            }
            Some(RustType::Bytes(_)) => FieldType::Bytes(bits.div_ceil(8) as usize),
            _ => type_by_name(entry.data_type.as_deref(), bits),
        };
        let wanted = match known {
            Some(e) => e.pdo_name(),
            None => ident(
                &entry.name,
                Case::Snake,
                &format!("object_{:04x}_{}", entry.index, entry.sub),
            ),
        };
        let (name, _) = names.claim(
            &wanted,
            entry.index,
            &[format!("{:04x}_{}", entry.index, entry.sub)],
        );
        let title = match known {
            Some(e) => e.title().trim().to_owned(),
            None => doc_text(entry.name.trim()),
        };
        let kind = match known {
            Some(e) => e.basic.name().to_owned(),
            None => format!(
                "{}, not in the dictionary",
                doc_text(entry.data_type.as_deref().unwrap_or("no DataType"))
            ),
        };
        let doc = format!(
            " {title} ({:04X}h sub {}, {kind}): bits {offset} to {}.",
            entry.index,
            entry.sub,
            offset + bits - 1
        );
        layout.push(format!(
            " - bits {offset} to {}: `{name}`",
            offset + bits - 1
        ));
        fields.push(Field {
            name,
            ty,
            offset,
            bits,
            doc,
        });
        offset += bits;
    }
    let name = pdo_struct_name(pdo, rx);
    let assigned = match pdo.sm {
        Some(sm) => format!(", assigned to SM{sm} by default"),
        None => ", not assigned by default".to_owned(),
    };
    let mut doc = vec![
        format!(
            " {} {:04X}h {}: {offset} bits ({} bytes){assigned}.",
            if rx {
                "RxPDO (outputs)"
            } else {
                "TxPDO (inputs)"
            },
            pdo.index,
            code_span(pdo.name.trim()),
            offset.div_ceil(8)
        ),
        String::new(),
    ];
    doc.extend(layout);
    let fallible = fields.iter().any(|f| match f.ty {
        FieldType::Scalar(p @ (Prim::Unsigned(_) | Prim::Signed(_))) => f.bits < p.bits(),
        _ => false,
    });
    let eq = !fields
        .iter()
        .any(|f| matches!(f.ty, FieldType::Scalar(Prim::F32 | Prim::F64)));
    let default = !fields
        .iter()
        .any(|f| matches!(f.ty, FieldType::Bytes(n) if n > 32));
    PdoPlan {
        name,
        fields,
        bits: offset,
        doc,
        fallible,
        eq,
        default,
    }
}

/// `at` plus a constant bit offset.
pub(super) fn at_plus(offset: u32) -> TokenStream {
    if offset == 0 {
        quote!(at)
    } else {
        let off = Literal::usize_unsuffixed(offset as usize);
        quote!(at + #off)
    }
}

/// The private `put`, `get` and (for narrow fields) `check` of one PDO struct.
pub(super) fn pdo_methods(p: &PdoPlan) -> TokenStream {
    let typed = quote!(::edsgen_runtime::support);
    let mut puts = Vec::new();
    let mut gets = Vec::new();
    let mut checks = Vec::new();
    for f in &p.fields {
        let field = id(&f.name);
        let at = at_plus(f.offset);
        let nbits = Literal::u32_unsuffixed(f.bits);
        let name = &f.name;
        match f.ty {
            FieldType::Scalar(prim) => {
                let t = prim.tokens();
                let narrow = f.bits < prim.bits();
                let get = quote!(#typed::get_bits(buf, #at, #nbits));
                let (raw, read) = match prim {
                    Prim::Bool => (quote!(u64::from(self.#field)), quote!(#get != 0)),
                    Prim::F32 => (
                        quote!(u64::from(self.#field.to_bits())),
                        quote!(f32::from_bits(#get as u32)),
                    ),
                    Prim::F64 => (quote!(self.#field.to_bits()), quote!(f64::from_bits(#get))),
                    Prim::Unsigned(w) => {
                        let raw = if w == 64 {
                            quote!(self.#field)
                        } else {
                            quote!(u64::from(self.#field))
                        };
                        if narrow {
                            checks.push(quote! {
                                if !#typed::fits_unsigned(#raw, #nbits) {
                                    return Err(::edsgen_runtime::PdoError::OutOfRange { field: #name });
                                }
                            });
                        }
                        let read = if w == 64 { get } else { quote!(#get as #t) };
                        (raw, read)
                    }
                    Prim::Signed(w) => {
                        let wide = if w == 64 {
                            quote!(self.#field)
                        } else {
                            quote!(i64::from(self.#field))
                        };
                        if narrow {
                            checks.push(quote! {
                                if !#typed::fits_signed(#wide, #nbits) {
                                    return Err(::edsgen_runtime::PdoError::OutOfRange { field: #name });
                                }
                            });
                        }
                        let ext = quote!(#typed::sign_extend(#get, #nbits));
                        let read = if w == 64 { ext } else { quote!(#ext as #t) };
                        (quote!(#wide as u64), read)
                    }
                };
                puts.push(quote!(#typed::put_bits(buf, #at, #nbits, #raw);));
                gets.push(quote!(#field: #read,));
            }
            FieldType::Bytes(n) => {
                let n_lit = Literal::usize_unsuffixed(n);
                let total = Literal::usize_unsuffixed(f.bits as usize);
                // Whole bytes, the last one possibly partial.
                puts.push(quote! {
                    for (i, byte) in self.#field.iter().enumerate() {
                        let bits = (#total - 8 * i).min(8) as u32;
                        #typed::put_bits(buf, #at + 8 * i, bits, u64::from(*byte));
                    }
                });
                gets.push(quote!(#field: {
                    let mut bytes = [0u8; #n_lit];
                    for (i, byte) in bytes.iter_mut().enumerate() {
                        let bits = (#total - 8 * i).min(8) as u32;
                        *byte = #typed::get_bits(buf, #at + 8 * i, bits) as u8;
                    }
                    bytes
                },));
            }
        }
    }
    let (buf, at) = if p.fields.is_empty() {
        (quote!(_buf), quote!(_at))
    } else {
        (quote!(buf), quote!(at))
    };
    let check = if p.fallible {
        quote! {
            /// `OutOfRange` if a field does not fit its mapped bits.
            fn check(&self) -> Result<(), ::edsgen_runtime::PdoError> {
                #(#checks)*
                Ok(())
            }
        }
    } else {
        TokenStream::new()
    };
    quote! {
        /// Writes the fields from bit `at` (bits beyond `buf` are dropped).
        fn put(&self, #buf: &mut [u8], #at: usize) {
            #(#puts)*
        }

        /// Reads the fields from bit `at` (bits beyond `buf` read as zero).
        fn get(#buf: &[u8], #at: usize) -> Self {
            Self { #(#gets)* }
        }

        #check
    }
}

/// One struct with its fields' declarations, the image API (`SIZE`, `from_bytes`, `to_bytes`,
/// `from_slice`), and `ProcessData`.
pub(super) fn emit_struct(p: &PdoPlan, methods: &TokenStream) -> TokenStream {
    let fields = p.fields.iter().map(|f| {
        let field = id(&f.name);
        let doc = &f.doc;
        let ty = match f.ty {
            FieldType::Scalar(prim) => prim.tokens(),
            FieldType::Bytes(n) => {
                let n = Literal::usize_unsuffixed(n);
                quote!([u8; #n])
            }
        };
        quote!(#[doc = #doc] pub #field: #ty,)
    });
    emit_item(
        &p.name,
        &p.doc,
        quote!(#(#fields)*),
        p.bits,
        p.fallible,
        p.eq,
        p.default,
        methods,
    )
}

/// The struct, its inherent image API and private methods, its `ProcessData`
/// implementation and the ethercrab-wire hook: shared by PDOs and process images.
#[allow(clippy::too_many_arguments)]
pub(super) fn emit_item(
    name: &str,
    doc: &[String],
    fields: TokenStream,
    bits: u32,
    fallible: bool,
    eq: bool,
    default: bool,
    methods: &TokenStream,
) -> TokenStream {
    let name = id(name);
    let bits_count = bits;
    let len = Literal::usize_unsuffixed(bits.div_ceil(8) as usize);
    let bits = Literal::usize_unsuffixed(bits as usize);
    let doc_attrs = doc.iter().map(|l| quote!(#[doc = #l]));
    let derives = pdo_derives(eq, default);
    let size = bits_count.div_ceil(8) as usize;
    let (to_bytes, check) = if fallible {
        (
            quote! {
                /// The bytes, bit-exact (least significant bit first, little-endian); an error if
                /// a field does not fit its mapped bits.
                pub fn to_bytes(self) -> Result<[u8; #len], ::edsgen_runtime::PdoError> {
                    self.check()?;
                    let mut bytes = [0u8; #len];
                    self.put(&mut bytes, 0);
                    Ok(bytes)
                }
            },
            quote!(self.check()?;),
        )
    } else {
        (
            quote! {
                /// The bytes, bit-exact (least significant bit first, little-endian).
                pub fn to_bytes(self) -> [u8; #len] {
                    let mut bytes = [0u8; #len];
                    self.put(&mut bytes, 0);
                    bytes
                }
            },
            TokenStream::new(),
        )
    };
    let size_and_from_slice =
        crate::emit::image_api::size_and_from_slice(size, "The length in bytes.");
    quote! {
        #(#doc_attrs)*
        #[derive(#(#derives),*)]
        pub struct #name {
            #fields
        }

        impl #name {
            #size_and_from_slice

            /// The fields of the image's bytes.
            pub fn from_bytes(bytes: &[u8; #len]) -> Self {
                Self::get(bytes, 0)
            }

            #to_bytes

            #methods
        }

        impl ::edsgen_runtime::ethercat::ProcessData for #name {
            const BITS: usize = #bits;
            const LEN: usize = #len;

            fn write_to(&self, buf: &mut [u8], bit_offset: usize) -> Result<(), ::edsgen_runtime::PdoError> {
                ::edsgen_runtime::ethercat::check_len(buf, bit_offset, #bits)?;
                #check
                self.put(buf, bit_offset);
                Ok(())
            }

            fn read_from(buf: &[u8], bit_offset: usize) -> Result<Self, ::edsgen_runtime::PdoError> {
                ::edsgen_runtime::ethercat::check_len(buf, bit_offset, #bits)?;
                Ok(Self::get(buf, bit_offset))
            }
        }

        ::edsgen_runtime::ethercrab_wire!(#name);
    }
}
