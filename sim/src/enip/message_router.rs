//! The Message Router (class 2): parses a request and its path and hands it to the object
//! whose class the path names; it has no attributes of its own beyond instance 1.

use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};

use edsgen_runtime::Instant;

use super::adapter::Adapter;
use super::bytes::{response, status_only as status};

impl Adapter {
    /// One Message Router request; the response's bytes.
    pub fn route(&mut self, client: u64, bytes: &[u8], now: Instant) -> Vec<u8> {
        let Ok(request) = Request::parse(bytes) else {
            let service = bytes.first().copied().unwrap_or(0);
            return status(service, general::NOT_ENOUGH_DATA);
        };
        let Ok(path) = Path::parse(request.path) else {
            return status(request.service, general::PATH_SEGMENT_ERROR);
        };
        match path.class {
            Some(1) => self.identity_service(&request, &path),
            Some(2) => self.simple_get(&request, &path, |_, _| None),
            Some(4) => self.assembly_service(&request, &path),
            Some(6) => self.connection_manager(client, &request, now),
            Some(0x0F) => self.parameter_service(&request, &path),
            Some(0xF5) => self.simple_get(&request, &path, Adapter::tcp_ip_attribute),
            Some(0xF6) => self.simple_get(&request, &path, Adapter::ethernet_link_attribute),
            _ => status(request.service, general::PATH_DESTINATION_UNKNOWN),
        }
    }

    /// Get_Attribute_Single on instance 1 of an object whose attributes `get` gives.
    fn simple_get(
        &self,
        request: &Request<'_>,
        path: &Path,
        get: impl Fn(&Adapter, u32) -> Option<Vec<u8>>,
    ) -> Vec<u8> {
        if path.instance.unwrap_or(1) != 1 {
            return status(request.service, general::OBJECT_DOES_NOT_EXIST);
        }
        match request.service {
            service::GET_ATTRIBUTE_SINGLE => match path.attribute.and_then(|a| get(self, a)) {
                Some(data) => response(request.service, general::SUCCESS, &[], &data),
                None => status(request.service, general::ATTRIBUTE_NOT_SUPPORTED),
            },
            service::SET_ATTRIBUTE_SINGLE => {
                status(request.service, general::ATTRIBUTE_NOT_SETTABLE)
            }
            _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
        }
    }
}
