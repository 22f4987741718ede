//! The Ethernet Link object (class 0xF6, instance 1), read-only: interface speed (100 Mbit/s),
//! interface flags (link up, full duplex, negotiated) and the MAC address.

use super::cip::CipObject;
use super::state::DeviceState;

/// The Ethernet Link object.
#[derive(Debug)]
pub struct EthernetLink;

impl CipObject for EthernetLink {
    fn class_id(&self) -> u32 {
        0xF6
    }

    fn attribute(&self, device: &DeviceState, _instance: u32, attribute: u32) -> Option<Vec<u8>> {
        match attribute {
            1 => Some(100u32.to_le_bytes().to_vec()),
            2 => Some(0x0000_000Fu32.to_le_bytes().to_vec()),
            3 => Some(device.mac.to_vec()),
            _ => None,
        }
    }
}
