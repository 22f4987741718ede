//! The plan: the typed-address name and rustdoc of each stored entry, beside its Rust type,
//! initial value and limits (`edsgen_model::values`). Built from the model in (index, sub) order
//! so names and output are deterministic; every problem becomes an `EDS7xx` diagnostic.

use std::fmt::Write as _;
use std::ops::Range;
use std::rc::Rc;

use proc_macro2::{Ident, Span as TokenSpan};

use super::names::{ident, member_name, Case, Namespace};
use super::text::{decimal_digits, push_decimal, push_hex4};
use super::types::{Number, RustType};
use edsgen_model::diag::Diagnostic;
use edsgen_model::model::{AccessType, BasicType, Device, Object, SubObject};
use edsgen_model::rules;
pub use edsgen_model::values::Initial;
use edsgen_model::values::{entry_value, entry_value_without_infos, EntryValue};

use super::Infos;

/// Everything the emitter needs to know about one stored entry (borrowing its names from the
/// device).
#[derive(Debug, Clone)]
pub struct EntryPlan<'a> {
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
    /// The initial value.
    pub init: Initial,
    /// LowLimit and HighLimit, when the entry has at least one usable limit (the type's range,
    /// or an infinity for a REAL, stands in for the missing one).
    pub limits: Option<(Number, Number)>,
    /// Whether the entry's rustdoc name is `Object: Sub` (a sub-entry named apart from its
    /// object), or its own name alone (see [`EntryPlan::title`]).
    pub titled_by_object: bool,
    /// The typed address's rustdoc: where its first line (name, place, type, access, value) is
    /// in the plan's text ([`Plan::doc`]).
    pub doc: Range<usize>,
    /// Its further lines (the entry's Denotation, unit, description and factor), if any.
    pub notes: Vec<String>,
    /// The typed-address constant's name: in `od` for a VAR, in the object's module otherwise
    /// (shared with the namespace that gave it).
    pub const_name: Rc<str>,
    /// The module in `od` of the ARRAY or RECORD the entry belongs to (`None` for a VAR); one
    /// shared by the object's entries.
    pub module: Option<Rc<str>>,
    /// The name of the entry's object, escaped for rustdoc; one shared by the object's entries.
    pub object_title: Rc<str>,
    /// Where the value starts in the value image (set once the whole device is planned).
    pub offset: usize,
    /// The entry's own name in the file (a sub-object's, not its object's).
    pub own_name: &'a str,
}

impl EntryPlan<'_> {
    /// The typed address's path from `od`: `CONTROLWORD`, `identity_object::VENDOR_ID`.
    pub fn path(&self) -> String {
        match &self.module {
            Some(module) => format!("{module}::{}", self.const_name),
            None => self.const_name.to_string(),
        }
    }

    /// The entry's name for rustdoc (`Object: Sub` for a sub-entry), escaped.
    pub fn title(&self) -> String {
        let mut title = String::with_capacity(self.object_title.len() + self.own_name.len() + 8);
        self.push_title(&mut title);
        title
    }

    /// [`Self::title`] appended to `out` (written straight into the entry's rustdoc).
    fn push_title(&self, out: &mut String) {
        if self.titled_by_object {
            out.push_str(&self.object_title);
            out.push_str(": ");
        }
        push_doc_text(out, self.own_name);
    }

    /// The field name for PDO structs mapping this entry: snake case of its own name. Made
    /// when a PDO needs it (case conversion of every entry's name was a fifth of the planning).
    pub fn pdo_name(&self) -> String {
        ident(
            self.own_name,
            Case::Snake,
            &format!("object_{:04x}_{}", self.index, self.sub),
        )
    }
}

/// The plan for a whole device.
#[derive(Debug)]
pub struct Plan<'a> {
    /// Stored entries in (index, sub-index) order: their order in `ENTRIES` and the image.
    pub entries: Vec<EntryPlan<'a>>,
    /// The value image's size in bytes: every entry's [`RustType::image_size`].
    pub image_size: usize,
    /// Diagnostics found while planning.
    pub diagnostics: Vec<Diagnostic>,
    /// The entries' rustdoc lines, one after the other (see [`Plan::doc`]).
    docs: String,
}

impl Plan<'_> {
    /// The first line of an entry's rustdoc (see [`EntryPlan::doc`]).
    pub fn doc(&self, entry: &EntryPlan) -> &str {
        &self.docs[entry.doc.clone()]
    }

    /// The entry at (index, sub), if stored.
    pub fn entry(&self, index: u16, sub: u8) -> Option<&EntryPlan<'_>> {
        // In (index, sub-index) order: a binary search, not a scan per PDO-mapped entry.
        self.entries
            .binary_search_by_key(&(index, sub), |e| (e.index, e.sub))
            .ok()
            .map(|at| &self.entries[at])
    }
}

