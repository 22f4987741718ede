//! CIP routing's contract, OpENer-style: a [`CipObject`] is one class (its ID, its attributes,
//! the services it serves on the [`DeviceState`] it borrows), and a [`Registry`] holds the
//! classes the Message Router dispatches to. The objects know neither the encapsulation nor
//! each other; what they share is in the device state.

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};
use edsgen_runtime::Instant;

use super::bytes::{response, status_only as status};
use super::state::DeviceState;

/// Who sent a request and when: what the Connection Manager records with a connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Call {
    /// The driver's key for the client (TCP connection; `u64::MAX` for UDP).
    pub client: u64,
    /// The session the request came in.
    pub session: u32,
    /// When it came.
    pub now: Instant,
}

/// One CIP object class.
pub trait CipObject: std::fmt::Debug + Sync {
    /// Its class ID.
    fn class_id(&self) -> u32;

    /// Attribute `attribute` of instance `instance` (0: the class); `None` when unsupported.
    fn attribute(&self, _device: &DeviceState, _instance: u32, _attribute: u32) -> Option<Vec<u8>> {
        None
    }

    /// Set_Attribute_Single of `attribute` of `instance` to `data`: the general status.
    fn set_attribute(
        &self,
        _device: &mut DeviceState,
        _instance: u32,
        _attribute: u32,
        _data: &[u8],
    ) -> u8 {
        general::ATTRIBUTE_NOT_SETTABLE
    }

    /// One request whose path names this class; the response's bytes. By default instance 1
    /// only: Get_Attribute_Single from [`attribute`](Self::attribute), Set_Attribute_Single
    /// from [`set_attribute`](Self::set_attribute), no other service.
    fn serve(
        &self,
        device: &mut DeviceState,
        _call: &Call,
        request: &Request<'_>,
        path: &Path,
    ) -> Vec<u8> {
        serve_attributes(self, device, request, path)
    }
}

/// [`CipObject::serve`]'s default: instance 1 only; Get_Attribute_Single and
/// Set_Attribute_Single through the object's attributes, no other service.
pub fn serve_attributes<O: CipObject + ?Sized>(
    object: &O,
    device: &mut DeviceState,
    request: &Request<'_>,
    path: &Path,
) -> Vec<u8> {
    let instance = path.instance.unwrap_or(1);
    if instance != 1 {
        return status(request.service, general::OBJECT_DOES_NOT_EXIST);
    }
    let attribute = path.attribute.unwrap_or(0);
    match request.service {
        service::GET_ATTRIBUTE_SINGLE => {
            let value = path
                .attribute
                .and_then(|a| object.attribute(device, instance, a));
            match value {
                Some(data) => response(request.service, general::SUCCESS, &[], &data),
                None => status(request.service, general::ATTRIBUTE_NOT_SUPPORTED),
            }
        }
        service::SET_ATTRIBUTE_SINGLE => {
            let code = object.set_attribute(device, instance, attribute, request.data);
            status(request.service, code)
        }
        _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
    }
}

/// The classes the Message Router reaches, by class ID.
#[derive(Debug, Clone)]
pub struct Registry {
    objects: Vec<&'static dyn CipObject>,
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Self {
        Registry {
            objects: Vec::new(),
        }
    }

    /// Adds `object`, replacing a class with its ID.
    pub fn register(&mut self, object: &'static dyn CipObject) {
        self.objects.retain(|o| o.class_id() != object.class_id());
        self.objects.push(object);
    }

    /// The object of class `class`.
    pub fn find(&self, class: u32) -> Option<&'static dyn CipObject> {
        self.objects.iter().copied().find(|o| o.class_id() == class)
    }
}

impl Default for Registry {
    fn default() -> Self {
        Registry::new()
    }
}
