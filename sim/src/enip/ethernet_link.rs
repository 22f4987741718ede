//! The Ethernet Link object (class 0xF6, instance 1), read-only: interface speed (100 Mbit/s),
//! interface flags (link up, full duplex, negotiated) and the MAC address.

use super::adapter::Adapter;

impl Adapter {
    /// Ethernet Link attribute `attribute`.
    pub(super) fn ethernet_link_attribute(&self, attribute: u32) -> Option<Vec<u8>> {
        match attribute {
            1 => Some(100u32.to_le_bytes().to_vec()),
            2 => Some(0x0000_000Fu32.to_le_bytes().to_vec()),
            3 => Some(self.mac.to_vec()),
            _ => None,
        }
    }
}