pub(crate) fn id(name: &str) -> Ident {
    Ident::new(name, TokenSpan::call_site())
}

/// Text from the file as a rustdoc code span, shown exactly as written (no escapes, which a
/// code span would show): in backticks, or fenced by more backticks when it holds some.
pub fn code_span(text: &str) -> String {
    let text: String = text
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    // A span holding backticks is fenced by one more than its longest run, padded by spaces.
    let longest = text.split(|c| c != '`').map(str::len).max().unwrap_or(0);
    if longest == 0 {
        return format!("`{text}`");
    }
    let fence = "`".repeat(longest + 1);
    format!("{fence} {text} {fence}")
}

/// Escapes text from the file for rustdoc: no links, no HTML, no control characters. Inside a
/// code span use [`code_span`], where an escape would show.
pub fn doc_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    push_doc_text(&mut out, text);
    out
}

/// [`doc_text`] appended to `out` (an entry's title is written straight into its string).
pub fn push_doc_text(out: &mut String, text: &str) {
    // Most text needs no escape: copied whole, not char by char (slow in a debug build script),
    // after one table look-up a byte.
    if text.bytes().all(|b| PLAIN[usize::from(b)]) {
        out.push_str(text);
        return;
    }
    out.reserve(text.len());
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
}

/// The bytes [`push_doc_text`] copies as they are: printable ASCII but what rustdoc's markdown
/// would read.
const PLAIN: [bool; 256] = {
    let mut plain = [false; 256];
    let mut b = b' ';
    while b <= b'~' {
        plain[b as usize] = !matches!(
            b,
            b'[' | b']' | b'<' | b'>' | b'`' | b'*' | b'_' | b'\\' | b'#'
        );
        b += 1;
    }
    plain
};

struct Planner<'a> {
    device: &'a Device,
    diagnostics: Vec<Diagnostic>,
    infos: Infos,
    /// The constants of `od` (VAR objects).
    consts: Namespace,
    /// The modules of `od` (ARRAY and RECORD objects).
    modules: Namespace,
    /// The buffer a member's wanted name is written into.
    wanted: String,
    /// The entries' rustdoc lines ([`Plan::doc`]).
    docs: String,
}

/// Plans every stored object of `device` (objects from 1000h on; data type definitions below
/// that are not stored).
pub fn plan(device: &Device) -> Plan<'_> {
    plan_reporting(device, Infos::Reported)
}

/// [`plan`], making its infos (EDS705) only when `infos` says so.
pub fn plan_reporting(device: &Device, infos: Infos) -> Plan<'_> {
    plan_checked(device, infos, Sizes::Unchecked)
}

/// Whether the device's sizes (EDS707, `edsgen_model::validate::size_errors`) are known to be
/// within the generator's limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sizes {
    /// Validation found no error in the device: the planner does not check them again.
    Validated,
    /// Not known: the planner checks them.
    Unchecked,
}

/// [`plan_reporting`], checking the device's sizes only when `sizes` says they are not known.
pub fn plan_checked(device: &Device, infos: Infos, sizes: Sizes) -> Plan<'_> {
    let diagnostics = match sizes {
        Sizes::Validated => Vec::new(),
        Sizes::Unchecked => edsgen_model::validate::size_errors(device),
    };
    let stored = device
        .objects
        .range(0x1000..)
        .map(|(_, o)| o.subs.len())
        .sum();
    let mut p = Planner {
        device,
        diagnostics,
        infos,
        consts: Namespace::default(),
        modules: Namespace::default(),
        wanted: String::new(),
        // About 130 bytes a line.
        docs: String::with_capacity(130 * stored),
    };
    let mut entries: Vec<EntryPlan> = Vec::with_capacity(stored);
    let mut image_size = 0usize;
    for object in device.objects.values() {
        if object.index < 0x1000 || object.subs.is_empty() {
            continue;
        }
        let first = entries.len();
        p.object(object, &mut entries);
        for entry in &mut entries[first..] {
            entry.offset = image_size;
            image_size += entry.ty.image_size();
        }
    }
    Plan {
        entries,
        image_size,
        diagnostics: p.diagnostics,
        docs: p.docs,
    }
}

impl<'a> Planner<'a> {
    fn renamed(&mut self, span: edsgen_model::model::Span, what: &str, wanted: &str, got: &str) {
        self.diagnostics.push(
            Diagnostic::new(
                &rules::NAME_COLLISION,
                Some(span),
                format!("the {what} name `{wanted}` is already used; this one is `{got}`"),
            )
            .with_label("renamed in the generated code"),
        );
    }

