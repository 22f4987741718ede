//! Simulated devices: CANopen nodes built at run time from a description file, with no generated
//! code ([`dictionary`]), served by the runtime's `Node` as firmware serves a generated `Od`.

pub mod dictionary;

pub use dictionary::{DictionaryHooks, RuntimeDictionary};

use edsgen_model::model::Device;

/// The node-ID a DCF's `[DeviceComissioning]` section gives, if any (not range-checked: a
/// caller reports a value outside 1..=127).
pub fn commissioned_node_id(device: &Device) -> Option<u32> {
    Some(device.commissioning.as_ref()?.node_id.as_ref()?.value)
}
