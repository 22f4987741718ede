//! The `ethercat` module's constants: identity, SyncManagers, distributed-clock modes, the
//! CoE mailbox and the op modes.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::emit::plan::{code_span, id};
use crate::emit::types::hex;
use edsgen_model::model::{EtherCat, SmKind};

pub(super) fn constants(ec: &EtherCat) -> TokenStream {
    let rt = quote!(::edsgen_runtime::ethercat);
    let type_name = Literal::string(&ec.type_name);
    let type_doc = format!(
        " The device's type name in the ESI file ({}).",
        code_span(&ec.type_name)
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
            SmKind::Other(text) => (quote!(Other), code_span(text)),
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
