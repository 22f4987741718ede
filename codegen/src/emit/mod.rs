//! The emitter: a device model to one formatted, deterministic Rust module.
//!
//! `quote!` builds the tokens, `prettyplease` formats them. The module holds the identity and PDO
//! count constants, the `Od` struct with `Od::new(node_id)` and its `ObjectDictionary`
//! implementation over the sorted `ENTRIES` table ([`od`]), typed addresses (`od::NAME`), and
//! typed PDOs (`pdo::RpdoN`, `pdo::TpdoN`, [`pdo`]). Names come from [`names`], types and values
//! from [`types`]; [`plan`] decides both, in (index, sub-index) order. Generated code uses absolute
//! paths only, needs neither `std` nor `alloc`, and holds no `unsafe`, `static mut` or `unwrap`.

pub mod cip;
mod cip_connections;
mod cip_enums;
mod cip_pkw_pzd;
pub mod dp;
mod dp_configuration;
pub mod ethercat;
mod image_api;
pub mod names;
pub mod od;
pub mod pdo;
pub mod plan;
mod profinet;
pub mod text;
pub mod types;

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use edsgen_model::diag::{Diagnostic, Severity};
use edsgen_model::model::{Bus, Device, Format, Value};

/// Generated code and what the emitter said about the device.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The module name used (snake case).
    pub module: String,
    /// The formatted Rust source: one `pub mod NAME { ... }` item.
    pub code: String,
    /// `EDS7xx` warnings and infos (no errors: those fail generation).
    pub diagnostics: Vec<Diagnostic>,
}

/// The module name for a requested name or file stem: snake case, a valid identifier.
pub fn module_name(requested: &str) -> String {
    names::ident(requested, names::Case::Snake, "device")
}

/// Whether the emitter reports infos beside its warnings and errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Infos {
    /// Infos too: EDS705 for every entry without a default value, and the others.
    Reported,
    /// None, for a caller that shows none (the build script, `edsgen generate`): a file without
    /// defaults has thousands, not worth making unseen.
    Skipped,
}

/// Generates the module for one device. On an `EDS7xx` error, returns every diagnostic the
/// emitter found (errors included) and no code.
pub fn generate_module(device: &Device, module: &str) -> Result<Generated, Vec<Diagnostic>> {
    generate_module_reporting(device, module, Infos::Reported)
}

/// [`generate_module`], with infos in the diagnostics only when `infos` says so.
pub fn generate_module_reporting(
    device: &Device,
    module: &str,
    infos: Infos,
) -> Result<Generated, Vec<Diagnostic>> {
    generate_module_checked(device, module, infos, plan::Sizes::Unchecked)
}

/// [`generate_module_reporting`] for a device in which `edsgen_model::validate` found no error
/// (the builder's case): the size checks validation made (EDS707) are not made again.
pub fn generate_validated_module(
    device: &Device,
    module: &str,
    infos: Infos,
) -> Result<Generated, Vec<Diagnostic>> {
    generate_module_checked(device, module, infos, plan::Sizes::Validated)
}

