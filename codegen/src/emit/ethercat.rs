//! Tokens for the EtherCAT side of a device read from an ESI file: the `ethercat` module with the
//! identity, SyncManager, DC and CoE constants, one struct per `RxPdo`/`TxPdo`, and one per
//! SyncManager's default process image (the PDOs assigned to it, concatenated as the master sees
//! them).
//!
//! Every struct implements `edsgen_runtime::ethercat::ProcessData`: bit-exact, any length, fields
//! of any width at any bit offset, least significant bit first and little-endian as EtherCAT lays
//! them out, through the runtime's `put_bits`/`get_bits`. Padding entries (index 0) take their bits
//! but no field. A field's type is its dictionary entry's; an entry the dictionary does not hold
//! is typed by its `DataType` and bit length.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::names::{ident, Case, Namespace};
use super::plan::{doc_text, id, Plan};
use super::types::{hex, Prim, RustType};
use crate::model::{EcPdo, EtherCat, SmKind};

/// What a field holds.
#[derive(Clone, Copy)]
enum FieldType {
    /// A scalar; narrower mappings are range-checked on write and sign-extended on read.
    Scalar(Prim),
    /// Bytes, least significant first (strings and anything wider than 64 bits).
    Bytes(usize),
}

struct Field {
    name: String,
    ty: FieldType,
    offset: u32,
    bits: u32,
    doc: String,
}

struct PdoPlan {
    name: String,
    fields: Vec<Field>,
    bits: u32,
    doc: Vec<String>,
    /// A field is narrower than its Rust type: writing can fail.
    fallible: bool,
    eq: bool,
    default: bool,
}

/// The `ethercat` module for a device with an EtherCAT side.
pub fn module(ec: &EtherCat, plan: &Plan) -> TokenStream {
    let constants = constants(ec);
    let mut items = Vec::new();
    let mut planned = Vec::new();
    for (pdo, rx) in ec
        .rx_pdos
        .iter()
        .map(|p| (p, true))
        .chain(ec.tx_pdos.iter().map(|p| (p, false)))
    {
        let p = plan_pdo(pdo, rx, plan);
        items.push(emit_struct(&p, &pdo_methods(&p)));
        planned.push((pdo, rx, p));
    }
    items.extend(images(ec, &planned));
    quote! {
        /// The EtherCAT side of the device: identity, SyncManagers, distributed-clock modes, the
        /// CoE mailbox, one struct per PDO and one per SyncManager's default process image.
        pub mod ethercat {
            #constants
            #(#items)*
        }
    }
}

