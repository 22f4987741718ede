//! One struct per submodule direction (`Input`, `Output`): a field per `DataItem`, big-endian
//! on the wire as PROFINET carries IO data, with the image API (`SIZE`, `from_bytes`,
//! `to_bytes`, `from_slice`) over the data bytes, `_with_iops` over the data and its IOPS byte,
//! and a mask constant per named bit of a `UseAsBits` item.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::emit::names::{ident, Case};
use crate::emit::plan::{code_span, doc_text, id};
use edsgen_model::model::{DataItem, PnDataType};

/// What a field holds.
enum Ty {
    /// A scalar with `to_be_bytes`/`from_be_bytes`, and its byte count.
    Scalar(&'static str, usize),
    /// A `Boolean` byte.
    Bool,
    /// Bytes as written (strings, fixed-size composite types).
    Bytes(usize),
}

fn ty(item: &DataItem) -> Option<Ty> {
    use PnDataType::*;
    Some(match item.kind? {
        Unsigned8 => Ty::Scalar("u8", 1),
        Unsigned16 => Ty::Scalar("u16", 2),
        Unsigned32 => Ty::Scalar("u32", 4),
        Unsigned64 => Ty::Scalar("u64", 8),
        Integer8 => Ty::Scalar("i8", 1),
        Integer16 => Ty::Scalar("i16", 2),
        Integer32 => Ty::Scalar("i32", 4),
        Integer64 => Ty::Scalar("i64", 8),
        Float32 => Ty::Scalar("f32", 4),
        Float64 => Ty::Scalar("f64", 8),
        Boolean => Ty::Bool,
        _ => Ty::Bytes(item.size()? as usize),
    })
}

/// The struct `name` for `items`; nothing when there are none or a size is unknown (the
/// validator reports those, PN003).
pub(super) fn image(items: &[DataItem], name: &str, what: &str) -> TokenStream {
    if items.is_empty() {
        return TokenStream::new();
    }
    let Some(types) = items.iter().map(ty).collect::<Option<Vec<Ty>>>() else {
        return TokenStream::new();
    };
    let mut names: Vec<String> = Vec::new();
    let mut fields = Vec::new();
    let mut encodes = Vec::new();
    let mut decodes = Vec::new();
    let mut masks = Vec::new();
    let mut accessors = Vec::new();
    // The image's method names, which a bit's accessors must not take.
    let mut methods: Vec<String> = RESERVED_METHODS.iter().map(|m| (*m).to_owned()).collect();
    let mut offset = 0usize;
    let mut float = false;
    for (n, (item, ty)) in items.iter().zip(&types).enumerate() {
        let wanted = ident(
            item.name.as_deref().unwrap_or(""),
            Case::Snake,
            &format!("item_{n}"),
        );
        let mut field = wanted.clone();
        let mut k = 2;
        while names.contains(&field) {
            field = format!("{wanted}_{k}");
            k += 1;
        }
        names.push(field.clone());
        let f = id(&field);
        let doc = format!(
            " Byte {offset}: {}{}.",
            code_span(&item.data_type.value),
            item.name
                .as_deref()
                .map(|t| format!(", {}", doc_text(t)))
                .unwrap_or_default()
        );
        let (rust, len) = match ty {
            Ty::Scalar(t, len) => {
                float |= t.starts_with('f');
                let t = id(t);
                let at: Vec<TokenStream> = (offset..offset + len)
                    .map(|i| {
                        let i = Literal::usize_unsuffixed(i);
                        quote!(bytes[#i])
                    })
                    .collect();
                let range = range(offset, *len);
                encodes.push(quote!(out[#range].copy_from_slice(&self.#f.to_be_bytes());));
                decodes.push(quote!(#f: #t::from_be_bytes([#(#at),*]),));
                (quote!(#t), *len)
            }
            Ty::Bool => {
                let i = Literal::usize_unsuffixed(offset);
                encodes.push(quote!(out[#i] = u8::from(self.#f);));
                decodes.push(quote!(#f: bytes[#i] != 0,));
                (quote!(bool), 1)
            }
            Ty::Bytes(len) => {
                let range = range(offset, *len);
                let n = Literal::usize_unsuffixed(*len);
                encodes.push(quote!(out[#range].copy_from_slice(&self.#f);));
                decodes.push(quote!(#f: {
                    let mut field = [0u8; #n];
                    field.copy_from_slice(&bytes[#range]);
                    field
                },));
                (quote!([u8; #n]), *len)
            }
        };
        // Named bits of an integer (a float has none to name).
        if let Ty::Scalar(t @ ("u8" | "u16" | "u32" | "u64" | "i8" | "i16" | "i32" | "i64"), _) = ty
        {
            let t = id(t);
            let mut taken: Vec<String> = Vec::new();
            for bit in &item.bits {
                if u64::from(bit.bit_offset) >= (len as u64) * 8 {
                    continue;
                }
                let wanted = ident(
                    &format!("{field} {}", bit.name.as_deref().unwrap_or("")),
                    Case::Shouty,
                    "BIT",
                );
                let wanted = if bit.name.is_none() {
                    format!("{}_BIT_{}", field.to_ascii_uppercase(), bit.bit_offset)
                } else {
                    wanted
                };
                let mut name = wanted.clone();
                let mut k = 2;
                while taken.contains(&name) {
                    name = format!("{wanted}_{k}");
                    k += 1;
                }
                taken.push(name.clone());
                let shift = Literal::u32_unsuffixed(bit.bit_offset);
                let doc = format!(
                    " Bit {} of `{field}`{}.",
                    bit.bit_offset,
                    bit.name
                        .as_deref()
                        .map(|t| format!(": {}", doc_text(t)))
                        .unwrap_or_default()
                );
                let mask = id(&name);
                masks.push(quote! {
                    #[doc = #doc]
                    pub const #mask: #t = 1 << #shift;
                });
                accessors.push(bit_accessors(&field, &name, bit.bit_offset, &mut methods));
            }
        }
        fields.push(quote! {
            #[doc = #doc]
            pub #f: #rust,
        });
        offset += len;
    }
    let name = id(name);
    let len = Literal::usize_unsuffixed(offset);
    let with_iops = Literal::usize_unsuffixed(offset + 1);
    let last = Literal::usize_unsuffixed(offset);
    let doc = format!(" The submodule's {what}: {offset} bytes, big-endian.");
    let eq = (!float).then(|| quote!(Eq,));
    let size_and_from_slice =
        crate::emit::image_api::size_and_from_slice(offset, "Bytes of data, without the IOPS.");
    quote! {
        #[doc = #doc]
        #[derive(Debug, Clone, Copy, PartialEq, #eq)]
        pub struct #name {
            #(#fields)*
        }

        impl #name {
            #size_and_from_slice
            #(#masks)*
            #(#accessors)*

            /// The data bytes, big-endian.
            pub fn to_bytes(self) -> [u8; #len] {
                let mut out = [0u8; #len];
                #(#encodes)*
                out
            }

            /// Reads the data bytes.
            pub fn from_bytes(bytes: &[u8; #len]) -> Self {
                Self { #(#decodes)* }
            }

            /// The data bytes followed by the provider status (IOPS), as the frame carries them.
            pub fn to_bytes_with_iops(self, iops: u8) -> [u8; #with_iops] {
                let mut out = [0u8; #with_iops];
                out[..#len].copy_from_slice(&self.to_bytes());
                out[#last] = iops;
                out
            }

            /// Reads the data bytes and the IOPS that follows them.
            pub fn from_bytes_with_iops(bytes: &[u8; #with_iops]) -> (Self, u8) {
                let mut data = [0u8; #len];
                data.copy_from_slice(&bytes[..#len]);
                (Self::from_bytes(&data), bytes[#last])
            }
        }

        impl Default for #name {
            fn default() -> Self {
                Self::from_bytes(&[0u8; #len])
            }
        }
    }
}

/// The methods an image has besides its bits' accessors (the image API, the PKW/PZD
/// conversions, the derived traits' methods).
const RESERVED_METHODS: &[&str] = &[
    "to_bytes",
    "from_bytes",
    "from_slice",
    "to_bytes_with_iops",
    "from_bytes_with_iops",
    "pkw_pzd",
    "from_pkw_pzd",
    "default",
    "clone",
    "eq",
    "ne",
    "fmt",
];

/// A named bit's getter and setter on the image (`ready(self) -> bool`,
/// `set_ready(&mut self, bool)`), named as its mask constant `mask` in snake case; a name
/// already among `methods` is numbered.
fn bit_accessors(field: &str, mask: &str, bit: u32, methods: &mut Vec<String>) -> TokenStream {
    let wanted = ident(mask, Case::Snake, "bit");
    let mut getter = wanted.clone();
    let mut k = 2;
    while methods.contains(&getter) || methods.contains(&format!("set_{getter}")) {
        getter = format!("{wanted}_{k}");
        k += 1;
    }
    let setter = format!("set_{getter}");
    methods.push(getter.clone());
    methods.push(setter.clone());
    let get_doc = format!(" Whether bit {bit} of `{field}` is set ([`Self::{mask}`]).");
    let set_doc = format!(" Sets (`true`) or clears bit {bit} of `{field}` ([`Self::{mask}`]).");
    let (f, mask, getter, setter) = (id(field), id(mask), id(&getter), id(&setter));
    quote! {
        #[doc = #get_doc]
        pub const fn #getter(self) -> bool {
            self.#f & Self::#mask != 0
        }

        #[doc = #set_doc]
        pub fn #setter(&mut self, on: bool) {
            if on {
                self.#f |= Self::#mask;
            } else {
                self.#f &= !Self::#mask;
            }
        }
    }
}

fn range(offset: usize, len: usize) -> TokenStream {
    let (a, b) = (
        Literal::usize_unsuffixed(offset),
        Literal::usize_unsuffixed(offset + len),
    );
    quote!(#a..#b)
}