    /// Appends the entries of one object to `entries`: all of them, or none when one cannot be
    /// represented (its diagnostic says why), so that an object is never half there. (Planned
    /// in place: an entry moved through a vector per object was a tenth of the planning.)
    fn object(&mut self, object: &'a Object, entries: &mut Vec<EntryPlan<'a>>) {
        if !object.object_type.has_subs() {
            let Some(sub) = object.subs.get(&0).or_else(|| object.subs.values().next()) else {
                return;
            };
            let base = self.base_name(object);
            let const_name = self.var_name(object, base);
            let object_title: Rc<str> = doc_text(&object.name).into();
            self.entry(object, sub, const_name, &object_title, None, entries);
            return;
        }
        let first = entries.len();
        let mut ok = true;
        let base = self.base_name(object);
        let module = self.module_name(object);
        let object_title: Rc<str> = doc_text(&object.name).into();
        let numbering = self.numbering(object);
        let mut members = Namespace::with_capacity(object.subs.len());
        for sub in object.subs.values() {
            let const_name = self.member_name(object, &base, numbering, sub, &mut members);
            let module = Some(Rc::clone(&module));
            ok &= self.entry(object, sub, const_name, &object_title, module, entries);
        }
        if !ok {
            entries.truncate(first);
        }
    }

    /// The object's part of its constants' names (made once per object, not per entry).
    fn base_name(&self, object: &Object) -> String {
        ident(
            self.device
                .naming
                .objects
                .get(&object.index)
                .unwrap_or(&object.name),
            Case::Shouty,
            &format!("OBJECT_{:04X}", object.index),
        )
    }

    /// A VAR's constant in `od`: the overlay's name of its entry or object, else the object's.
    fn var_name(&mut self, object: &Object, base: String) -> Rc<str> {
        let wanted = match self.device.naming.entries.get(&(object.index, 0)) {
            Some(name) => ident(name, Case::Shouty, "SUB0"),
            None => base,
        };
        let (name, renamed) = self.consts.claim_with(&wanted, object.index, || {
            vec![format!("{:04X}", object.index)]
        });
        if let Some(wanted) = renamed {
            self.renamed(object.span, "constant", &wanted, &name);
        }
        name
    }

    /// An ARRAY's or RECORD's module in `od`: the snake case of its (overlay's) name.
    fn module_name(&mut self, object: &Object) -> Rc<str> {
        let name = self
            .device
            .naming
            .objects
            .get(&object.index)
            .unwrap_or(&object.name);
        let wanted = ident(name, Case::Snake, &format!("object_{:04x}", object.index));
        let (name, renamed) = self.modules.claim_with(&wanted, object.index, || {
            vec![format!("{:04x}", object.index)]
        });
        if let Some(wanted) = renamed {
            self.renamed(object.span, "module", &wanted, &name);
        }
        name
    }

    /// The device's numbering of an ARRAY's elements (the overlay's [numbering]): the number of
    /// sub-index 1 and the digits every number is written with (the highest one's).
    fn numbering(&self, object: &Object) -> Option<(u32, usize)> {
        let first = *self.device.naming.first_number.get(&object.index)?;
        let highest = object.subs.keys().next_back().map_or(0, |s| u32::from(*s));
        let width = decimal_digits(highest.saturating_sub(1) + first);
        Some((first, width))
    }

    /// A member's constant in its object's module: the overlay's name, the device's numbering of
    /// an array's elements (`numbering`), else what its name adds to the object's (see
    /// [`member_name`]).
    fn member_name(
        &mut self,
        object: &Object,
        base: &str,
        numbering: Option<(u32, usize)>,
        sub: &SubObject,
        members: &mut Namespace,
    ) -> Rc<str> {
        let naming = &self.device.naming;
        let sub_index = sub.sub_index;
        // Written into one buffer for every member (the namespace keeps its own copy).
        let mut wanted = std::mem::take(&mut self.wanted);
        wanted.clear();
        if let Some(name) = naming.entries.get(&(object.index, sub_index)) {
            wanted.push_str(&ident(name, Case::Shouty, &format!("SUB{sub_index}")));
        } else if let Some((first, width)) = numbering.filter(|_| sub_index >= 1) {
            let number = u32::from(sub_index - 1) + first;
            wanted.push_str(base);
            wanted.push('_');
            for _ in decimal_digits(number)..width {
                wanted.push('0');
            }
            push_decimal(&mut wanted, number);
        } else {
            let own = ident(&sub.name, Case::Shouty, &format!("SUB{sub_index}"));
            wanted.push_str(&member_name(base, &own, sub_index));
        }
        let (name, renamed) =
            members.claim_with(&wanted, object.index, || vec![format!("SUB{sub_index}")]);
        self.wanted = wanted;
        if let Some(wanted) = renamed {
            self.renamed(sub.span, "constant", &wanted, &name);
        }
        name
    }

