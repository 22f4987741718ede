//! The Message Router (class 2): parses a request and its path and hands it to the object of
//! the [`Registry`] whose class the path names; it has no attributes of its own (instance 1).

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, RequestRepr as Request};

use super::assembly::AssemblyObject;
use super::bytes::status_only as status;
use super::cip::{Call, CipObject, Registry};
use super::connection_manager::ConnectionManager;
use super::ethernet_link::EthernetLink;
use super::identity::IdentityObject;
use super::parameter::ParameterObject;
use super::state::DeviceState;
use super::tcp_ip::TcpIpInterface;

/// The Message Router object.
#[derive(Debug)]
pub struct MessageRouter;

impl CipObject for MessageRouter {
    fn class_id(&self) -> u32 {
        2
    }
}

/// The registry of the objects an adapter serves: Identity, Message Router, Assembly,
/// Connection Manager, Parameter, TCP/IP Interface and Ethernet Link.
pub fn standard_objects() -> Registry {
    let mut registry = Registry::new();
    registry.register(&IdentityObject);
    registry.register(&MessageRouter);
    registry.register(&AssemblyObject);
    registry.register(&ConnectionManager);
    registry.register(&ParameterObject);
    registry.register(&TcpIpInterface);
    registry.register(&EthernetLink);
    registry
}

/// One Message Router request to the objects of `registry`; the response's bytes.
pub fn route(registry: &Registry, device: &mut DeviceState, call: &Call, bytes: &[u8]) -> Vec<u8> {
    let Ok(request) = Request::parse(bytes) else {
        let service = bytes.first().copied().unwrap_or(0);
        return status(service, general::NOT_ENOUGH_DATA);
    };
    let Ok(path) = Path::parse(request.path) else {
        return status(request.service, general::PATH_SEGMENT_ERROR);
    };
    match path.class.and_then(|class| registry.find(class)) {
        Some(object) => object.serve(device, call, &request, &path),
        None => status(request.service, general::PATH_DESTINATION_UNKNOWN),
    }
}