fn generate_module_checked(
    device: &Device,
    module: &str,
    infos: Infos,
    sizes: plan::Sizes,
) -> Result<Generated, Vec<Diagnostic>> {
    let module = module_name(module);
    let mut plan = match &device.bus {
        // An ODVA EDS has no object dictionary: identity, assembly images and connections.
        Bus::Cip(cip) => {
            return cip::generate(device, cip, &module).map(|mut generated| {
                if infos == Infos::Skipped {
                    generated
                        .diagnostics
                        .retain(|d| d.severity != Severity::Info);
                }
                generated
            })
        }
        // A GSDML device has no object dictionary: its own module, from the PROFINET side.
        Bus::Profinet(pn) => {
            let tokens = profinet::module(pn, &module_doc(device), &plan::id(&module))?;
            return without_dictionary(device, module, tokens);
        }
        // A GSD file has no dictionary: its module is the DP one alone.
        Bus::Dp(dp) => {
            return without_dictionary(device, module.clone(), dp::module(device, dp, &module))
        }
        Bus::CanOpen | Bus::EtherCat(_) => plan::plan_checked(device, infos, sizes),
    };
    let mut diagnostics = std::mem::take(&mut plan.diagnostics);
    let mut splices = text::Splices::default();
    // An ESI device has no COB-IDs nor PDO communication objects: its PDOs are EtherCAT's.
    let pdo_tokens = match &device.bus {
        Bus::EtherCat(ec) => ethercat::module(ec, &plan),
        Bus::CanOpen | Bus::Cip(_) | Bus::Profinet(_) | Bus::Dp(_) => {
            pdo::pdos(device, &plan, &mut diagnostics, &mut splices)
        }
    };
    if infos == Infos::Skipped {
        diagnostics.retain(|d| d.severity != Severity::Info);
    }
    edsgen_model::diag::sort(&mut diagnostics);
    if diagnostics.iter().any(|d| d.severity == Severity::Error) {
        return Err(diagnostics);
    }
    let structs = od::structs(&plan, &mut splices);
    let table = od::descriptors(&plan, &mut splices);
    let od_impl = od::od_impl(&plan, &mut splices);
    let addresses = od::addresses(&plan, &mut splices);
    let header = header(device);
    let module_ident = plan::id(&module);
    let module_doc = module_doc(device);
    let tokens = quote! {
        #(#[doc = #module_doc])*
        // Defaults and limits are the file's numbers, even when they resemble a constant. A
        // firmware uses a few of the addresses and PDOs: the rest is not dead code to warn about,
        // also where the module is included in a private module.
        #[allow(dead_code, clippy::approx_constant)]
        pub mod #module_ident {
            #header
            #structs
            #table
            #od_impl
            #addresses
            #pdo_tokens
        }
    };
    let code = format_tokens(tokens, device, &splices)?;
    Ok(Generated {
        module,
        code,
        diagnostics,
    })
}

/// The module of a device without an object dictionary: `tokens` formatted, no diagnostics.
fn without_dictionary(
    device: &Device,
    module: String,
    tokens: TokenStream,
) -> Result<Generated, Vec<Diagnostic>> {
    let code = format_tokens(tokens, device, &text::Splices::default())?;
    Ok(Generated {
        module,
        code,
        diagnostics: Vec::new(),
    })
}

/// Generates the module for one device as text; an error message when generation fails (the
/// `edsgen generate` entry point; [`generate_module`] gives the diagnostics).
pub fn generate(device: &Device, module: &str) -> Result<String, String> {
    match generate_module(device, module) {
        Ok(generated) => Ok(generated.code),
        Err(diags) => Err(diags
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| {
                let line = d
                    .span
                    .map_or(String::new(), |s| format!("line {}: ", s.line));
                format!("{line}{}[{}]: {}", d.severity.as_str(), d.code(), d.message)
            })
            .collect::<Vec<_>>()
            .join("\n")),
    }
}

fn format_tokens(
    tokens: TokenStream,
    device: &Device,
    splices: &text::Splices,
) -> Result<String, Vec<Diagnostic>> {
    let file: syn::File = match syn::parse2(tokens) {
        Ok(file) => file,
        Err(err) => {
            return Err(vec![Diagnostic::new(
                &edsgen_model::rules::UNREPRESENTABLE_TYPE,
                None,
                format!(
                "internal error: generated tokens do not parse ({err}); please report this file"
            ),
            )])
        }
    };
    let file_name = device
        .source
        .path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut code = format!("// @generated by edsgen from `{file_name}`. Do not edit.\n");
    splices.apply(&prettyplease::unparse(&file), &mut code);
    Ok(code)
}

