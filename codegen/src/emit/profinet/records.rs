//! One module per parameter record (`record_125`): its index, its length, its default bytes
//! (the `Const` bytes, then each `Ref`'s `DefaultValue`, big-endian), each field's offset, and
//! an enum per field that names a `ValueItem` (`value_enums`).

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
        let fields = record.fields.iter().enumerate().map(|(n, f)| {
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
            let values = super::value_enums::value_enum(f, value_lists, &mut enums);
            quote! {
                #[doc = #doc]
                pub const #name: usize = #offset;
                #values
            }
        });
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
            }
        });
    }
    quote!(#(#out)*)
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
