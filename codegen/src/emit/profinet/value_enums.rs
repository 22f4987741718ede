//! A record field's `ValueItem` (its `Assignments`: values with texts) as a Rust enum in the
//! record's module, as ODVA `EnumN` become enums: a variant per text, `raw()`, and
//! `TryFrom<raw>` giving the raw value back when no variant names it.

use heck::ToUpperCamelCase;
use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::emit::names::{ident, Case};
use crate::emit::plan::{code_span, id};
use edsgen_model::model::{PnDataType, RecordField, ValueList};

/// The raw type of a field that names values, and its range.
fn raw_type(field: &RecordField) -> Option<(&'static str, i128, i128)> {
    use PnDataType::*;
    Some(match field.kind? {
        Bit => ("u8", 0, 1),
        BitArea if field.bit_length.unwrap_or(1) <= 8 => ("u8", 0, 255),
        BitArea => ("u16", 0, 65_535),
        Unsigned8 => ("u8", 0, u8::MAX.into()),
        Unsigned16 => ("u16", 0, u16::MAX.into()),
        Unsigned32 => ("u32", 0, u32::MAX.into()),
        Integer8 => ("i8", i8::MIN.into(), i8::MAX.into()),
        Integer16 => ("i16", i16::MIN.into(), i16::MAX.into()),
        Integer32 => ("i32", i32::MIN.into(), i32::MAX.into()),
        _ => return None,
    })
}

/// `FIELD` values as `enum FieldValues`; nothing when the field names no list with texts.
pub(super) fn value_enum(
    field: &RecordField,
    lists: &[ValueList],
    taken: &mut Vec<String>,
) -> TokenStream {
    let Some(target) = &field.value_item else {
        return TokenStream::new();
    };
    let Some(list) = lists.iter().find(|l| l.id == target.value) else {
        return TokenStream::new();
    };
    let Some((raw, low, high)) = raw_type(field) else {
        return TokenStream::new();
    };
    let mut variants: Vec<(String, i128, &str)> = Vec::new();
    for (value, text) in &list.assignments {
        let Some(text) = text.as_deref() else {
            continue;
        };
        if !(low..=high).contains(value) || variants.iter().any(|(_, v, _)| v == value) {
            continue;
        }
        let fallback = format!("Value{}", value.unsigned_abs());
        let mut name = ident(text, Case::Snake, "").to_upper_camel_case();
        if name.is_empty() || name == "Self" {
            name.clone_from(&fallback);
        }
        if variants.iter().any(|(n, _, _)| *n == name) {
            name = format!("{name}{fallback}");
        }
        variants.push((name, *value, text));
    }
    if variants.is_empty() {
        return TokenStream::new();
    }
    let field_name = field.name.as_deref().unwrap_or(&list.id);
    // Unique in the record's module: a second field of the same name gets its byte offset.
    let mut name = format!(
        "{}Values",
        ident(field_name, Case::Snake, "field").to_upper_camel_case()
    );
    while taken.contains(&name) {
        name = format!("{name}{}", field.byte_offset);
    }
    taken.push(name.clone());
    let ty = id(&name);
    let raw_ty = id(raw);
    let literal = |v: i128| {
        let magnitude = Literal::u128_unsuffixed(v.unsigned_abs());
        if v < 0 {
            quote!(-#magnitude)
        } else {
            quote!(#magnitude)
        }
    };
    let doc = format!(
        " The values {} names for {} (`ValueItem` {}).",
        code_span(&list.id),
        code_span(field_name),
        code_span(&list.id)
    );
    let declared = variants.iter().map(|(n, v, text)| {
        let (n, vdoc) = (id(n), format!(" {} ({v}).", code_span(text)));
        quote!(#[doc = #vdoc] #n,)
    });
    let to_raw = variants.iter().map(|(n, v, _)| {
        let (n, v) = (id(n), literal(*v));
        quote!(Self::#n => #v,)
    });
    let from_raw = variants.iter().map(|(n, v, _)| {
        let (n, v) = (id(n), literal(*v));
        quote!(#v => ::core::result::Result::Ok(Self::#n),)
    });
    // Every value of the raw type named (the field's own range may be narrower): no other arm.
    let values_of_raw: i128 = match raw {
        "u8" | "i8" => 1 << 8,
        "u16" | "i16" => 1 << 16,
        _ => 1 << 32,
    };
    let other = if variants.len() as i128 == values_of_raw {
        TokenStream::new()
    } else {
        quote!(other => ::core::result::Result::Err(other),)
    };
    quote! {
        #[doc = #doc]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum #ty {
            #(#declared)*
        }

        impl #ty {
            /// The raw value of the field.
            pub const fn raw(self) -> #raw_ty {
                match self {
                    #(#to_raw)*
                }
            }
        }

        impl ::core::convert::TryFrom<#raw_ty> for #ty {
            /// The raw value, when no variant names it.
            type Error = #raw_ty;

            fn try_from(raw: #raw_ty) -> ::core::result::Result<Self, #raw_ty> {
                match raw {
                    #(#from_raw)*
                    #other
                }
            }
        }
    }
}
