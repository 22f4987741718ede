//! A modular ESI device as its firmware shows it with its modules plugged: the description
//! configured ([`Device::configured`]: the module instances' PDOs and objects, their
//! `DependOnSlot` indices moved per slot), and, where the description leaves them out, the
//! CoE objects a MainDevice reads the process images from: the PDO assignment (1C12h/1C13h,
//! written anew from the configured default assignment), each PDO's mapping object and the
//! mapped objects. SOEM and ethercrab then size the images as the SII's PDO categories do.

use edsgen_model::model::{
    AccessType, Device, EcPdo, KeySpans, Object, ObjectType, SmKind, Span, SubObject, Subs, Value,
    ValueSource,
};

/// `device` as served with the modules its configuration plugs (`EtherCat::chosen`); a device
/// without a configuration, or without an EtherCAT side, as it is.
pub fn plugged(device: &Device) -> Device {
    let Some(chosen) = device.ethercat().and_then(|ec| ec.chosen.as_ref()) else {
        return device.clone();
    };
    let mut served = device.configured();
    if chosen.slots.is_empty() || device.objects.is_empty() {
        // Nothing plugged, or no CoE dictionary to show it in.
        return served;
    }
    let Some(ec) = served.ethercat().cloned() else {
        return served;
    };
    let objects = &mut served.objects;
    for (kind, pdos) in [
        (SmKind::Outputs, &ec.rx_pdos),
        (SmKind::Inputs, &ec.tx_pdos),
    ] {
        let Some(sm) = ec.sync_managers.iter().position(|s| s.kind == kind) else {
            continue;
        };
        let assigned: Vec<u64> = pdos
            .iter()
            .filter(|p| usize::from(p.sm.unwrap_or(u8::MAX)) == sm)
            .map(|p| u64::from(p.index))
            .collect();
        let index = 0x1C10 + sm as u16;
        let name = format!("Sync manager {sm} PDO assignment");
        objects.insert(index, list(index, &name, 0x0006, &assigned));
        for pdo in pdos {
            objects
                .entry(pdo.index)
                .or_insert_with(|| mapping_object(pdo));
            for entry in pdo.entries.iter().filter(|e| e.index != 0) {
                let Some(data_type) = data_type_of(entry.bit_len) else {
                    continue;
                };
                let object = objects.entry(entry.index).or_insert_with(|| Object {
                    index: entry.index,
                    name: entry.name.clone(),
                    object_type: ObjectType::Var,
                    ..empty(entry.index)
                });
                if object.subs.contains_key(&entry.sub) {
                    continue;
                }
                object.subs.insert(
                    entry.sub,
                    sub(entry.sub, &entry.name, data_type, AccessType::Rw, true, 0),
                );
                if entry.sub > 0 {
                    // Entries under sub-index 0, which counts them.
                    let count = object.subs.keys().copied().max().unwrap_or(0);
                    object.object_type = ObjectType::Record;
                    object.subs.insert(
                        0,
                        sub(
                            0,
                            "Number of entries",
                            0x0005,
                            AccessType::Ro,
                            false,
                            u64::from(count),
                        ),
                    );
                }
            }
        }
    }
    served
}

/// A PDO's mapping object: sub-index 0 the count, then each entry as index, sub-index and bit
/// length (`iiiissll`).
fn mapping_object(pdo: &EcPdo) -> Object {
    let entries: Vec<u64> = pdo
        .entries
        .iter()
        .map(|e| u64::from(e.index) << 16 | u64::from(e.sub) << 8 | u64::from(e.bit_len & 0xFF))
        .collect();
    list(pdo.index, &pdo.name, 0x0007, &entries)
}

/// An ARRAY of `values` of `data_type` under a sub-index 0 that counts them, read-write.
fn list(index: u16, name: &str, data_type: u16, values: &[u64]) -> Object {
    let mut subs = Subs::new();
    let count = values.len() as u64;
    subs.insert(
        0,
        sub(0, "Number of entries", 0x0005, AccessType::Rw, false, count),
    );
    for (n, &value) in values.iter().enumerate() {
        let s = n as u8 + 1;
        let name = format!("Entry {s}");
        subs.insert(s, sub(s, &name, data_type, AccessType::Rw, false, value));
    }
    Object {
        name: name.to_owned(),
        object_type: ObjectType::Array,
        subs,
        ..empty(index)
    }
}

