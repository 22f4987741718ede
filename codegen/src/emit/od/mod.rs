//! Tokens for the object dictionary of one device: the `Od` value image with `Od::new(node_id)`
//! and the typed `get`/`set`, the sorted `ENTRIES` descriptor table with the image's layout
//! (`OFFSETS`, `LIMITS`, `LAYOUT`), the `ObjectDictionary` implementation, and the typed addresses
//! in `od`. Why a byte image rather than a struct field per entry: `docs/generated-code.md`.

use std::fmt::Write as _;

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use super::plan::{EntryPlan, Initial, Plan};
use super::text::{self, Splices, ITEM_INDENT};
use super::types::{access_variant, data_type_variant, NumberTokens, Prim, RustType};

mod addresses;
mod fixed;
pub use addresses::addresses;

/// The `Od` struct (the value image), `Od::new` and the typed `get`/`set`; `DEFAULTS` as text.
pub fn structs(plan: &Plan, splices: &mut Splices) -> TokenStream {
    let size = Literal::usize_unsuffixed(plan.image_size);
    let stage_size = Literal::usize_unsuffixed(stage_size(plan));
    // Default values go into the default image, kept as runs of its non-zero bytes
    // (`DEFAULTS`); `$NODEID` ones hold their offset, to which `Od::new` adds the node-ID.
    let mut image = vec![0u8; plan.image_size];
    let mut node_relative = Vec::new();
    for e in &plan.entries {
        let at = e.offset;
        match (&e.init, e.ty) {
            // The wire bytes only: a negative INTEGER16 is FF FF, not 64 bits of ones.
            (Initial::Raw(raw) | Initial::NodeRelative(raw), RustType::Scalar(_, wire)) => {
                image[at..at + wire].copy_from_slice(&raw.to_le_bytes()[..wire]);
                if let Initial::NodeRelative(raw) = e.init {
                    node_relative.push((at, node_id_reach(raw, wire)));
                }
            }
            (Initial::Bytes(bytes), _) => {
                image[at..at + 2].copy_from_slice(&(bytes.len() as u16).to_le_bytes());
                image[at + 2..at + 2 + bytes.len()].copy_from_slice(bytes);
            }
            _ => {}
        }
    }
    let defaults = splices.item(defaults(plan, &image, &node_relative));
    let od = splices.item(fixed::od_struct());
    quote! {
        /// The size of the value image in bytes.
        const IMAGE_SIZE: usize = #size;

        /// The longest value an SDO download stages before it is written (the largest
        /// writable string, octet string or domain): a download changes its entry only once
        /// complete.
        pub const STAGE_SIZE: usize = #stage_size;

        #defaults

        #od
    }
}

/// How many low bytes of a `$NODEID` default of `wire` bytes holding `raw` (its offset from
/// the node-ID) a node-ID's carry can reach: the bytes above them are zero and stay so, so its
/// run in `DEFAULTS` leaves them out (`$NODEID+0x180` in an UNSIGNED32 needs 80 01 only).
fn node_id_reach(raw: u64, wire: usize) -> usize {
    let value = u128::from(raw) & ((1u128 << (8 * wire)) - 1);
    (1..wire)
        .find(|&bytes| value + 255 < 1u128 << (8 * bytes))
        .unwrap_or(wire)
}

/// `DEFAULTS`, the default image as runs (see [`default_runs`]), with its doc and the table of
/// the defaults it packs.
/// The staging room's size: the largest capacity of a writable string, octet string or domain
/// (0 when there is none). Read-only ones are never downloaded, fixed-size values are collected
/// by the SDO server itself.
fn stage_size(plan: &Plan) -> usize {
    plan.entries
        .iter()
        .filter(|e| e.access.writable())
        .filter_map(|e| match e.ty {
            RustType::Bytes(capacity) => Some(capacity),
            RustType::Scalar(..) => None,
        })
        .max()
        .unwrap_or(0)
}

