//! The `cip` object of `edsgen dump` for an ODVA EDS: identity, parameters, enumerations,
//! assemblies, connections (their words decoded), ports, capacity and the kept sections.

use serde_json::{json, Value as Json};

use crate::model::{real_time_format_name, Cip, CipNumber, ConnectionData, FieldRef, Spanned};

fn number(n: &Option<Spanned<CipNumber>>) -> Json {
    match n.as_ref().map(|n| n.value) {
        Some(CipNumber::Int(v)) => {
            i64::try_from(v).map_or_else(|_| json!(v.to_string()), |v| json!(v))
        }
        Some(CipNumber::Real(v)) => json!(v),
        None => Json::Null,
    }
}

fn field_ref(r: &FieldRef) -> Json {
    match r {
        FieldRef::Empty => Json::Null,
        FieldRef::Number(n) => json!(n),
        FieldRef::Param(n) => json!(format!("Param{n}")),
        FieldRef::Assem(n) => json!(format!("Assem{n}")),
        FieldRef::Other(t) => json!(t),
    }
}

fn data(d: &ConnectionData) -> Json {
    json!({
        "rpi": field_ref(&d.rpi.value),
        "size": field_ref(&d.size.value),
        "format": field_ref(&d.format.value),
    })
}

/// The CIP part of the model as JSON.
pub fn cip(cip: &Cip) -> Json {
    let id = &cip.identity;
    let params: Vec<Json> = cip
        .params
        .values()
        .map(|p| {
            json!({
                "number": p.number,
                "name": p.name,
                "data_type": p.data_type.as_ref().map(|t| t.value),
                "data_size": p.data_size.as_ref().map(|t| t.value),
                "descriptor": p.descriptor.as_ref().map(|t| t.value),
                "units": p.units,
                "help": p.help,
                "min": number(&p.min),
                "max": number(&p.max),
                "default": number(&p.default),
                "scaling": p.scaling,
                "decimals": p.decimals,
                "link_path": p.link_path.as_ref().map(|l| l.value.clone()),
            })
        })
        .collect();
    let enums: Vec<Json> = cip
        .enums
        .values()
        .map(|e| {
            json!({
                "param": e.number,
                "values": e.values.iter().map(|(v, t)| json!([v, t])).collect::<Vec<_>>(),
            })
        })
        .collect();
    let assemblies: Vec<Json> = cip
        .assemblies
        .values()
        .map(|a| {
            json!({
                "instance": a.number,
                "name": a.name,
                "path": a.path.as_ref().map(|p| p.value.clone()),
                "size": a.size.as_ref().map(|s| s.value),
                "descriptor": a.descriptor.as_ref().map(|s| s.value),
                "members": a.members.iter().map(|m| json!({
                    "bits": m.bits,
                    "member": field_ref(&m.member),
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let connections: Vec<Json> = cip
        .connections
        .values()
        .map(|c| {
            let tt = c.trigger_transport.as_ref().map(|t| t.value);
            let cp = c.params.as_ref().map(|p| p.value);
            json!({
                "number": c.number,
                "name": c.name,
                "help": c.help,
                "trigger_transport": tt.map(|t| t.0),
                "transport_classes": tt.map(|t| t.classes()),
                "triggers": tt.map(|t| t.triggers()),
                "application_types": tt.map(|t| t.application_types()),
                "server": tt.map(|t| t.server()),
                "connection_params": cp.map(|p| p.0),
                "o_t_fixed": cp.map(|p| p.o_t_fixed()),
                "o_t_variable": cp.map(|p| p.o_t_variable()),
                "t_o_fixed": cp.map(|p| p.t_o_fixed()),
                "t_o_variable": cp.map(|p| p.t_o_variable()),
                "o_t_format": cp.map(|p| real_time_format_name(p.o_t_format())),
                "t_o_format": cp.map(|p| real_time_format_name(p.t_o_format())),
                "o_t_types": cp.map(|p| p.o_t_types()),
                "t_o_types": cp.map(|p| p.t_o_types()),
                "o_t_priorities": cp.map(|p| p.o_t_priorities()),
                "t_o_priorities": cp.map(|p| p.t_o_priorities()),
                "o_t": data(&c.o_t),
                "t_o": data(&c.t_o),
                "config1": data(&c.config1),
                "config2": data(&c.config2),
                "path": c.path.as_ref().map(|p| p.value.clone()),
            })
        })
        .collect();
    json!({
        "file": {
            "desc_text": cip.file.desc_text,
            "create_date": cip.file.create_date,
            "mod_date": cip.file.mod_date,
            "revision": cip.file.revision,
        },
        "identity": {
            "vendor_code": id.vendor_code.as_ref().map(|v| v.value),
            "vendor_name": id.vendor_name,
            "product_type": id.product_type.as_ref().map(|v| v.value),
            "product_type_str": id.product_type_str,
            "product_code": id.product_code.as_ref().map(|v| v.value),
            "major_revision": id.major_revision.as_ref().map(|v| v.value),
            "minor_revision": id.minor_revision.as_ref().map(|v| v.value),
            "product_name": id.product_name,
            "catalog": id.catalog,
        },
        "classifications": cip.classifications.iter().map(|c| c.value.clone()).collect::<Vec<_>>(),
        "params": params,
        "enums": enums,
        "assemblies": assemblies,
        "connections": connections,
        "ports": cip.ports.values().map(|p| json!({
            "number": p.number,
            "type": p.port_type,
            "name": p.name,
            "path": p.path,
            "port_number": p.port_number,
        })).collect::<Vec<_>>(),
        "capacity": cip.capacity.iter().map(|e| json!({
            "key": e.key,
            "fields": e.fields.iter().map(|f| f.text.clone()).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "other_sections": cip.other_sections.iter().map(|s| s.name.clone()).collect::<Vec<_>>(),
    })
}
