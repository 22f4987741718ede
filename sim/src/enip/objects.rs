//! The Message Router (class 2) and the objects behind it: Identity (1), Assembly (4),
//! Connection Manager (6: Forward_Open, Large_Forward_Open, Forward_Close; class 1 to assemblies,
//! class 3 to the Message Router), Parameter (0x0F, in `parameter`), TCP/IP Interface
//! (0xF5) and Ethernet Link (0xF6). Each refusal carries CIP's general status (and the
//! Connection Manager's extended status).

use edsgen_runtime::enip::wire::connection_manager::{
    extended, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr,
};
use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};
use edsgen_runtime::enip::wire::{Emit, Error};

use edsgen_runtime::{Duration, Instant};

use super::adapter::{Adapter, Event, IoConnection};
use super::bytes::{response, status_only};
use super::class3::ExplicitOpen;

fn status(service: u8, code: u8) -> Vec<u8> {
    status_only(service, code)
}

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
            Some(0xF5) => self.simple_get(&request, &path, |a, attr| match attr {
                1 => Some(2u32.to_le_bytes().to_vec()),
                2 => Some(0x0000_0014u32.to_le_bytes().to_vec()),
                3 => Some(2u32.to_le_bytes().to_vec()),
                5 => {
                    let mut v: Vec<u8> = a.address.iter().rev().copied().collect();
                    v.extend_from_slice(&[0, 255, 255, 255]);
                    v.extend_from_slice(&[0; 14]);
                    Some(v)
                }
                _ => None,
            }),
            Some(0xF6) => self.simple_get(&request, &path, |a, attr| match attr {
                1 => Some(100u32.to_le_bytes().to_vec()),
                2 => Some(0x0000_000Fu32.to_le_bytes().to_vec()),
                3 => Some(a.mac.to_vec()),
                _ => None,
            }),
            _ => status(request.service, general::PATH_DESTINATION_UNKNOWN),
        }
    }

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

    fn identity_service(&self, request: &Request<'_>, path: &Path) -> Vec<u8> {
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

    fn assembly_service(&mut self, request: &Request<'_>, path: &Path) -> Vec<u8> {
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

    fn connection_manager(&mut self, client: u64, request: &Request<'_>, now: Instant) -> Vec<u8> {
        match request.service {
            service::FORWARD_OPEN => self.forward_open(client, request, now, false),
            service::LARGE_FORWARD_OPEN => self.forward_open(client, request, now, true),
            service::FORWARD_CLOSE => self.forward_close(request),
            _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
        }
    }

    fn forward_open(
        &mut self,
        client: u64,
        request: &Request<'_>,
        now: Instant,
        large: bool,
    ) -> Vec<u8> {
        let open = match ForwardOpenRepr::parse(request.data, large) {
            Ok(open) => open,
            Err(Error::Trailing) => return status(request.service, general::TOO_MUCH_DATA),
            Err(_) => return status(request.service, general::NOT_ENOUGH_DATA),
        };
        let t_o_id = open.t_o_id;
        let triad = (
            open.triad.serial,
            open.triad.vendor,
            open.triad.originator_serial,
        );
        let fail = |code: u16| {
            response(
                request.service,
                general::CONNECTION_FAILURE,
                &[code],
                &open.triad.reply(),
            )
        };
        let in_use = self.connections.iter().any(|c| c.triad == triad)
            || self.explicit.iter().any(|c| c.triad == triad);
        if in_use {
            return fail(extended::CONNECTION_IN_USE);
        }
        let Ok(path) = Path::parse(open.path) else {
            return fail(extended::INVALID_SEGMENT);
        };
        let timeout = Duration::from_micros(open.timeout_us());
        let opened = |id: u32| {
            let reply = ForwardOpenReply {
                o_t_id: id,
                t_o_id,
                triad: open.triad,
                o_t_api: open.o_t_rpi,
                t_o_api: open.t_o_rpi,
            };
            let mut data = [0; 26];
            let _ = reply.emit(&mut data);
            response(request.service, general::SUCCESS, &[], &data)
        };
        match open.transport & 0x0F {
            1 => {}
            // Class 3, server: explicit messages to the Message Router (path 20 02 24 01).
            3 if open.transport & 0x80 != 0 => {
                let router = path.class == Some(2)
                    && path.instance == Some(1)
                    && path.points().is_empty()
                    && path.attribute.is_none();
                if !router {
                    return fail(extended::INVALID_SEGMENT);
                }
                let open = ExplicitOpen {
                    t_o_id,
                    triad,
                    t_o_size: usize::from(open.t_o_size()),
                    o_t_size: usize::from(open.o_t_size()),
                    timeout,
                };
                let id = self.open_explicit(open, now);
                return opened(id);
            }
            _ => return fail(extended::TRANSPORT_NOT_SUPPORTED),
        }
        let (o_t_point, t_o_point) = match (path.class, path.points()) {
            (Some(4), [o_t, t_o]) => (*o_t, *t_o),
            _ => return fail(extended::INVALID_SEGMENT),
        };
        if let Some(config) = path.instance {
            if !self.config_instances.contains(&config) && !self.assemblies.contains_key(&config) {
                return fail(extended::INVALID_CONFIG_PATH);
            }
        }
        let Some(consumed) = self.assemblies.get(&o_t_point).filter(|a| a.consumed) else {
            return fail(extended::INVALID_CONSUMING_PATH);
        };
        let Some(produced) = self.assemblies.get(&t_o_point) else {
            return fail(extended::INVALID_PRODUCING_PATH);
        };
        // Class 1: a 2-byte sequence count both ways, the 4-byte run/idle header O→T.
        let (want_o_t, want_t_o) = (consumed.data.len() + 6, produced.data.len() + 2);
        if usize::from(open.o_t_size()) != want_o_t {
            return response(
                request.service,
                general::CONNECTION_FAILURE,
                &[extended::INVALID_O_T_SIZE, want_o_t as u16],
                &[],
            );
        }
        if usize::from(open.t_o_size()) != want_t_o {
            return response(
                request.service,
                general::CONNECTION_FAILURE,
                &[extended::INVALID_T_O_SIZE, want_t_o as u16],
                &[],
            );
        }
        if self.connections.iter().any(|c| c.o_t_point == o_t_point) {
            return fail(extended::CONNECTION_IN_USE);
        }
        let id = self.next_connection_id;
        self.next_connection_id = self.next_connection_id.wrapping_add(1);
        let o_t = Duration::from_micros(u64::from(open.o_t_rpi.max(1000)));
        self.connections.push(IoConnection {
            o_t_id: id,
            t_o_id,
            triad,
            o_t_point,
            t_o_point,
            o_t_rpi: o_t,
            t_o_rpi: Duration::from_micros(u64::from(open.t_o_rpi.max(1000))),
            timeout,
            last_heard: now,
            next_produce: now,
            t_o_sequence: 0,
            o_t_sequence: None,
            run: false,
            peer: client,
            t_o_port: None,
        });
        self.events.push_back(Event::Opened(id));
        opened(id)
    }

    fn forward_close(&mut self, request: &Request<'_>) -> Vec<u8> {
        let Ok(close) = ForwardCloseRepr::parse(request.data) else {
            return status(request.service, general::NOT_ENOUGH_DATA);
        };
        let data = close.triad.reply();
        let (serial, vendor, orig_serial) = (
            close.triad.serial,
            close.triad.vendor,
            close.triad.originator_serial,
        );
        if self.close_explicit((serial, vendor, orig_serial)) {
            return response(request.service, general::SUCCESS, &[], &data);
        }
        let Some(at) = self
            .connections
            .iter()
            .position(|c| c.triad == (serial, vendor, orig_serial))
        else {
            return response(
                request.service,
                general::CONNECTION_FAILURE,
                &[extended::CONNECTION_NOT_FOUND],
                &data,
            );
        };
        let closed = self.connections.remove(at);
        self.events.push_back(Event::Closed(closed.o_t_id));
        response(request.service, general::SUCCESS, &[], &data)
    }
}