/// The basic type of a mapped entry of `bits`: BOOLEAN, UNSIGNED8/16/32/64; none for others.
fn data_type_of(bits: u16) -> Option<u16> {
    match bits {
        1 => Some(0x0001),
        8 => Some(0x0005),
        16 => Some(0x0006),
        32 => Some(0x0007),
        64 => Some(0x001B),
        _ => None,
    }
}

/// An object with no entries yet, implied (not written in the file).
fn empty(index: u16) -> Object {
    Object {
        index,
        name: String::new(),
        object_type: ObjectType::Var,
        subs: Subs::new(),
        sub_number: None,
        compact_sub_obj: None,
        obj_flags: 0,
        span: Span::default(),
        custom: Vec::new(),
        object_links: Vec::new(),
        implicit: true,
    }
}

/// One implied entry with its default `value`.
fn sub(
    sub_index: u8,
    name: &str,
    data_type: u16,
    access: AccessType,
    pdo_mapping: bool,
    value: u64,
) -> SubObject {
    SubObject {
        sub_index,
        name: name.to_owned(),
        data_type: Some(data_type),
        access: Some(access),
        pdo_mapping,
        default: Some(ValueSource {
            value: Some(Value::Integer(i128::from(value))),
            raw: format!("{value:#x}"),
            span: Span::default(),
        }),
        parameter_value: None,
        low_limit: None,
        high_limit: None,
        obj_flags: 0,
        denotation: None,
        upload_file: None,
        download_file: None,
        span: Span::default(),
        custom: Vec::new(),
        implicit: true,
        key_spans: KeySpans::default(),
        capacity: None,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use edsgen_model::model::modules::{choose_ec, parse_choices};
    use edsgen_runtime::ObjectDictionary;

    use super::*;
    use crate::ethercat::EsiDevice;

    /// A CoE device with two slots (`SlotIndexIncrement` 800h, `SlotPdoIncrement` 16) taking
    /// a position module (RxPDO 1600h: 607Ah:0 32 bits, 6040h:0 16 bits; TxPDO 1A00h:
    /// 6064h:1 32 bits) or a status module (TxPDO 1A01h: 6041h:0 16 bits), all `DependOnSlot`.
    const ESI: &str = r##"<?xml version="1.0"?>
<EtherCATInfo><Vendor><Id>#x1234</Id></Vendor><Descriptions><Devices>
<Device><Type ProductCode="#x1" RevisionNo="#x1">Two axes</Type><Name>Two axes</Name>
<Profile><Dictionary><DataTypes><DataType><Name>UDINT</Name><BitSize>32</BitSize></DataType></DataTypes>
<Objects><Object><Index>#x1000</Index><Name>Device type</Name><Type>UDINT</Type><BitSize>32</BitSize>
<Info><DefaultData>92010000</DefaultData></Info><Flags><Access>ro</Access></Flags></Object></Objects>
</Dictionary></Profile>
<Sm StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm>
<Sm StartAddress="#x1400" ControlByte="#x22" Enable="1">MBoxIn</Sm>
<Sm StartAddress="#x1800" ControlByte="#x64" Enable="1">Outputs</Sm>
<Sm StartAddress="#x1C00" ControlByte="#x20" Enable="1">Inputs</Sm>
<Mailbox><CoE SdoInfo="1" PdoAssign="1" PdoConfig="1"/></Mailbox>
<Slots SlotPdoIncrement="16" SlotIndexIncrement="#x800">
<Slot><Name>Axis 1</Name><ModuleIdent Default="1">#x100</ModuleIdent><ModuleIdent>#x200</ModuleIdent></Slot>
<Slot><Name>Axis 2</Name><ModuleIdent Default="1">#x100</ModuleIdent><ModuleIdent>#x200</ModuleIdent></Slot>
</Slots></Device></Devices>
<Modules>
<Module><Type ModuleIdent="#x100">Position</Type><Name>Position</Name>
<RxPdo Fixed="1" Sm="2"><Index DependOnSlot="1">#x1600</Index><Name>Outputs</Name>
<Entry><Index DependOnSlot="1">#x607A</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><Name>Target</Name><DataType>UDINT</DataType></Entry>
<Entry><Index DependOnSlot="1">#x6040</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Control</Name><DataType>UINT</DataType></Entry>
</RxPdo>
<TxPdo Fixed="1" Sm="3"><Index DependOnSlot="1">#x1A00</Index><Name>Inputs</Name>
<Entry><Index DependOnSlot="1">#x6064</Index><SubIndex>1</SubIndex><BitLen>32</BitLen><Name>Position</Name><DataType>UDINT</DataType></Entry>
</TxPdo></Module>
<Module><Type ModuleIdent="#x200">Status</Type><Name>Status</Name>
<TxPdo Fixed="1" Sm="3"><Index DependOnSlot="1">#x1A01</Index><Name>Status</Name>
<Entry><Index DependOnSlot="1">#x6041</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Status</Name><DataType>UINT</DataType></Entry>
</TxPdo></Module>
</Modules></Descriptions></EtherCATInfo>"##;

    /// The device with `choices` plugged.
    fn served(choices: &[&str]) -> Device {
        let mut device =
            edsgen_model::read::read_bytes(Path::new("two.xml"), ESI.as_bytes()).device;
        let ec = device.ethercat_mut().expect("an ESI device");
        let choices = parse_choices(choices).expect("choices");
        ec.chosen = Some(choose_ec(ec, &choices).expect("allowed"));
        plugged(&device)
    }

    fn u32_at(app: &EsiDevice, index: u16, sub: u8) -> u32 {
        let mut b = [0u8; 4];
        let len = app.dictionary().value_len(index, sub).expect("the entry");
        app.dictionary()
            .read(index, sub, 0, &mut b[..len])
            .expect("readable");
        u32::from_le_bytes(b)
    }

    #[test]
    fn the_plugged_modules_are_assigned_mapped_and_in_the_images() {
        // Slot 1 the status module, slot 2 its default (position): its indices move by one slot.
        let device = served(&["1=Status"]);
        let app = EsiDevice::new(&device, None).expect("served");
        assert_eq!(app.assigned(2, true), [0x1610]);
        assert_eq!(app.assigned(3, false), [0x1A01, 0x1A10]);
        assert_eq!(u32_at(&app, 0x1C13, 0), 2);
        assert_eq!(u32_at(&app, 0x1C13, 2), 0x1A10);
        assert_eq!(u32_at(&app, 0x1610, 0), 2);
        assert_eq!(u32_at(&app, 0x1610, 1), 0x687A_0020);
        assert_eq!(u32_at(&app, 0x1610, 2), 0x6840_0010);
        assert_eq!(u32_at(&app, 0x1A10, 1), 0x6864_0120);
        assert_eq!(
            app.image(false),
            [(0x6041, 0, 16), (0x6864, 1, 32)],
            "the inputs image"
        );
        use crate::ethercat::Application;
        assert_eq!(app.image_sizes(), (6, 6));
        // The mapped objects are there to read and write, with the mapped sizes.
        assert_eq!(app.dictionary().value_len(0x6864, 1), Ok(4));
        assert_eq!(app.dictionary().value_len(0x6041, 0), Ok(2));
        // And the SII's PDO categories have them.
        let sii = edsgen_model::sii::build(&device).expect("an SII image");
        let read = edsgen_model::read::read_bytes(Path::new("two.bin"), &sii).device;
        let ec = read.ethercat().expect("read back");
        let indices = |pdos: &[EcPdo]| pdos.iter().map(|p| p.index).collect::<Vec<_>>();
        assert_eq!(indices(&ec.rx_pdos), [0x1610]);
        assert_eq!(indices(&ec.tx_pdos), [0x1A01, 0x1A10]);
    }

    #[test]
    fn a_device_without_modules_chosen_is_served_as_described() {
        let device = edsgen_model::read::read_bytes(Path::new("two.xml"), ESI.as_bytes()).device;
        assert_eq!(plugged(&device), device);
    }
}
