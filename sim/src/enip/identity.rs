//! The Identity object (class 1, instance 1): vendor, device type, product code, revision,
//! status (bit 0 owned: a connection is open), serial and product name, by
//! Get_Attribute_Single and Get_Attributes_All; none settable.

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};

use super::bytes::response;
use super::cip::{serve_attributes, Call, CipObject};
use super::state::DeviceState;

/// The Identity object.
#[derive(Debug)]
pub struct IdentityObject;

impl CipObject for IdentityObject {
    fn class_id(&self) -> u32 {
        1
    }

    fn attribute(&self, device: &DeviceState, _instance: u32, attribute: u32) -> Option<Vec<u8>> {
        let id = &device.identity;
        Some(match attribute {
            1 => id.vendor.to_le_bytes().to_vec(),
            2 => id.device_type.to_le_bytes().to_vec(),
            3 => id.product_code.to_le_bytes().to_vec(),
            4 => vec![id.revision.0, id.revision.1],
            5 => device.identity_status().to_le_bytes().to_vec(),
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

    /// Get_Attributes_All (attributes 1 to 7 in a row) besides the default services.
    fn serve(
        &self,
        device: &mut DeviceState,
        _call: &Call,
        request: &Request<'_>,
        path: &Path,
    ) -> Vec<u8> {
        if request.service == service::GET_ATTRIBUTES_ALL && path.instance.unwrap_or(1) == 1 {
            let data: Vec<u8> = (1..=7)
                .filter_map(|a| self.attribute(device, 1, a))
                .flatten()
                .collect();
            return response(request.service, general::SUCCESS, &[], &data);
        }
        serve_attributes(self, device, request, path)
    }
}
