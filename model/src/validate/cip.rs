//! The ODVA EDS rules (CIP005, CIP010..CIP032): the identity a scanner matches, parameters against
//! their data types and limits, enumerations against parameters, assemblies against their
//! members and the members against their parameters, and connections against the assemblies
//! their sizes, formats and paths name.
//!
//! Policy as for the other formats: an error where a scanner configured from the file would open
//! a connection the device refuses, or read a value the device would not hold; a warning where
//! the file is merely odd.

use crate::diag::Diagnostic;
use crate::model::{
    data_type_info, data_type_range, decode_path, Cip, CipAssembly, CipConnection, CipNumber,
    CipParam, FieldRef, PathSegment, Spanned,
};
use crate::rules;

/// Judges the CIP part of a device read from an ODVA EDS.
pub fn check(cip: &Cip, out: &mut Vec<Diagnostic>) {
    identity(cip, out);
    for param in cip.params.values() {
        param_type(param, out);
        param_limits(param, out);
    }
    for e in cip.enums.values() {
        if !cip.params.contains_key(&e.number) {
            out.push(
                Diagnostic::new(
                    &rules::CIP_ENUM_ORPHAN,
                    Some(e.span),
                    format!(
                        "Enum{} names the values of Param{}, which the file does not have",
                        e.number, e.number
                    ),
                )
                .with_label("no such parameter"),
            );
        }
    }
    for assembly in cip.assemblies.values() {
        assembly_members(cip, assembly, out);
        member_params(cip, assembly, out);
    }
    for connection in cip.connections.values() {
        connection_refs(cip, connection, out);
        connection_sizes(cip, connection, out);
        connection_path(cip, connection, out);
        connection_words(connection, out);
    }
}

fn identity(cip: &Cip, out: &mut Vec<Diagnostic>) {
    if cip.file.span.is_none() {
        out.push(Diagnostic::new(
            &rules::CIP_IDENTITY,
            None,
            "the file has no [File] section",
        ));
    }
    let id = &cip.identity;
    let Some(span) = id.span else {
        out.push(
            Diagnostic::new(
                &rules::CIP_IDENTITY,
                None,
                "the file has no [Device] section",
            )
            .with_help("a scanner matches VendCode, ProdType, ProdCode, MajRev and MinRev"),
        );
        return;
    };
    let missing: Vec<&str> = [
        ("VendCode", id.vendor_code.is_none()),
        ("ProdType", id.product_type.is_none()),
        ("ProdCode", id.product_code.is_none()),
        ("MajRev", id.major_revision.is_none()),
        ("MinRev", id.minor_revision.is_none()),
        ("ProdName", id.product_name.is_none()),
    ]
    .into_iter()
    .filter(|(_, missing)| *missing)
    .map(|(k, _)| k)
    .collect();
    if !missing.is_empty() {
        out.push(
            Diagnostic::new(
                &rules::CIP_IDENTITY,
                Some(span),
                format!("[Device] has no {}", missing.join(", ")),
            )
            .with_label("identity incomplete")
            .with_help("a scanner's electronic key compares these with the Identity object"),
        );
    }
}

fn param_type(param: &CipParam, out: &mut Vec<Diagnostic>) {
    let Some(data_type) = &param.data_type else {
        return;
    };
    let Some((name, size)) = data_type_info(data_type.value) else {
        out.push(
            Diagnostic::new(
                &rules::CIP_DATA_TYPE,
                Some(data_type.span),
                format!(
                    "Param{} `{}` has data type {:#04X}, not a CIP elementary type",
                    param.number, param.name, data_type.value
                ),
            )
            .with_label("unknown data type")
            .with_help(
                "elementary types are 0xC1 (BOOL) to 0xDE (STRINGI): 0xC7 is UINT, 0xC3 INT",
            ),
        );
        return;
    };
    if let (Some(size), Some(written)) = (size, &param.data_size) {
        if written.value != size {
            out.push(
                Diagnostic::new(
                    &rules::CIP_DATA_TYPE,
                    Some(written.span),
                    format!(
                        "Param{} `{}` is {name} ({size} byte{}) but its data size says {}",
                        param.number,
                        param.name,
                        if size == 1 { "" } else { "s" },
                        written.value
                    ),
                )
                .with_label(format!("{name} takes {size}"))
                .with_help(format!(
                    "set the data size to {size}, or the type to one of {} bytes",
                    written.value
                )),
            );
        }
    }
}

