//! The module generated for a GSDML file: identity constants, the default access point's
//! constants, and per module a module of its own holding per submodule its ident numbers, its
//! typed input and output images ([`image`]), their conversions to the Goodrive350's PKW/PZD
//! images when the overlay names the submodule ([`pkw_pzd`]), and its parameter records'
//! indexes, lengths and default bytes ([`records`]).
//!
//! PROFINET carries IO data big-endian; each image encodes to and decodes from its data bytes,
//! and with the provider status (IOPS) byte that follows the data in the frame. No object
//! dictionary is generated: a GSDML device has none.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::names::{ident, Case};
use super::plan::{code_span, doc_text, id};
use super::types::hex;
use edsgen_model::diag::Diagnostic;
use edsgen_model::model::{Profinet, Submodule, ValueList};

mod image;
mod pkw_pzd;
mod records;
mod value_enums;

/// The tokens of the whole generated module for a device with a PROFINET side.
pub(super) fn module(
    pn: &Profinet,
    module_doc: &[String],
    module_ident: &proc_macro2::Ident,
) -> Result<TokenStream, Vec<Diagnostic>> {
    let identity = identity(pn);
    let mut names = Vec::new();
    let mut modules = Vec::new();
    let access_point = pn
        .chosen
        .as_ref()
        .and_then(|c| c.access_point(pn))
        .or(pn.access_points.first());
    if let Some(dap) = access_point {
        let subs: Vec<TokenStream> = submodules(&dap.submodules, &pn.value_lists);
        let doc = match &pn.chosen {
            Some(_) => format!(
                " The chosen access point's own submodules ({}, slot 0).",
                code_span(&dap.id)
            ),
            None => " The default access point's own submodules (slot 0).".to_owned(),
        };
        modules.push(quote! {
            #[doc = #doc]
            pub mod access_point {
                #(#subs)*
            }
        });
    }
    let mut module_names = vec![None; pn.modules.len()];
    for (n, m) in pn.modules.iter().enumerate() {
        let name = unique(
            &mut names,
            ident(
                m.name.as_deref().unwrap_or(&m.id),
                Case::Snake,
                &format!("module_{n}"),
            ),
        );
        let ident_doc = format!(" {}'s ModuleIdentNumber.", code_span(&m.id));
        let module_ident_value = hex(
            u128::from(m.module_ident.as_ref().map_or(0, |v| v.value)),
            8,
        );
        let doc = format!(
            " Module {}{}.",
            code_span(&m.id),
            m.name
                .as_deref()
                .map(|n| format!(": {}", doc_text(n)))
                .unwrap_or_default()
        );
        let info = m
            .info_text
            .as_deref()
            .map(|t| format!(" {}", doc_text(t)))
            .into_iter();
        let subs = submodules(&m.submodules, &pn.value_lists);
        let slots = slot_constants(pn, &m.id);
        module_names[n] = Some(name.clone());
        let name = id(&name);
        modules.push(quote! {
            #[doc = #doc]
            #(#[doc = ""] #[doc = #info])*
            pub mod #name {
                #[doc = #ident_doc]
                pub const MODULE_IDENT: u32 = #module_ident_value;
                #slots
                #(#subs)*
            }
        });
    }
    let configuration = configuration(pn, &module_names);
    Ok(quote! {
        #(#[doc = #module_doc])*
        // A controller uses a few of the images: the rest is not dead code to warn about.
        #[allow(dead_code, clippy::approx_constant)]
        pub mod #module_ident {
            #identity
            /// An IOPS or IOCS byte saying "good" (DataState bit 7 set).
            pub const IOXS_GOOD: u8 = 0x80;
            /// An IOPS or IOCS byte saying "bad, by the subslot".
            pub const IOXS_BAD: u8 = 0x00;
            /// The modules: per module, its submodules' images and records.
            pub mod modules {
                #(#modules)*
            }
            #configuration
        }
    })
}

