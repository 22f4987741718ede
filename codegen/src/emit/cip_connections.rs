//! The connections of an ODVA EDS's `[Connection Manager]` as constants of one `Connection`
//! type: the trigger/transport and connection-parameter words, the O→T, T→O and configuration
//! assembly instances, the sizes, the RPI and the path bytes (part of the CIP module, `cip`).

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::names::{ident, Case};
use super::plan::{code_span, id};
use super::types;
use edsgen_model::model::{path_bytes, Cip, CipAssembly, CipNumber, FieldRef};

/// The `Connection` type and one constant per connection.
pub(super) fn connections(cip: &Cip) -> TokenStream {
    if cip.connections.is_empty() {
        return TokenStream::new();
    }
    let mut items = Vec::new();
    let mut names: Vec<String> = Vec::new();
    let instance = |r: &FieldRef| match r {
        FieldRef::Assem(n) => cip.assemblies.get(n).map(CipAssembly::instance),
        _ => None,
    };
    let option = |v: Option<u32>| match v {
        Some(v) => {
            let v = Literal::u32_unsuffixed(v);
            quote!(Some(#v))
        }
        None => quote!(None),
    };
    for c in cip.connections.values() {
        let size = |d: &edsgen_model::model::ConnectionData| -> u64 {
            match &d.size.value {
                FieldRef::Number(n) => *n,
                FieldRef::Param(n) => cip
                    .params
                    .get(n)
                    .and_then(|p| match p.default.as_ref()?.value {
                        CipNumber::Int(v) => u64::try_from(v).ok(),
                        CipNumber::Real(_) => None,
                    })
                    .unwrap_or(0),
                _ => match &d.format.value {
                    FieldRef::Assem(n) => cip
                        .assemblies
                        .get(n)
                        .and_then(|a| cip.assembly_size(a))
                        .unwrap_or(0),
                    _ => 0,
                },
            }
        };
        let rpi = match &c.o_t.rpi.value {
            FieldRef::Number(n) => u32::try_from(*n).unwrap_or(0),
            FieldRef::Param(n) => cip
                .params
                .get(n)
                .and_then(|p| match p.default.as_ref()?.value {
                    CipNumber::Int(v) => u32::try_from(v).ok(),
                    CipNumber::Real(_) => None,
                })
                .unwrap_or(0),
            _ => 0,
        };
        let path: Vec<u8> = c
            .path
            .as_ref()
            .and_then(|p| path_bytes(&p.value).ok())
            .unwrap_or_default();
        let config = instance(&c.config2.format.value).or(instance(&c.config1.format.value));
        let wanted = ident(&c.name, Case::Shouty, &format!("CONNECTION_{}", c.number));
        let mut name = wanted.clone();
        if names.contains(&name) {
            name = format!("{wanted}_{}", c.number);
        }
        names.push(name.clone());
        let const_name = id(&name);
        let doc = format!(" Connection{} {}.", c.number, code_span(&c.name));
        let cname = c.name.clone();
        let tt = types::hex(
            u128::from(c.trigger_transport.as_ref().map_or(0, |t| t.value.0)),
            8,
        );
        let params = types::hex(u128::from(c.params.as_ref().map_or(0, |p| p.value.0)), 8);
        let o_t = option(instance(&c.o_t.format.value));
        let t_o = option(instance(&c.t_o.format.value));
        let config = option(config);
        // Forward_Open carries a connection size in 16 bits (9 in a small Forward_Open).
        let o_t_size = Literal::u16_unsuffixed(size(&c.o_t).min(u64::from(u16::MAX)) as u16);
        let t_o_size = Literal::u16_unsuffixed(size(&c.t_o).min(u64::from(u16::MAX)) as u16);
        let rpi = Literal::u32_unsuffixed(rpi);
        let path = path.iter().map(|b| types::hex(u128::from(*b), 2));
        items.push(quote! {
            #[doc = #doc]
            pub const #const_name: Connection = Connection {
                name: #cname,
                trigger_transport: #tt,
                connection_params: #params,
                o_t_assembly: #o_t,
                t_o_assembly: #t_o,
                config_assembly: #config,
                o_t_size: #o_t_size,
                t_o_size: #t_o_size,
                rpi_us: #rpi,
                path: &[#(#path),*],
            };
        });
    }
    quote! {
        /// A connection `[Connection Manager]` describes.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub struct Connection {
            /// Its name.
            pub name: &'static str,
            /// The trigger and transport word (bits 0-15 classes, 16-18 triggers, 24-27
            /// application type, 31 server).
            pub trigger_transport: u32,
            /// The connection parameters word (sizes, real-time formats, types, priorities).
            pub connection_params: u32,
            /// The O->T assembly instance (its format), if it names one.
            pub o_t_assembly: Option<u32>,
            /// The T->O assembly instance, if it names one.
            pub t_o_assembly: Option<u32>,
            /// The configuration assembly instance, if it names one.
            pub config_assembly: Option<u32>,
            /// The O->T data size in bytes (without the run/idle header), as Forward_Open's
            /// 16-bit connection size carries it.
            pub o_t_size: u16,
            /// The T->O data size in bytes.
            pub t_o_size: u16,
            /// The O->T RPI in microseconds (the parameter's default when a parameter holds it;
            /// 0 when the file gives none).
            pub rpi_us: u32,
            /// The connection path (empty when the file's path is not plain hex bytes).
            pub path: &'static [u8],
        }

        #(#items)*
    }
}
