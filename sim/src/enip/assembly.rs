//! The Assembly object (class 4): each instance's bytes (attribute 3), read by
//! Get_Attribute_Single or Get_Attributes_All, written by Set_Attribute_Single when consumed
//! (O→T) and no class-1 connection writes it.

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};

use super::bytes::{response, status_only as status};
use super::cip::{Call, CipObject};
use super::state::{DeviceState, Event};

/// The Assembly object.
#[derive(Debug)]
pub struct AssemblyObject;

impl CipObject for AssemblyObject {
    fn class_id(&self) -> u32 {
        4
    }

    /// Attribute 3, the data.
    fn attribute(&self, device: &DeviceState, instance: u32, attribute: u32) -> Option<Vec<u8>> {
        let assembly = device.assemblies.get(&instance)?;
        (attribute == 3).then(|| assembly.data.clone())
    }

    /// Attribute 3 of a consumed assembly no class-1 connection writes, at its size.
    fn set_attribute(
        &self,
        device: &mut DeviceState,
        instance: u32,
        attribute: u32,
        data: &[u8],
    ) -> u8 {
        let owned = device.written_by_connection(instance);
        let Some(assembly) = device.assemblies.get_mut(&instance) else {
            return general::OBJECT_DOES_NOT_EXIST;
        };
        if attribute != 3 {
            return general::ATTRIBUTE_NOT_SUPPORTED;
        }
        if !assembly.consumed {
            return general::ATTRIBUTE_NOT_SETTABLE;
        }
        if owned {
            return general::DEVICE_STATE_CONFLICT;
        }
        match data.len().cmp(&assembly.data.len()) {
            std::cmp::Ordering::Less => general::NOT_ENOUGH_DATA,
            std::cmp::Ordering::Greater => general::TOO_MUCH_DATA,
            std::cmp::Ordering::Equal => {
                assembly.data.copy_from_slice(data);
                device.events.push_back(Event::Consumed(instance));
                general::SUCCESS
            }
        }
    }

    /// The instance from the path's instance or first connection point, attribute 3 when the
    /// path names none; Get_Attributes_All as Get_Attribute_Single.
    fn serve(
        &self,
        device: &mut DeviceState,
        _call: &Call,
        request: &Request<'_>,
        path: &Path,
    ) -> Vec<u8> {
        let Some(instance) = path.instance.or(path.points().first().copied()) else {
            return status(request.service, general::PATH_DESTINATION_UNKNOWN);
        };
        if !device.assemblies.contains_key(&instance) {
            return status(request.service, general::OBJECT_DOES_NOT_EXIST);
        }
        let attribute = path.attribute.unwrap_or(3);
        if attribute != 3 {
            return status(request.service, general::ATTRIBUTE_NOT_SUPPORTED);
        }
        match request.service {
            service::GET_ATTRIBUTE_SINGLE | service::GET_ATTRIBUTES_ALL => {
                match self.attribute(device, instance, attribute) {
                    Some(data) => response(request.service, general::SUCCESS, &[], &data),
                    None => status(request.service, general::OBJECT_DOES_NOT_EXIST),
                }
            }
            service::SET_ATTRIBUTE_SINGLE => {
                let code = self.set_attribute(device, instance, attribute, request.data);
                status(request.service, code)
            }
            _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
        }
    }
}