    /// Appends one entry's plan to `entries`, or returns `false` when it cannot be represented;
    /// `object_title` is the object's name escaped for rustdoc (made once per object).
    fn entry(
        &mut self,
        object: &'a Object,
        sub: &'a SubObject,
        const_name: Rc<str>,
        object_title: &Rc<str>,
        module: Option<Rc<str>>,
        entries: &mut Vec<EntryPlan<'a>>,
    ) -> bool {
        let value = match self.infos {
            Infos::Reported => entry_value(self.device, object, sub, &mut self.diagnostics),
            Infos::Skipped => {
                entry_value_without_infos(self.device, object, sub, &mut self.diagnostics)
            }
        };
        let Some(EntryValue {
            basic,
            ty,
            access,
            init,
            limits,
            ..
        }) = value
        else {
            return false;
        };
        // ` TITLE (IIIIh sub S: TYPE, ACCESS, PDO-mappable[, capacity N bytes][; default `V`]
        // [; limits `L` to `H`]).`, written in one string sized for it (formatting piece by
        // piece into growing strings was most of the planning).
        let mut entry = EntryPlan {
            index: object.index,
            sub: sub.sub_index,
            basic,
            ty,
            access,
            pdo_mappable: sub.pdo_mapping,
            init,
            limits,
            titled_by_object: sub.name != object.name && object.object_type.has_subs(),
            doc: 0..0,
            notes: Vec::new(),
            const_name,
            module,
            object_title: Rc::clone(object_title),
            offset: 0,
            own_name: &sub.name,
        };
        // Appended to the plan's text, where every entry's line is (a string each was a tenth of
        // generating a dictionary of arrays, made and freed).
        let mut doc = std::mem::take(&mut self.docs);
        let start = doc.len();
        doc.push(' ');
        entry.push_title(&mut doc);
        doc.push_str(" (");
        push_hex4(&mut doc, object.index);
        doc.push_str("h sub ");
        push_decimal(&mut doc, u32::from(sub.sub_index));
        doc.push_str(": ");
        doc.push_str(basic.name());
        doc.push_str(", ");
        doc.push_str(access.as_str());
        doc.push_str(if sub.pdo_mapping {
            ", PDO-mappable"
        } else {
            ", not PDO-mappable"
        });
        if let RustType::Bytes(n) = ty {
            let _ = write!(doc, ", capacity {n} bytes");
        }
        // A value from the file in backticks: a backtick in it becomes `'`, a control
        // character a space.
        let value_text = |doc: &mut String, raw: &str| {
            if raw.bytes().all(|b| b != b'`' && !b.is_ascii_control()) && raw.is_ascii() {
                doc.push_str(raw);
                return;
            }
            doc.extend(raw.chars().map(|c| match c {
                '`' => '\'',
                c if c.is_control() => ' ',
                c => c,
            }));
        };
        if let Some(p) = sub.parameter_value.as_ref().filter(|p| p.value.is_some()) {
            doc.push_str("; ParameterValue `");
            value_text(&mut doc, &p.raw);
            doc.push('`');
        } else if let Some(d) = &sub.default {
            doc.push_str("; default `");
            value_text(&mut doc, &d.raw);
            doc.push('`');
        }
        if sub.low_limit.is_some() || sub.high_limit.is_some() {
            doc.push_str("; limits `");
            match &sub.low_limit {
                Some(v) => value_text(&mut doc, &v.raw),
                None => doc.push('-'),
            }
            doc.push_str("` to `");
            match &sub.high_limit {
                Some(v) => value_text(&mut doc, &v.raw),
                None => doc.push('-'),
            }
            doc.push('`');
        }
        doc.push_str(").");
        entry.doc = start..doc.len();
        self.docs = doc;
        if let Some(d) = &sub.denotation {
            entry.notes.push(format!(" Denotation: {}.", doc_text(d)));
        }
        for (key, value) in sub.custom.iter().chain(object.custom.iter()) {
            if ["unit", "description", "factor"]
                .iter()
                .any(|k| key.eq_ignore_ascii_case(k))
            {
                entry
                    .notes
                    .push(format!(" {}: {}.", doc_text(key), doc_text(value)));
            }
        }
        entries.push(entry);
        true
    }
}
