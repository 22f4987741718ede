//! The device state the CIP objects share and borrow, one struct ([`DeviceState`]), and the data
//! it is made of: the identity, the assemblies' bytes, the parameters, the addresses, the open
//! class-1 and class-3 connections and the events for the application. It imports no object:
//! the objects (and the encapsulation) import it.

use std::collections::{BTreeMap, VecDeque};

use edsgen_model::model::CipNumber;
use edsgen_runtime::{Duration, Instant};

use super::application::Reaction;

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

/// What the Identity object (class 1) reports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Identity {
    /// Vendor ID (attribute 1).
    pub vendor: u16,
    /// Device type (attribute 2).
    pub device_type: u16,
    /// Product code (attribute 3).
    pub product_code: u16,
    /// Major and minor revision (attribute 4).
    pub revision: (u8, u8),
    /// Serial number (attribute 6).
    pub serial: u32,
    /// Product name (attribute 7).
    pub name: String,
}

/// An assembly the adapter serves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Assembly {
    /// Its bytes.
    pub data: Vec<u8>,
    /// Whether an originator writes it (O→T): a class-1 connection or Set_Attribute_Single.
    pub consumed: bool,
}

/// A class-1 connection.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IoConnection {
    /// The ID the originator sends O→T data with (chosen by the adapter).
    pub o_t_id: u32,
    /// The ID the adapter produces T→O data with (the originator's choice).
    pub t_o_id: u32,
    /// Connection serial, originator vendor and serial: the triad Forward_Close names.
    pub triad: (u16, u16, u32),
    /// The O→T assembly instance.
    pub o_t_point: u32,
    /// The T→O assembly instance.
    pub t_o_point: u32,
    /// O→T and T→O RPI.
    pub o_t_rpi: Duration,
    /// T→O RPI.
    pub t_o_rpi: Duration,
    /// The timeout: the multiplier times the O→T RPI.
    pub timeout: Duration,
    /// When O→T data last came (or the connection opened).
    pub last_heard: Instant,
    /// When T→O data is next due.
    pub next_produce: Instant,
    /// The T→O sequence count and encapsulation sequence number.
    pub t_o_sequence: u32,
    /// The last O→T sequence count seen.
    pub o_t_sequence: Option<u16>,
    /// The originator's run/idle flag (bit 0 of the 32-bit header).
    pub run: bool,
    /// The originator's address key (the driver's: where T→O data goes).
    pub peer: u64,
    /// The UDP port the originator asked T→O data on with a T→O sockaddr info item in its
    /// Forward_Open (as OpENer honours it); `None`: the class-1 port, 2222.
    pub t_o_port: Option<u16>,
}

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

/// Where a parameter's value is kept.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Storage {
    /// Its own bytes, little-endian.
    Own(Vec<u8>),
    /// Bits `bit..bit + bits` of an assembly's data.
    Member {
        /// The Assembly instance.
        instance: u32,
        /// The first bit.
        bit: usize,
        /// The width in bits.
        bits: usize,
    },
}

/// One instance of the Parameter object.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// The descriptor word (attribute 4; bit 4 read-only).
    pub descriptor: u16,
    /// The data type code (attribute 5: 0xC1 BOOL .. 0xDE).
    pub data_type: u8,
    /// The data size in bytes (attribute 6).
    pub size: usize,
    /// The link path's bytes (attributes 2 and 3).
    pub link_path: Vec<u8>,
    /// Name, units and help (attributes 7, 8, 9).
    pub strings: [String; 3],
    /// Minimum, maximum and default (attributes 10, 11, 12).
    pub limits: [Option<CipNumber>; 3],
    /// Scaling multiplier, divisor, base (13–15) and offset (16).
    pub scaling: [i64; 4],
    /// Decimal precision (attribute 21).
    pub decimals: u8,
    /// Where the value is.
    pub storage: Storage,
}

/// What happened to the connections that the application should know.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    /// A connection opened (its O→T ID).
    Opened(u32),
    /// Forward_Close closed a connection.
    Closed(u32),
    /// A connection timed out: no O→T data for its timeout.
    TimedOut(u32),
    /// O→T data written into an assembly (its instance).
    Consumed(u32),
    /// A class-3 connection closed with its session or after its timeout without a request.
    Expired(u32),
    /// The application acted on a connection's end.
    Reacted(Reaction),
}

impl Event {
    /// The line a driver logs for it: connections opening and ending, what the application did
    /// (none for an assembly written).
    pub fn log_line(&self) -> Option<String> {
        Some(match self {
            Event::Opened(id) => format!("connection {id:#010x} opened"),
            Event::Closed(id) => format!("connection {id:#010x} closed"),
            Event::TimedOut(id) => format!("connection {id:#010x} timed out"),
            Event::Expired(id) => format!("explicit connection {id:#010x} closed"),
            Event::Reacted(reaction) => reaction.to_string(),
            Event::Consumed(_) => return None,
        })
    }
}
