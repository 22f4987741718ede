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
        if let Ty::Scalar(t, _) = ty {
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
                let name = id(&name);
                let shift = Literal::u32_unsuffixed(bit.bit_offset);
                let doc = format!(
                    " Bit {} of `{field}`{}.",
                    bit.bit_offset,
                    bit.name
                        .as_deref()
                        .map(|t| format!(": {}", doc_text(t)))
                        .unwrap_or_default()
                );
                masks.push(quote! {
                    #[doc = #doc]
                    pub const #name: #t = 1 << #shift;
                });
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

fn range(offset: usize, len: usize) -> TokenStream {
    let (a, b) = (
        Literal::usize_unsuffixed(offset),
        Literal::usize_unsuffixed(offset + len),
    );
    quote!(#a..#b)
}
