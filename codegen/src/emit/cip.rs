//! The module of an ODVA EDS (CIP): identity constants (the Identity object's attributes a
//! scanner's electronic key compares), one typed image per assembly with the image API (`SIZE`,
//! `from_bytes`, `to_bytes`, `from_slice`) over its bytes, and the connections of
//! `[Connection Manager]` as constants.
//!
//! CIP carries data little-endian and packs an assembly's members from bit 0 of byte 0, each
//! member's bits least significant first: the images follow that. Runs of equal members
//! (`8,Param1` written 32 times) become one array field. A member's default is its parameter's
//! default when the type holds it, else zero; a member whose parameter gives scaling has
//! `NAME_scaled()`, its engineering value. The module needs neither `std` nor `alloc`; of the
//! runtime it names only `PdoError` and the length check of `from_slice`.

use std::collections::BTreeMap;

use heck::ToUpperCamelCase;
use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::names::{ident, Case};
use super::plan::{code_span, doc_text, id};
use super::{types, Generated};
use edsgen_model::diag::Diagnostic;
use edsgen_model::model::{
    data_type_info, Cip, CipAssembly, CipNumber, CipParam, Device, FieldRef,
};

/// Generates the module of a device read from an ODVA EDS.
pub fn generate(device: &Device, cip: &Cip, module: &str) -> Result<Generated, Vec<Diagnostic>> {
    let identity = identity(cip);
    let assembly_names = assembly_type_names(cip);
    let enum_names = super::cip_enums::enum_names(cip, &assembly_names);
    let enums = super::cip_enums::enums(cip, &enum_names);
    let assemblies = assemblies(cip, &assembly_names, &enum_names);
    let connections = super::cip_connections::connections(cip);
    let module_ident = id(module);
    let module_doc = super::module_doc(device);
    let tokens = quote! {
        #(#[doc = #module_doc])*
        // A firmware uses a few of the images and connections: the rest is not dead code to warn
        // about, also where the module is included in a private module.
        #[allow(dead_code)]
        pub mod #module_ident {
            #identity
            #enums
            #assemblies
            #connections
        }
    };
    let code = super::format_tokens(tokens, device, &super::text::Splices::default())?;
    Ok(Generated {
        module: module.to_owned(),
        code,
        diagnostics: Vec::new(),
    })
}

fn identity(cip: &Cip) -> TokenStream {
    let id_ = &cip.identity;
    let v16 = |v: Option<u16>| types::hex(u128::from(v.unwrap_or(0)), 4);
    let vendor = v16(id_.vendor_code.as_ref().map(|v| v.value));
    let device_type = Literal::u16_unsuffixed(id_.product_type.as_ref().map_or(0, |v| v.value));
    let product = Literal::u16_unsuffixed(id_.product_code.as_ref().map_or(0, |v| v.value));
    let major = Literal::u8_unsuffixed(id_.major_revision.as_ref().map_or(0, |v| v.value));
    let minor = Literal::u8_unsuffixed(id_.minor_revision.as_ref().map_or(0, |v| v.value));
    let name = id_.product_name.clone().unwrap_or_default();
    let said = |given: bool, key: &str| {
        if given {
            format!("`[Device]` {key}")
        } else {
            format!("`[Device]` has no {key}; 0")
        }
    };
    let docs = [
        format!(
            " Vendor ID, Identity attribute 1 ({}).",
            said(id_.vendor_code.is_some(), "VendCode")
        ),
        format!(
            " Device type, Identity attribute 2 ({}).",
            said(id_.product_type.is_some(), "ProdType")
        ),
        format!(
            " Product code, Identity attribute 3 ({}).",
            said(id_.product_code.is_some(), "ProdCode")
        ),
        format!(
            " Major revision, Identity attribute 4 ({}).",
            said(id_.major_revision.is_some(), "MajRev")
        ),
        format!(
            " Minor revision, Identity attribute 4 ({}).",
            said(id_.minor_revision.is_some(), "MinRev")
        ),
    ];
    let [d0, d1, d2, d3, d4] = docs;
    quote! {
        #[doc = #d0]
        pub const VENDOR_ID: u16 = #vendor;
        #[doc = #d1]
        pub const DEVICE_TYPE: u16 = #device_type;
        #[doc = #d2]
        pub const PRODUCT_CODE: u16 = #product;
        #[doc = #d3]
        pub const MAJOR_REVISION: u8 = #major;
        #[doc = #d4]
        pub const MINOR_REVISION: u8 = #minor;
        /// Product name, Identity attribute 7 (`[Device]` ProdName).
        pub const PRODUCT_NAME: &str = #name;
    }
}

