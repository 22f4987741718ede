//! The Identity object (class 1, instance 1): vendor, device type, product code, revision,
//! status (bit 0 owned: a connection is open), serial and product name, by
//! Get_Attribute_Single and Get_Attributes_All; none settable.

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};

use super::adapter::Adapter;
use super::bytes::{response, status_only as status};

/// What the Identity object (class 1) reports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Identity {
    /// Vendor ID (attribute 1).
    pub vendor: u16,
    /// Device type (attribute 2).
    pub device_type: u16,
    /// Product code (attribute 3).
    pub product_code: u16,
    /// Major and minor revision (attribute 4).
    pub revision: (u8, u8),
    /// Serial number (attribute 6).
    pub serial: u32,
    /// Product name (attribute 7).
    pub name: String,
}

impl Adapter {
    /// Identity attribute 5: bit 0 owned (a connection is open).
    pub(super) fn identity_status(&self) -> u16 {
        u16::from(!self.connections.is_empty())
    }

    /// One class-1 datagram (O→T) from `peer` at `now`: its data goes into the connection's

    fn identity_attribute(&self, attribute: u32) -> Option<Vec<u8>> {
        let id = &self.identity;
        Some(match attribute {
            1 => id.vendor.to_le_bytes().to_vec(),
            2 => id.device_type.to_le_bytes().to_vec(),
            3 => id.product_code.to_le_bytes().to_vec(),
            4 => vec![id.revision.0, id.revision.1],
            5 => self.identity_status().to_le_bytes().to_vec(),
            6 => id.serial.to_le_bytes().to_vec(),
            7 => {
                let name = id.name.as_bytes();
                let name = &name[..name.len().min(32)];
                let mut v = vec![name.len() as u8];
                v.extend_from_slice(name);
                v
            }
            _ => return None,
        })
    }

    pub(super) fn identity_service(&self, request: &Request<'_>, path: &Path) -> Vec<u8> {
        if path.instance.unwrap_or(1) != 1 {
            return status(request.service, general::OBJECT_DOES_NOT_EXIST);
        }
        match request.service {
            service::GET_ATTRIBUTES_ALL => {
                let data: Vec<u8> = (1..=7)
                    .filter_map(|a| self.identity_attribute(a))
                    .flatten()
                    .collect();
                response(request.service, general::SUCCESS, &[], &data)
            }
            service::GET_ATTRIBUTE_SINGLE => {
                match path.attribute.and_then(|a| self.identity_attribute(a)) {
                    Some(data) => response(request.service, general::SUCCESS, &[], &data),
                    None => status(request.service, general::ATTRIBUTE_NOT_SUPPORTED),
                }
            }
            service::SET_ATTRIBUTE_SINGLE => {
                status(request.service, general::ATTRIBUTE_NOT_SETTABLE)
            }
            _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
        }
    }
}
