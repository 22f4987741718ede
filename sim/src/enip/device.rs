//! What the adapter serves: any ODVA EDS's identity and assemblies (each filled with its
//! members' parameter defaults, little-endian, packed from bit 0 as CIP packs them), or the
//! Goodrive350 EtherNet/IP card with its drive; both with the Parameter object of their EDS's
//! `[Params]`.

use std::collections::BTreeMap;

use edsgen_model::model::{cip_value, Cip, FieldRef};
use edsgen_runtime::Instant;

use super::parameter as param_object;
use super::{Adapter, Assembly, Identity};
use crate::cards::goodrive350_enip as card;
use crate::drives::pkw_pzd::{parameter, Bus, PkwPzdDrive};

/// An adapter for the device an ODVA EDS describes: its identity, its assemblies with their
/// defaults (consumed when a connection names them O→T), the configuration instances its
/// connections name.
pub fn from_cip(cip: &Cip, address: [u8; 4]) -> Adapter {
    let id = &cip.identity;
    let identity = Identity {
        vendor: id.vendor_code.as_ref().map_or(0, |v| v.value),
        device_type: id.product_type.as_ref().map_or(0, |v| v.value),
        product_code: id.product_code.as_ref().map_or(0, |v| v.value),
        revision: (
            id.major_revision.as_ref().map_or(0, |v| v.value),
            id.minor_revision.as_ref().map_or(0, |v| v.value),
        ),
        serial: 1,
        name: id.product_name.clone().unwrap_or_default(),
    };
    let consumed: Vec<u32> = cip
        .connections
        .values()
        .filter_map(|c| match c.o_t.format.value {
            FieldRef::Assem(n) => Some(n),
            _ => None,
        })
        .collect();
    let mut assemblies = BTreeMap::new();
    let mut config_instances = Vec::new();
    for a in cip.assemblies.values() {
        let size = cip.assembly_size(a).unwrap_or(0) as usize;
        if size == 0 {
            config_instances.push(a.instance());
            continue;
        }
        let mut data = vec![0u8; size];
        for place in cip_value::layout(cip, a) {
            if let FieldRef::Param(n) = place.member.member {
                if let Some(p) = cip.params.get(&n) {
                    let default = param_object::default_bytes(p);
                    cip_value::write_bits(&mut data, place.bit, u64::from(place.bits), &default);
                }
            }
        }
        assemblies.insert(
            a.instance(),
            Assembly {
                data,
                consumed: consumed.contains(&a.number),
            },
        );
    }
    let parameters = param_object::from_cip(cip, &assemblies);
    let mut adapter = Adapter::new(identity, assemblies, address);
    adapter.device.config_instances = config_instances;
    adapter.device.parameters = parameters;
    adapter
}

/// The card's EDS, whose `[Params]` the Parameter object serves.
const CARD_EDS: &str = include_str!("../../../eds/goodrive350-enip.eds");

/// The Goodrive350 EtherNet/IP card: its generated identity and images, the drive behind it
/// with P00.01 = 2 and P00.02 = 3 (5.4.1: run commands from EtherNet/IP) and P00.06 = 13 (the
/// frequency from it); the PZD functions (P16.32-P16.53) at their defaults, 0, for the scanner to
/// set through PKW. The drive is the adapter's application.
pub fn goodrive350(address: [u8; 4], now: Instant) -> Adapter<PkwPzdDrive> {
    let identity = Identity {
        vendor: card::VENDOR_ID,
        device_type: card::DEVICE_TYPE,
        product_code: card::PRODUCT_CODE,
        revision: (card::MAJOR_REVISION, card::MINOR_REVISION),
        serial: 0x0035_0001,
        name: card::PRODUCT_NAME.to_owned(),
    };
    let mut drive = PkwPzdDrive::new(Bus::EthernetIp, now);
    for (address, value) in [
        (parameter::RUN_COMMAND_CHANNEL, 2),
        (
            parameter::COMMUNICATION_CHANNEL,
            Bus::EthernetIp.command_channel(),
        ),
        (
            parameter::FREQUENCY_A_SOURCE,
            Bus::EthernetIp.frequency_source(),
        ),
    ] {
        // At rest and in range.
        let _ = drive.set_parameter(address, value);
    }
    let mut assemblies = BTreeMap::new();
    assemblies.insert(
        card::Input::INSTANCE,
        Assembly {
            data: card::Input::default().to_bytes().to_vec(),
            consumed: false,
        },
    );
    assemblies.insert(
        card::Output::INSTANCE,
        Assembly {
            data: card::Output::default().to_bytes().to_vec(),
            consumed: true,
        },
    );
    let read = edsgen_model::read::read_bytes(
        std::path::Path::new("eds/goodrive350-enip.eds"),
        CARD_EDS.as_bytes(),
    );
    let parameters = read
        .device
        .cip()
        .map(|cip| param_object::from_cip(cip, &assemblies))
        .unwrap_or_default();
    let mut adapter = Adapter::new(identity, assemblies, address);
    adapter
        .device
        .config_instances
        .push(card::Configuration::INSTANCE);
    adapter.device.parameters = parameters;
    adapter.with_application(drive)
}