/// The Rust type of a member.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Ty {
    Bool,
    Unsigned(u8),
    Signed(u8),
    F32,
    F64,
    Bytes(usize),
}

impl Ty {
    fn tokens(self) -> TokenStream {
        match self {
            Ty::Bool => quote!(bool),
            Ty::Unsigned(w) => {
                let t = id(&format!("u{w}"));
                quote!(#t)
            }
            Ty::Signed(w) => {
                let t = id(&format!("i{w}"));
                quote!(#t)
            }
            Ty::F32 => quote!(f32),
            Ty::F64 => quote!(f64),
            Ty::Bytes(n) => quote!([u8; #n]),
        }
    }

    /// The raw bits as this type (`raw` is a `u64` expression).
    fn read_raw(self, raw: TokenStream) -> TokenStream {
        match self {
            Ty::Bool => quote!(#raw != 0),
            Ty::Unsigned(w) => {
                let t = id(&format!("u{w}"));
                quote!(#raw as #t)
            }
            Ty::Signed(w) => {
                let (u, i) = (id(&format!("u{w}")), id(&format!("i{w}")));
                quote!(#raw as #u as #i)
            }
            Ty::F32 => quote!(f32::from_bits(#raw as u32)),
            Ty::F64 => quote!(f64::from_bits(#raw)),
            Ty::Bytes(_) => quote!(#raw as u8),
        }
    }

    /// A value of this type as raw `u64` bits.
    fn to_raw(self, value: TokenStream) -> TokenStream {
        match self {
            Ty::Bool | Ty::Unsigned(_) => quote!(u64::from(#value)),
            Ty::Signed(w) => {
                let u = id(&format!("u{w}"));
                quote!(u64::from(#value as #u))
            }
            Ty::F32 => quote!(u64::from(#value.to_bits())),
            Ty::F64 => quote!(#value.to_bits()),
            Ty::Bytes(_) => quote!(u64::from(#value)),
        }
    }

    fn zero(self) -> TokenStream {
        match self {
            Ty::Bool => quote!(false),
            Ty::F32 | Ty::F64 => quote!(0.0),
            Ty::Bytes(n) => quote!([0; #n]),
            _ => quote!(0),
        }
    }

    /// A parameter's default as a literal of this type, if it holds it.
    fn literal(self, value: CipNumber) -> Option<TokenStream> {
        match (self, value) {
            (Ty::Bool, CipNumber::Int(v)) => {
                Some(if v != 0 { quote!(true) } else { quote!(false) })
            }
            (Ty::Unsigned(w), CipNumber::Int(v)) if v >= 0 && v < (1i128 << w) => {
                let v = Literal::u64_unsuffixed(u64::try_from(v).ok()?);
                Some(quote!(#v))
            }
            (Ty::Signed(w), CipNumber::Int(v))
                if v >= -(1i128 << (w - 1)) && v < (1i128 << (w - 1)) =>
            {
                let magnitude = Literal::u64_unsuffixed(u64::try_from(v.unsigned_abs()).ok()?);
                Some(if v < 0 {
                    quote!(-#magnitude)
                } else {
                    quote!(#magnitude)
                })
            }
            (Ty::F32 | Ty::F64, n) => {
                let v = Literal::f64_unsuffixed(n.as_f64());
                n.as_f64().is_finite().then(|| quote!(#v))
            }
            _ => None,
        }
    }
}

fn unsigned_for(bits: u32) -> Ty {
    match bits {
        0..=8 => Ty::Unsigned(8),
        9..=16 => Ty::Unsigned(16),
        17..=32 => Ty::Unsigned(32),
        _ => Ty::Unsigned(64),
    }
}

/// The type of a member of `bits` bits naming `param`.
fn member_type(bits: u32, param: Option<&CipParam>) -> Ty {
    if bits == 1 {
        return Ty::Bool;
    }
    let whole = param.and_then(|p| {
        let t = p.data_type.as_ref()?.value;
        let (_, size) = data_type_info(t)?;
        (size? * 8 == bits).then_some(t)
    });
    match whole {
        Some(0xC1) => Ty::Bool,
        Some(0xC2) => Ty::Signed(8),
        Some(0xC3) => Ty::Signed(16),
        Some(0xC4) => Ty::Signed(32),
        Some(0xC5) => Ty::Signed(64),
        Some(0xCA) => Ty::F32,
        Some(0xCB) => Ty::F64,
        _ if bits <= 64 => unsigned_for(bits),
        _ => Ty::Bytes(bits.div_ceil(8) as usize),
    }
}

/// One field of an image: a member, or a run of equal members as an array.
struct Slot {
    name: String,
    ty: Ty,
    bit: u64,
    bits: u32,
    count: usize,
    doc: String,
    default: Option<CipNumber>,
    /// The parameter's scaling (multiplier, divisor, base, offset), when the file gives any.
    scaling: Option<[i64; 4]>,
}

fn member_bits(cip: &Cip, bits: Option<u32>, member: &FieldRef) -> u32 {
    bits.or_else(|| match member {
        FieldRef::Param(n) => cip.params.get(n)?.data_size.as_ref().map(|s| s.value * 8),
        FieldRef::Assem(n) => cip
            .assemblies
            .get(n)
            .and_then(|a| cip.assembly_size(a))
            .and_then(|s| u32::try_from(s * 8).ok()),
        _ => None,
    })
    .unwrap_or(0)
}

/// The fields of an assembly's image and its size in bits; `enums` names the enumeration type
/// of each parameter that has one, for the field's documentation to link.
fn slots(cip: &Cip, assembly: &CipAssembly, enums: &BTreeMap<u32, String>) -> (Vec<Slot>, u64) {
    let mut slots: Vec<Slot> = Vec::new();
    let mut bit = 0u64;
    let mut names: Vec<String> = Vec::new();
    let mut previous: Option<(FieldRef, u32)> = None;
    for m in &assembly.members {
        let bits = member_bits(cip, m.bits, &m.member);
        let param = match &m.member {
            FieldRef::Param(n) => cip.params.get(n),
            _ => None,
        };
        let same = previous.as_ref() == Some(&(m.member.clone(), bits));
        previous = Some((m.member.clone(), bits));
        if m.member == FieldRef::Empty || bits == 0 {
            bit += u64::from(bits);
            continue;
        }
        let ty = member_type(bits, param);
        if let Some(last) = slots.last_mut() {
            let arrayable = bits.is_multiple_of(8) && !matches!(ty, Ty::Bytes(_));
            if same && arrayable && last.bit + u64::from(bits) * last.count as u64 == bit {
                last.count += 1;
                bit += u64::from(bits);
                continue;
            }
        }
        let (wanted, doc, default) = match (&m.member, param) {
            (FieldRef::Param(n), Some(p)) => {
                let mut doc = format!(" Param{n} {}", code_span(&p.name));
                if let Some(e) = enums.get(n) {
                    doc.push_str(&format!(" (values: [`{e}`])"));
                }
                if !p.units.is_empty() {
                    doc.push_str(&format!(", in {}", doc_text(&p.units)));
                }
                if p.scaling.iter().any(Option::is_some) {
                    let [mult, div, base, offset] = p.scaling;
                    doc.push_str(&format!(
                        " (scaling: multiplier {}, divisor {}, base {}, offset {})",
                        mult.unwrap_or(1),
                        div.unwrap_or(1),
                        base.unwrap_or(1),
                        offset.unwrap_or(0)
                    ));
                }
                (
                    ident(&p.name, Case::Snake, &format!("param_{n}")),
                    doc,
                    p.default.as_ref().map(|d| d.value),
                )
            }
            (FieldRef::Param(n), None) => (format!("param_{n}"), format!(" Param{n}"), None),
            (FieldRef::Assem(n), _) => (format!("assem_{n}"), format!(" Assem{n}"), None),
            (other, _) => {
                let text = match other {
                    FieldRef::Number(v) => v.to_string(),
                    FieldRef::Other(t) => t.clone(),
                    _ => String::new(),
                };
                ("member".to_owned(), format!(" {}", code_span(&text)), None)
            }
        };
        let mut name = wanted.clone();
        let mut k = 2;
        while names.contains(&name) {
            name = format!("{wanted}_{k}");
            k += 1;
        }
        names.push(name.clone());
        slots.push(Slot {
            name,
            ty,
            bit,
            bits,
            count: 1,
            doc,
            default,
            scaling: param
                .filter(|p| p.scaling.iter().any(Option::is_some))
                .map(|p| {
                    let [mult, div, base, offset] = p.scaling;
                    [
                        mult.unwrap_or(1),
                        div.unwrap_or(1),
                        base.unwrap_or(1),
                        offset.unwrap_or(0),
                    ]
                }),
        });
        bit += u64::from(bits);
    }
    (slots, bit)
}

/// The type name of each assembly's image, in `cip.assemblies`' order: its name in
/// UpperCamelCase, with its number appended on a clash (with another image, or a name the module
/// or the prelude uses).
fn assembly_type_names(cip: &Cip) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for assembly in cip.assemblies.values() {
        let wanted = ident(&assembly.name, Case::Snake, "assembly").to_upper_camel_case();
        let mut name = wanted.clone();
        if names.contains(&name) || super::cip_enums::reserved(&name) {
            name = format!("{wanted}{}", assembly.number);
        }
        names.push(name);
    }
    names
}

fn assemblies(cip: &Cip, names: &[String], enums: &BTreeMap<u32, String>) -> TokenStream {
    if cip.assemblies.is_empty() {
        return TokenStream::new();
    }
    let mut items = Vec::new();
    for (assembly, name) in cip.assemblies.values().zip(names) {
        let (slots, member_bits) = slots(cip, assembly, enums);
        let declared = assembly.size.as_ref().map_or(0, |s| u64::from(s.value));
        let size = declared.max(member_bits.div_ceil(8));
        let size_lit = Literal::usize_unsuffixed(usize::try_from(size).unwrap_or(0));
        let ty = id(name);
        let instance = Literal::u32_unsuffixed(assembly.instance());
        let doc = format!(
            " Assem{} {}: assembly instance {}, {size} bytes.",
            assembly.number,
            code_span(&assembly.name),
            assembly.instance()
        );
        let mut fields = Vec::new();
        let mut gets = Vec::new();
        let mut puts = Vec::new();
        let mut defaults = Vec::new();
        let mut scaled = Vec::new();
        for s in &slots {
            let field = id(&s.name);
            let t = s.ty.tokens();
            let bit = Literal::u64_unsuffixed(s.bit);
            let bits = Literal::u32_unsuffixed(s.bits);
            let fdoc = format!(
                "{}: bit {} of the image, {} bit{}{}.",
                s.doc,
                s.bit,
                s.bits,
                if s.bits == 1 { "" } else { "s" },
                if s.count > 1 {
                    format!(" each, {} times", s.count)
                } else {
                    String::new()
                }
            );
            let value = s
                .default
                .and_then(|d| s.ty.literal(d))
                .unwrap_or_else(|| s.ty.zero());
            if s.count > 1 {
                let count = Literal::usize_unsuffixed(s.count);
                fields.push(quote!(#[doc = #fdoc] pub #field: [#t; #count],));
                let read = s.ty.read_raw(quote!(get(buf, #bit + i * #bits, #bits)));
                gets.push(quote!(#field: core::array::from_fn(|i| #read),));
                let write = s.ty.to_raw(quote!(*v));
                puts.push(quote! {
                    for (i, v) in self.#field.iter().enumerate() {
                        put(&mut buf, #bit + i * #bits, #bits, #write);
                    }
                });
                defaults.push(quote!(#field: [#value; #count],));
            } else if let Ty::Bytes(_) = s.ty {
                fields.push(quote!(#[doc = #fdoc] pub #field: #t,));
                gets.push(
                    quote!(#field: core::array::from_fn(|i| get(buf, #bit + i * 8, 8) as u8),),
                );
                puts.push(quote! {
                    for (i, v) in self.#field.iter().enumerate() {
                        put(&mut buf, #bit + i * 8, 8, u64::from(*v));
                    }
                });
                defaults.push(quote!(#field: #value,));
            } else {
                fields.push(quote!(#[doc = #fdoc] pub #field: #t,));
                let read = s.ty.read_raw(quote!(get(buf, #bit, #bits)));
                gets.push(quote!(#field: #read,));
                let write = s.ty.to_raw(quote!(self.#field));
                puts.push(quote!(put(&mut buf, #bit, #bits, #write);));
                defaults.push(quote!(#field: #value,));
            }
        }
        let (bytes_in, to_bytes_body) = if slots.is_empty() {
            (quote!(_bytes), quote!([0u8; #size_lit]))
        } else {
            (
                quote!(buf),
                quote! {
                    let mut buf = [0u8; #size_lit];
                    #(#puts)*
                    buf
                },
            )
        };
        let size_and_from_slice = super::image_api::size_and_from_slice(
            usize::try_from(size).unwrap_or(0),
            "The size in bytes.",
        );
        for s in &slots {
            scaled.extend(scaled_getter(s));
        }
        let scaled_impl = (!scaled.is_empty()).then(|| quote!(impl #ty { #(#scaled)* }));
        items.push(super::cip_pkw_pzd::conversions(cip, assembly.number, &ty));
        items.push(quote! {
            #[doc = #doc]
            #[derive(Debug, Clone, Copy, PartialEq)]
            pub struct #ty {
                #(#fields)*
            }

            impl #ty {
                /// The Assembly object instance (connection point).
                pub const INSTANCE: u32 = #instance;
                #size_and_from_slice

                /// Reads the image from the assembly's bytes.
                pub fn from_bytes(#bytes_in: &[u8; #size_lit]) -> Self {
                    Self { #(#gets)* }
                }

                /// The assembly's bytes (members not named here are zero).
                pub fn to_bytes(self) -> [u8; #size_lit] {
                    #to_bytes_body
                }
            }

            impl Default for #ty {
                /// The parameters' defaults, where the file gives them.
                fn default() -> Self {
                    Self { #(#defaults)* }
                }
            }
        });
        items.push(quote!(#scaled_impl));
    }
    quote! {
        /// Bits `at..at + len` of `buf`, least significant first (CIP's order); bits past the
        /// end read as zero.
        fn get(buf: &[u8], at: usize, len: u32) -> u64 {
            let mut value = 0u64;
            for i in 0..len as usize {
                let bit = at + i;
                if let Some(byte) = buf.get(bit / 8) {
                    if (byte >> (bit % 8)) & 1 != 0 {
                        value |= 1u64 << i;
                    }
                }
            }
            value
        }

        /// Writes the low `len` bits of `value` at bit `at` of `buf`, least significant first.
        fn put(buf: &mut [u8], at: usize, len: u32, value: u64) {
            for i in 0..len as usize {
                let bit = at + i;
                if let Some(byte) = buf.get_mut(bit / 8) {
                    if (value >> i) & 1 != 0 {
                        *byte |= 1 << (bit % 8);
                    } else {
                        *byte &= !(1 << (bit % 8));
                    }
                }
            }
        }

        #(#items)*
    }
}

/// `NAME_scaled()`, the engineering value of a numeric member whose parameter gives scaling:
/// `(value + offset) * multiplier * base / divisor`, CIP's Parameter object formula.
fn scaled_getter(s: &Slot) -> Option<TokenStream> {
    let [mult, div, base, offset] = s.scaling?;
    if s.count != 1 || div == 0 {
        return None;
    }
    let field = id(&s.name);
    let raw = match s.ty {
        Ty::Unsigned(64) | Ty::Signed(64) => quote!(self.#field as f64),
        Ty::Unsigned(_) | Ty::Signed(_) | Ty::F32 => quote!(f64::from(self.#field)),
        Ty::F64 => quote!(self.#field),
        Ty::Bool | Ty::Bytes(_) => return None,
    };
    let name = id(&format!("{}_scaled", s.name));
    // The formula without its identity terms (`+ 0`, `* 1`): what the file's numbers do.
    let mut text = "raw".to_owned();
    let mut value = raw;
    // A negative number as `-magnitude` (a literal token is never negative).
    let number = |v: i64| {
        let magnitude = Literal::f64_unsuffixed(v.unsigned_abs() as f64);
        if v < 0 {
            quote!(-#magnitude)
        } else {
            quote!(#magnitude)
        }
    };
    if offset != 0 {
        let o = number(offset);
        text = format!("(raw + {offset})");
        value = quote!((#value + #o));
    }
    for (factor, v) in [("*", mult), ("*", base), ("/", div)] {
        if v != 1 {
            let n = number(v);
            text = format!("{text} {factor} {v}");
            value = if factor == "*" {
                quote!(#value * #n)
            } else {
                quote!(#value / #n)
            };
        }
    }
    if text == "raw" {
        return None;
    }
    let doc = format!(
        " The engineering value of `{}`: `{text}`, its parameter's scaling.",
        s.name
    );
    Some(quote! {
        #[doc = #doc]
        pub fn #name(self) -> f64 {
            #value
        }
    })
}
