//! Default COB-IDs: values of the predefined connection set that do not follow it.

use crate::diag::Diagnostic;
use crate::model::{Device, Value};
use crate::rules;
use crate::validate::entry_name;

/// The predefined connection set: (index, sub, CAN-ID base, what).
const PREDEFINED: [(u16, u8, u32, &str); 11] = [
    (0x1014, 0, 0x080, "EMCY"),
    (0x1200, 1, 0x600, "SDO server receive (client to server)"),
    (0x1200, 2, 0x580, "SDO server transmit (server to client)"),
    (0x1400, 1, 0x200, "RPDO1"),
    (0x1401, 1, 0x300, "RPDO2"),
    (0x1402, 1, 0x400, "RPDO3"),
    (0x1403, 1, 0x500, "RPDO4"),
    (0x1800, 1, 0x180, "TPDO1"),
    (0x1801, 1, 0x280, "TPDO2"),
    (0x1802, 1, 0x380, "TPDO3"),
    (0x1803, 1, 0x480, "TPDO4"),
];

pub(super) fn default_cob_ids(device: &Device, out: &mut Vec<Diagnostic>) {
    // A master's PDOs carry the COB-IDs of the slaves it talks to, not its own defaults.
    let master = device.device_info.simple_boot_up_master
        || device
            .commissioning
            .as_ref()
            .is_some_and(|c| c.canopen_manager);
    if master {
        return;
    }
    for (index, sub_index, base, what) in PREDEFINED {
        let Some(sub) = device.entry(index, sub_index) else {
            continue;
        };
        let Some(src) = sub.default.as_ref() else {
            continue;
        };
        let name = entry_name(device, index, sub_index);
        let problem = match src.value {
            Some(Value::NodeRelative(offset)) => {
                let id = (offset as u32) & 0x3FFF_FFFF;
                (id != base).then(|| format!("is $NODEID+{id:#X}, not $NODEID+{base:#X}"))
            }
            Some(Value::Integer(v)) => {
                let v = v as u32;
                if v & 0x8000_0000 != 0 {
                    None // not valid: the COB-ID must be written before use anyway.
                } else {
                    let id = v & 0x7FF;
                    Some(if id > base && id <= base + 127 {
                        format!("is the fixed value {v:#X} (the COB-ID for node-ID {}), not $NODEID+{base:#X}", id - base)
                    } else {
                        format!("is the fixed value {v:#X}, not $NODEID+{base:#X}")
                    })
                }
            }
            _ => None,
        };
        if let Some(problem) = problem {
            out.push(
                Diagnostic::new(
                    &rules::DEFAULT_COB_ID,
                    Some(src.span),
                    format!("the default COB-ID of {name} ({what}) {problem}"),
                )
                .with_label("not the predefined connection set")
                .with_help(format!(
                    "write `DefaultValue=$NODEID+{base:#X}` so the COB-ID follows the node-ID"
                )),
            );
        }
    }
}
