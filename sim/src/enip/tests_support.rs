//! The tests' owned messages over the runtime's wire views: an encapsulation message with its
//! data in a vector, and CPF items as (type, data) pairs.

use edsgen_runtime::enip::wire::cpf::{CpfRepr, Item, Items};
use edsgen_runtime::enip::wire::encap::{EncapError, EncapRepr};
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::Instant;

use super::{Adapter, EnipApplication, Event, Peer};

/// The adapter's events since the last call, oldest first.
pub(super) fn events<A: EnipApplication>(a: &mut Adapter<A>) -> Vec<Event> {
    std::iter::from_fn(|| a.poll_event()).collect()
}

/// The T→O datagrams due at `now`, with the peer key of each.
pub(super) fn produce<A: EnipApplication>(a: &mut Adapter<A>, now: Instant) -> Vec<(u64, Vec<u8>)> {
    a.handle_timeout(now);
    std::iter::from_fn(|| a.poll_transmit(now))
        .map(|(to, bytes)| match to {
            Peer::Io(key) => (key, bytes),
            other => panic!("a T→O datagram goes to class-1 I/O, not {other:?}"),
        })
        .collect()
}

impl<A: EnipApplication> Adapter<A> {
    /// One encapsulation message from TCP client `client` (`u64::MAX`: a UDP datagram) at
    /// `now`: the reply it queued, if any, and the bytes consumed.
    pub(super) fn request(
        &mut self,
        client: u64,
        bytes: &[u8],
        now: Instant,
    ) -> Result<(Option<Vec<u8>>, usize), EncapError> {
        let from = if client == u64::MAX {
            Peer::Udp
        } else {
            Peer::Tcp(client)
        };
        let used = self.handle(now, from, bytes)?;
        // The reply is taken; T→O datagrams (a Forward_Open's first) stay queued, in order,
        // for `produce`.
        let (mut replies, others): (Vec<_>, Vec<_>) =
            std::iter::from_fn(|| self.poll_transmit(now)).partition(|(to, _)| *to == from);
        self.transmit.extend(others);
        assert!(replies.len() <= 1, "one reply per request");
        let mut replies: Vec<Vec<u8>> = replies.drain(..).map(|(_, reply)| reply).collect();
        Ok((replies.pop(), used))
    }

    /// One class-1 datagram from the originator of client `client` at `now`.
    pub(super) fn io(&mut self, client: u64, bytes: &[u8], now: Instant) {
        assert_eq!(self.handle(now, Peer::Io(client), bytes), Ok(bytes.len()));
    }
}

/// An encapsulation message that owns its data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Encapsulation {
    pub command: u16,
    pub session: u32,
    pub status: u32,
    pub context: [u8; 8],
    pub options: u32,
    pub data: Vec<u8>,
}

impl Encapsulation {
    pub fn parse(bytes: &[u8]) -> Result<(Encapsulation, usize), EncapError> {
        let (m, used) = EncapRepr::parse_prefix(bytes)?;
        let owned = Encapsulation {
            command: m.command,
            session: m.session,
            status: m.status,
            context: m.context,
            options: m.options,
            data: m.data.to_vec(),
        };
        Ok((owned, used))
    }

    pub fn emit(&self) -> Vec<u8> {
        EncapRepr {
            command: self.command,
            session: self.session,
            status: self.status,
            context: self.context,
            options: self.options,
            data: &self.data,
        }
        .to_vec()
        .expect("a test message fits")
    }
}

pub(super) fn emit_items(items: &[(u16, &[u8])]) -> Vec<u8> {
    let items: Vec<Item<'_>> = items.iter().map(|(k, d)| Item::new(*k, d)).collect();
    CpfRepr { items: &items }.to_vec().expect("test items fit")
}

pub(super) fn parse_items(bytes: &[u8]) -> Option<Vec<(u16, &[u8])>> {
    let items = Items::parse(bytes).ok()?;
    Some(items.iter().map(|i| (i.kind, i.data)).collect())
}