fn module_doc(device: &Device) -> Vec<String> {
    let info = &device.device_info;
    let product = info.product_name.as_deref().unwrap_or("Unnamed device");
    let mut lines = vec![format!(" {}", plan::doc_text(product))];
    lines.push(String::new());
    let format = match device.source.format {
        Format::Eds => "EDS",
        Format::Dcf => "DCF",
        Format::Xdd => "XDD",
        Format::Xdc => "XDC",
        Format::Esi => "ESI",
        Format::OdvaEds => "ODVA EDS",
        Format::Gsdml => "GSDML",
        Format::Gsd => "GSD",
    };
    let file_name = device
        .source
        .path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    lines.push(format!(
        " Generated by edsgen from the {format} `{}`.",
        file_name.replace('`', "'")
    ));
    if let Some(vendor) = &info.vendor_name {
        lines.push(format!(" Vendor: {}.", plan::doc_text(vendor)));
    }
    let fi = &device.file_info;
    if fi.file_version.is_some() || fi.file_revision.is_some() {
        lines.push(format!(
            " File version {}, revision {}.",
            plan::doc_text(fi.file_version.as_deref().unwrap_or("-")),
            plan::doc_text(fi.file_revision.as_deref().unwrap_or("-"))
        ));
    }
    if let Some(desc) = &fi.description {
        if !desc.trim().is_empty() {
            lines.push(format!(" {}", plan::doc_text(desc.trim())));
        }
    }
    lines
}

/// The identity (1018h sub 1-3, else `[DeviceInfo]`) and PDO count constants.
fn header(device: &Device) -> TokenStream {
    let identity = |sub: u8, info: Option<u32>| -> (u32, String) {
        let from_od =
            device.entry(0x1018, sub).and_then(
                |s| match edsgen_model::model::layout::initial_value(s) {
                    Some(Value::Integer(v)) => u32::try_from(*v).ok(),
                    _ => None,
                },
            );
        match (from_od, info) {
            (Some(v), _) => (v, format!("1018h sub {sub}")),
            (None, Some(v)) if device.ethercat().is_some() => {
                (v, "the ESI's `Vendor` and `Type`".to_owned())
            }
            (None, Some(v)) => (v, "`[DeviceInfo]`".to_owned()),
            (None, None) => (0, "not given by the file; 0".to_owned()),
        }
    };
    let info = &device.device_info;
    let (vendor, vendor_src) = identity(1, info.vendor_number.as_ref().map(|v| v.value));
    let (product, product_src) = identity(2, info.product_number.as_ref().map(|v| v.value));
    let (revision, revision_src) = identity(3, info.revision_number.as_ref().map(|v| v.value));
    let count = |range: std::ops::RangeInclusive<u16>, given: Option<u32>| -> (u32, &'static str) {
        match given {
            Some(n) => (n, "`[DeviceInfo]`"),
            None => (
                device.objects.keys().filter(|i| range.contains(i)).count() as u32,
                "counted communication parameter objects",
            ),
        }
    };
    let (rx, rx_src) = count(0x1400..=0x15FF, info.nr_of_rx_pdo.as_ref().map(|v| v.value));
    let (tx, tx_src) = count(0x1800..=0x19FF, info.nr_of_tx_pdo.as_ref().map(|v| v.value));
    let hex = |v: u32| -> TokenStream { types::hex(u128::from(v), 8) };
    let (vendor, product, revision) = (hex(vendor), hex(product), hex(revision));
    let (rx, tx) = (
        Literal::u16_unsuffixed(rx.min(512) as u16),
        Literal::u16_unsuffixed(tx.min(512) as u16),
    );
    let vendor_doc = format!(" Vendor-ID ({vendor_src}).");
    let product_doc = format!(" Product code ({product_src}).");
    let revision_doc = format!(" Revision number ({revision_src}).");
    let rx_doc = format!(" Number of RPDOs ({rx_src}).");
    let tx_doc = format!(" Number of TPDOs ({tx_src}).");
    let identity = quote! {
        #[doc = #vendor_doc]
        pub const VENDOR_ID: u32 = #vendor;
        #[doc = #product_doc]
        pub const PRODUCT_CODE: u32 = #product;
        #[doc = #revision_doc]
        pub const REVISION_NUMBER: u32 = #revision;
    };
    if device.ethercat().is_some() {
        // CANopen's PDO counts mean nothing on EtherCAT (the ethercat module lists the PDOs).
        return identity;
    }
    quote! {
        #identity
        #[doc = #rx_doc]
        pub const NR_OF_RXPDO: u16 = #rx;
        #[doc = #tx_doc]
        pub const NR_OF_TXPDO: u16 = #tx;
    }
}
