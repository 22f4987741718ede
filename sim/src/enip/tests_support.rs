//! The tests' owned messages over the runtime's wire views: an encapsulation message with its
//! data in a vector, and CPF items as (type, data) pairs.

use edsgen_runtime::enip::wire::cpf::{CpfRepr, Item, Items};
use edsgen_runtime::enip::wire::encap::{EncapError, EncapRepr};
use edsgen_runtime::enip::wire::Emit;
use edsgen_runtime::Instant;

use super::{Adapter, Event};

/// The adapter's events since the last call, oldest first.
pub(super) fn events(a: &mut Adapter) -> Vec<Event> {
    std::iter::from_fn(|| a.poll_event()).collect()
}

/// The T→O datagrams due at `now`, with the peer key of each.
pub(super) fn produce(a: &mut Adapter, now: Instant) -> Vec<(u64, Vec<u8>)> {
    a.handle_timeout(now);
    std::iter::from_fn(|| a.poll_transmit()).collect()
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
