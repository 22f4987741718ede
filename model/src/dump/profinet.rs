//! The `profinet` object of `edsgen dump`: what a GSDML file says (identity, access points,
//! modules, submodules with their IO data and records, value lists, channel diagnostics with
//! their extended ones).

use serde_json::{json, Value as Json};

use crate::model::{
    AccessPoint, DataItem, ParameterRecord, PnModule, Profinet, RecordField, Submodule,
    SubslotLabel, SystemSubmodule,
};

pub(super) fn profinet(pn: &Profinet) -> Json {
    json!({
        "vendor_id": pn.vendor_id.as_ref().map(|v| v.value),
        "device_id": pn.device_id.as_ref().map(|v| v.value),
        "vendor_name": pn.vendor_name,
        "info_text": pn.info_text,
        "family": pn.family.as_ref().map(|(main, product)| json!({"main": main, "product": product})),
        "access_points": pn.access_points.iter().map(access_point).collect::<Vec<_>>(),
        "modules": pn.modules.iter().map(module).collect::<Vec<_>>(),
        "value_lists": pn.value_lists.iter().map(|v| json!({
            "id": v.id,
            "assignments": v.assignments.iter().map(|(value, text)| json!({"value": number(*value), "text": text})).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "channel_diagnostics": pn.channel_diagnostics.iter().map(|d| json!({
            "error_type": d.error_type, "name": d.name, "help": d.help,
            "ext": d.ext.iter().map(|x| json!({
                "error_type": x.error_type.value, "name": x.name, "help": x.help,
                "add_values": x.add_values.iter().map(|v| json!({
                    "id": v.id, "data_type": v.data_type.value, "length": v.length,
                })).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}

/// An integer as a JSON integer (i64 covers every GSDML value; wider ones as strings).
fn number(value: i128) -> Json {
    i64::try_from(value).map_or_else(|_| Json::String(value.to_string()), Json::from)
}

fn access_point(dap: &AccessPoint) -> Json {
    json!({
        "id": dap.id,
        "name": dap.name,
        "module_ident": dap.module_ident.as_ref().map(|v| v.value),
        "physical_slots": dap.physical_slots,
        "fixed_in_slots": dap.fixed_in_slots,
        "min_device_interval": dap.min_device_interval,
        "dns_compatible_name": dap.dns_compatible_name,
        "pnio_version": dap.pnio_version,
        "max_input_length": dap.max_input_length.as_ref().map(|v| v.value),
        "max_output_length": dap.max_output_length.as_ref().map(|v| v.value),
        "useable_modules": dap.useable_modules.iter().map(|r| json!({
            "target": r.target.value,
            "allowed_in_slots": r.allowed_in_slots,
            "fixed_in_slots": r.fixed_in_slots,
            "used_in_slots": r.used_in_slots,
        })).collect::<Vec<_>>(),
        "submodules": dap.submodules.iter().map(submodule).collect::<Vec<_>>(),
        "subslot_labels": subslot_labels(&dap.subslot_labels),
        "interface": dap.interface.as_ref().map(system_submodule),
        "ports": dap.ports.iter().map(system_submodule).collect::<Vec<_>>(),
    })
}

fn system_submodule(s: &SystemSubmodule) -> Json {
    json!({
        "id": s.id,
        "submodule_ident": s.submodule_ident.as_ref().map(|v| v.value),
        "subslot": s.subslot,
        "name": s.name,
        "rt_classes": s.rt_classes,
        "send_clock": s.send_clock,
        "reduction_ratio": s.reduction_ratio,
    })
}

fn module(m: &PnModule) -> Json {
    json!({
        "id": m.id,
        "module_ident": m.module_ident.as_ref().map(|v| v.value),
        "name": m.name,
        "info_text": m.info_text,
        "submodules": m.submodules.iter().map(submodule).collect::<Vec<_>>(),
        "subslot_labels": subslot_labels(&m.subslot_labels),
    })
}

fn subslot_labels(labels: &[SubslotLabel]) -> Json {
    labels
        .iter()
        .map(|l| json!({"subslot": l.subslot.value, "text": l.text}))
        .collect()
}

fn submodule(s: &Submodule) -> Json {
    json!({
        "id": s.id,
        "submodule_ident": s.submodule_ident.as_ref().map(|v| v.value),
        "subslot": s.subslot,
        "name": s.name,
        "inputs": s.inputs.iter().map(data_item).collect::<Vec<_>>(),
        "outputs": s.outputs.iter().map(data_item).collect::<Vec<_>>(),
        "records": s.records.iter().map(record).collect::<Vec<_>>(),
    })
}

fn data_item(d: &DataItem) -> Json {
    json!({
        "data_type": d.data_type.value,
        "size": d.size(),
        "name": d.name,
        "use_as_bits": d.use_as_bits,
        "bits": d.bits.iter().map(|b| json!({"bit_offset": b.bit_offset, "name": b.name})).collect::<Vec<_>>(),
    })
}

fn record(r: &ParameterRecord) -> Json {
    json!({
        "index": r.index.value,
        "length": r.length.value,
        "transfer_sequence": r.transfer_sequence,
        "name": r.name,
        "consts": r.consts.iter().map(|(offset, bytes)| json!({
            "byte_offset": offset,
            "data": bytes.iter().map(|b| format!("{b:02x}")).collect::<String>(),
        })).collect::<Vec<_>>(),
        "fields": r.fields.iter().map(field).collect::<Vec<_>>(),
    })
}

fn field(f: &RecordField) -> Json {
    json!({
        "data_type": f.data_type.value,
        "byte_offset": f.byte_offset,
        "bit_offset": f.bit_offset,
        "bit_length": f.bit_length,
        "length": f.length,
        "default": f.default.as_ref().map(|d| d.value.clone()),
        "allowed_values": f.allowed_values.iter().map(|(lo, hi)| json!([number(*lo), number(*hi)])).collect::<Vec<_>>(),
        "value_item": f.value_item.as_ref().map(|v| v.value.clone()),
        "changeable": f.changeable,
        "visible": f.visible,
        "name": f.name,
    })
}
