//! One struct per SyncManager's default process image: the PDOs assigned to it, concatenated
//! as the master sees them.

use proc_macro2::TokenStream;
use quote::quote;

use crate::emit::plan::id;
use edsgen_model::model::{EcPdo, EtherCat, SmKind};

use super::pdo::{at_plus, emit_item};
use super::PdoPlan;

/// One struct per SyncManager with PDOs assigned by default: `Outputs` / `Inputs` (or
/// `Sm2Outputs`, ... when several SyncManagers of one direction have PDOs). A PDO that excludes,
/// or is excluded by, one already assigned to the same SyncManager is left out.
pub(super) fn images(ec: &EtherCat, planned: &[(&EcPdo, bool, PdoPlan)]) -> Vec<TokenStream> {
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
