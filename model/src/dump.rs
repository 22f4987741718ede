//! `edsgen dump`: the resolved model as JSON, in the schema other tools and tests rely on.
//!
//! Every key is always present (`null` where the file gives nothing). Integers are exact JSON
//! integers (never floats), `$NODEID` formulas are `{"nodeid_offset": N}`, octet strings and
//! domains are lowercase hex strings, strings are as written, reals are numbers. Objects are sorted
//! by index and sub-objects by sub-index (the model's `BTreeMap` order).

use serde_json::{json, Map, Value as Json};

mod cip;
mod profinet;

use crate::model::{
    Commissioning, Device, DeviceInfo, Dp, DpModule, EcPdo, EtherCat, FileInfo, Format, Object,
    SmKind, Spanned, SubObject, TextEncoding, Value, ValueSource,
};

/// The model as a JSON value, with the field names and encodings of the design's contract.
pub fn to_json(device: &Device) -> Json {
    let format = match device.source.format {
        Format::Eds => "eds",
        Format::Dcf => "dcf",
        Format::Xdd => "xdd",
        Format::Xdc => "xdc",
        Format::Esi => "esi",
        Format::OdvaEds => "odva-eds",
        Format::Gsdml => "gsdml",
        Format::Gsd => "gsd",
    };
    let encoding = match device.source.encoding {
        TextEncoding::Ascii => "ascii",
        TextEncoding::Utf8 => "utf-8",
        TextEncoding::Utf8Bom => "utf-8-bom",
        TextEncoding::Windows1252 => "windows-1252",
        TextEncoding::Latin1 => "iso-8859-1",
        TextEncoding::Utf16Le => "utf-16le",
        TextEncoding::Utf16Be => "utf-16be",
    };
    let dummy_usage: Map<String, Json> = device
        .dummy_usage
        .iter()
        .map(|(index, used)| (index.to_string(), Json::Bool(*used)))
        .collect();
    json!({
        "file": device.source.path.display().to_string(),
        "format": format,
        "encoding": encoding,
        "file_info": file_info(&device.file_info),
        "device_info": device_info(&device.device_info),
        "dummy_usage": dummy_usage,
        "comments": device.comments,
        "commissioning": device.commissioning.as_ref().map(commissioning),
        "objects": device.objects.values().map(object).collect::<Vec<_>>(),
        "other_sections": device.other_sections.iter().map(|s| s.name.clone()).collect::<Vec<_>>(),
        "ethercat": device.ethercat().map(ethercat),
        "cip": device.cip().map(cip::cip),
        "profinet": device.profinet().map(profinet::profinet),
        "dp": device.dp().map(dp),
    })
}