fn show(n: CipNumber) -> String {
    match n {
        CipNumber::Int(v) => v.to_string(),
        CipNumber::Real(v) => v.to_string(),
    }
}

fn param_limits(param: &CipParam, out: &mut Vec<Diagnostic>) {
    let what = format!("Param{} `{}`", param.number, param.name);
    if let Some(range) = param
        .data_type
        .as_ref()
        .and_then(|t| data_type_range(t.value))
    {
        for (label, value) in [
            ("minimum", &param.min),
            ("maximum", &param.max),
            ("default", &param.default),
        ] {
            let Some(Spanned {
                value: CipNumber::Int(v),
                span,
            }) = value
            else {
                continue;
            };
            if *v < range.0 || *v > range.1 {
                out.push(
                    Diagnostic::new(
                        &rules::CIP_LIMITS,
                        Some(*span),
                        format!(
                            "the {label} of {what}, {v}, is outside its data type ({}..={})",
                            range.0, range.1
                        ),
                    )
                    .with_label("outside the type"),
                );
            }
        }
    }
    if let (Some(min), Some(max)) = (&param.min, &param.max) {
        if min.value.as_f64() > max.value.as_f64() {
            out.push(
                Diagnostic::new(
                    &rules::CIP_LIMITS,
                    Some(min.span),
                    format!(
                        "the minimum of {what}, {}, exceeds its maximum, {}",
                        show(min.value),
                        show(max.value)
                    ),
                )
                .with_label("minimum above maximum"),
            );
            return;
        }
    }
    let Some(default) = &param.default else {
        return;
    };
    let d = default.value.as_f64();
    let below = param.min.as_ref().filter(|m| d < m.value.as_f64());
    let above = param.max.as_ref().filter(|m| d > m.value.as_f64());
    if let Some((side, limit)) = below
        .map(|m| ("minimum", m))
        .or(above.map(|m| ("maximum", m)))
    {
        out.push(
            Diagnostic::new(
                &rules::CIP_LIMITS,
                Some(default.span),
                format!(
                    "the default of {what}, {}, is {} its {side}, {}",
                    show(default.value),
                    if side == "minimum" { "below" } else { "above" },
                    show(limit.value)
                ),
            )
            .with_label("default outside the limits"),
        );
    }
}

fn missing_ref(cip: &Cip, r: &FieldRef) -> Option<String> {
    match r {
        FieldRef::Param(n) if !cip.params.contains_key(n) => Some(format!("Param{n}")),
        FieldRef::Assem(n) if !cip.assemblies.contains_key(n) => Some(format!("Assem{n}")),
        _ => None,
    }
}

fn assembly_members(cip: &Cip, assembly: &CipAssembly, out: &mut Vec<Diagnostic>) {
    for m in &assembly.members {
        if let Some(name) = missing_ref(cip, &m.member) {
            out.push(
                Diagnostic::new(
                    &rules::CIP_MISSING_REF,
                    Some(m.span),
                    format!(
                        "a member of Assem{} `{}` is {name}, which the file does not have",
                        assembly.number, assembly.name
                    ),
                )
                .with_label("no such entry"),
            );
        }
    }
    let (Some(size), false) = (&assembly.size, assembly.members.is_empty()) else {
        return;
    };
    let Some(bits) = cip.members_bits(assembly) else {
        return;
    };
    // The last byte may be partly used: members that fill the size rounded up to bytes agree.
    if bits.div_ceil(8) != u64::from(size.value) {
        out.push(
            Diagnostic::new(
                &rules::CIP_ASSEMBLY_SIZE,
                Some(size.span),
                format!(
                    "Assem{} `{}` is {} bytes ({} bits) but its {} members add up to {bits} bits",
                    assembly.number,
                    assembly.name,
                    size.value,
                    u64::from(size.value) * 8,
                    assembly.members.len()
                ),
            )
            .with_label("size of the assembly")
            .with_help(size_help(bits, u64::from(size.value))),
        );
    }
}

/// CIP020's help: the reading of the members nearer the size (bits, or bytes as some authors
/// write them), and both ways to agree, since the file does not say which is wrong.
fn size_help(bits: u64, size: u64) -> String {
    let filled = bits.div_ceil(8);
    if bits.abs_diff(size) < filled.abs_diff(size) {
        return format!(
            "read as bytes, as this file may write them, the members make {bits} bytes, not \
             {size} either: correct the members or the size, whichever is wrong"
        );
    }
    let low = size.saturating_sub(1) * 8 + 1;
    format!(
        "read as bits, the members fill {filled} byte{s}, not {size}: correct the members (to \
         {low} to {high} bits) or the size (to {filled}), whichever is wrong",
        s = if filled == 1 { "" } else { "s" },
        high = size * 8,
    )
}

