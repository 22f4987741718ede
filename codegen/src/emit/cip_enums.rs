//! The enumerations of an ODVA EDS (`EnumN` of `ParamN`) as Rust enums (part of the CIP module,
//! `cip`): one per parameter that has an `EnumN`, named after the parameter, a variant per value
//! named after its text, with `TryFrom<raw>` (the raw value back as the error when no variant
//! names it), `From<enum> for raw` and `raw()`. The raw type is the parameter's (`u16` for UINT,
//! `i8` for SINT, ...). Names are valid, deterministic identifiers: a type name that clashes with
//! an image, another enumeration or a name the module or the prelude uses gets the parameter's
//! number; a variant that clashes with an earlier one gets its value. Values the raw type cannot
//! hold, and second texts for a value, have no variant (the documentation says which).

use std::collections::BTreeMap;

use heck::ToUpperCamelCase;
use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::names::{ident, Case};
use super::plan::{code_span, id};
use edsgen_model::model::{Cip, CipParam};

/// Type names the module's items and the prelude use: no image or enumeration takes them.
const RESERVED: &[&str] = &[
    "Self",
    "Connection",
    "Option",
    "Some",
    "None",
    "Result",
    "Ok",
    "Err",
    "Default",
    "Debug",
    "Clone",
    "Copy",
    "PartialEq",
    "Eq",
    "PartialOrd",
    "Ord",
    "Hash",
    "From",
    "Into",
    "TryFrom",
    "TryInto",
    "Iterator",
    "IntoIterator",
    "Extend",
    "Sized",
    "Send",
    "Sync",
    "Unpin",
    "Drop",
    "Fn",
    "FnMut",
    "FnOnce",
    "AsRef",
    "AsMut",
    "ToOwned",
    "ToString",
    "String",
    "Vec",
    "Box",
];

/// Whether a generated type may not be named `name`.
pub(super) fn reserved(name: &str) -> bool {
    RESERVED.contains(&name)
}

/// The raw integer type of a parameter: its data type's, else its data size's unsigned type;
/// `None` for REAL, strings and the like.
fn raw_type(p: &CipParam) -> Option<(&'static str, i128, i128)> {
    let by_type = match p.data_type.as_ref().map(|t| t.value) {
        Some(0xC2) => Some(("i8", i8::MIN.into(), i8::MAX.into())),
        Some(0xC3) => Some(("i16", i16::MIN.into(), i16::MAX.into())),
        Some(0xC4) => Some(("i32", i32::MIN.into(), i32::MAX.into())),
        Some(0xC5) => Some(("i64", i64::MIN.into(), i64::MAX.into())),
        Some(0xC1 | 0xC6 | 0xD1) => Some(("u8", 0, u8::MAX.into())),
        Some(0xC7 | 0xD2 | 0xCD | 0xD8 | 0xDD) => Some(("u16", 0, u16::MAX.into())),
        Some(0xC8 | 0xD3) => Some(("u32", 0, u32::MAX.into())),
        Some(0xC9 | 0xD4) => Some(("u64", 0, u64::MAX.into())),
        Some(_) => return None,
        None => None,
    };
    by_type.or_else(|| match p.data_size.as_ref().map(|s| s.value) {
        Some(1) => Some(("u8", 0, u8::MAX.into())),
        Some(2) => Some(("u16", 0, u16::MAX.into())),
        Some(4) => Some(("u32", 0, u32::MAX.into())),
        Some(8) => Some(("u64", 0, u64::MAX.into())),
        _ => None,
    })
}

/// `text` as an UpperCamelCase identifier, `fallback` (valid) when nothing of it survives or it
/// would be a keyword.
fn camel(text: &str, fallback: &str) -> String {
    let name = ident(text, Case::Snake, "").to_upper_camel_case();
    if name.is_empty() || name == "Self" {
        return fallback.to_owned();
    }
    name
}