fn defaults(plan: &Plan, image: &[u8], node_relative: &[(usize, usize)]) -> String {
    let mut out = String::new();
    let doc = [
        " The value image with every entry at its default, as runs of its non-zero bytes: a",
        " gap, a length and that many bytes each, a `$NODEID` default in a run of its own (its",
        " offset from the node-ID, which `Od::new` adds; see",
        " `edsgen_runtime::od::image::unpack_defaults`).",
    ];
    text::docs(&mut out, ITEM_INDENT, &doc);
    text::docs(&mut out, ITEM_INDENT, &default_table(plan));
    let runs = default_runs(image, node_relative);
    let head = format!("const DEFAULTS: [u8; {}] = ", runs.len());
    let runs = text::Decimals::new(runs.iter().map(|&b| u32::from(b)));
    text::literal_array(&mut out, ITEM_INDENT, &head, &runs.cells());
    out
}

/// The defaults `DEFAULTS` packs, readable: one doc line per entry whose default is not zero or
/// empty, `offset: NAME (index sub) = value`, in image order. Docs cost no flash.
fn default_table(plan: &Plan) -> Vec<String> {
    let mut lines = Vec::new();
    for e in &plan.entries {
        let value = match (&e.init, e.ty) {
            (Initial::Raw(0), _) => continue,
            (Initial::Raw(raw), RustType::Scalar(_, wire)) => {
                format!("0x{raw:0width$X}", width = wire * 2)
            }
            (Initial::NodeRelative(raw), _) => format!("$NODEID + 0x{raw:X}"),
            (Initial::Bytes(bytes), _) if bytes.is_empty() => continue,
            (Initial::Bytes(bytes), _) => match std::str::from_utf8(bytes) {
                Ok(text) if text.chars().all(|c| c.is_ascii_graphic() || c == ' ') => {
                    format!("{text:?}")
                }
                _ => bytes
                    .iter()
                    .map(|b| format!("{b:02X}"))
                    .collect::<Vec<_>>()
                    .join(" "),
            },
            _ => continue,
        };
        let value = if value.chars().count() > 60 {
            format!("{}...", value.chars().take(60).collect::<String>())
        } else {
            value
        };
        if lines.is_empty() {
            lines.push(String::new());
            lines.push(" The non-zero defaults, at their offset in the image:".to_owned());
            lines.push(String::new());
        }
        lines.push(format!(
            " - {:#06X}: `{}` ({:04X}h sub {}) = `{value}`",
            e.offset,
            e.path(),
            e.index,
            e.sub
        ));
    }
    lines
}

/// The runs `edsgen_runtime::od::image::unpack_defaults` turns back into `image`: for each stretch of
/// non-zero bytes, the gap since the previous run, the length and the bytes. Zero gaps of up to
/// two bytes stay inside a run (they cost what a new run's gap and length would); a gap longer
/// than 255 bytes or a stretch longer than 127 takes several runs. Each `$NODEID` default
/// (offset, bytes) in `node_relative` is a run of its own, its length marked with
/// `NODE_RELATIVE`: the bytes a node-ID's carry can reach, zeros included.
fn default_runs(image: &[u8], node_relative: &[(usize, usize)]) -> Vec<u8> {
    const LONGEST: usize = NODE_RELATIVE as usize - 1;
    // The width of the `$NODEID` default starting at each offset (0: none).
    let mut width_at = vec![0; image.len()];
    for &(at, width) in node_relative {
        width_at[at] = width;
    }
    let mut runs = Vec::new();
    let (mut end_of_previous, mut start) = (0usize, 0usize);
    while start < image.len() {
        let (end, mark) = if width_at[start] > 0 {
            (start + width_at[start], NODE_RELATIVE)
        } else if image[start] == 0 {
            start += 1;
            continue;
        } else {
            let mut end = start;
            while end < image.len() && end - start < LONGEST && width_at[end] == 0 {
                if image[end] != 0 {
                    end += 1;
                    continue;
                }
                let zeros = image[end..].iter().take_while(|&&b| b == 0).count();
                if zeros > 2
                    || end + zeros >= image.len()
                    || end + zeros - start >= LONGEST
                    || width_at[end..=end + zeros].iter().any(|&w| w > 0)
                {
                    break;
                }
                end += zeros;
            }
            (end, 0)
        };
        let mut gap = start - end_of_previous;
        while gap > 255 {
            runs.extend([255, 0]);
            gap -= 255;
        }
        runs.extend([gap as u8, (end - start) as u8 | mark]);
        runs.extend_from_slice(&image[start..end]);
        (end_of_previous, start) = (end, end);
    }
    runs
}

