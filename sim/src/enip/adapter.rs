//! The encapsulation layer, sans-IO, with the runtime's verbs: bytes in with the time and their
//! sender ([`Adapter::handle`]: an encapsulation message from a TCP client or a UDP datagram, or
//! a class-1 datagram), bytes out with their destination ([`Adapter::poll_transmit`]: replies,
//! and the T→O datagrams [`Adapter::handle_timeout`] finds due), events out
//! ([`Adapter::poll_event`]). It owns the sessions (RegisterSession, UnRegisterSession),
//! ListIdentity, ListServices, and the CPF of SendRRData (a request to the Message Router) and
//! SendUnitData (class 3: a request on a connection after its 16-bit sequence count; a
//! retransmission gets the previous reply again, a request longer than the O→T size general
//! status 0x15). It reaches the objects only through the Message Router, and tells its
//! application ([`EnipApplication`]) what the originators wrote and how connections ended.

use std::collections::{BTreeMap, VecDeque};

use edsgen_runtime::Instant;

use edsgen_runtime::enip::wire::cpf::{item, Item, Items, Sockaddr};
use edsgen_runtime::enip::wire::encap::{
    command, status as encap_status, EncapError, EncapRepr, IdentityItem, RegisterSession,
};
use edsgen_runtime::enip::wire::io::{ConnectedMessage, IoDatagram};
use edsgen_runtime::enip::wire::message::general;
use edsgen_runtime::enip::wire::{u16_at, u32_at, Emit};

use super::application::{Ending, EnipApplication};
use super::bytes::{items, send_data, status_only};
use super::cip::{Call, Registry};
use super::connection_manager::{end_session, expire_explicit};
use super::message_router::{self, standard_objects};
use super::parameter;
use super::state::{Assembly, DeviceState, Event, ExplicitConnection, Identity, IoConnection};

/// Where bytes come from or go to, in the driver's terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Peer {
    /// A TCP client on the encapsulation port: a key the driver chooses per connection.
    Tcp(u64),
    /// A UDP datagram on the encapsulation port; its reply goes back to its sender.
    Udp,
    /// Class-1 I/O (UDP 2222) with the originator of TCP client `key` (`u64::MAX`: none known).
    Io(u64),
}

/// The adapter: the encapsulation's sessions over the device state, the CIP objects and the
/// application `A`.
#[derive(Debug, Clone)]
pub struct Adapter<A = ()> {
    /// The state the objects share: identity, assemblies, parameters, connections, events.
    pub device: DeviceState,
    /// The objects the Message Router reaches.
    pub registry: Registry,
    app: A,
    sessions: BTreeMap<u32, u64>,
    next_session: u32,
    /// Bytes to send, with their destination.
    pub(super) transmit: VecDeque<(Peer, Vec<u8>)>,
    /// The session whose request [`Adapter::route`] serves (a class-3 connection's owner).
    serving_session: u32,
}

/// The key of UDP requests on the encapsulation port among the TCP clients' keys.
const UDP: u64 = u64::MAX;

impl Adapter<()> {
    /// An adapter with `identity` serving `assemblies`, no application behind them.
    pub fn new(identity: Identity, assemblies: BTreeMap<u32, Assembly>, address: [u8; 4]) -> Self {
        Adapter {
            device: DeviceState::new(identity, assemblies, address),
            registry: standard_objects(),
            app: (),
            sessions: BTreeMap::new(),
            next_session: 1,
            transmit: VecDeque::new(),
            serving_session: 0,
        }
    }
}

impl<A> Adapter<A> {
    /// The same adapter with `app` behind it.
    pub fn with_application<B>(self, app: B) -> Adapter<B> {
        Adapter {
            device: self.device,
            registry: self.registry,
            app,
            sessions: self.sessions,
            next_session: self.next_session,
            transmit: self.transmit,
            serving_session: self.serving_session,
        }
    }

    /// The application.
    pub fn app(&self) -> &A {
        &self.app
    }

    /// The application, to change.
    pub fn app_mut(&mut self) -> &mut A {
        &mut self.app
    }
}

impl<A: EnipApplication> Adapter<A> {
    /// One Message Router request from `client` at `now` (in the session last served); the
    /// response's bytes.
    pub fn route(&mut self, client: u64, bytes: &[u8], now: Instant) -> Vec<u8> {
        let call = Call {
            client,
            session: self.serving_session,
            now,
        };
        message_router::route(&self.registry, &mut self.device, &call, bytes)
    }

    /// The value of parameter `n` (its data size in bytes), from wherever it is kept.
    pub fn parameter_value(&self, n: u32) -> Option<Vec<u8>> {
        parameter::value(&self.device, n)
    }

