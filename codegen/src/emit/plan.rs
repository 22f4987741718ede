//! The plan: which struct field, Rust type, initial value, limits, docs and typed-address name each
//! stored entry gets. Built from the model in (index, sub) order so names and output are
//! deterministic; every problem becomes an `EDS7xx` diagnostic.

use proc_macro2::{Ident, Span as TokenSpan, TokenStream};
use quote::quote;

use super::names::{ident, Case, Namespace};
use super::types::{
    self, capacity, initial_value, node_relative_tokens, scalar_tokens, value_bytes, Prim,
    RustType, ValueProblem,
};
use crate::diag::Diagnostic;
use crate::model::{AccessType, BasicType, Device, Object, ObjectType, SubObject, Value};
use crate::rules;

/// Everything the emitter needs to know about one stored entry.
#[derive(Debug, Clone)]
pub struct EntryPlan {
    /// OD index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The basic data type.
    pub basic: BasicType,
    /// The Rust type.
    pub ty: RustType,
    /// The access type (`ro` when the file gives none; the reader has reported that).
    pub access: AccessType,
    /// PDOMapping.
    pub pdo_mappable: bool,
    /// The initial value's tokens (may use `node_id`).
    pub init: TokenStream,
    /// Whether the initial value depends on the node-ID (`$NODEID`).
    pub node_relative: bool,
    /// LowLimit and HighLimit tokens, when the entry has at least one usable limit.
    pub limits: Option<(TokenStream, TokenStream)>,
    /// Rustdoc lines.
    pub doc: Vec<String>,
    /// One-paragraph rustdoc for the typed address.
    pub short_doc: Vec<String>,
    /// The typed-address constant's name.
    pub const_name: Ident,
    /// The field path below `self` (`controlword`, `identity.vendor_id`, `errors.items[0]`).
    pub path: TokenStream,
    /// The field name for PDO structs mapping this entry (snake case of its own name).
    pub pdo_name: String,
}

/// How one object is stored.
#[derive(Debug, Clone)]
pub enum ObjectPlan {
    /// A VAR or DOMAIN: one field of the OD struct.
    Var {
        /// The OD struct field.
        field: Ident,
        /// The entry.
        entry: EntryPlan,
    },
    /// A RECORD, or an ARRAY that is sparse or mixes types: a nested struct, one field per
    /// present sub-index.
    Record {
        /// The OD struct field.
        field: Ident,
        /// The nested struct's name (in the `records` module).
        type_name: Ident,
        /// Rustdoc lines for the field and the type.
        doc: Vec<String>,
        /// (member field, entry) per present sub-index.
        members: Vec<(Ident, EntryPlan)>,
    },
    /// An ARRAY with sub-indices 1..=N of one type: a nested struct with sub-index 0 and
    /// `[T; N]`.
    Array {
        /// The OD struct field.
        field: Ident,
        /// The nested struct's name.
        type_name: Ident,
        /// Rustdoc lines.
        doc: Vec<String>,
        /// Sub-index 0's member field and entry.
        sub0: (Ident, EntryPlan),
        /// The array member's field name.
        items_field: Ident,
        /// The element type.
        elem: RustType,
        /// Sub-indices 1..=N.
        items: Vec<EntryPlan>,
    },
}

impl ObjectPlan {
    /// Every entry, in sub-index order.
    pub fn entries(&self) -> Vec<&EntryPlan> {
        match self {
            ObjectPlan::Var { entry, .. } => vec![entry],
            ObjectPlan::Record { members, .. } => members.iter().map(|(_, e)| e).collect(),
            ObjectPlan::Array { sub0, items, .. } => {
                std::iter::once(&sub0.1).chain(items.iter()).collect()
            }
        }
    }
}

/// The plan for a whole device.
#[derive(Debug)]
pub struct Plan {
    /// Stored objects in index order.
    pub objects: Vec<ObjectPlan>,
    /// Diagnostics found while planning.
    pub diagnostics: Vec<Diagnostic>,
}

impl Plan {
    /// The entry at (index, sub), if stored.
    pub fn entry(&self, index: u16, sub: u8) -> Option<&EntryPlan> {
        self.objects
            .iter()
            .flat_map(ObjectPlan::entries)
            .find(|e| e.index == index && e.sub == sub)
    }
}