/// The bit of a run's length that marks a `$NODEID` default: the runtime's
/// `edsgen_runtime::od::image::NODE_RELATIVE`.
const NODE_RELATIVE: u8 = 0x80;

/// A static array's initialiser: `[]`, or the rows after the `use` of the short names they need.
fn array_body(rows: &[TokenStream], imports: TokenStream) -> TokenStream {
    if rows.is_empty() {
        quote!([])
    } else {
        quote!({
            #imports
            [#(#rows),*]
        })
    }
}

/// The `ENTRIES` table and the value image's layout (`OFFSETS` as text, `LIMITS`, `LAYOUT`).
pub fn descriptors(plan: &Plan, splices: &mut Splices) -> TokenStream {
    let tables = splices.item(entries_and_offsets(plan));
    let limits: Vec<_> = plan
        .entries
        .iter()
        .enumerate()
        .filter_map(|(position, e)| {
            let (low, high) = e.limits?;
            let RustType::Scalar(prim, _) = e.ty else {
                return None;
            };
            let constructor = match prim {
                Prim::Signed(_) => quote!(signed),
                Prim::F32 => quote!(real32),
                Prim::F64 => quote!(real64),
                _ => quote!(unsigned),
            };
            let (low, high) = (low.tokens(prim), high.tokens(prim));
            let position = Literal::u16_unsuffixed(position as u16);
            Some(quote!((#position, L::#constructor(#low, #high))))
        })
        .collect();
    let k = Literal::usize_unsuffixed(limits.len());
    let limits_body = array_body(
        &limits,
        quote!(
            use ::edsgen_runtime::support::Limit as L;
        ),
    );
    quote! {
        #tables

        /// LowLimit and HighLimit by position in `ENTRIES`, for the entries that have them.
        static LIMITS: [(u16, ::edsgen_runtime::support::Limit); #k] = #limits_body;

        /// How `Od` lays out its values: what the `ObjectDictionary` implementation and the typed
        /// `get`/`set` work from.
        static LAYOUT: ::edsgen_runtime::support::Layout =
            ::edsgen_runtime::support::Layout::new(&ENTRIES, &OFFSETS, &LIMITS, IMAGE_SIZE);
    }
}

/// `ENTRIES` (a row per entry) and `OFFSETS`, as text.
fn entries_and_offsets(plan: &Plan) -> String {
    // About 100 bytes an entry: one allocation for the whole item.
    let mut out = String::with_capacity(100 * plan.entries.len() + 256);
    let n = plan.entries.len();
    text::docs(
        &mut out,
        ITEM_INDENT,
        &[" Every entry's descriptor, sorted by (index, sub-index)."],
    );
    text::indent(&mut out, ITEM_INDENT);
    let _ = write!(
        out,
        "pub static ENTRIES: [::edsgen_runtime::EntryDescriptor; {n}] = "
    );
    if n == 0 {
        out.push_str("[];\n");
    } else {
        // `E::new(0xIIII, 0xSS, D::TYPE, A::ACCESS, PDO_MAPPABLE)`, written without the
        // formatter (thousands of rows).
        let row = |out: &mut String, e: &EntryPlan| {
            out.push_str("E::new(0x");
            text::push_hex4(out, e.index);
            out.push_str(", 0x");
            text::push_hex2(out, e.sub);
            out.push_str(", D::");
            out.push_str(data_type_variant(e.basic));
            out.push_str(", A::");
            out.push_str(access_variant(e.access));
            out.push_str(if e.pdo_mappable {
                ", true)"
            } else {
                ", false)"
            });
        };
        let inner = ITEM_INDENT + 4;
        out.push_str("{\n");
        text::indent(&mut out, inner);
        out.push_str("use ::edsgen_runtime::{Access as A, DataType as D, EntryDescriptor as E};\n");
        text::indent(&mut out, inner);
        // A row per line, written in place; one line if they all fit (the rows are not
        // literals: no filling).
        out.push_str("[\n");
        let rows_at = out.len();
        let mut one_line = inner;
        for e in &plan.entries {
            text::indent(&mut out, inner + 4);
            let at = out.len();
            row(&mut out, e);
            one_line += out.len() - at + 2;
            out.push_str(",\n");
        }
        if one_line <= text::MARGIN {
            out.truncate(rows_at - 2);
            out.push('[');
            for (i, e) in plan.entries.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                row(&mut out, e);
            }
            out.push_str("]\n");
        } else {
            text::indent(&mut out, inner);
            out.push_str("]\n");
        }
        text::indent(&mut out, ITEM_INDENT);
        out.push_str("};\n");
    }
    text::docs(
        &mut out,
        ITEM_INDENT,
        &[
            " Where each entry of `ENTRIES` starts in the value image (a string's or domain's",
            " capacity is the room up to the next one).",
        ],
    );
    // The planner keeps offsets below 65536 (EDS707).
    let offsets = text::Decimals::new(plan.entries.iter().map(|e| e.offset as u32));
    let head = format!("static OFFSETS: [u16; {n}] = ");
    text::literal_array(&mut out, ITEM_INDENT, &head, &offsets.cells());
    out
}

/// The node's optional services (`edsgen_runtime::Services`' fields), each with the objects it
/// cannot run without.
const SERVICE_OBJECTS: [(&str, &[u16]); 7] = [
    ("error_history", &[0x1003]),
    ("sync_period", &[0x1006]),
    ("sync_window", &[0x1007]),
    ("sync_counter", &[0x1019]),
    ("emcy_inhibit", &[0x1015]),
    ("life_guarding", &[0x100C, 0x100D]),
    ("second_sdo", &[0x1201]),
];

/// `SERVICES`, which of the node's optional services the dictionary has the objects of, and
/// `impl ObjectDictionary for Od` (the same in every module: `fixed::OD_IMPL`).
pub fn od_impl(plan: &Plan, splices: &mut Splices) -> TokenStream {
    let streamed_writes = plan
        .entries
        .iter()
        .any(|e| e.access.writable() && matches!(e.ty, RustType::Bytes(_)));
    let mut out = services(
        |index| plan.entries.iter().any(|e| e.index == index),
        streamed_writes,
    );
    out.push_str(fixed::OD_IMPL);
    splices.item(out)
}

/// `SERVICES`, for a dictionary that `has` the objects of some indices, and writable strings,
/// octet strings or domains if `streamed_writes`.
fn services(has: impl Fn(u16) -> bool, streamed_writes: bool) -> String {
    let mut out = String::with_capacity(512);
    text::docs(
        &mut out,
        ITEM_INDENT,
        &[
            " Which of the node's optional services this dictionary has the objects of: a node",
            " builds no code for the others.",
        ],
    );
    text::indent(&mut out, ITEM_INDENT);
    out.push_str("const SERVICES: ::edsgen_runtime::Services = ::edsgen_runtime::Services {\n");
    for (field, objects) in SERVICE_OBJECTS {
        text::indent(&mut out, ITEM_INDENT + 4);
        let _ = writeln!(out, "{field}: {},", objects.iter().all(|&index| has(index)));
    }
    text::indent(&mut out, ITEM_INDENT + 4);
    let _ = writeln!(out, "streamed_writes: {streamed_writes},");
    text::indent(&mut out, ITEM_INDENT);
    out.push_str("};\n");
    out
}

#[cfg(test)]
mod tests {
    use super::{default_runs, node_id_reach, services, NODE_RELATIVE};
    use edsgen_runtime::od::image::unpack_defaults;
    use proptest::prelude::*;

    fn unpacked(runs: &[u8], len: usize, node_id: u8) -> Vec<u8> {
        let mut values = vec![0; len];
        unpack_defaults(&mut values, runs, node_id);
        values
    }

    #[test]
    fn runs_skip_zeros_and_keep_short_zero_gaps_inside() {
        assert_eq!(default_runs(&[0; 9], &[]), Vec::<u8>::new());
        assert_eq!(default_runs(&[0, 0, 5], &[]), vec![2, 1, 5]);
        // Two zeros stay inside the run, three start a new one.
        assert_eq!(default_runs(&[1, 0, 0, 2], &[]), vec![0, 4, 1, 0, 0, 2]);
        assert_eq!(
            default_runs(&[1, 0, 0, 0, 2, 0], &[]),
            vec![0, 1, 1, 3, 1, 2]
        );
        // A gap of 300 zeros takes an empty run of gap 255 first.
        let mut image = vec![0; 301];
        image[300] = 7;
        assert_eq!(default_runs(&image, &[]), vec![255, 0, 45, 1, 7]);
        // 300 non-zero bytes take three runs.
        let runs = default_runs(&[9; 300], &[]);
        assert_eq!(runs.len(), 2 + 127 + 2 + 127 + 2 + 46);
        assert_eq!((runs[0], runs[1], runs[129], runs[258]), (0, 127, 0, 0));
        assert_eq!((runs[130], runs[259]), (127, 46));
    }

    #[test]
    fn a_node_id_run_holds_the_bytes_a_carry_can_reach() {
        assert_eq!(node_id_reach(0x180, 4), 2);
        assert_eq!(node_id_reach(0x80, 4), 2);
        assert_eq!(node_id_reach(0, 4), 1);
        assert_eq!(node_id_reach(0, 1), 1);
        assert_eq!(node_id_reach(0xFF00, 2), 2);
        assert_eq!(node_id_reach(0xFEFF, 4), 2);
        assert_eq!(node_id_reach(0xFF01, 4), 3);
        assert_eq!(node_id_reach(u64::MAX, 8), 8);
    }

    #[test]
    fn the_node_id_mark_is_the_runtimes() {
        assert_eq!(NODE_RELATIVE, edsgen_runtime::od::image::NODE_RELATIVE);
    }

    #[test]
    fn a_node_id_default_is_a_run_of_its_own_with_its_zeros() {
        // `$NODEID+0x180` (4 bytes) after a 1 and before a 2: neither run takes it in.
        let image = [1, 0, 0x80, 0x01, 0, 0, 2];
        assert_eq!(
            default_runs(&image, &[(1, 4)]),
            vec![0, 1, 1, 0, 0x84, 0, 0x80, 0x01, 0, 1, 1, 2]
        );
        assert_eq!(
            unpacked(&default_runs(&image, &[(1, 4)]), 7, 5),
            [1, 5, 0x80, 0x01, 0, 0, 2]
        );
        // A zero default (`$NODEID` alone) still has its run.
        assert_eq!(default_runs(&[0, 0], &[(0, 2)]), vec![0, 0x82, 0, 0]);
    }

    proptest! {
        /// Whatever the image, its runs unpack to exactly it.
        #[test]
        fn runs_unpack_to_the_image(
            image in proptest::collection::vec(prop_oneof![4 => Just(0u8), 1 => any::<u8>()], 0..700),
        ) {
            prop_assert_eq!(unpacked(&default_runs(&image, &[]), image.len(), 0), image);
        }
    }

    #[test]
    fn services_say_which_service_objects_the_dictionary_has() {
        let cp301 = services(
            |index| matches!(index, 0x1000..=0x1018 if index != 0x1003),
            false,
        );
        assert!(cp301.contains("error_history: false,\n"));
        assert!(cp301.contains("sync_period: true,\n"));
        assert!(cp301.contains("emcy_inhibit: true,\n"));
        // Life guarding needs both 100Ch and 100Dh.
        assert!(cp301.contains("life_guarding: true,\n"));
        assert!(cp301.contains("second_sdo: false,\n"));
        assert!(cp301.contains("streamed_writes: false,\n"));
        let guard_time_only = services(|index| index == 0x100C, true);
        assert!(guard_time_only.contains("life_guarding: false,\n"));
        assert!(guard_time_only.contains("streamed_writes: true,\n"));
        // As prettyplease prints it.
        let module = format!("mod m {{\n{cp301}}}\n");
        let file: syn::File = syn::parse_str(&module).expect("parses");
        assert_eq!(prettyplease::unparse(&file), module);
    }
}
