//! The Connection Manager (class 6) and the connections it opens: Forward_Open and
//! Large_Forward_Open (class 1 between two assemblies, class 3 to the Message Router) and
//! Forward_Close, each refusal with CIP's general status and the Connection Manager's extended
//! status; the class-3 connections' bookkeeping (a connection belongs to the session that
//! opened it and closes with it, on Forward_Close, or after its timeout, multiplier × O→T RPI,
//! without a request). Class-1 data and SendUnitData travel in the encapsulation (`adapter`).

use edsgen_runtime::enip::wire::connection_manager::{
    extended, ForwardCloseRepr, ForwardOpenReply, ForwardOpenRepr,
};
use edsgen_runtime::enip::wire::epath::Path;
use edsgen_runtime::enip::wire::message::{general, service, RequestRepr as Request};

use edsgen_runtime::enip::wire::{Emit, Error};
use edsgen_runtime::{Duration, Instant};

use super::bytes::{response, status_only as status};
use super::cip::{Call, CipObject};
use super::state::{DeviceState, Event, ExplicitConnection, IoConnection};

/// What a class-3 Forward_Open asks, as the Connection Manager decoded it.
struct ExplicitOpen {
    pub t_o_id: u32,
    pub triad: (u16, u16, u32),
    pub t_o_size: usize,
    pub o_t_size: usize,
    pub timeout: Duration,
}

/// The Connection Manager object.
#[derive(Debug)]
pub struct ConnectionManager;

impl CipObject for ConnectionManager {
    fn class_id(&self) -> u32 {
        6
    }

    /// Forward_Open, Large_Forward_Open and Forward_Close only.
    fn serve(
        &self,
        device: &mut DeviceState,
        call: &Call,
        request: &Request<'_>,
        _path: &Path,
    ) -> Vec<u8> {
        match request.service {
            service::FORWARD_OPEN => forward_open(device, call, request, false),
            service::LARGE_FORWARD_OPEN => forward_open(device, call, request, true),
            service::FORWARD_CLOSE => forward_close(device, request),
            _ => status(request.service, general::SERVICE_NOT_SUPPORTED),
        }
    }
}

fn forward_open(
    device: &mut DeviceState,
    call: &Call,
    request: &Request<'_>,
    large: bool,
) -> Vec<u8> {
    let (client, now) = (call.client, call.now);
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
    let in_use = device.connections.iter().any(|c| c.triad == triad)
        || device.explicit.iter().any(|c| c.triad == triad);
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
            let id = open_explicit(device, call.session, open, now);
            return opened(id);
        }
        _ => return fail(extended::TRANSPORT_NOT_SUPPORTED),
    }
    let (o_t_point, t_o_point) = match (path.class, path.points()) {
        (Some(4), [o_t, t_o]) => (*o_t, *t_o),
        _ => return fail(extended::INVALID_SEGMENT),
    };
    if let Some(config) = path.instance {
        if !device.config_instances.contains(&config) && !device.assemblies.contains_key(&config) {
            return fail(extended::INVALID_CONFIG_PATH);
        }
    }
    let Some(consumed) = device.assemblies.get(&o_t_point).filter(|a| a.consumed) else {
        return fail(extended::INVALID_CONSUMING_PATH);
    };
    let Some(produced) = device.assemblies.get(&t_o_point) else {
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
    if device.connections.iter().any(|c| c.o_t_point == o_t_point) {
        return fail(extended::CONNECTION_IN_USE);
    }
    let id = device.take_connection_id();
    let o_t = Duration::from_micros(u64::from(open.o_t_rpi.max(1000)));
    device.connections.push(IoConnection {
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
    device.events.push_back(Event::Opened(id));
    opened(id)
}

fn forward_close(device: &mut DeviceState, request: &Request<'_>) -> Vec<u8> {
    let Ok(close) = ForwardCloseRepr::parse(request.data) else {
        return status(request.service, general::NOT_ENOUGH_DATA);
    };
    let data = close.triad.reply();
    let (serial, vendor, orig_serial) = (
        close.triad.serial,
        close.triad.vendor,
        close.triad.originator_serial,
    );
    if close_explicit(device, (serial, vendor, orig_serial)) {
        return response(request.service, general::SUCCESS, &[], &data);
    }
    let Some(at) = device
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
    let closed = device.connections.remove(at);
    device.events.push_back(Event::Closed(closed.o_t_id));
    response(request.service, general::SUCCESS, &[], &data)
}

/// Opens a class-3 connection for `session`; the O→T ID it got.
fn open_explicit(device: &mut DeviceState, session: u32, open: ExplicitOpen, now: Instant) -> u32 {
    let id = device.take_connection_id();
    device.explicit.push(ExplicitConnection {
        o_t_id: id,
        t_o_id: open.t_o_id,
        triad: open.triad,
        session,
        t_o_size: open.t_o_size,
        o_t_size: open.o_t_size,
        timeout: open.timeout,
        last_heard: now,
        last: None,
    });
    device.events.push_back(Event::Opened(id));
    id
}

/// Forward_Close of the class-3 connection with `triad`; whether there was one.
fn close_explicit(device: &mut DeviceState, triad: (u16, u16, u32)) -> bool {
    let Some(at) = device.explicit.iter().position(|c| c.triad == triad) else {
        return false;
    };
    let closed = device.explicit.remove(at);
    device.events.push_back(Event::Closed(closed.o_t_id));
    true
}

/// The class-3 connections of `session` close with it.
pub(super) fn end_session(device: &mut DeviceState, session: u32) {
    let mut ended = Vec::new();
    device.explicit.retain(|c| {
        let keep = c.session != session;
        if !keep {
            ended.push(c.o_t_id);
        }
        keep
    });
    device.events.extend(ended.into_iter().map(Event::Expired));
}

/// Closes the class-3 connections that heard no request for their timeout.
pub(super) fn expire_explicit(device: &mut DeviceState, now: Instant) {
    let mut expired = Vec::new();
    device.explicit.retain(|c| {
        let alive = now < c.last_heard + c.timeout;
        if !alive {
            expired.push(c.o_t_id);
        }
        alive
    });
    device
        .events
        .extend(expired.into_iter().map(Event::Expired));
}