pub(crate) fn id(name: &str) -> Ident {
    Ident::new(name, TokenSpan::call_site())
}

/// Escapes text from the file for rustdoc: no links, no HTML, no control characters.
pub fn doc_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '[' | ']' | '<' | '>' | '`' | '*' | '_' | '\\' | '#' => {
                out.push('\\');
                out.push(c);
            }
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

struct Planner<'a> {
    device: &'a Device,
    diagnostics: Vec<Diagnostic>,
    fields: Namespace,
    types: Namespace,
    consts: Namespace,
}

/// Plans every stored object of `device` (objects from 1000h on; data type definitions below
/// that are not stored).
pub fn plan(device: &Device) -> Plan {
    let mut p = Planner {
        device,
        diagnostics: Vec::new(),
        fields: Namespace::default(),
        types: Namespace::default(),
        consts: Namespace::default(),
    };
    let mut objects = Vec::new();
    for object in device.objects.values() {
        if object.index < 0x1000 || object.subs.is_empty() {
            continue;
        }
        if let Some(plan) = p.object(object) {
            objects.push(plan);
        }
    }
    Plan {
        objects,
        diagnostics: p.diagnostics,
    }
}

impl Planner<'_> {
    fn renamed(&mut self, span: crate::model::Span, what: &str, wanted: &str, got: &str) {
        self.diagnostics.push(
            Diagnostic::new(
                &rules::NAME_COLLISION,
                Some(span),
                format!("the {what} name `{wanted}` is already used; this one is `{got}`"),
            )
            .with_label("renamed in the generated code"),
        );
    }

    fn object(&mut self, object: &Object) -> Option<ObjectPlan> {
        let hex = format!("{:04x}", object.index);
        let (field, changed) = self.fields.claim(
            &ident(&object.name, Case::Snake, &format!("object_{hex}")),
            std::slice::from_ref(&hex),
        );
        if changed {
            self.renamed(
                object.span,
                "field",
                &ident(&object.name, Case::Snake, ""),
                &field,
            );
        }
        let field_id = id(&field);
        if !object.object_type.has_subs() {
            let sub = object
                .subs
                .get(&0)
                .or_else(|| object.subs.values().next())?;
            let const_name = self.const_name(object, None);
            let entry = self.entry(object, sub, const_name, quote!(#field_id))?;
            return Some(ObjectPlan::Var {
                field: field_id,
                entry,
            });
        }
        let upper = format!("{:04X}", object.index);
        let (type_name, changed) = self.types.claim_camel(
            &ident(&object.name, Case::Camel, &format!("Object{upper}")),
            std::slice::from_ref(&upper),
        );
        if changed {
            self.renamed(
                object.span,
                "type",
                &ident(&object.name, Case::Camel, ""),
                &type_name,
            );
        }
        let kind = match object.object_type {
            ObjectType::Array => "ARRAY",
            ObjectType::DefStruct => "DEFSTRUCT",
            _ => "RECORD",
        };
        let doc = vec![
            format!(" {}", doc_text(&object.name)),
            String::new(),
            format!(
                " Object {:04X}h, {kind}, sub-indices {}.",
                object.index,
                object
                    .subs
                    .keys()
                    .map(u8::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ];
        if let Some(plan) = self.array(object, &field_id, &type_name, &doc) {
            return Some(plan);
        }
        let mut members_ns = Namespace::default();
        let mut members = Vec::new();
        let mut ok = true;
        for sub in object.subs.values() {
            let (member, changed) = members_ns.claim(
                &ident(&sub.name, Case::Snake, &format!("sub{}", sub.sub_index)),
                &[format!("sub{}", sub.sub_index)],
            );
            if changed {
                self.renamed(
                    sub.span,
                    "field",
                    &ident(&sub.name, Case::Snake, ""),
                    &member,
                );
            }
            let member_id = id(&member);
            let const_name = self.const_name(object, Some(sub));
            match self.entry(object, sub, const_name, quote!(#field_id.#member_id)) {
                Some(entry) => members.push((member_id, entry)),
                None => ok = false,
            }
        }
        ok.then_some(ObjectPlan::Record {
            field: field_id,
            type_name: id(&type_name),
            doc,
            members,
        })
    }

    /// An ARRAY whose sub-indices are exactly 0..=N (N ≥ 1) with one element type.
    fn array(
        &mut self,
        object: &Object,
        field: &Ident,
        type_name: &str,
        doc: &[String],
    ) -> Option<ObjectPlan> {
        if object.object_type != ObjectType::Array {
            return None;
        }
        let n = object.subs.len() - 1;
        if n == 0 || !object.subs.keys().copied().eq(0..=(n as u8)) || n > 255 {
            return None;
        }
        let element_types: Vec<_> = object
            .subs
            .values()
            .skip(1)
            .map(|s| s.data_type.and_then(|t| self.device.basic_type(t)))
            .collect();
        let first = *element_types.first()?;
        let basic = first?;
        if element_types.iter().any(|t| *t != first) {
            return None;
        }
        let cap = object
            .subs
            .values()
            .skip(1)
            .map(|s| capacity(basic, s))
            .max()
            .unwrap_or(0);
        let elem = RustType::of(basic, cap);
        let sub0 = object.subs.get(&0)?;
        let mut members_ns = Namespace::with_reserved(&["items"]);
        let (sub0_member, _) = members_ns.claim(
            &ident(&sub0.name, Case::Snake, "sub0"),
            &["sub0".to_owned()],
        );
        let sub0_id = id(&sub0_member);
        let const0 = self.const_name(object, Some(sub0));
        let sub0_plan = self.entry(object, sub0, const0, quote!(#field.#sub0_id))?;
        let items_id = id("items");
        let mut items = Vec::new();
        for (i, sub) in object.subs.values().skip(1).enumerate() {
            let const_name = self.const_name(object, Some(sub));
            let pos = proc_macro2::Literal::usize_unsuffixed(i);
            let mut entry = self.entry_with_capacity(
                object,
                sub,
                const_name,
                quote!(#field.#items_id[#pos]),
                Some(cap),
            )?;
            entry.ty = elem;
            items.push(entry);
        }
        Some(ObjectPlan::Array {
            field: field.clone(),
            type_name: id(type_name),
            doc: doc.to_vec(),
            sub0: (sub0_id, sub0_plan),
            items_field: items_id,
            elem,
            items,
        })
    }

    fn const_name(&mut self, object: &Object, sub: Option<&SubObject>) -> Ident {
        let base = ident(
            &object.name,
            Case::Shouty,
            &format!("OBJECT_{:04X}", object.index),
        );
        let (wanted, suffixes) = match sub {
            None => (base, vec![format!("{:04X}", object.index)]),
            Some(sub) => {
                let sub_part = ident(&sub.name, Case::Shouty, &format!("SUB{}", sub.sub_index));
                let joined = if sub_part.starts_with("N_")
                    && sub_part[2..].starts_with(|c: char| c.is_ascii_digit())
                {
                    format!("{base}_{}", &sub_part[2..])
                } else {
                    format!("{base}_{sub_part}")
                };
                (
                    joined,
                    vec![
                        format!("SUB{}", sub.sub_index),
                        format!("{:04X}", object.index),
                    ],
                )
            }
        };
        let (name, changed) = self.consts.claim(&wanted, &suffixes);
        if changed {
            let span = sub.map_or(object.span, |s| s.span);
            self.renamed(span, "constant", &wanted, &name);
        }
        id(&name)
    }

    fn entry(
        &mut self,
        object: &Object,
        sub: &SubObject,
        const_name: Ident,
        path: TokenStream,
    ) -> Option<EntryPlan> {
        self.entry_with_capacity(object, sub, const_name, path, None)
    }

    fn entry_with_capacity(
        &mut self,
        object: &Object,
        sub: &SubObject,
        const_name: Ident,
        path: TokenStream,
        forced_capacity: Option<usize>,
    ) -> Option<EntryPlan> {
        let where_ = format!("{:04X}h sub {}", object.index, sub.sub_index);
        let Some(basic) = sub.data_type.and_then(|t| self.device.basic_type(t)) else {
            let what = match sub.data_type {
                Some(t) => format!("data type {t:04X}h is not a basic type"),
                None => "no data type".to_owned(),
            };
            self.diagnostics.push(
                Diagnostic::new(
                    &rules::UNREPRESENTABLE_TYPE,
                    Some(sub.span),
                    format!("{where_} `{}`: {what}; no Rust type can hold it", sub.name),
                )
                .with_help("give the entry a CiA 301 basic data type (0001h-001Bh)"),
            );
            return None;
        };
        let cap = forced_capacity.unwrap_or_else(|| capacity(basic, sub));
        if matches!(RustType::of(basic, 0), RustType::Bytes(_)) && cap > usize::from(u16::MAX) {
            self.diagnostics.push(Diagnostic::new(
                &rules::CAPACITY_TOO_LARGE,
                Some(sub.span),
                format!(
                    "{where_} `{}`: needs {cap} bytes; an entry holds at most 65535",
                    sub.name
                ),
            ));
            return None;
        }
        let ty = RustType::of(basic, cap);
        let (init, node_relative) = self.initial(sub, basic, ty, &where_)?;
        let limits = match ty {
            RustType::Scalar(prim, _) if prim != Prim::Bool => {
                self.limits(sub, basic, prim, &where_)
            }
            _ => None,
        };
        let access = sub.access.unwrap_or(AccessType::Ro);
        let title = if sub.name != object.name && object.object_type.has_subs() {
            format!("{}: {}", doc_text(&object.name), doc_text(&sub.name))
        } else {
            doc_text(&sub.name)
        };
        let mut facts = format!(
            "{:04X}h sub {}: {}, {}, {}",
            object.index,
            sub.sub_index,
            basic.name(),
            access.as_str(),
            if sub.pdo_mapping {
                "PDO-mappable"
            } else {
                "not PDO-mappable"
            }
        );
        if let RustType::Bytes(n) = ty {
            facts.push_str(&format!(", capacity {n} bytes"));
        }
        let value_text = |raw: &str| {
            raw.chars()
                .map(|c| match c {
                    '`' => '\'',
                    c if c.is_control() => ' ',
                    c => c,
                })
                .collect::<String>()
        };
        if let Some(p) = sub.parameter_value.as_ref().filter(|p| p.value.is_some()) {
            facts.push_str(&format!("; ParameterValue `{}`", value_text(&p.raw)));
        } else if let Some(d) = &sub.default {
            facts.push_str(&format!("; default `{}`", value_text(&d.raw)));
        }
        if sub.low_limit.is_some() || sub.high_limit.is_some() {
            facts.push_str(&format!(
                "; limits `{}` to `{}`",
                sub.low_limit
                    .as_ref()
                    .map_or("-".to_owned(), |v| value_text(&v.raw)),
                sub.high_limit
                    .as_ref()
                    .map_or("-".to_owned(), |v| value_text(&v.raw))
            ));
        }
        let mut extra = Vec::new();
        if let Some(d) = &sub.denotation {
            extra.push(format!(" Denotation: {}.", doc_text(d)));
        }
        for (key, value) in sub.custom.iter().chain(object.custom.iter()) {
            let k = key.to_ascii_lowercase();
            if matches!(k.as_str(), "unit" | "description" | "factor") {
                extra.push(format!(" {}: {}.", doc_text(key), doc_text(value)));
            }
        }
        let mut doc = vec![
            format!(" {title}"),
            String::new(),
            format!(" Object {facts}."),
        ];
        doc.extend(extra.iter().cloned());
        let mut short_doc = vec![format!(" {title} ({facts}).")];
        short_doc.extend(extra);
        Some(EntryPlan {
            index: object.index,
            sub: sub.sub_index,
            basic,
            ty,
            access,
            pdo_mappable: sub.pdo_mapping,
            init,
            node_relative,
            limits,
            doc,
            short_doc,
            const_name,
            path,
            pdo_name: ident(
                &sub.name,
                Case::Snake,
                &format!("object_{:04x}_{}", object.index, sub.sub_index),
            ),
        })
    }

    fn initial(
        &mut self,
        sub: &SubObject,
        basic: BasicType,
        ty: RustType,
        where_: &str,
    ) -> Option<(TokenStream, bool)> {
        let value = initial_value(sub);
        let source_span = sub
            .parameter_value
            .as_ref()
            .filter(|v| v.value.is_some())
            .or(sub.default.as_ref())
            .map_or(sub.span, |v| v.span);
        let Some(value) = value else {
            if sub
                .default
                .as_ref()
                .is_some_and(|d| d.value.is_none() && !d.raw.is_empty())
            {
                // The reader reported the unparseable value; generation cannot invent one.
                self.diagnostics.push(Diagnostic::new(
                    &rules::UNREPRESENTABLE_VALUE,
                    Some(source_span),
                    format!(
                        "{where_} `{}`: the default `{}` could not be read",
                        sub.name,
                        sub.default.as_ref().map_or("", |d| d.raw.as_str())
                    ),
                ));
                return None;
            }
            self.diagnostics.push(Diagnostic::new(
                &rules::NO_DEFAULT,
                Some(sub.span),
                format!(
                    "{where_} `{}` has no default value; it starts at zero or empty",
                    sub.name
                ),
            ));
            let zero = match ty {
                RustType::Scalar(Prim::Bool, _) => quote!(false),
                RustType::Scalar(Prim::F32 | Prim::F64, _) => quote!(0.0),
                RustType::Scalar(..) => quote!(0),
                RustType::Bytes(_) => quote!(::edsgen_runtime::FixedBytes::empty()),
            };
            return Some((zero, false));
        };
        let node_relative = matches!((ty, value), (RustType::Scalar(..), Value::NodeRelative(_)));
        let result = match (ty, value) {
            (RustType::Bytes(_), v) => match value_bytes(basic, v) {
                Some(bytes) => {
                    let lit = proc_macro2::Literal::byte_string(&bytes);
                    Ok(quote!(::edsgen_runtime::FixedBytes::from_slice(#lit)))
                }
                None => Err(ValueProblem::WrongKind),
            },
            (RustType::Scalar(prim, _), Value::NodeRelative(offset)) => {
                node_relative_tokens(*offset, basic, prim)
            }
            (RustType::Scalar(prim, _), v) => scalar_tokens(v, basic, prim),
        };
        match result {
            Ok(tokens) => Some((tokens, node_relative)),
            Err(problem) => {
                let why = match problem {
                    ValueProblem::OutOfRange => "is outside the range of",
                    ValueProblem::WrongKind => "is not a value of",
                };
                let raw = sub
                    .parameter_value
                    .as_ref()
                    .filter(|v| v.value.is_some())
                    .or(sub.default.as_ref())
                    .map_or("", |v| v.raw.as_str());
                self.diagnostics.push(Diagnostic::new(
                    &rules::UNREPRESENTABLE_VALUE,
                    Some(source_span),
                    format!("{where_} `{}`: `{raw}` {why} {}", sub.name, basic.name()),
                ));
                None
            }
        }
    }

    fn limits(
        &mut self,
        sub: &SubObject,
        basic: BasicType,
        prim: Prim,
        where_: &str,
    ) -> Option<(TokenStream, TokenStream)> {
        if sub.low_limit.is_none() && sub.high_limit.is_none() {
            return None;
        }
        let mut bound = |source: &Option<crate::model::ValueSource>,
                         is_low: bool|
         -> Option<TokenStream> {
            let ty = prim.tokens();
            let default = match (prim, is_low) {
                (Prim::F32 | Prim::F64, true) => quote!(#ty::NEG_INFINITY),
                (Prim::F32 | Prim::F64, false) => quote!(#ty::INFINITY),
                _ => {
                    let (min, max) = basic.integer_range().unwrap_or((0, 0));
                    types::int_literal(if is_low { min } else { max }, prim)
                }
            };
            let Some(source) = source else {
                return Some(default);
            };
            let parsed = match &source.value {
                Some(Value::NodeRelative(_)) | None => Err(ValueProblem::WrongKind),
                Some(v) => scalar_tokens(v, basic, prim),
            };
            match parsed {
                Ok(t) => Some(t),
                Err(_) => {
                    self.diagnostics.push(Diagnostic::new(
                        &rules::UNUSABLE_LIMIT,
                        Some(source.span),
                        format!(
                            "{where_} `{}`: the {} `{}` is not a constant {}; writes are not checked against it",
                            sub.name,
                            if is_low { "LowLimit" } else { "HighLimit" },
                            source.raw,
                            basic.name()
                        ),
                    ));
                    Some(default)
                }
            }
        };
        let low = bound(&sub.low_limit, true)?;
        let high = bound(&sub.high_limit, false)?;
        Some((low, high))
    }
}