/// CIP023: each member that names a parameter against the parameter's data size. A BOOL or a
/// bit string (BYTE, WORD, DWORD, LWORD) may take fewer bits: single bits are packed.
fn member_params(cip: &Cip, assembly: &CipAssembly, out: &mut Vec<Diagnostic>) {
    for m in &assembly.members {
        // A member of 0 bits holds nothing: a placeholder, not a size.
        let (Some(bits @ 1..), FieldRef::Param(n)) = (m.bits, &m.member) else {
            continue;
        };
        let Some(param) = cip.params.get(n) else {
            continue;
        };
        let Some(size) = param.data_size.as_ref().map(|s| u64::from(s.value) * 8) else {
            continue;
        };
        // A data size that disagrees with the type is CIP010's: which one is meant is unknown.
        let typed = param
            .data_type
            .as_ref()
            .and_then(|t| data_type_info(t.value));
        if typed.is_some_and(|(_, bytes)| bytes.is_some_and(|b| u64::from(b) * 8 != size)) {
            continue;
        }
        let packed = param
            .data_type
            .as_ref()
            .is_some_and(|t| matches!(t.value, 0xC1 | 0xD1..=0xD4));
        let bits = u64::from(bits);
        if bits == size || (packed && bits < size) {
            continue;
        }
        out.push(
            Diagnostic::new(
                &rules::CIP_MEMBER_PARAM,
                Some(m.span),
                format!(
                    "a member of Assem{} `{}` takes {bits} bits of Param{n} `{}`, whose data size \
                     is {} byte{} ({size} bits)",
                    assembly.number,
                    assembly.name,
                    param.name,
                    size / 8,
                    if size == 8 { "" } else { "s" },
                ),
            )
            .with_label(format!("Param{n} is {size} bits"))
            .with_help(format!(
                "a scanner places Param{n}'s value in these bits: make the member {size} bits, or \
                 the parameter's data size match"
            )),
        );
    }
}

fn connection_refs(cip: &Cip, c: &CipConnection, out: &mut Vec<Diagnostic>) {
    for (direction, data) in [
        ("O->T", &c.o_t),
        ("T->O", &c.t_o),
        ("config #1", &c.config1),
        ("config #2", &c.config2),
    ] {
        for field in [&data.rpi, &data.size, &data.format] {
            if let Some(name) = missing_ref(cip, &field.value) {
                out.push(
                    Diagnostic::new(
                        &rules::CIP_MISSING_REF,
                        Some(field.span),
                        format!(
                            "Connection{} `{}` names {name} ({direction}), which the file does not have",
                            c.number, c.name
                        ),
                    )
                    .with_label("no such entry"),
                );
            }
        }
    }
}

fn connection_sizes(cip: &Cip, c: &CipConnection, out: &mut Vec<Diagnostic>) {
    for (direction, data) in [
        ("O->T", &c.o_t),
        ("T->O", &c.t_o),
        ("config #1", &c.config1),
        ("config #2", &c.config2),
    ] {
        let (FieldRef::Number(size), FieldRef::Assem(n)) = (&data.size.value, &data.format.value)
        else {
            continue;
        };
        let Some(assembly) = cip.assemblies.get(n) else {
            continue;
        };
        let Some(expected) = cip.assembly_size(assembly) else {
            continue;
        };
        if *size != expected {
            out.push(
                Diagnostic::new(
                    &rules::CIP_CONNECTION_SIZE,
                    Some(data.size.span),
                    format!(
                        "Connection{} `{}` gives {direction} a size of {size} bytes, but its format \
                         Assem{n} `{}` is {expected} bytes",
                        c.number, c.name, assembly.name
                    ),
                )
                .with_label(format!("Assem{n} is {expected} bytes"))
                .with_help("a scanner opening this connection would be refused (invalid connection size)"),
            );
        }
    }
}

