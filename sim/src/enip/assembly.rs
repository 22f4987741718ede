//! The Assembly object (class 4): each instance's bytes (attribute 3), read by
//! Get_Attribute_Single or Get_Attributes_All, written by Set_Attribute_Single when consumed
//! (O→T) and no class-1 connection writes it.

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};

use super::adapter::{Adapter, Event};
use super::bytes::{response, status_only as status};

/// An assembly the adapter serves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Assembly {
    /// Its bytes.
    pub data: Vec<u8>,
    /// Whether an originator writes it (O→T): a class-1 connection or Set_Attribute_Single.
    pub consumed: bool,
}

impl Adapter {
    pub(super) fn assembly_service(&mut self, request: &Request<'_>, path: &Path) -> Vec<u8> {
        let Some(instance) = path.instance.or(path.points().first().copied()) else {
            return status(request.service, general::PATH_DESTINATION_UNKNOWN);
        };
        let owned = self.connections.iter().any(|c| c.o_t_point == instance);
        let Some(assembly) = self.assemblies.get_mut(&instance) else {
            return status(request.service, general::OBJECT_DOES_NOT_EXIST);
        };
        if path.attribute.unwrap_or(3) != 3 {
            return status(request.service, general::ATTRIBUTE_NOT_SUPPORTED);
        }
        match request.service {
            service::GET_ATTRIBUTE_SINGLE | service::GET_ATTRIBUTES_ALL => {
                response(request.service, general::SUCCESS, &[], &assembly.data)
            }
            service::SET_ATTRIBUTE_SINGLE if !assembly.consumed => {
                status(request.service, general::ATTRIBUTE_NOT_SETTABLE)
            }
            service::SET_ATTRIBUTE_SINGLE if owned => {
                status(request.service, general::DEVICE_STATE_CONFLICT)
            }
            service::SET_ATTRIBUTE_SINGLE => {
                let code = match request.data.len().cmp(&assembly.data.len()) {
                    std::cmp::Ordering::Less => general::NOT_ENOUGH_DATA,
                    std::cmp::Ordering::Greater => general::TOO_MUCH_DATA,
                    std::cmp::Ordering::Equal => {
                        assembly.data.copy_from_slice(request.data);
                        self.events.push_back(Event::Consumed(instance));
                        general::SUCCESS
                    }
                };
                status(request.service, code)
            }
            _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
        }
    }
}
