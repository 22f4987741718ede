//! One module per parameter record (`record_125`): its index, its length, its default bytes
//! (the `Const` bytes, then each `Ref`'s `DefaultValue`, big-endian), each field's offset, an
//! enum per field that names a `ValueItem` (`value_enums`), and the record as a `Record` struct
//! of typed fields with the image API over its bytes, its default the file's.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::emit::names::{ident, Case};
use crate::emit::plan::{code_span, doc_text, id};
use edsgen_model::model::{ParameterRecord, PnDataType, RecordField, ValueList};
use edsgen_model::read::esi::values::parse_number;

pub(super) fn records(records: &[ParameterRecord], value_lists: &[ValueList]) -> TokenStream {
    let mut out = Vec::new();
    let mut taken: Vec<u16> = Vec::new();
    for record in records {
        if taken.contains(&record.index.value) {
            // PN014 reports it; the first one is generated.
            continue;
        }
        taken.push(record.index.value);
        let name = id(&format!("record_{}", record.index.value));
        let index = Literal::u16_unsuffixed(record.index.value);
        let length = Literal::usize_unsuffixed(record.length.value as usize);
        let bytes = default_bytes(record)
            .into_iter()
            .map(Literal::u8_unsuffixed);
        let doc = format!(
            " Parameter record {}{}, {} bytes.",
            record.index.value,
            record
                .name
                .as_deref()
                .map(|n| format!(" ({})", doc_text(n)))
                .unwrap_or_default(),
            record.length.value
        );
        let mut names: Vec<String> = Vec::new();
        let mut enums: Vec<String> = Vec::new();
        // Per field, the enum naming its values, if one is generated.
        let mut value_enums: Vec<Option<String>> = Vec::new();
        let fields: Vec<TokenStream> = record
            .fields
            .iter()
            .enumerate()
            .map(|(n, f)| {
                let wanted = ident(
                    f.name.as_deref().unwrap_or(""),
                    Case::Shouty,
                    &format!("FIELD_{n}"),
                );
                let mut name = wanted.clone();
                let mut k = 2;
                while names.contains(&name) {
                    name = format!("{wanted}_{k}");
                    k += 1;
                }
                names.push(name.clone());
                let name = id(&format!("{name}_BYTE_OFFSET"));
                let offset = Literal::usize_unsuffixed(f.byte_offset as usize);
                let doc = format!(
                    " Byte offset of the {} field{}{}.",
                    code_span(&f.data_type.value),
                    f.name
                        .as_deref()
                        .map(|t| format!(" {}", doc_text(t)))
                        .unwrap_or_default(),
                    f.bit_offset
                        .map(|b| format!(" (bit {b})"))
                        .unwrap_or_default()
                );
                let before = enums.len();
                let values = super::value_enums::value_enum(f, value_lists, &mut enums);
                value_enums.push(enums.get(before).cloned());
                quote! {
                    #[doc = #doc]
                    pub const #name: usize = #offset;
                    #values
                }
            })
            .collect();
        let record_struct = record_struct(record, &value_enums);
        out.push(quote! {
            #[doc = #doc]
            pub mod #name {
                /// The record index a controller writes.
                pub const INDEX: u16 = #index;
                /// The record's length in bytes.
                pub const LENGTH: usize = #length;
                /// The default bytes: the `Const` data, then each field's `DefaultValue`.
                pub const DEFAULT: [u8; #length] = [#(#bytes),*];
                #(#fields)*
                #record_struct
            }
        });
    }
    quote!(#(#out)*)
}

/// How a field's bits become a Rust value.
enum FieldType {
    /// A big-endian scalar (`u16`, `i32`, `f32`, ...) of this many bytes.
    Scalar(&'static str, usize),
    /// `Boolean`: one byte, zero or not.
    Boolean,
    /// `Bit`: one bit of a byte.
    Bit(u32),
    /// `BitArea`: bits (offset, width) of one byte, as a `u8`.
    BitArea(u32, u32),
    /// Strings and the fixed-size types carried as bytes.
    Bytes(usize),
}

fn field_type(field: &RecordField) -> Option<FieldType> {
    use PnDataType::*;
    let bit = field.bit_offset.unwrap_or(0);
    Some(match field.kind? {
        Bit if bit < 8 => FieldType::Bit(bit),
        BitArea => {
            let width = field.bit_length.unwrap_or(1);
            if width == 0 || bit + width > 8 {
                return None;
            }
            FieldType::BitArea(bit, width)
        }
        Bit => return None,
        Boolean => FieldType::Boolean,
        Integer8 => FieldType::Scalar("i8", 1),
        Integer16 => FieldType::Scalar("i16", 2),
        Integer32 => FieldType::Scalar("i32", 4),
        Integer64 => FieldType::Scalar("i64", 8),
        Unsigned8 => FieldType::Scalar("u8", 1),
        Unsigned16 => FieldType::Scalar("u16", 2),
        Unsigned32 => FieldType::Scalar("u32", 4),
        Unsigned64 => FieldType::Scalar("u64", 8),
        Float32 => FieldType::Scalar("f32", 4),
        Float64 => FieldType::Scalar("f64", 8),
        OctetString | VisibleString | UnicodeString8 => FieldType::Bytes(field.length? as usize),
        Fixed(n) => FieldType::Bytes(n as usize),
    })
}

/// `Record`: the fields as typed values, `to_bytes` over `DEFAULT` (so `Const` bytes stay),
/// `from_bytes`, `from_slice` and `SIZE`, `FIELD_value()` for a field whose values an enum of
/// `value_enums` names; its `Default` the file's defaults. Nothing when a field has no type,
/// lies past the record's length (PN010), or the record has no field.
fn record_struct(record: &ParameterRecord, value_enums: &[Option<String>]) -> TokenStream {
    let length = record.length.value as usize;
    let mut names: Vec<String> = Vec::new();
    let (mut fields, mut encodes, mut decodes) = (Vec::new(), Vec::new(), Vec::new());
    let mut float = false;
    let mut accessors = Vec::new();
    for (n, field) in record.fields.iter().enumerate() {
        let Some(ty) = field_type(field) else {
            return TokenStream::new();
        };
        let at = field.byte_offset as usize;
        let end = at
            + match ty {
                FieldType::Scalar(_, len) | FieldType::Bytes(len) => len,
                _ => 1,
            };
        if end > length {
            return TokenStream::new();
        }
        let wanted = ident(
            field.name.as_deref().unwrap_or(""),
            Case::Snake,
            &format!("field_{n}"),
        );
        let mut name = wanted.clone();
        let mut k = 2;
        while names.contains(&name) {
            name = format!("{wanted}_{k}");
            k += 1;
        }
        names.push(name.clone());
        let f = id(&name);
        let i = Literal::usize_unsuffixed(at);
        let range = {
            let (a, b) = (
                Literal::usize_unsuffixed(at),
                Literal::usize_unsuffixed(end),
            );
            quote!(#a..#b)
        };
        let place = match ty {
            FieldType::Bit(bit) | FieldType::BitArea(bit, _) => format!("Byte {at}, bit {bit}"),
            _ => format!("Byte {at}"),
        };
        let doc = format!(
            " {place}: {}{}.",
            code_span(&field.data_type.value),
            field
                .name
                .as_deref()
                .map(|t| format!(", {}", doc_text(t)))
                .unwrap_or_default()
        );
        let rust = match ty {
            FieldType::Scalar(t, _) => {
                float |= t.starts_with('f');
                let t = id(t);
                encodes.push(quote!(out[#range].copy_from_slice(&self.#f.to_be_bytes());));
                let each = (at..end).map(|i| {
                    let i = Literal::usize_unsuffixed(i);
                    quote!(bytes[#i])
                });
                decodes.push(quote!(#f: #t::from_be_bytes([#(#each),*]),));
                quote!(#t)
            }
            FieldType::Boolean => {
                encodes.push(quote!(out[#i] = u8::from(self.#f);));
                decodes.push(quote!(#f: bytes[#i] != 0,));
                quote!(bool)
            }
            FieldType::Bit(bit) => {
                let mask = Literal::u8_unsuffixed(1 << bit);
                let bit = Literal::u32_unsuffixed(bit);
                encodes.push(quote!(out[#i] = (out[#i] & !#mask) | (u8::from(self.#f) << #bit);));
                decodes.push(quote!(#f: bytes[#i] & #mask != 0,));
                quote!(bool)
            }
            FieldType::BitArea(bit, width) => {
                let mask = Literal::u8_unsuffixed(((1u16 << width) - 1) as u8);
                let bit = Literal::u32_unsuffixed(bit);
                encodes.push(quote!(
                    out[#i] = (out[#i] & !(#mask << #bit)) | ((self.#f & #mask) << #bit);
                ));
                decodes.push(quote!(#f: (bytes[#i] >> #bit) & #mask,));
                quote!(u8)
            }
            FieldType::Bytes(len) => {
                let n = Literal::usize_unsuffixed(len);
                encodes.push(quote!(out[#range].copy_from_slice(&self.#f);));
                decodes.push(quote!(#f: {
                    let mut field = [0u8; #n];
                    field.copy_from_slice(&bytes[#range]);
                    field
                },));
                quote!([u8; #n])
            }
        };
        if let Some(values) = value_enums.get(n).and_then(Option::as_ref) {
            let (raw, conv) = match ty {
                FieldType::Bit(_) => (quote!(u8), quote!(u8::from(self.#f))),
                _ => (rust.clone(), quote!(self.#f)),
            };
            let method = id(&format!("{name}_value"));
            let values_ty = id(values);
            let doc = format!(" `{name}` as [`{values}`]; the raw value when no variant names it.");
            accessors.push(quote! {
                #[doc = #doc]
                pub fn #method(self) -> ::core::result::Result<#values_ty, #raw> {
                    <#values_ty as ::core::convert::TryFrom<#raw>>::try_from(#conv)
                }
            });
        }
        fields.push(quote!(#[doc = #doc] pub #f: #rust,));
    }
    if fields.is_empty() {
        return TokenStream::new();
    }
    let len = Literal::usize_unsuffixed(length);
    let eq = (!float).then(|| quote!(Eq,));
    let size_and_from_slice =
        crate::emit::image_api::size_and_from_slice(length, "The record's length in bytes.");
    quote! {
        /// The record as typed fields, big-endian as the controller writes it.
        #[derive(Debug, Clone, Copy, PartialEq, #eq)]
        pub struct Record {
            #(#fields)*
        }

        impl Record {
            #size_and_from_slice

            /// The record's bytes: [`DEFAULT`] (its `Const` data) with each field written.
            pub fn to_bytes(self) -> [u8; #len] {
                let mut out = DEFAULT;
                #(#encodes)*
                out
            }

            /// Reads the fields from the record's bytes.
            pub fn from_bytes(bytes: &[u8; #len]) -> Self {
                Self { #(#decodes)* }
            }

            #(#accessors)*
        }

        impl Default for Record {
            /// The file's defaults ([`DEFAULT`]).
            fn default() -> Self {
                Self::from_bytes(&DEFAULT)
            }
        }
    }
}

/// The record's default content; fields that do not fit (PN010 reports them) are left out.
pub fn default_bytes(record: &ParameterRecord) -> Vec<u8> {
    let len = record.length.value as usize;
    let mut out = vec![0u8; len];
    for (offset, data) in &record.consts {
        for (i, b) in data.iter().enumerate() {
            if let Some(slot) = out.get_mut(*offset as usize + i) {
                *slot = *b;
            }
        }
    }
    for field in &record.fields {
        apply_default(field, &mut out);
    }
    out
}

fn apply_default(field: &RecordField, out: &mut [u8]) {
    let Some(default) = &field.default else {
        return;
    };
    let at = field.byte_offset as usize;
    let value = parse_number(&default.value);
    let bytes: Vec<u8> = match (field.kind, value) {
        (Some(PnDataType::Bit), Some(v)) => {
            let bit = field.bit_offset.unwrap_or(0);
            if let (Some(byte), true) = (out.get_mut(at), bit < 8) {
                if v != 0 {
                    *byte |= 1 << bit;
                } else {
                    *byte &= !(1 << bit);
                }
            }
            return;
        }
        (Some(PnDataType::BitArea), Some(v)) => {
            let bit = field.bit_offset.unwrap_or(0);
            let width = field.bit_length.unwrap_or(1);
            if bit + width <= 8 {
                if let Some(byte) = out.get_mut(at) {
                    let mask = (((1u16 << width) - 1) << bit) as u8;
                    *byte = (*byte & !mask) | (((v as u16) << bit) as u8 & mask);
                }
            }
            return;
        }
        (Some(PnDataType::Float32), _) => match default.value.trim().parse::<f32>() {
            Ok(f) => f.to_be_bytes().to_vec(),
            Err(_) => return,
        },
        (Some(PnDataType::Float64), _) => match default.value.trim().parse::<f64>() {
            Ok(f) => f.to_be_bytes().to_vec(),
            Err(_) => return,
        },
        (Some(kind), Some(v)) => match kind.size() {
            Some(size @ 1..=8) => {
                let be = (v as i64).to_be_bytes();
                be[8 - size as usize..].to_vec()
            }
            _ => return,
        },
        _ => return,
    };
    if at + bytes.len() <= out.len() {
        out[at..at + bytes.len()].copy_from_slice(&bytes);
    }
}