    /// The open class-1 connections.
    pub fn connections(&self) -> &[IoConnection] {
        &self.device.connections
    }

    /// The next event, oldest first.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.device.events.pop_front()
    }

    /// The next bytes to send, oldest first, with their destination: replies (to the TCP
    /// client or UDP sender of the request) and T→O datagrams (a connection's first right
    /// after its Forward_Open's reply, the next ones after
    /// [`handle_timeout`](Self::handle_timeout)).
    pub fn poll_transmit(&mut self, _now: Instant) -> Option<(Peer, Vec<u8>)> {
        self.transmit.pop_front()
    }

    /// Bytes `from` a peer at `now`: one encapsulation message from the front of a TCP
    /// client's stream or a UDP datagram (its reply, if any, waits in
    /// [`poll_transmit`](Self::poll_transmit): none for UnRegisterSession or NOP), or one
    /// class-1 datagram. Returns the bytes consumed; an incomplete encapsulation message
    /// consumes none ([`EncapError`]).
    pub fn handle(&mut self, now: Instant, from: Peer, bytes: &[u8]) -> Result<usize, EncapError> {
        let before = self.device.events.len();
        let client = match from {
            Peer::Io(key) => {
                self.receive_io(now, key, bytes);
                self.tell_application(now, before);
                return Ok(bytes.len());
            }
            Peer::Tcp(key) => key,
            Peer::Udp => UDP,
        };
        let (message, used) = EncapRepr::parse_prefix(bytes)?;
        let reply = self.command(client, &message, now).and_then(|reply| {
            EncapRepr {
                session: reply.session.unwrap_or(message.session),
                ..message.reply(reply.status, &reply.data)
            }
            .to_vec()
            .ok()
        });
        if let Some(reply) = reply {
            self.transmit.push_back((from, reply));
        }
        // A class-1 connection's first T→O follows its Forward_Open reply at once, so that it
        // shows the assemblies as they were when the connection opened, whatever the
        // originator's first O→T then changes.
        if self
            .device
            .events
            .iter()
            .skip(before)
            .any(|e| matches!(e, Event::Opened(_)))
        {
            self.produce(now);
        }
        self.tell_application(now, before);
        Ok(used)
    }

    /// Hands the events since the `before`-th to the application: the assemblies written, the
    /// class-1 connections ended (what it did about them becomes an event too).
    fn tell_application(&mut self, now: Instant, before: usize) {
        let new: Vec<Event> = self.device.events.iter().skip(before).cloned().collect();
        for event in new {
            let ending = match event {
                Event::Consumed(instance) => {
                    self.app.consumed(now, instance, &mut self.device);
                    continue;
                }
                Event::Closed(_) => Ending::Closed,
                Event::TimedOut(_) => Ending::TimedOut,
                Event::Opened(_) | Event::Expired(_) | Event::Reacted(_) => continue,
            };
            if let Some(reaction) = self.app.connection_ended(now, ending, &mut self.device) {
                self.device.events.push_back(Event::Reacted(reaction));
            }
        }
    }

    /// A TCP client went away at `now`: its sessions end, and their class-3 connections.
    pub fn client_gone(&mut self, now: Instant, client: u64) {
        let before = self.device.events.len();
        let ended: Vec<u32> = self
            .sessions
            .iter()
            .filter(|(_, c)| **c == client)
            .map(|(s, _)| *s)
            .collect();
        for session in ended {
            self.sessions.remove(&session);
            end_session(&mut self.device, session);
        }
        self.tell_application(now, before);
    }

    fn command(&mut self, client: u64, m: &EncapRepr<'_>, now: Instant) -> Option<Reply> {
        let session_ok = self.sessions.get(&m.session) == Some(&client);
        Some(match m.command {
            command::NOP => return None,
            command::LIST_IDENTITY => Reply::success(self.list_identity()),
            command::LIST_SERVICES => {
                let mut body = Vec::new();
                body.extend_from_slice(&1u16.to_le_bytes());
                // Capability: bit 5 CIP over TCP, bit 8 class 0/1 over UDP.
                body.extend_from_slice(&0x0120u16.to_le_bytes());
                body.extend_from_slice(b"Communications\0\0");
                Reply::success(items(&[Item::new(item::SERVICES, &body)]))
            }
            command::LIST_INTERFACES => Reply::success(0u16.to_le_bytes().to_vec()),
            // TCP only (CIP Vol 2 Table 2-3.2): over UDP an invalid command, as any other.
            command::REGISTER_SESSION | command::SEND_RR_DATA | command::SEND_UNIT_DATA
                if client == UDP =>
            {
                Reply::status(encap_status::INVALID_COMMAND, Vec::new())
            }
            command::REGISTER_SESSION => match RegisterSession::parse(m.data) {
                Err(_) => Reply::status(encap_status::INVALID_LENGTH, m.data.to_vec()),
                Ok(register) if register.protocol_version != 1 => Reply::status(
                    encap_status::UNSUPPORTED_PROTOCOL,
                    1u32.to_le_bytes().to_vec(),
                ),
                Ok(_) => {
                    let handle = self.next_session;
                    self.next_session = self.next_session.wrapping_add(1).max(1);
                    self.sessions.insert(handle, client);
                    Reply {
                        session: Some(handle),
                        ..Reply::success(m.data.to_vec())
                    }
                }
            },
            command::UNREGISTER_SESSION => {
                if session_ok {
                    self.sessions.remove(&m.session);
                    end_session(&mut self.device, m.session);
                }
                return None;
            }
            command::SEND_RR_DATA | command::SEND_UNIT_DATA if !session_ok => {
                Reply::status(encap_status::INVALID_SESSION, Vec::new())
            }
            command::SEND_RR_DATA => self.send_rr_data(client, m, now),
            command::SEND_UNIT_DATA => self.send_unit_data(client, m, now),
            _ => Reply::status(encap_status::INVALID_COMMAND, Vec::new()),
        })
    }

    fn send_rr_data(&mut self, client: u64, m: &EncapRepr<'_>, now: Instant) -> Reply {
        let found = Items::parse_send_data(m.data).ok().and_then(|items| {
            let t_o_port = items.find(item::SOCKADDR_T_O).map(Sockaddr::parse);
            Some((items.find(item::UNCONNECTED_DATA)?, t_o_port))
        });
        let Some((request, t_o_port)) = found else {
            return Reply::status(encap_status::INCORRECT_DATA, Vec::new());
        };
        self.serving_session = m.session;
        let opened = self.device.connections.len();
        let response = self.route(client, request, now);
        if let (Some(Ok(sockaddr)), Some(c)) = (t_o_port, self.device.connections.get_mut(opened)) {
            c.t_o_port = Some(sockaddr.port);
        }
        Reply::success(send_data(&[
            Item::new(item::NULL_ADDRESS, &[]),
            Item::new(item::UNCONNECTED_DATA, &response),
        ]))
    }

    /// The ListIdentity reply's data (one identity item).
    pub fn list_identity(&self) -> Vec<u8> {
        let id = &self.device.identity;
        let name = id.name.as_bytes();
        let body = IdentityItem {
            protocol_version: 1,
            port: 44818,
            address: self.device.address,
            vendor: id.vendor,
            device_type: id.device_type,
            product_code: id.product_code,
            revision: id.revision,
            status: self.device.identity_status(),
            serial: id.serial,
            name: &name[..name.len().min(32)],
            state: 3, // operational
        };
        // 66 bytes at most: always written.
        let body = body.to_vec().unwrap_or_default();
        items(&[Item::new(item::IDENTITY, &body)])
    }

    /// One class-1 datagram (O→T) at `now`: its data goes into the connection's assembly.
    /// Datagrams for no connection, too short, or out of sequence are dropped, as CIP drops
    /// them.
    fn receive_io(&mut self, now: Instant, _peer: u64, bytes: &[u8]) {
        let Ok(IoDatagram {
            connection: id,
            data,
            ..
        }) = IoDatagram::parse(bytes)
        else {
            return;
        };
        let Some(conn) = self.device.connections.iter_mut().find(|c| c.o_t_id == id) else {
            return;
        };
        let (Some(sequence), Some(header)) = (u16_at(data, 0), u32_at(data, 2)) else {
            return;
        };
        conn.last_heard = now;
        if conn.o_t_sequence == Some(sequence) {
            return; // the same data again
        }
        conn.o_t_sequence = Some(sequence);
        conn.run = header & 1 != 0;
        let point = conn.o_t_point;
        if let Some(assembly) = self.device.assemblies.get_mut(&point) {
            let payload = &data[6..];
            if payload.len() == assembly.data.len() {
                assembly.data.copy_from_slice(payload);
                self.device.events.push_back(Event::Consumed(point));
            }
        }
    }

    /// When [`handle_timeout`](Self::handle_timeout) has something to do next: a T→O
    /// production or a timeout.
    pub fn poll_timeout(&self) -> Option<Instant> {
        let explicit = self
            .device
            .explicit
            .iter()
            .map(|c| c.last_heard + c.timeout);
        self.device
            .connections
            .iter()
            .flat_map(|c| [c.next_produce, c.last_heard + c.timeout])
            .chain(explicit)
            .chain(self.app.poll_timeout())
            .min()
    }

    /// At `now`: closes connections whose O→T data (class 1) or requests (class 3) stopped for
    /// their timeout, moves the application on, and queues the T→O datagrams due
    /// ([`poll_transmit`](Self::poll_transmit)).
    pub fn handle_timeout(&mut self, now: Instant) {
        let before = self.device.events.len();
        expire_explicit(&mut self.device, now);
        let mut timed_out = Vec::new();
        self.device.connections.retain(|c| {
            let alive = now < c.last_heard + c.timeout;
            if !alive {
                timed_out.push(c.o_t_id);
            }
            alive
        });
        self.device
            .events
            .extend(timed_out.into_iter().map(Event::TimedOut));
        self.tell_application(now, before);
        self.app.handle_timeout(now, &mut self.device);
        self.produce(now);
    }

    /// Queues the T→O datagram of every class-1 connection whose production is due at `now`.
    fn produce(&mut self, now: Instant) {
        for c in &mut self.device.connections {
            if now < c.next_produce {
                continue;
            }
            c.t_o_sequence = c.t_o_sequence.wrapping_add(1);
            c.next_produce = now + c.t_o_rpi;
            let data = self
                .device
                .assemblies
                .get(&c.t_o_point)
                .map_or(&[][..], |a| &a.data[..]);
            let mut payload = (c.t_o_sequence as u16).to_le_bytes().to_vec();
            payload.extend_from_slice(data);
            let datagram = IoDatagram {
                connection: c.t_o_id,
                sequence: c.t_o_sequence,
                data: &payload,
            };
            // An assembly fits a datagram (the Forward_Open checked its size).
            if let Ok(bytes) = datagram.to_vec() {
                self.transmit.push_back((Peer::Io(c.peer), bytes));
            }
        }
    }

    /// The open class-3 connections.
    pub fn explicit_connections(&self) -> &[ExplicitConnection] {
        &self.device.explicit
    }

    /// SendUnitData (its session checked): the request on its connection, the reply on the
    /// connection's T→O ID with the same sequence count.
    fn send_unit_data(&mut self, client: u64, m: &EncapRepr<'_>, now: Instant) -> Reply {
        let Ok(request) = ConnectedMessage::parse(m.data) else {
            return incorrect();
        };
        let (id, sequence) = (request.connection, request.sequence);
        let Some(at) = self
            .device
            .explicit
            .iter()
            .position(|c| c.o_t_id == id && c.session == m.session)
        else {
            return incorrect();
        };
        self.device.explicit[at].last_heard = now;
        let t_o_id = self.device.explicit[at].t_o_id;
        let service = request.message.first().copied().unwrap_or(0);
        let reply = match &self.device.explicit[at].last {
            Some((last, reply)) if *last == sequence => reply.clone(),
            // A request longer than the connection's O→T size is not executed: too much data.
            _ if request.payload_len() > self.device.explicit[at].o_t_size => {
                let reply = status_only(service, general::TOO_MUCH_DATA);
                self.device.explicit[at].last = Some((sequence, reply.clone()));
                reply
            }
            _ => {
                self.serving_session = m.session;
                let mut reply = self.route(client, request.message, now);
                // Routing may have closed connections (a Forward_Close on this one).
                let Some(at) = self.device.explicit.iter().position(|c| c.o_t_id == id) else {
                    return connected_reply(t_o_id, sequence, &reply);
                };
                if reply.len() + 2 > self.device.explicit[at].t_o_size {
                    reply = status_only(service, general::REPLY_DATA_TOO_LARGE);
                }
                self.device.explicit[at].last = Some((sequence, reply.clone()));
                reply
            }
        };
        connected_reply(t_o_id, sequence, &reply)
    }
}

/// SendUnitData refused with the encapsulation's "incorrect data" (0x0003): malformed, or for a
/// connection that is not open (OpENer drops such a message unanswered; an answer tells the
/// originator at once).
fn incorrect() -> Reply {
    Reply::status(encap_status::INCORRECT_DATA, Vec::new())
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

/// An encapsulation reply before it is written: status and data, and the session handle
/// RegisterSession issued (other replies keep the request's).
struct Reply {
    session: Option<u32>,
    status: u32,
    data: Vec<u8>,
}

impl Reply {
    fn success(data: Vec<u8>) -> Reply {
        Reply::status(encap_status::SUCCESS, data)
    }

    fn status(status: u32, data: Vec<u8>) -> Reply {
        Reply {
            session: None,
            status,
            data,
        }
    }
}