/// `pub mod configuration`: the chosen access point and the modules in their slots (the
/// overlay's `[modules]`), each slot a path to its module's generated images; nothing when no
/// configuration is chosen.
fn configuration(pn: &Profinet, names: &[Option<String>]) -> TokenStream {
    let Some(chosen) = &pn.chosen else {
        return TokenStream::new();
    };
    let Some(dap) = chosen.access_point(pn) else {
        return TokenStream::new();
    };
    let dap_id = Literal::string(&dap.id);
    let dap_ident = hex(
        u128::from(dap.module_ident.as_ref().map_or(0, |v| v.value)),
        8,
    );
    let mut slots = Vec::new();
    let mut uses = Vec::new();
    for plugged in &chosen.slots {
        let (Some(module), Some(Some(name))) =
            (pn.modules.get(plugged.module), names.get(plugged.module))
        else {
            continue;
        };
        let slot = Literal::u16_unsuffixed(plugged.slot);
        let ident = hex(
            u128::from(module.module_ident.as_ref().map_or(0, |v| v.value)),
            8,
        );
        let module_id = Literal::string(&module.id);
        slots.push(quote!((#slot, #ident, #module_id)));
        let alias = quote::format_ident!("slot_{}", plugged.slot);
        let target = id(name);
        let doc = format!(" Slot {}: module {}.", plugged.slot, code_span(&module.id));
        uses.push(quote!(#[doc = #doc] pub use super::modules::#target as #alias;));
    }
    let n_slots = Literal::usize_unsuffixed(slots.len());
    quote! {
        /// The configuration chosen in the overlay's `[modules]`: the access point and the
        /// modules in their slots.
        #[allow(unused_imports)]
        pub mod configuration {
            /// The access point's `ID`.
            pub const ACCESS_POINT: &str = #dap_id;
            /// The access point's ModuleIdentNumber (slot 0).
            pub const ACCESS_POINT_IDENT: u32 = #dap_ident;
            /// The modules: slot, ModuleIdentNumber and `ID`, in slot order.
            pub const SLOTS: [(u16, u32, &str); #n_slots] = [#(#slots),*];
            #(#uses)*
        }
    }
}

/// `name`, else `name_2`, `name_3`, ... when taken.
fn unique(taken: &mut Vec<String>, name: String) -> String {
    let mut candidate = name.clone();
    let mut n = 2;
    while taken.contains(&candidate) {
        candidate = format!("{name}_{n}");
        n += 1;
    }
    taken.push(candidate.clone());
    candidate
}

fn identity(pn: &Profinet) -> TokenStream {
    let vendor = hex(u128::from(pn.vendor_id.as_ref().map_or(0, |v| v.value)), 4);
    let device = hex(u128::from(pn.device_id.as_ref().map_or(0, |v| v.value)), 4);
    let mut items = vec![quote! {
        /// `DeviceIdentity/@VendorID`.
        pub const VENDOR_ID: u16 = #vendor;
        /// `DeviceIdentity/@DeviceID`.
        pub const DEVICE_ID: u16 = #device;
    }];
    if let Some(dap) = pn.access_points.first() {
        let ident = hex(
            u128::from(dap.module_ident.as_ref().map_or(0, |v| v.value)),
            8,
        );
        let doc = format!(
            " The default access point {}'s ModuleIdentNumber (slot 0).",
            code_span(&dap.id)
        );
        items.push(quote! {
            #[doc = #doc]
            pub const DAP_MODULE_IDENT: u32 = #ident;
        });
        if let Some(name) = &dap.dns_compatible_name {
            let name = Literal::string(name);
            items.push(quote! {
                /// `DNS_CompatibleName`: the default name of station.
                pub const DNS_COMPATIBLE_NAME: &str = #name;
            });
        }
        if let Some(n) = dap.min_device_interval {
            let n = Literal::u32_unsuffixed(n);
            items.push(quote! {
                /// `MinDeviceInterval`, in units of 31.25 µs.
                pub const MIN_DEVICE_INTERVAL: u32 = #n;
            });
        }
        for (name, value, doc) in [
            (
                "MAX_INPUT_LENGTH",
                &dap.max_input_length,
                " `IOConfigData/@MaxInputLength`: input bytes of all submodules, with IOPS and IOCS.",
            ),
            (
                "MAX_OUTPUT_LENGTH",
                &dap.max_output_length,
                " `IOConfigData/@MaxOutputLength`: output bytes of all submodules, with IOPS and IOCS.",
            ),
        ] {
            if let Some(v) = value {
                let name = id(name);
                let v = Literal::u32_unsuffixed(v.value);
                items.push(quote! {
                    #[doc = #doc]
                    pub const #name: u32 = #v;
                });
            }
        }
    }
    quote!(#(#items)*)
}

/// One module per submodule (`submodule_1`, ... by subslot) holding its images and records.
fn submodules(subs: &[Submodule], value_lists: &[ValueList]) -> Vec<TokenStream> {
    subs.iter()
        .map(|sub| {
            let name = id(&format!("subslot_{}", sub.subslot));
            let ident = hex(
                u128::from(sub.submodule_ident.as_ref().map_or(0, |v| v.value)),
                8,
            );
            let subslot = Literal::u16_unsuffixed(sub.subslot);
            let doc = format!(
                " Submodule {} in subslot {}{}.",
                code_span(&sub.id),
                sub.subslot,
                sub.name
                    .as_deref()
                    .map(|n| format!(": {}", doc_text(n)))
                    .unwrap_or_default()
            );
            let input = image::image(&sub.inputs, "Input", "data the device sends (input CR)");
            let output = image::image(
                &sub.outputs,
                "Output",
                "data the controller sends (output CR)",
            );
            let records = records::records(&sub.records, value_lists);
            let conversions = if sub.pkw_pzd {
                pkw_pzd::conversions()
            } else {
                TokenStream::new()
            };
            quote! {
                #[doc = #doc]
                pub mod #name {
                    /// `SubmoduleIdentNumber`.
                    pub const SUBMODULE_IDENT: u32 = #ident;
                    /// The subslot number.
                    pub const SUBSLOT: u16 = #subslot;
                    #input
                    #output
                    #conversions
                    #records
                }
            }
        })
        .collect()
}

/// The slots the default access point lets module `id` go in (`ModuleItemRef`), as constants;
/// nothing when it does not list the module.
fn slot_constants(pn: &Profinet, module_id: &str) -> TokenStream {
    let Some(reference) = pn.access_points.first().and_then(|dap| {
        dap.useable_modules
            .iter()
            .find(|r| r.target.value == module_id)
    }) else {
        return TokenStream::new();
    };
    let list = |slots: &[u16]| {
        let slots = slots.iter().map(|s| Literal::u16_unsuffixed(*s));
        quote!(&[#(#slots),*])
    };
    let (allowed, fixed, used) = (
        list(&reference.allowed_in_slots),
        list(&reference.fixed_in_slots),
        list(&reference.used_in_slots),
    );
    quote! {
        /// The slots the default access point allows the module in (`AllowedInSlots`, else
        /// `FixedInSlots`, else `UsedInSlots`).
        pub const ALLOWED_IN_SLOTS: &[u16] = #allowed;
        /// The slots the module is always in (`FixedInSlots`).
        pub const FIXED_IN_SLOTS: &[u16] = #fixed;
        /// The slots the module is in by default (`UsedInSlots`).
        pub const USED_IN_SLOTS: &[u16] = #used;
    }
}
