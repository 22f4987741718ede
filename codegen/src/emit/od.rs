//! Tokens for the object dictionary of one device: the `Od` struct and its nested record and
//! array structs, `Od::new(node_id)`, the sorted `ENTRIES` descriptor table, the
//! `ObjectDictionary` implementation, and the typed addresses in `od`.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::plan::{EntryPlan, ObjectPlan, Plan};
use super::types::{access_tokens, data_type_tokens, Prim, RustType};

fn docs(lines: &[String]) -> TokenStream {
    let attrs = lines.iter().map(|l| quote!(#[doc = #l]));
    quote!(#(#attrs)*)
}

fn hex16(v: u16) -> TokenStream {
    super::types::hex(u128::from(v), 4)
}

fn hex8(v: u8) -> TokenStream {
    super::types::hex(u128::from(v), 2)
}

/// The `Od` struct, its nested types (in `records`) and `Od::new`.
pub fn structs(plan: &Plan) -> TokenStream {
    let mut fields = Vec::new();
    let mut inits = Vec::new();
    let mut records = Vec::new();
    for object in &plan.objects {
        match object {
            ObjectPlan::Var { field, entry } => {
                let ty = entry.ty.tokens();
                let doc = docs(&entry.doc);
                let init = &entry.init;
                fields.push(quote!(#doc pub #field: #ty,));
                inits.push(quote!(#field: #init,));
            }
            ObjectPlan::Record {
                field,
                type_name,
                doc,
                members,
            } => {
                let doc_tokens = docs(doc);
                let member_fields = members.iter().map(|(name, e)| {
                    let ty = e.ty.tokens();
                    let d = docs(&e.doc);
                    quote!(#d pub #name: #ty,)
                });
                let member_inits = members.iter().map(|(name, e)| {
                    let init = &e.init;
                    quote!(#name: #init,)
                });
                records.push(quote! {
                    #doc_tokens
                    #[derive(Debug, Clone, PartialEq)]
                    pub struct #type_name { #(#member_fields)* }
                });
                fields.push(quote!(#doc_tokens pub #field: records::#type_name,));
                inits.push(quote!(#field: records::#type_name { #(#member_inits)* },));
            }
            ObjectPlan::Array {
                field,
                type_name,
                doc,
                sub0,
                items_field,
                elem,
                items,
            } => {
                let doc_tokens = docs(doc);
                let (sub0_name, sub0_entry) = sub0;
                let sub0_ty = sub0_entry.ty.tokens();
                let sub0_doc = docs(&sub0_entry.doc);
                let sub0_init = &sub0_entry.init;
                let elem_ty = elem.tokens();
                let n = Literal::usize_unsuffixed(items.len());
                let item_inits = items.iter().map(|e| &e.init);
                let items_doc = format!(
                    " Sub-indices 1 to {}: element `i` is sub-index `i + 1`.",
                    items.len()
                );
                records.push(quote! {
                    #doc_tokens
                    #[derive(Debug, Clone, PartialEq)]
                    pub struct #type_name {
                        #sub0_doc
                        pub #sub0_name: #sub0_ty,
                        #[doc = #items_doc]
                        pub #items_field: [#elem_ty; #n],
                    }
                });
                fields.push(quote!(#doc_tokens pub #field: records::#type_name,));
                inits.push(quote!(#field: records::#type_name {
                    #sub0_name: #sub0_init,
                    #items_field: [#(#item_inits),*],
                },));
            }
        }
    }
    let node_param = if plan.uses_node_id {
        quote!(node_id)
    } else {
        quote!(_node_id)
    };
    let records_mod = if records.is_empty() {
        quote!()
    } else {
        quote! {
            /// The nested structs of RECORD and ARRAY objects.
            pub mod records {
                #(#records)*
            }
        }
    };
    quote! {
        /// The object dictionary: one field per stored entry, records and arrays as nested
        /// structs.
        #[derive(Debug, Clone, PartialEq)]
        pub struct Od {
            #(#fields)*
        }

        impl Od {
            /// The dictionary with every entry at its default (a DCF's ParameterValue where
            /// given); `$NODEID` defaults are computed from `node_id`.
            pub const fn new(#node_param: u8) -> Self {
                Od { #(#inits)* }
            }
        }

        #records_mod
    }
}

fn all_entries(plan: &Plan) -> impl Iterator<Item = &EntryPlan> {
    plan.objects.iter().flat_map(ObjectPlan::entries)
}

/// The `ENTRIES` table.
pub fn descriptors(plan: &Plan) -> TokenStream {
    let rows: Vec<_> = all_entries(plan)
        .map(|e| {
            let index = hex16(e.index);
            let sub = hex8(e.sub);
            let data_type = data_type_tokens(e.basic);
            let access = access_tokens(e.access);
            let pdo = e.pdo_mappable;
            let size = Literal::u16_unsuffixed(match e.ty {
                RustType::Scalar(_, wire) => wire as u16,
                RustType::Bytes(n) => n as u16,
            });
            quote! {
                ::edsgen_runtime::EntryDescriptor {
                    index: #index, sub: #sub, data_type: #data_type, access: #access,
                    pdo_mappable: #pdo, size: #size,
                }
            }
        })
        .collect();
    let n = Literal::usize_unsuffixed(rows.len());
    quote! {
        /// Every entry's descriptor, sorted by (index, sub-index).
        pub static ENTRIES: [::edsgen_runtime::EntryDescriptor; #n] = [#(#rows),*];
    }
}

/// `impl ObjectDictionary for Od`.
pub fn od_impl(plan: &Plan) -> TokenStream {
    let mut len_arms = Vec::new();
    let mut read_arms = Vec::new();
    let mut write_arms = Vec::new();
    for e in all_entries(plan) {
        let key = {
            let index = hex16(e.index);
            let sub = hex8(e.sub);
            quote!((#index, #sub))
        };
        let path = &e.path;
        let read_source = match e.ty {
            RustType::Bytes(_) => quote!(self.#path.as_bytes()),
            RustType::Scalar(Prim::Bool, _) => quote!(&[u8::from(self.#path)]),
            RustType::Scalar(prim, wire) if (wire as u32) * 8 < prim.bits() => {
                let w = Literal::usize_unsuffixed(wire);
                quote!(&self.#path.to_le_bytes()[..#w])
            }
            RustType::Scalar(..) => quote!(&self.#path.to_le_bytes()),
        };
        read_arms.push(
            quote!(#key => Ok(::edsgen_runtime::typed::read_bytes(#read_source, offset, buf)),),
        );
        let write_body = match e.ty {
            RustType::Bytes(_) => quote!(self.#path.set(data)),
            RustType::Scalar(prim, wire) => {
                let ty = prim.tokens();
                let decode = match prim {
                    Prim::Bool => quote!(::edsgen_runtime::typed::boolean(data)?),
                    _ if (wire as u32) * 8 < prim.bits() => {
                        let w = Literal::usize_unsuffixed(wire);
                        if matches!(prim, Prim::Signed(_)) {
                            quote!(::edsgen_runtime::typed::int_le::<#w>(data)? as #ty)
                        } else {
                            quote!(::edsgen_runtime::typed::uint_le::<#w>(data)? as #ty)
                        }
                    }
                    _ => quote!(#ty::from_le_bytes(::edsgen_runtime::typed::exact(data)?)),
                };
                match &e.limits {
                    Some((low, high)) => quote! {
                        let value = ::edsgen_runtime::typed::check_limits(#decode, #low, #high)?;
                        self.#path = value;
                        Ok(())
                    },
                    None => quote! {
                        self.#path = #decode;
                        Ok(())
                    },
                }
            }
        };
        write_arms.push(quote!(#key => { #write_body }));
        if let RustType::Bytes(_) = e.ty {
            len_arms.push(quote!(#key => Ok(self.#path.len()),));
        }
    }
    quote! {
        impl ::edsgen_runtime::ObjectDictionary for Od {
            fn entries(&self) -> &[::edsgen_runtime::EntryDescriptor] {
                &ENTRIES
            }

            fn value_len(&self, index: u16, sub: u8) -> Result<usize, ::edsgen_runtime::SdoAbort> {
                if let Some(size) = ::edsgen_runtime::ObjectDictionary::find(self, index, sub)?.data_type.fixed_size() {
                    return Ok(size);
                }
                match (index, sub) {
                    #(#len_arms)*
                    _ => Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub)),
                }
            }

            fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, ::edsgen_runtime::SdoAbort> {
                match (index, sub) {
                    #(#read_arms)*
                    _ => Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub)),
                }
            }

            fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), ::edsgen_runtime::SdoAbort> {
                match (index, sub) {
                    #(#write_arms)*
                    _ => Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub)),
                }
            }
        }
    }
}

/// The typed addresses: `pub mod od { pub const CONTROLWORD: Entry<u16> = ...; }`.
pub fn addresses(plan: &Plan) -> TokenStream {
    let consts = all_entries(plan).map(|e| {
        let name = &e.const_name;
        let ty = e.ty.tokens();
        let index = hex16(e.index);
        let sub = hex8(e.sub);
        let doc = docs(&e.doc);
        quote! {
            #doc
            pub const #name: ::edsgen_runtime::Entry<#ty> = ::edsgen_runtime::Entry::new(#index, #sub);
        }
    });
    quote! {
        /// Typed addresses of every entry: the (index, sub-index) and the Rust type of its value.
        pub mod od {
            #(#consts)*
        }
    }
}