/// The assembly instances a connection path names: (configuration instance, O→T point, T→O
/// point), as CIP orders them: instance, then consuming point, then producing point.
fn path_points(segments: &[PathSegment]) -> (Option<u32>, Option<u32>, Option<u32>) {
    let mut assembly = false;
    let mut config = None;
    let mut points = Vec::new();
    for seg in segments {
        match *seg {
            PathSegment::Class(c) => assembly = c == 4,
            PathSegment::Instance(i) if assembly => config = Some(i),
            PathSegment::ConnectionPoint(p) if assembly => points.push(p),
            _ => {}
        }
    }
    match points.as_slice() {
        [] => (config, None, None),
        [t_o] => (config, None, Some(*t_o)),
        [o_t, t_o, ..] => (config, Some(*o_t), Some(*t_o)),
    }
}

fn connection_path(cip: &Cip, c: &CipConnection, out: &mut Vec<Diagnostic>) {
    let Some(path) = &c.path else { return };
    // A path may take numbers from parameters (`[ParamN]`, `ParamN`): not checkable statically.
    if path.value.to_ascii_lowercase().contains("param") {
        return;
    }
    let segments = match decode_path(&path.value) {
        Ok(s) => s,
        Err(at) => {
            out.push(
                Diagnostic::new(
                    &rules::CIP_PATH,
                    Some(path.span),
                    format!(
                        "the path of Connection{} `{}` does not decode as an EPATH (at byte {at})",
                        c.number, c.name
                    ),
                )
                .with_label("not an EPATH")
                .with_help("write the path as hex bytes: \"20 04 24 01 2C 96 2C 64\""),
            );
            return;
        }
    };
    if cip.assemblies.is_empty() {
        return;
    }
    let (config, o_t, t_o) = path_points(&segments);
    let used = |d: &crate::model::ConnectionData| {
        !matches!(d.format.value, FieldRef::Empty)
            || !matches!(d.size.value, FieldRef::Empty | FieldRef::Number(0))
    };
    let checks = [
        (
            "configuration instance",
            config,
            used(&c.config1) || used(&c.config2),
            None,
        ),
        (
            "O->T connection point",
            o_t,
            used(&c.o_t),
            Some(&c.o_t.format.value),
        ),
        (
            "T->O connection point",
            t_o,
            used(&c.t_o),
            Some(&c.t_o.format.value),
        ),
    ];
    for (what, instance, used, format) in checks {
        let (Some(instance), true) = (instance, used) else {
            continue;
        };
        let Some(assembly) = cip.assemblies.values().find(|a| a.instance() == instance) else {
            out.push(
                Diagnostic::new(
                    &rules::CIP_PATH,
                    Some(path.span),
                    format!(
                        "the path of Connection{} `{}` names assembly {instance} as its {what}, \
                         which [Assembly] does not have",
                        c.number, c.name
                    ),
                )
                .with_label(format!("no assembly {instance}")),
            );
            continue;
        };
        if let Some(FieldRef::Assem(n)) = format {
            if *n != assembly.number {
                out.push(
                    Diagnostic::new(
                        &rules::CIP_PATH,
                        Some(path.span),
                        format!(
                            "the path of Connection{} `{}` names assembly {instance} (Assem{}) as \
                             its {what}, but its format is Assem{n}",
                            c.number, c.name, assembly.number
                        ),
                    )
                    .with_label(format!("Assem{}, not Assem{n}", assembly.number)),
                );
            }
        }
    }
}

fn connection_words(c: &CipConnection, out: &mut Vec<Diagnostic>) {
    let mut problems = Vec::new();
    let mut span = c.span;
    if let Some(tt) = &c.trigger_transport {
        span = tt.span;
        if tt.value.classes().is_empty() {
            problems.push("no transport class (bits 0-15)");
        }
        if tt.value.triggers().is_empty() {
            problems.push("no trigger (bits 16-18)");
        }
    }
    if let Some(p) = &c.params {
        if !p.value.o_t_fixed() && !p.value.o_t_variable() {
            problems.push("neither fixed nor variable O->T size (bits 0-1)");
        }
        if !p.value.t_o_fixed() && !p.value.t_o_variable() {
            problems.push("neither fixed nor variable T->O size (bits 2-3)");
        }
        if problems.is_empty() {
            return;
        }
        if c.trigger_transport.is_none() {
            span = p.span;
        }
    }
    if problems.is_empty() {
        return;
    }
    out.push(
        Diagnostic::new(
            &rules::CIP_CONNECTION_WORD,
            Some(span),
            format!(
                "Connection{} `{}` allows {}",
                c.number,
                c.name,
                problems.join(", ")
            ),
        )
        .with_label("connection words"),
    );
}