fn constants(ec: &EtherCat) -> TokenStream {
    let rt = quote!(::edsgen_runtime::ethercat);
    let type_name = Literal::string(&ec.type_name);
    let type_doc = format!(
        " The device's type name in the ESI file (`{}`).",
        doc_text(&ec.type_name).replace('`', "'")
    );
    let profiles: Vec<_> = ec
        .profiles
        .iter()
        .map(|p| Literal::u32_unsuffixed(*p))
        .collect();
    let n_profiles = Literal::usize_unsuffixed(profiles.len());
    let mut sms = Vec::new();
    let mut sm_names = Vec::new();
    for (n, sm) in ec.sync_managers.iter().enumerate() {
        let (kind, what) = match &sm.kind {
            SmKind::MailboxOut => (
                quote!(MailboxOut),
                "mailbox out (master to device)".to_owned(),
            ),
            SmKind::MailboxIn => (
                quote!(MailboxIn),
                "mailbox in (device to master)".to_owned(),
            ),
            SmKind::Outputs => (quote!(Outputs), "process data outputs".to_owned()),
            SmKind::Inputs => (quote!(Inputs), "process data inputs".to_owned()),
            SmKind::Other(text) => (
                quote!(Other),
                format!("`{}`", doc_text(text).replace('`', "'")),
            ),
        };
        let size = sm.default_size.unwrap_or(0);
        let doc = match sm.default_size {
            Some(size) => format!(" SM{n}: {what}, {size} bytes at {:04X}h.", sm.start_address),
            None => format!(
                " SM{n}: {what} at {:04X}h, size set by the master.",
                sm.start_address
            ),
        };
        let name = id(&format!("SM{n}"));
        let start = hex(u128::from(sm.start_address), 4);
        let size = Literal::u16_unsuffixed(size);
        let control = hex(u128::from(sm.control_byte), 2);
        let enable = sm.enable;
        sms.push(quote! {
            #[doc = #doc]
            pub const #name: #rt::SyncManager = #rt::SyncManager {
                kind: #rt::SmKind::#kind,
                start_address: #start,
                default_size: #size,
                control_byte: #control,
                enable: #enable,
            };
        });
        sm_names.push(name);
    }
    let n_sms = Literal::usize_unsuffixed(sm_names.len());
    let op_modes: Vec<_> = ec
        .op_modes
        .iter()
        .map(|m| {
            let name = Literal::string(&m.name);
            let desc = Literal::string(&m.description);
            let assign = hex(u128::from(m.assign_activate), 4);
            let cycle = Literal::u32_unsuffixed(m.cycle_time_sync0);
            quote! {
                #rt::OpMode {
                    name: #name,
                    description: #desc,
                    assign_activate: #assign,
                    cycle_time_sync0: #cycle,
                }
            }
        })
        .collect();
    let n_op_modes = Literal::usize_unsuffixed(op_modes.len());
    let coe = ec.coe.as_ref().map(|c| {
        let (info, assign, config, complete, segmented) = (
            c.sdo_info,
            c.pdo_assign,
            c.pdo_config,
            c.complete_access,
            c.segmented_sdo,
        );
        quote! {
            /// The CoE mailbox's services.
            pub const COE: #rt::Coe = #rt::Coe {
                sdo_info: #info,
                pdo_assign: #assign,
                pdo_config: #config,
                complete_access: #complete,
                segmented_sdo: #segmented,
            };
        }
    });
    quote! {
        /// The identity a SubDevice reports (vendor ID, product code, revision): compare a
        /// discovered device with it.
        pub const IDENTITY: #rt::Identity = #rt::Identity {
            vendor_id: super::VENDOR_ID,
            product_code: super::PRODUCT_CODE,
            revision: super::REVISION_NUMBER,
        };
        #[doc = #type_doc]
        pub const TYPE_NAME: &str = #type_name;
        /// The device profiles (`ProfileNo`: 402 for a drive, 5001 for a modular device).
        pub const PROFILES: [u32; #n_profiles] = [#(#profiles),*];
        #(#sms)*
        /// The SyncManagers in order.
        pub const SYNC_MANAGERS: [#rt::SyncManager; #n_sms] = [#(#sm_names),*];
        /// The distributed-clock operation modes.
        pub const OP_MODES: [#rt::OpMode; #n_op_modes] = [#(#op_modes),*];
        #coe
    }
}

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

fn plan_pdo(pdo: &EcPdo, rx: bool, plan: &Plan) -> PdoPlan {
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
            Some(e) => e.title.trim().to_owned(),
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
            " {} {:04X}h `{}`: {offset} bits ({} bytes){assigned}.",
            if rx {
                "RxPDO (outputs)"
            } else {
                "TxPDO (inputs)"
            },
            pdo.index,
            doc_text(pdo.name.trim()).replace('`', "'"),
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
fn at_plus(offset: u32) -> TokenStream {
    if offset == 0 {
        quote!(at)
    } else {
        let off = Literal::usize_unsuffixed(offset as usize);
        quote!(at + #off)
    }
}

/// The private `put`, `get` and (for narrow fields) `check` of one PDO struct.
fn pdo_methods(p: &PdoPlan) -> TokenStream {
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

/// One struct with its fields' declarations, `LEN`, `encode`/`decode`, and `ProcessData`.
fn emit_struct(p: &PdoPlan, methods: &TokenStream) -> TokenStream {
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

/// The struct, its inherent `LEN`, `encode`, `decode` and private methods, its `ProcessData`
/// implementation and the ethercrab-wire hook: shared by PDOs and process images.
#[allow(clippy::too_many_arguments)]
fn emit_item(
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
    let len = Literal::usize_unsuffixed(bits.div_ceil(8) as usize);
    let bits = Literal::usize_unsuffixed(bits as usize);
    let doc_attrs = doc.iter().map(|l| quote!(#[doc = #l]));
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
    let (encode, check) = if fallible {
        (
            quote! {
                /// The bytes, bit-exact (least significant bit first, little-endian); an error if
                /// a field does not fit its mapped bits.
                pub fn encode(&self) -> Result<[u8; #len], ::edsgen_runtime::PdoError> {
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
                pub fn encode(&self) -> [u8; #len] {
                    let mut bytes = [0u8; #len];
                    self.put(&mut bytes, 0);
                    bytes
                }
            },
            TokenStream::new(),
        )
    };
    quote! {
        #(#doc_attrs)*
        #[derive(#(#derives),*)]
        pub struct #name {
            #fields
        }

        impl #name {
            /// The length in bytes.
            pub const LEN: usize = #len;

            #encode

            /// The fields of exactly [`Self::LEN`] bytes.
            pub fn decode(bytes: &[u8]) -> Result<Self, ::edsgen_runtime::PdoError> {
                let bytes = ::edsgen_runtime::support::payload::<#len>(bytes)?;
                Ok(Self::get(&bytes, 0))
            }

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

/// One struct per SyncManager with PDOs assigned by default: `Outputs` / `Inputs` (or
/// `Sm2Outputs`, ... when several SyncManagers of one direction have PDOs). A PDO that excludes,
/// or is excluded by, one already assigned to the same SyncManager is left out.
fn images(ec: &EtherCat, planned: &[(&EcPdo, bool, PdoPlan)]) -> Vec<TokenStream> {
    let mut out = Vec::new();
    for rx in [true, false] {
        let mut sms: Vec<u8> = planned
            .iter()
            .filter(|(_, r, _)| *r == rx)
            .filter_map(|(pdo, _, _)| pdo.sm)
            .collect();
        sms.sort_unstable();
        sms.dedup();
        let word = if rx { "Outputs" } else { "Inputs" };
        for &sm in &sms {
            let mut members: Vec<&(&EcPdo, bool, PdoPlan)> = Vec::new();
            let mut left_out = Vec::new();
            for item in planned
                .iter()
                .filter(|(p, r, _)| *r == rx && p.sm == Some(sm))
            {
                let clash = members.iter().any(|(m, _, _)| {
                    m.exclude.iter().any(|x| x.value == item.0.index)
                        || item.0.exclude.iter().any(|x| x.value == m.index)
                });
                if clash {
                    left_out.push(item.0.index);
                } else {
                    members.push(item);
                }
            }
            let name = if sms.len() == 1 {
                word.to_owned()
            } else {
                format!("Sm{sm}{word}")
            };
            let kind = ec
                .sync_managers
                .get(usize::from(sm))
                .map_or("not described", |s| match s.kind {
                    SmKind::Outputs => "outputs",
                    SmKind::Inputs => "inputs",
                    SmKind::MailboxOut | SmKind::MailboxIn => "a mailbox",
                    SmKind::Other(_) => "other",
                });
            out.push(emit_image(&name, sm, kind, word, &members, &left_out));
        }
    }
    out
}

fn emit_image(
    name: &str,
    sm: u8,
    kind: &str,
    word: &str,
    members: &[&(&EcPdo, bool, PdoPlan)],
    left_out: &[u16],
) -> TokenStream {
    let mut fields = Vec::new();
    let mut puts = Vec::new();
    let mut gets = Vec::new();
    let mut checks = Vec::new();
    let mut layout = Vec::new();
    let mut offset = 0u32;
    for (pdo, _, p) in members {
        let field_name = format!(
            "{}_pdo_{:04x}",
            if p.name.starts_with("Rx") { "rx" } else { "tx" },
            pdo.index
        );
        let field = id(&field_name);
        let ty = id(&p.name);
        let at = at_plus(offset);
        let doc = format!(
            " {} {:04X}h: bits {offset} to {} of the image.",
            if p.name.starts_with("Rx") {
                "RxPDO"
            } else {
                "TxPDO"
            },
            pdo.index,
            (offset + p.bits).max(1) - 1
        );
        layout.push(format!(
            " - bits {offset} to {}: [`{}`]",
            (offset + p.bits).max(1) - 1,
            p.name
        ));
        fields.push(quote!(#[doc = #doc] pub #field: #ty,));
        puts.push(quote!(self.#field.put(buf, #at);));
        gets.push(quote!(#field: #ty::get(buf, #at),));
        if p.fallible {
            checks.push(quote!(self.#field.check()?;));
        }
        offset += p.bits;
    }
    let fallible = !checks.is_empty();
    let mut doc = vec![
        format!(
            " SM{sm} ({kind}): the {} image of the default PDO assignment, {offset} bits ({} bytes).",
            word.to_lowercase(),
            offset.div_ceil(8)
        ),
        String::new(),
    ];
    doc.extend(layout);
    if !left_out.is_empty() {
        let list: Vec<String> = left_out.iter().map(|i| format!("{i:04X}h")).collect();
        doc.push(String::new());
        doc.push(format!(
            " Also marked for SM{sm} but excluded by a PDO above: {}.",
            list.join(", ")
        ));
    }
    let check = if fallible {
        quote! {
            /// `OutOfRange` if a field of a PDO does not fit its mapped bits.
            fn check(&self) -> Result<(), ::edsgen_runtime::PdoError> {
                #(#checks)*
                Ok(())
            }
        }
    } else {
        TokenStream::new()
    };
    let (buf, at) = if members.is_empty() {
        (quote!(_buf), quote!(_at))
    } else {
        (quote!(buf), quote!(at))
    };
    let methods = quote! {
        /// Writes every PDO from bit `at`.
        fn put(&self, #buf: &mut [u8], #at: usize) {
            #(#puts)*
        }

        /// Reads every PDO from bit `at`.
        fn get(#buf: &[u8], #at: usize) -> Self {
            Self { #(#gets)* }
        }

        #check
    };
    let eq = members.iter().all(|(_, _, p)| p.eq);
    let default = members.iter().all(|(_, _, p)| p.default);
    emit_item(
        name,
        &doc,
        quote!(#(#fields)*),
        offset,
        fallible,
        eq,
        default,
        &methods,
    )
}
