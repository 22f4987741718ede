//! The tokens of CiA 301 data types: each entry's Rust type, its default value and limits, and
//! its descriptor's data type and access. Which primitive holds each basic type, and the values
//! as numbers, are `model::layout`'s (re-exported here). Strings, octet strings and domains are
//! `FixedBytes<N>` (see [`capacity`](edsgen_model::model::layout::capacity) for `N`).

use proc_macro2::{Literal, TokenStream};
use quote::quote;

pub use edsgen_model::model::layout::{
    node_relative_offset, normalise_integer, scalar_number, Number, Prim, RustType, ValueProblem,
};
use edsgen_model::model::{AccessType, BasicType};

/// The tokens of a type: a primitive's name (`u16`), or `FixedBytes<N>`.
pub trait TypeTokens {
    /// The type's tokens.
    fn tokens(self) -> TokenStream;
}

impl TypeTokens for Prim {
    /// The type's tokens (`u16`).
    fn tokens(self) -> TokenStream {
        let name = proc_macro2::Ident::new(self.name(), proc_macro2::Span::call_site());
        quote!(#name)
    }
}

impl TypeTokens for RustType {
    /// The type's tokens.
    fn tokens(self) -> TokenStream {
        match self {
            RustType::Scalar(p, _) => p.tokens(),
            RustType::Bytes(n) => {
                let n = Literal::usize_unsuffixed(n);
                quote!(::edsgen_runtime::FixedBytes<#n>)
            }
        }
    }
}

/// The tokens of a constant number.
pub trait NumberTokens {
    /// The number as a literal of `prim`'s kind: an integer for a `u64`/`i64` parameter, a REAL
    /// for an `f32`/`f64` one.
    fn tokens(self, prim: Prim) -> TokenStream;
}

impl NumberTokens for Number {
    fn tokens(self, prim: Prim) -> TokenStream {
        match self {
            Number::Integer(v) if v < 0 => {
                let magnitude = Literal::u128_unsuffixed(v.unsigned_abs());
                quote!(-#magnitude)
            }
            Number::Integer(v) if v >= 256 => hex(v as u128, 1),
            Number::Integer(v) => Literal::u128_unsuffixed(v as u128).into_token_stream(),
            Number::Real(f) => {
                let ty = prim.tokens();
                if f.is_nan() {
                    return quote!(#ty::NAN);
                }
                if f.is_infinite() {
                    return if f > 0.0 {
                        quote!(#ty::INFINITY)
                    } else {
                        quote!(#ty::NEG_INFINITY)
                    };
                }
                let magnitude = if prim == Prim::F32 {
                    Literal::f32_unsuffixed(f.abs() as f32)
                } else {
                    Literal::f64_unsuffixed(f.abs())
                };
                if f.is_sign_negative() {
                    quote!(-#magnitude)
                } else {
                    magnitude.into_token_stream()
                }
            }
        }
    }
}

/// The runtime `DataType` variant of a basic type (written `D::Variant` in the table).
pub fn data_type_variant(basic: BasicType) -> &'static str {
    use BasicType as B;
    match basic {
        B::Boolean => "Boolean",
        B::Integer8 => "Integer8",
        B::Integer16 => "Integer16",
        B::Integer24 => "Integer24",
        B::Integer32 => "Integer32",
        B::Integer40 => "Integer40",
        B::Integer48 => "Integer48",
        B::Integer56 => "Integer56",
        B::Integer64 => "Integer64",
        B::Unsigned8 => "Unsigned8",
        B::Unsigned16 => "Unsigned16",
        B::Unsigned24 => "Unsigned24",
        B::Unsigned32 => "Unsigned32",
        B::Unsigned40 => "Unsigned40",
        B::Unsigned48 => "Unsigned48",
        B::Unsigned56 => "Unsigned56",
        B::Unsigned64 => "Unsigned64",
        B::Real32 => "Real32",
        B::Real64 => "Real64",
        B::VisibleString => "VisibleString",
        B::OctetString => "OctetString",
        B::UnicodeString => "UnicodeString",
        B::TimeOfDay => "TimeOfDay",
        B::TimeDifference => "TimeDifference",
        B::Domain => "Domain",
    }
}

/// The runtime `Access` variant (written `A::Variant` in the table).
pub fn access_variant(access: AccessType) -> &'static str {
    match access {
        AccessType::Ro => "Ro",
        AccessType::Wo => "Wo",
        AccessType::Rw => "Rw",
        AccessType::Rwr => "Rwr",
        AccessType::Rww => "Rww",
        AccessType::Const => "Const",
    }
}

/// The derives of a generated PDO or process-image struct: `Eq` only when no field is a float,
/// `Default` only when every field has one.
pub fn pdo_derives(eq: bool, default: bool) -> Vec<TokenStream> {
    let mut derives = vec![
        quote!(Debug),
        quote!(Clone),
        quote!(Copy),
        quote!(PartialEq),
    ];
    if eq {
        derives.push(quote!(Eq));
    }
    if default {
        derives.push(quote!(Default));
    }
    derives
}

/// A hexadecimal literal of at least `digits` digits (`0x0180`).
pub fn hex(value: u128, digits: usize) -> TokenStream {
    syn::LitInt::new(
        &format!("0x{value:0digits$X}"),
        proc_macro2::Span::call_site(),
    )
    .into_token_stream()
}

/// An integer literal: hexadecimal from 256 up for unsigned types, decimal otherwise.
pub fn int_literal(value: i128, prim: Prim) -> TokenStream {
    if value < 0 {
        let magnitude = Literal::u128_unsuffixed(value.unsigned_abs());
        return quote!(-#magnitude);
    }
    if matches!(prim, Prim::Unsigned(_)) && value >= 256 {
        return hex(value as u128, 1);
    }
    Literal::u128_unsuffixed(value as u128).into_token_stream()
}

use quote::ToTokens;