/// The PROFIBUS-DP side of a GSD device: identity, baud rates, the master's flags, modules with
/// their configuration bytes decoded, the parameterisation. `null` for other descriptions.
fn dp(dp: &Dp) -> Json {
    let module = |m: &DpModule| {
        let (input, output) = m.io_lengths();
        json!({
            "name": m.name,
            "config": hex(&m.config),
            "reference": m.reference,
            "input_bytes": input,
            "output_bytes": output,
            "identifiers": m.identifiers().iter().map(|id| json!({
                "bytes": hex(&id.bytes),
                "input_bytes": id.input_bytes,
                "output_bytes": id.output_bytes,
                "words": id.words,
                "consistent": id.consistent,
                "special": id.special,
            })).collect::<Vec<_>>(),
        })
    };
    let value = |v: &Option<Spanned<u32>>| v.as_ref().map(|v| v.value);
    json!({
        "gsd_revision": dp.gsd_revision,
        "vendor_name": dp.vendor_name,
        "model_name": dp.model_name,
        "revision": dp.revision,
        "order_number": dp.order_number,
        "ident_number": dp.ident_number.as_ref().map(|i| i.value),
        "baud_rates": dp.baud_rates.iter().map(|b| json!({
            "rate": b.rate.keyword(),
            "max_tsdr": b.max_tsdr,
        })).collect::<Vec<_>>(),
        "auto_baud": dp.auto_baud,
        "freeze": dp.freeze,
        "sync": dp.sync,
        "fail_safe": dp.fail_safe,
        "set_slave_add": dp.set_slave_add,
        "dpv1": dp.dpv1,
        "min_slave_interval": dp.min_slave_interval,
        "max_diag_data_len": dp.max_diag_data_len,
        "modular_station": dp.modular_station,
        "max_module": dp.max_module,
        "max_input_len": value(&dp.max_input_len),
        "max_output_len": value(&dp.max_output_len),
        "max_data_len": value(&dp.max_data_len),
        "user_prm_data_len": value(&dp.user_prm_data_len),
        "default_user_prm_data": hex(&dp.default_user_prm_data()),
        "prm_definitions": dp.prm_definitions.iter().map(|d| json!({
            "reference": d.reference,
            "name": d.name,
            "default": d.default,
            "text_ref": d.text_ref,
        })).collect::<Vec<_>>(),
        "prm_texts": dp.prm_texts.iter().map(|t| json!({
            "reference": t.reference,
            "texts": t.texts.iter().map(|(v, s)| json!([v, s])).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "modules": dp.modules.iter().map(module).collect::<Vec<_>>(),
        "slots": dp.slots.iter().map(|s| json!({
            "number": s.number,
            "name": s.name,
            "default_module": s.default_module,
            "allowed": s.allowed,
        })).collect::<Vec<_>>(),
        "unit_diag": dp.unit_diag.iter().map(|u| json!({
            "bits": [u.bits.0, u.bits.1],
            "value": u.value,
            "not": u.not,
            "text": u.text,
        })).collect::<Vec<_>>(),
        "other": dp.other.iter().map(|k| json!([k.key, k.value])).collect::<Vec<_>>(),
    })
}

/// Bytes as lowercase hex.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The EtherCAT side of an ESI device: SyncManagers, PDOs, CoE mailbox, DC op-modes,
/// alternative PDO assignments, slots, the file's modules, other devices of the file. `null` for CANopen descriptions.
fn ethercat(ec: &EtherCat) -> Json {
    let sm_kind = |kind: &SmKind| match kind {
        SmKind::MailboxOut => "MBoxOut".to_owned(),
        SmKind::MailboxIn => "MBoxIn".to_owned(),
        SmKind::Outputs => "Outputs".to_owned(),
        SmKind::Inputs => "Inputs".to_owned(),
        SmKind::Other(text) => text.clone(),
    };
    let pdo = |p: &EcPdo| {
        json!({
            "index": p.index,
            "name": p.name,
            "sm": p.sm,
            "fixed": p.fixed,
            "mandatory": p.mandatory,
            "exclude": p.exclude.iter().map(|e| e.value).collect::<Vec<_>>(),
            "bits": p.entries.iter().map(|e| u64::from(e.bit_len)).sum::<u64>(),
            "entries": p.entries.iter().map(|e| json!({
                "index": e.index,
                "sub": e.sub,
                "bit_len": e.bit_len,
                "name": e.name,
                "data_type": e.data_type,
            })).collect::<Vec<_>>(),
        })
    };
    json!({
        "type_name": ec.type_name,
        "profiles": ec.profiles,
        "sync_managers": ec.sync_managers.iter().map(|sm| json!({
            "kind": sm_kind(&sm.kind),
            "start_address": sm.start_address,
            "default_size": sm.default_size,
            "control_byte": sm.control_byte,
            "enable": sm.enable,
        })).collect::<Vec<_>>(),
        "rx_pdos": ec.rx_pdos.iter().map(pdo).collect::<Vec<_>>(),
        "tx_pdos": ec.tx_pdos.iter().map(pdo).collect::<Vec<_>>(),
        "coe": ec.coe.as_ref().map(|coe| json!({
            "sdo_info": coe.sdo_info,
            "pdo_assign": coe.pdo_assign,
            "pdo_config": coe.pdo_config,
            "complete_access": coe.complete_access,
            "segmented_sdo": coe.segmented_sdo,
            "init_cmds": coe.init_cmds.iter().map(|c| json!({
                "transitions": c.transitions,
                "index": c.index,
                "sub": c.sub,
                "data": c.data.iter().map(|b| format!("{b:02x}")).collect::<String>(),
                "complete_access": c.complete_access,
            })).collect::<Vec<_>>(),
        })),
        "op_modes": ec.op_modes.iter().map(|m| json!({
            "name": m.name,
            "description": m.description,
            "assign_activate": m.assign_activate,
            "cycle_time_sync0": m.cycle_time_sync0,
        })).collect::<Vec<_>>(),
        "alternative_mappings": ec.alternative_mappings.iter().map(|a| json!({
            "name": a.name,
            "default": a.default,
            "sms": a.sms.iter().map(|(sm, pdos)| json!({
                "sm": sm,
                "pdos": pdos.iter().map(|p| p.value).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "slots": ec.slots.iter().map(|s| json!({
            "name": s.name,
            "min_instances": s.min_instances,
            "max_instances": s.max_instances,
            "module_idents": s.module_idents,
            "module_classes": s.module_classes,
            "default_module": s.default_module,
            "index_increment": s.index_increment,
            "pdo_increment": s.pdo_increment,
        })).collect::<Vec<_>>(),
        "modules": ec.modules.iter().map(|m| json!({
            "ident": m.ident,
            "type_name": m.type_name,
            "class": m.class,
            "name": m.name,
            "rx_pdos": m.rx_pdos.iter().map(pdo).collect::<Vec<_>>(),
            "tx_pdos": m.tx_pdos.iter().map(pdo).collect::<Vec<_>>(),
            "objects": m.objects.values().map(object).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "other_devices": ec.other_devices.iter().map(|(name, code, revision)| json!({
            "type_name": name,
            "product_code": code,
            "revision": revision,
        })).collect::<Vec<_>>(),
    })
}

fn file_info(info: &FileInfo) -> Json {
    json!({
        "file_name": info.file_name,
        "file_version": info.file_version,
        "file_revision": info.file_revision,
        "eds_version": info.eds_version.as_ref().map(|v| v.value.clone()),
        "description": info.description,
        "creation_time": info.creation_time,
        "creation_date": info.creation_date,
        "created_by": info.created_by,
        "modification_time": info.modification_time,
        "modification_date": info.modification_date,
        "modified_by": info.modified_by,
        "last_eds": info.last_eds,
    })
}

fn device_info(info: &DeviceInfo) -> Json {
    let baud_rates: Map<String, Json> = info
        .baud_rates
        .iter()
        .map(|(rate, supported)| (rate.to_string(), Json::Bool(*supported)))
        .collect();
    json!({
        "vendor_name": info.vendor_name,
        "vendor_number": info.vendor_number.as_ref().map(|v| v.value),
        "product_name": info.product_name,
        "product_number": info.product_number.as_ref().map(|v| v.value),
        "revision_number": info.revision_number.as_ref().map(|v| v.value),
        "order_code": info.order_code,
        "baud_rates": baud_rates,
        "simple_boot_up_master": info.simple_boot_up_master,
        "simple_boot_up_slave": info.simple_boot_up_slave,
        "granularity": info.granularity.as_ref().map(|v| v.value),
        "dynamic_channels_supported": info.dynamic_channels_supported,
        "group_messaging": info.group_messaging,
        "nr_of_rx_pdo": info.nr_of_rx_pdo.as_ref().map(|v| v.value),
        "nr_of_tx_pdo": info.nr_of_tx_pdo.as_ref().map(|v| v.value),
        "lss_supported": info.lss_supported,
        "compact_pdo": info.compact_pdo.as_ref().map(|v| v.value),
    })
}

fn commissioning(c: &Commissioning) -> Json {
    json!({
        "node_id": c.node_id.as_ref().map(|v| v.value),
        "node_name": c.node_name,
        "baudrate": c.baudrate.as_ref().map(|v| v.value),
        "net_number": c.net_number,
        "network_name": c.network_name,
        "canopen_manager": c.canopen_manager,
        "lss_serial_number": c.lss_serial_number,
    })
}

fn object(o: &Object) -> Json {
    json!({
        "index": o.index,
        "name": o.name,
        "object_type": o.object_type.code(),
        "implicit": o.implicit,
        "obj_flags": o.obj_flags,
        "subs": o.subs.values().map(sub_object).collect::<Vec<_>>(),
    })
}

fn sub_object(s: &SubObject) -> Json {
    json!({
        "sub": s.sub_index,
        "name": s.name,
        "data_type": s.data_type,
        "access": s.access.map(|a| a.as_str()),
        "pdo_mapping": s.pdo_mapping,
        "default": value(s.default.as_ref()),
        "parameter_value": value(s.parameter_value.as_ref()),
        "low_limit": value(s.low_limit.as_ref()),
        "high_limit": value(s.high_limit.as_ref()),
        "obj_flags": s.obj_flags,
        "denotation": s.denotation,
        "implicit": s.implicit,
    })
}

/// A value in the dump's encoding; `null` when absent or unparseable.
pub fn value(source: Option<&ValueSource>) -> Json {
    match source.and_then(|s| s.value.as_ref()) {
        None => Json::Null,
        Some(Value::Integer(v)) => integer(*v),
        Some(Value::NodeRelative(offset)) => json!({ "nodeid_offset": offset }),
        Some(Value::Real(v)) => serde_json::Number::from_f64(*v).map_or(Json::Null, Json::Number),
        Some(Value::Text(text)) => Json::String(text.clone()),
        Some(Value::Bytes(bytes)) => {
            Json::String(bytes.iter().map(|b| format!("{b:02x}")).collect())
        }
    }
}

/// An exact JSON integer: i64 or u64; a decimal string if it fits neither (no CiA type does).
fn integer(v: i128) -> Json {
    if let Ok(small) = i64::try_from(v) {
        Json::from(small)
    } else if let Ok(big) = u64::try_from(v) {
        Json::from(big)
    } else {
        Json::String(v.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Span;

    fn source(value: Value) -> ValueSource {
        ValueSource {
            value: Some(value),
            raw: String::new(),
            span: Span::default(),
        }
    }

    #[test]
    fn values_are_encoded_exactly() {
        assert_eq!(value(None), Json::Null);
        assert_eq!(
            value(Some(&source(Value::Integer(u64::MAX as i128)))).to_string(),
            "18446744073709551615"
        );
        assert_eq!(value(Some(&source(Value::Integer(-5)))).to_string(), "-5");
        assert_eq!(
            value(Some(&source(Value::NodeRelative(0x180)))).to_string(),
            r#"{"nodeid_offset":384}"#
        );
        assert_eq!(
            value(Some(&source(Value::Bytes(vec![0x01, 0xAB])))).to_string(),
            r#""01ab""#
        );
        assert_eq!(value(Some(&source(Value::Real(1.5)))).to_string(), "1.5");
        assert_eq!(value(Some(&source(Value::Real(f64::NAN)))), Json::Null);
        assert_eq!(
            value(Some(&source(Value::Text("\"a\"".into())))).to_string(),
            r#""\"a\"""#
        );
    }
}
