//! The TCP/IP Interface object (class 0xF5, instance 1), read-only: status (a configured
//! address), capability, configuration control, and the interface configuration (the adapter's
//! address, netmask 255.255.255.0, no gateway or name servers).

use super::cip::CipObject;
use super::state::DeviceState;

/// The TCP/IP Interface object.
#[derive(Debug)]
pub struct TcpIpInterface;

impl CipObject for TcpIpInterface {
    fn class_id(&self) -> u32 {
        0xF5
    }

    fn attribute(&self, device: &DeviceState, _instance: u32, attribute: u32) -> Option<Vec<u8>> {
        match attribute {
            1 => Some(2u32.to_le_bytes().to_vec()),
            2 => Some(0x0000_0014u32.to_le_bytes().to_vec()),
            3 => Some(2u32.to_le_bytes().to_vec()),
            5 => {
                let mut v: Vec<u8> = device.address.iter().rev().copied().collect();
                v.extend_from_slice(&[0, 255, 255, 255]);
                v.extend_from_slice(&[0; 14]);
                Some(v)
            }
            _ => None,
        }
    }
}
