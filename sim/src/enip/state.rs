//! The device state the CIP objects share and borrow, one struct: the identity, the assemblies'
//! bytes, the parameters, the addresses, the open class-1 and class-3 connections and the events
//! for the application. It has no behaviour of its own beyond what several objects read.

use std::collections::{BTreeMap, VecDeque};

use super::parameter::Parameter;
use super::{Assembly, Event, ExplicitConnection, Identity, IoConnection};

/// What the objects of one adapter share.
#[derive(Debug, Clone)]
pub struct DeviceState {
    /// The Identity object's attributes.
    pub identity: Identity,
    /// The assemblies by instance.
    pub assemblies: BTreeMap<u32, Assembly>,
    /// The adapter's IPv4 address (ListIdentity, TCP/IP Interface).
    pub address: [u8; 4],
    /// The MAC address (Ethernet Link).
    pub mac: [u8; 6],
    /// The configuration assembly instances a connection path may name (size 0).
    pub config_instances: Vec<u32>,
    /// The Parameter object's instances (class 0x0F), by instance.
    pub parameters: BTreeMap<u32, Parameter>,
    /// The open class-1 connections.
    pub connections: Vec<IoConnection>,
    /// The open class-3 connections.
    pub explicit: Vec<ExplicitConnection>,
    /// The O→T ID the next connection gets.
    pub next_connection_id: u32,
    /// What happened that the application should know, oldest first.
    pub events: VecDeque<Event>,
}

impl DeviceState {
    /// A device with `identity` serving `assemblies` at `address`, no connection open.
    pub fn new(identity: Identity, assemblies: BTreeMap<u32, Assembly>, address: [u8; 4]) -> Self {
        DeviceState {
            identity,
            assemblies,
            address,
            mac: [0x02, 0x00, address[0], address[1], address[2], address[3]],
            config_instances: Vec::new(),
            parameters: BTreeMap::new(),
            connections: Vec::new(),
            explicit: Vec::new(),
            next_connection_id: 0x1000_0001,
            events: VecDeque::new(),
        }
    }

    /// Identity attribute 5: bit 0 owned (a class-1 connection is open).
    pub fn identity_status(&self) -> u16 {
        u16::from(!self.connections.is_empty())
    }

    /// Whether a class-1 connection writes assembly `instance` (O→T).
    pub fn written_by_connection(&self, instance: u32) -> bool {
        self.connections.iter().any(|c| c.o_t_point == instance)
    }

    /// A new connection's O→T ID.
    pub fn take_connection_id(&mut self) -> u32 {
        let id = self.next_connection_id;
        self.next_connection_id = self.next_connection_id.wrapping_add(1);
        id
    }
}
