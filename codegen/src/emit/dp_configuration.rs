//! The chosen configuration of a modular DP slave (the overlay's `[modules]`), generated as
//! `configuration`: its Chk_Cfg bytes (every module's in slot order), its slots, and the slave's
//! whole input and output images, one field per slot holding that module's image (a module
//! without data in a direction has no field there), with the image API every bus shares.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use super::plan::{doc_text, id};
use super::types::hex;
use edsgen_model::model::Dp;

/// One slot's part of an image: its field, the module's generated name, its size.
struct Part {
    field: Ident,
    module: Ident,
    size: usize,
    doc: String,
}

/// `pub mod configuration { ... }`, or nothing when no configuration is chosen. `names[n]` is
/// the generated module name of `dp.modules[n]` (`None` for one not generated).
pub(super) fn configuration(dp: &Dp, names: &[Option<String>]) -> TokenStream {
    let Some(chosen) = &dp.chosen else {
        return TokenStream::new();
    };
    let config: Vec<_> = chosen
        .config_bytes(dp)
        .iter()
        .map(|b| hex(u128::from(*b), 2))
        .collect();
    let n_config = Literal::usize_unsuffixed(config.len());
    let mut slots = Vec::new();
    let mut inputs = Vec::new();
    let mut outputs = Vec::new();
    for plugged in &chosen.slots {
        let (slot, index) = (plugged.slot, plugged.module);
        let (Some(module), Some(Some(name))) = (dp.modules.get(index), names.get(index)) else {
            continue;
        };
        let slot_number = Literal::u32_unsuffixed(slot);
        let module_name = Literal::string(&module.name);
        slots.push(quote!((#slot_number, #module_name)));
        let (input_len, output_len) = module.io_lengths();
        let doc = format!(" Slot {slot}: module \"{}\".", doc_text(module.name.trim()));
        for (parts, size) in [(&mut inputs, input_len), (&mut outputs, output_len)] {
            if size > 0 {
                parts.push(Part {
                    field: format_ident!("slot_{slot}"),
                    module: id(name),
                    size: size as usize,
                    doc: doc.clone(),
                });
            }
        }
    }
    let n_slots = Literal::usize_unsuffixed(slots.len());
    let inputs = image(
        "Inputs",
        "The slave's inputs (slave to master), every module's in slot order",
        &inputs,
    );
    let outputs = image(
        "Outputs",
        "The slave's outputs (master to slave), every module's in slot order",
        &outputs,
    );
    quote! {
        /// The configuration chosen in the overlay's `[modules]`: the modules in slot order.
        pub mod configuration {
            /// The configuration bytes a master sends in Chk_Cfg: every module's, in slot order.
            pub const CONFIG: [u8; #n_config] = [#(#config),*];
            /// The slots and their modules' names, in slot order.
            pub const SLOTS: [(u32, &str); #n_slots] = [#(#slots),*];
            #inputs
            #outputs
        }
    }
}

/// The whole image of one direction: the slots' images one after the other.
fn image(name: &str, doc: &str, parts: &[Part]) -> TokenStream {
    let ty = format_ident!("{name}");
    let total: usize = parts.iter().map(|p| p.size).sum();
    let mut decls = Vec::new();
    let mut zero = Vec::new();
    let mut reads = Vec::new();
    let mut writes = Vec::new();
    let mut offset = 0usize;
    for part in parts {
        let (field, module, doc) = (&part.field, &part.module, &part.doc);
        let at = Literal::usize_unsuffixed(offset);
        let end = Literal::usize_unsuffixed(offset + part.size);
        let ty = quote!(super::modules::#module::#ty);
        decls.push(quote!(#[doc = #doc] pub #field: #ty,));
        zero.push(quote!(#field: #ty::ZERO,));
        let byte = if offset == 0 {
            quote!(bytes[i])
        } else {
            quote!(bytes[#at + i])
        };
        reads.push(quote!(#field: #ty::from_bytes(&::core::array::from_fn(|i| #byte)),));
        writes.push(quote!(bytes[#at..#end].copy_from_slice(&self.#field.to_bytes());));
        offset += part.size;
    }
    super::dp::image_struct(
        &ty,
        doc,
        total,
        super::dp::Fields {
            decls,
            zero,
            reads,
            writes,
        },
    )
}
