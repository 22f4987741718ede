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
//!
//! A modular device's chosen module instances add their PDOs (indices moved per slot) to the
//! device's, and so to its images. `constants` emits the constants, `pdo` the PDO structs and `image` the process images; the
//! planned PDOs and fields both kinds of struct are built from live here.

use proc_macro2::TokenStream;
use quote::quote;

use super::plan::Plan;
use super::types::Prim;
use edsgen_model::model::EtherCat;

mod constants;
mod image;
mod pdo;

use constants::constants;
use image::images;
use pdo::{emit_struct, pdo_methods, plan_pdo};

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

/// The `ethercat` module for a device with an EtherCAT side: as configured, with the PDOs of the
/// modules its overlay's `[modules]` plugs ([`EtherCat::configured`]).
pub fn module(ec: &EtherCat, plan: &Plan) -> TokenStream {
    let ec = &ec.configured();
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