/// The enumeration type name of each parameter that gets one (it has an `EnumN` with a value its
/// raw type holds), clear of `taken` (the images' names) and of each other.
pub(super) fn enum_names(cip: &Cip, taken: &[String]) -> BTreeMap<u32, String> {
    let mut used: Vec<String> = taken.to_vec();
    let mut out = BTreeMap::new();
    for (n, e) in &cip.enums {
        let Some(p) = cip.params.get(n) else { continue };
        let Some((_, low, high)) = raw_type(p) else {
            continue;
        };
        if !e
            .values
            .iter()
            .any(|(v, _)| (low..=high).contains(&i128::from(*v)))
        {
            continue;
        }
        let wanted = camel(&p.name, &format!("Param{n}"));
        let mut name = wanted.clone();
        let mut k = 1;
        while used.contains(&name) || reserved(&name) {
            name = if k == 1 {
                format!("{wanted}{n}")
            } else {
                format!("{wanted}{n}_{k}")
            };
            k += 1;
        }
        used.push(name.clone());
        out.insert(*n, name);
    }
    out
}

/// A literal of the raw type (negative values as `-magnitude`).
fn literal(v: i64) -> TokenStream {
    let magnitude = Literal::u64_unsuffixed(v.unsigned_abs());
    if v < 0 {
        quote!(-#magnitude)
    } else {
        quote!(#magnitude)
    }
}

/// The enums, in parameter order.
pub(super) fn enums(cip: &Cip, names: &BTreeMap<u32, String>) -> TokenStream {
    let mut items = Vec::new();
    for (n, name) in names {
        let (Some(p), Some(e)) = (cip.params.get(n), cip.enums.get(n)) else {
            continue;
        };
        let Some((raw, low, high)) = raw_type(p) else {
            continue;
        };
        let raw_ty = id(raw);
        let ty = id(name);
        let mut variants: Vec<(String, i64, &str)> = Vec::new();
        let mut left_out = Vec::new();
        for (v, text) in &e.values {
            let fits = (low..=high).contains(&i128::from(*v));
            if !fits || variants.iter().any(|(_, seen, _)| seen == v) {
                left_out.push(format!("{v} {}", code_span(text)));
                continue;
            }
            let value_name = if *v < 0 {
                format!("Minus{}", v.unsigned_abs())
            } else {
                format!("Value{v}")
            };
            let wanted = camel(text, &value_name);
            let mut variant = wanted.clone();
            if variants.iter().any(|(seen, _, _)| *seen == variant) {
                variant = format!("{wanted}{value_name}");
            }
            let mut k = 2;
            while variants.iter().any(|(seen, _, _)| *seen == variant) {
                variant = format!("{wanted}{value_name}_{k}");
                k += 1;
            }
            variants.push((variant, *v, text));
        }
        let mut doc = vec![format!(
            " Param{n} {}: the values `Enum{n}` names (raw `{raw}`).",
            code_span(&p.name)
        )];
        if !left_out.is_empty() {
            doc.push(String::new());
            doc.push(format!(
                " Without a variant (outside `{raw}`, or a second text for a value): {}.",
                left_out.join(", ")
            ));
        }
        let declared = variants.iter().map(|(variant, v, text)| {
            let variant = id(variant);
            let vdoc = format!(" {} ({v}).", code_span(text));
            quote!(#[doc = #vdoc] #variant,)
        });
        let to_raw = variants.iter().map(|(variant, v, _)| {
            let variant = id(variant);
            let v = literal(*v);
            quote!(Self::#variant => #v,)
        });
        let from_raw = variants.iter().map(|(variant, v, _)| {
            let variant = id(variant);
            let v = literal(*v);
            quote!(#v => ::core::result::Result::Ok(Self::#variant),)
        });
        // Every raw value named: no other value to refuse.
        let other = if variants.len() as i128 == high - low + 1 {
            TokenStream::new()
        } else {
            quote!(other => ::core::result::Result::Err(other),)
        };
        items.push(quote! {
            #(#[doc = #doc])*
            #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
            pub enum #ty {
                #(#declared)*
            }

            impl #ty {
                /// The raw value of the parameter.
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

            impl ::core::convert::From<#ty> for #raw_ty {
                fn from(value: #ty) -> #raw_ty {
                    value.raw()
                }
            }
        });
    }
    quote!(#(#items)*)
}
