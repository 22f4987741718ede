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

/// An entry's value in `Od::DEFAULTS`: its initial value, or 0 for a `$NODEID` value, which
/// `Od::new` sets.
fn default_tokens(e: &EntryPlan) -> TokenStream {
    if e.node_relative {
        quote!(0)
    } else {
        e.init.clone()
    }
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
                let init = default_tokens(entry);
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
                    let init = default_tokens(e);
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
                let sub0_init = default_tokens(sub0_entry);
                let elem_ty = elem.tokens();
                let n = Literal::usize_unsuffixed(items.len());
                let item_inits: Vec<_> = items.iter().map(default_tokens).collect();
                let first = item_inits.first().map(|t| t.to_string());
                let repeat =
                    items.len() > 1 && item_inits.iter().all(|t| Some(t.to_string()) == first);
                let items_init = if repeat {
                    let init = &item_inits[0];
                    quote!([#init; #n])
                } else {
                    quote!([#(#item_inits),*])
                };
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
                    #items_field: #items_init,
                },));
            }
        }
    }
    let node_fields: Vec<_> = all_entries(plan)
        .filter(|e| e.node_relative)
        .map(|e| {
            let path = &e.path;
            let init = &e.init;
            quote!(od.#path = #init;)
        })
        .collect();
    let new_body = if node_fields.is_empty() {
        quote!(Self::DEFAULTS)
    } else {
        quote! {
            let mut od = Self::DEFAULTS;
            #(#node_fields)*
            od
        }
    };
    let node_param = if node_fields.is_empty() {
        quote!(_node_id)
    } else {
        quote!(node_id)
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
            /// Every entry at its default, with 0 for the `$NODEID` ones. `new` copies it and
            /// sets those: one copy from flash rather than code that stores each field.
            const DEFAULTS: Self = Od { #(#inits)* };

            /// The dictionary with every entry at its default (a DCF's ParameterValue where
            /// given); `$NODEID` defaults are computed from `node_id`.
            pub const fn new(#node_param: u8) -> Self {
                #new_body
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
            quote!(E::new(#index, #sub, #data_type, #access, #pdo, #size))
        })
        .collect();
    let n = Literal::usize_unsuffixed(rows.len());
    let body = if rows.is_empty() {
        quote!([])
    } else {
        quote!({
            use ::edsgen_runtime::{Access as A, DataType as D, EntryDescriptor as E};
            [#(#rows),*]
        })
    };
    quote! {
        /// Every entry's descriptor, sorted by (index, sub-index).
        pub static ENTRIES: [::edsgen_runtime::EntryDescriptor; #n] = #body;
    }
}

fn key(index: u16, sub: u8) -> TokenStream {
    let index = hex16(index);
    let sub = hex8(sub);
    quote!((#index, #sub))
}

/// The `read`, `write` and (for variable-length values) `value_len` arms of one entry, or of
/// all elements of a uniform array when `key` is a sub-index range and `path` indexes by `sub`.
fn arms(
    e: &EntryPlan,
    key: TokenStream,
    position: TokenStream,
    path: &TokenStream,
) -> (TokenStream, TokenStream, Option<TokenStream>) {
    let read_source = match e.ty {
        RustType::Bytes(_) => quote!(self.#path.as_bytes()),
        RustType::Scalar(prim, wire) => {
            let raw = match prim {
                Prim::Bool | Prim::Unsigned(8 | 16 | 32) => quote!(u64::from(self.#path)),
                Prim::Unsigned(_) => quote!(self.#path),
                Prim::Signed(_) => quote!(self.#path as u64),
                Prim::F32 => quote!(u64::from(self.#path.to_bits())),
                Prim::F64 => quote!(self.#path.to_bits()),
            };
            let w = Literal::usize_unsuffixed(wire);
            quote!(t::le(&mut s, #raw, #w))
        }
    };
    let write_stmt = match e.ty {
        RustType::Bytes(_) => quote!(self.#path.set(data)?),
        RustType::Scalar(prim, wire) => {
            let ty = prim.tokens();
            let decode = match prim {
                Prim::Bool => quote!(t::boolean(data)?),
                _ if (wire as u32) * 8 < prim.bits() => {
                    let w = Literal::usize_unsuffixed(wire);
                    if matches!(prim, Prim::Signed(_)) {
                        quote!(t::int_le::<#w>(data)? as #ty)
                    } else {
                        quote!(t::uint_le::<#w>(data)? as #ty)
                    }
                }
                _ => quote!(#ty::from_le_bytes(t::exact(data)?)),
            };
            let plain = !matches!(prim, Prim::Bool) && (wire as u32) * 8 >= prim.bits();
            match &e.limits {
                Some((low, high)) => quote!(self.#path = t::check_limits(#decode, #low, #high)?),
                // One shared, non-inlined store per type keeps the arm small in flash.
                None if plain => quote!(t::store(&mut self.#path, data)?),
                None => quote!(self.#path = #decode),
            }
        }
    };
    let len = matches!(e.ty, RustType::Bytes(_)).then(|| quote!(#key => Ok(self.#path.len()),));
    (
        quote!(#position => #read_source,),
        quote!(#position => #write_stmt,),
        len,
    )
}

/// `impl ObjectDictionary for Od`.
pub fn od_impl(plan: &Plan) -> TokenStream {
    let mut len_arms = Vec::new();
    let mut read_arms = Vec::new();
    let mut write_arms = Vec::new();
    // `read_at` and `write_at` dispatch on the entry's position in `ENTRIES` (a dense jump
    // table), which is much smaller in flash than a match on (index, sub); `read` and `write`
    // find the position with one binary search.
    // The pattern of the next `count` positions, and the first of them.
    let mut next_position = 0usize;
    let mut position = |count: usize| {
        let first = next_position;
        next_position += count;
        let start = Literal::usize_unsuffixed(first);
        let pattern = if count == 1 {
            quote!(#start)
        } else {
            let end = Literal::usize_unsuffixed(first + count - 1);
            quote!(#start..=#end)
        };
        (pattern, start)
    };
    for object in &plan.objects {
        if let ObjectPlan::Array {
            field,
            sub0,
            items_field,
            items,
            ..
        } = object
        {
            let uniform = items.windows(2).all(|w| {
                w[0].ty == w[1].ty
                    && w[0]
                        .limits
                        .as_ref()
                        .map(|(l, h)| (l.to_string(), h.to_string()))
                        == w[1]
                            .limits
                            .as_ref()
                            .map(|(l, h)| (l.to_string(), h.to_string()))
            });
            if uniform && items.len() > 1 {
                let (e0, e) = (&sub0.1, &items[0]);
                let (r, w, l) = arms(e0, key(e0.index, e0.sub), position(1).0, &e0.path);
                read_arms.push(r);
                write_arms.push(w);
                len_arms.extend(l);
                let index = hex16(e.index);
                let last = hex8(items.len() as u8);
                let ranged_key = quote!((#index, sub @ 0x01..=#last));
                let len_path = quote!(#field.#items_field[usize::from(sub) - 1]);
                let (pattern, first) = position(items.len());
                let path = quote!(#field.#items_field[position - #first]);
                let (r, w, _) = arms(e, ranged_key.clone(), pattern, &path);
                let (_, _, l) = arms(e, ranged_key, quote!(_), &len_path);
                read_arms.push(r);
                write_arms.push(w);
                len_arms.extend(l);
                continue;
            }
        }
        for e in object.entries() {
            let (r, w, l) = arms(e, key(e.index, e.sub), position(1).0, &e.path);
            read_arms.push(r);
            write_arms.push(w);
            len_arms.extend(l);
        }
    }
    let scratch = if all_entries(plan).any(|e| matches!(e.ty, RustType::Scalar(..))) {
        quote!(let mut s = [0u8; 8];)
    } else {
        quote!()
    };
    let (read_body, write_body) = if read_arms.is_empty() {
        (
            quote! {
                let _ = (offset, buf);
                Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub))
            },
            quote! {
                let _ = data;
                Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub))
            },
        )
    } else {
        (
            quote! {
                self.read_at(::edsgen_runtime::typed::position(&ENTRIES, index, sub)?, offset, buf)
            },
            quote! {
                self.write_at(::edsgen_runtime::typed::position(&ENTRIES, index, sub)?, data)
            },
        )
    };
    // By position in `ENTRIES` (from `locate`): the protocols look an entry up once, then
    // access it here without a second search. Out of line, so `read`/`write` do not copy them.
    let at_fns = if read_arms.is_empty() {
        quote!()
    } else {
        quote! {
            #[inline(never)]
            fn read_at(&self, position: usize, offset: usize, buf: &mut [u8]) -> Result<usize, ::edsgen_runtime::SdoAbort> {
                use ::edsgen_runtime::typed as t;
                #scratch
                let value: &[u8] = match position {
                    #(#read_arms)*
                    _ => return Err(::edsgen_runtime::SdoAbort::NoObject),
                };
                Ok(t::read_bytes(value, offset, buf))
            }

            #[inline(never)]
            fn write_at(&mut self, position: usize, data: &[u8]) -> Result<(), ::edsgen_runtime::SdoAbort> {
                use ::edsgen_runtime::typed as t;
                match position {
                    #(#write_arms)*
                    _ => return Err(::edsgen_runtime::SdoAbort::NoObject),
                }
                Ok(())
            }
        }
    };
    let len_match = if len_arms.is_empty() {
        quote!(Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub)))
    } else {
        quote! {
            match (index, sub) {
                #(#len_arms)*
                _ => Err(::edsgen_runtime::typed::missing(&ENTRIES, index, sub)),
            }
        }
    };
    quote! {
        impl ::edsgen_runtime::ObjectDictionary for Od {
            fn entries(&self) -> &[::edsgen_runtime::EntryDescriptor] {
                &ENTRIES
            }

            fn value_len(&self, index: u16, sub: u8) -> Result<usize, ::edsgen_runtime::SdoAbort> {
                if let Some(size) = ::edsgen_runtime::ObjectDictionary::find(self, index, sub)?.data_type.fixed_size() {
                    return Ok(size);
                }
                #len_match
            }

            fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, ::edsgen_runtime::SdoAbort> {
                #read_body
            }

            fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), ::edsgen_runtime::SdoAbort> {
                #write_body
            }

            #at_fns
        }
    }
}

/// The typed addresses: `pub mod od { pub const CONTROLWORD: Entry<u16> = ...; }`.
pub fn addresses(plan: &Plan) -> TokenStream {
    let consts: Vec<_> = all_entries(plan)
        .map(|e| {
            let name = &e.const_name;
            let ty = match e.ty {
                RustType::Bytes(n) => {
                    let n = Literal::usize_unsuffixed(n);
                    quote!(FixedBytes<#n>)
                }
                RustType::Scalar(..) => e.ty.tokens(),
            };
            let index = hex16(e.index);
            let sub = hex8(e.sub);
            let doc = docs(&e.short_doc);
            let constructor = match e.ty {
                RustType::Scalar(prim, wire)
                    if (wire as u32) * 8 < prim.bits() && prim != Prim::Bool =>
                {
                    let w = Literal::u8_unsuffixed(wire as u8);
                    quote!(Entry::with_width(#index, #sub, #w))
                }
                _ => quote!(Entry::new(#index, #sub)),
            };
            quote! {
                #doc
                pub const #name: Entry<#ty> = #constructor;
            }
        })
        .collect();
    let uses_bytes = all_entries(plan).any(|e| matches!(e.ty, RustType::Bytes(_)));
    let imports = match (consts.is_empty(), uses_bytes) {
        (true, _) => quote!(),
        (false, false) => quote!(
            use ::edsgen_runtime::Entry;
        ),
        (false, true) => quote!(
            use ::edsgen_runtime::{Entry, FixedBytes};
        ),
    };
    quote! {
        /// Typed addresses of every entry: the (index, sub-index) and the Rust type of its value.
        pub mod od {
            #imports
            #(#consts)*
        }
    }
}
