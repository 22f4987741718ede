//! Class-3 connected explicit messaging, sans-IO: the connections a Forward_Open (or
//! Large_Forward_Open) with transport class 3 opens to the Message Router, and SendUnitData on
//! them. A request travels in a Connected Data item (0xB1) after its 16-bit sequence count,
//! addressed by the O→T connection ID in a Connected Address item (0xA1); the reply carries the
//! T→O connection ID and echoes the count. A request with the count of the previous one is a
//! retransmission: it gets the previous reply again and is not executed twice. A request longer
//! than the connection's O→T size (count included) is not executed: general status 0x15. A connection
//! belongs to the session that opened it and closes with it, on Forward_Close, or after its
//! timeout (multiplier × O→T RPI) without a request.

use edsgen_runtime::{Duration, Instant};

use edsgen_runtime::enip::wire::encap::{status as encap_status, EncapRepr};
use edsgen_runtime::enip::wire::io::ConnectedMessage;
use edsgen_runtime::enip::wire::message::general;
use edsgen_runtime::enip::wire::Emit;

use super::adapter::{Adapter, Event, Reply};
use super::bytes::status_only;

/// A class-3 connection.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExplicitConnection {
    /// The ID requests come with (chosen by the adapter).
    pub o_t_id: u32,
    /// The ID replies go with (the originator's choice).
    pub t_o_id: u32,
    /// Connection serial, originator vendor and serial: the triad Forward_Close names.
    pub triad: (u16, u16, u32),
    /// The session that opened it.
    pub session: u32,
    /// The largest reply the originator takes, sequence count included (the T→O size).
    pub t_o_size: usize,
    /// The largest request it may send, sequence count included (the O→T size).
    pub o_t_size: usize,
    /// The timeout: the multiplier times the O→T RPI.
    pub timeout: Duration,
    /// When the last request came (or the connection opened).
    pub last_heard: Instant,
    /// The last request's sequence count and the reply it got.
    pub last: Option<(u16, Vec<u8>)>,
}

/// What a class-3 Forward_Open asks, as the Connection Manager decoded it.
pub(super) struct ExplicitOpen {
    pub t_o_id: u32,
    pub triad: (u16, u16, u32),
    pub t_o_size: usize,
    pub o_t_size: usize,
    pub timeout: Duration,
}

/// SendUnitData refused with the encapsulation's "incorrect data" (0x0003): malformed, or for a
/// connection that is not open (OpENer drops such a message unanswered; an answer tells the
/// originator at once).
fn incorrect() -> Reply {
    Reply::status(encap_status::INCORRECT_DATA, Vec::new())
}

impl Adapter {
    /// The open class-3 connections.
    pub fn explicit_connections(&self) -> &[ExplicitConnection] {
        &self.explicit
    }

    /// Opens a class-3 connection for the session `route` serves; the O→T ID it got.
    pub(super) fn open_explicit(&mut self, open: ExplicitOpen, now: Instant) -> u32 {
        let id = self.next_connection_id;
        self.next_connection_id = self.next_connection_id.wrapping_add(1);
        self.explicit.push(ExplicitConnection {
            o_t_id: id,
            t_o_id: open.t_o_id,
            triad: open.triad,
            session: self.serving_session,
            t_o_size: open.t_o_size,
            o_t_size: open.o_t_size,
            timeout: open.timeout,
            last_heard: now,
            last: None,
        });
        self.events.push_back(Event::Opened(id));
        id
    }

    /// Forward_Close of the class-3 connection with `triad`; whether there was one.
    pub(super) fn close_explicit(&mut self, triad: (u16, u16, u32)) -> bool {
        let Some(at) = self.explicit.iter().position(|c| c.triad == triad) else {
            return false;
        };
        let closed = self.explicit.remove(at);
        self.events.push_back(Event::Closed(closed.o_t_id));
        true
    }

    /// The class-3 connections of `session` close with it.
    pub(super) fn end_session(&mut self, session: u32) {
        let mut ended = Vec::new();
        self.explicit.retain(|c| {
            let keep = c.session != session;
            if !keep {
                ended.push(c.o_t_id);
            }
            keep
        });
        self.events.extend(ended.into_iter().map(Event::Expired));
    }

    /// Closes the class-3 connections that heard no request for their timeout.
    pub(super) fn expire_explicit(&mut self, now: Instant) {
        let mut expired = Vec::new();
        self.explicit.retain(|c| {
            let alive = now < c.last_heard + c.timeout;
            if !alive {
                expired.push(c.o_t_id);
            }
            alive
        });
        self.events.extend(expired.into_iter().map(Event::Expired));
    }

    /// SendUnitData (its session checked): the request on its connection, the reply on the
    /// connection's T→O ID with the same sequence count.
    pub(super) fn send_unit_data(&mut self, client: u64, m: &EncapRepr<'_>, now: Instant) -> Reply {
        let Ok(request) = ConnectedMessage::parse(m.data) else {
            return incorrect();
        };
        let (id, sequence) = (request.connection, request.sequence);
        let Some(at) = self
            .explicit
            .iter()
            .position(|c| c.o_t_id == id && c.session == m.session)
        else {
            return incorrect();
        };
        self.explicit[at].last_heard = now;
        let t_o_id = self.explicit[at].t_o_id;
        let service = request.message.first().copied().unwrap_or(0);
        let reply = match &self.explicit[at].last {
            Some((last, reply)) if *last == sequence => reply.clone(),
            // A request longer than the connection's O→T size is not executed: too much data.
            _ if request.payload_len() > self.explicit[at].o_t_size => {
                let reply = status_only(service, general::TOO_MUCH_DATA);
                self.explicit[at].last = Some((sequence, reply.clone()));
                reply
            }
            _ => {
                self.serving_session = m.session;
                let mut reply = self.route(client, request.message, now);
                // Routing may have closed connections (a Forward_Close on this one).
                let Some(at) = self.explicit.iter().position(|c| c.o_t_id == id) else {
                    return connected_reply(t_o_id, sequence, &reply);
                };
                if reply.len() + 2 > self.explicit[at].t_o_size {
                    reply = status_only(service, general::REPLY_DATA_TOO_LARGE);
                }
                self.explicit[at].last = Some((sequence, reply.clone()));
                reply
            }
        };
        connected_reply(t_o_id, sequence, &reply)
    }
}

/// SendUnitData's reply: the response on the connection's T→O ID with the request's count.
fn connected_reply(t_o_id: u32, sequence: u16, response: &[u8]) -> Reply {
    let message = ConnectedMessage {
        connection: t_o_id,
        sequence,
        message: response,
    };
    // A response fits an encapsulation message (`bytes::response`).
    Reply::success(message.to_vec().unwrap_or_default())
}
