//! What a machine is, as its file says: the buses in order, where each serves its devices, and
//! each device's card or file and address ([`file`](super::file) reads and checks them).

use std::path::PathBuf;

/// A whole machine: its buses in the order of the file.
#[derive(Debug)]
pub struct Machine {
    /// One per `[[bus]]` table.
    pub sections: Vec<Section>,
}

/// The buses a machine file has a table for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bus {
    /// `[[canopen]]`: devices on an edsgen bus (socketcand) or a SocketCAN interface.
    CanOpen,
    /// `[[ethercat]]`: a segment on a network interface.
    EtherCat,
    /// `[[profibus]]`: slaves on a serial line.
    Profibus,
    /// `[[profinet]]`: IO devices on a network interface.
    Profinet,
    /// `[[enip]]`: EtherNet/IP adapters, one per IP address of the host.
    Enip,
}

impl Bus {
    pub(super) const ALL: [Bus; 5] = [
        Bus::CanOpen,
        Bus::EtherCat,
        Bus::Profibus,
        Bus::Profinet,
        Bus::Enip,
    ];

    /// Its table's name.
    pub fn table(self) -> &'static str {
        match self {
            Bus::CanOpen => "canopen",
            Bus::EtherCat => "ethercat",
            Bus::Profibus => "profibus",
            Bus::Profinet => "profinet",
            Bus::Enip => "enip",
        }
    }

    /// The keys its table takes beside `devices`.
    pub(super) fn place_keys(self) -> &'static [&'static str] {
        match self {
            Bus::CanOpen => &["bus", "socketcan"],
            Bus::EtherCat | Bus::Profinet => &["interface"],
            Bus::Profibus => &["tty"],
            Bus::Enip => &[],
        }
    }

    /// The bundled cards it serves.
    pub(super) fn cards(self) -> Vec<&'static str> {
        match self {
            Bus::CanOpen => edsgen_sim::drives::CARDS.iter().map(|c| c.name).collect(),
            Bus::EtherCat => vec!["ec-tx508"],
            Bus::Profibus => vec![crate::cmd::dp::simulate::CARD],
            Bus::Profinet => vec!["goodrive350-pn"],
            Bus::Enip => vec!["goodrive350-enip"],
        }
    }

    /// How many devices one of its tables may list: what its simulator serves in one process.
    pub fn capacity(self) -> usize {
        match self {
            Bus::CanOpen => 127,
            Bus::Profibus => 126,
            // An EtherCAT segment addresses up to 65,535 SubDevices (auto-increment positions).
            Bus::EtherCat => 65_535,
            Bus::Enip | Bus::Profinet => usize::MAX,
        }
    }
}

/// One bus table.
#[derive(Debug)]
pub struct Section {
    /// Which bus.
    pub bus: Bus,
    /// Where the devices are served: the `bus`, `socketcan`, `interface` or `tty` value.
    pub place: Place,
    /// The devices, in the order given (an EtherCAT segment's order).
    pub devices: Vec<Planned>,
}

/// Where a bus table's devices are served.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Place {
    /// An edsgen bus (`edsgen bus`), `HOST:PORT`.
    CanBus(String),
    /// A SocketCAN interface.
    SocketCan(String),
    /// A network interface (EtherCAT, PROFINET).
    Interface(String),
    /// A serial line (PROFIBUS-DP).
    Tty(String),
    /// The host's own addresses (EtherNet/IP: each device names its address).
    Host,
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Place::CanBus(addr) => write!(f, "bus {addr}"),
            Place::SocketCan(iface) => write!(f, "SocketCAN {iface}"),
            Place::Interface(iface) => write!(f, "interface {iface}"),
            Place::Tty(tty) => write!(f, "line {tty}"),
            Place::Host => f.write_str("this host"),
        }
    }
}

/// One device of a bus table.
#[derive(Debug, Clone)]
pub struct Planned {
    /// The name faults on standard input use: `name = ...`, else the entry as written.
    pub name: String,
    /// A bundled card or a description file.
    pub source: Source,
    /// Its address on its bus.
    pub address: Address,
    /// The modules plugged in it (`SLOT=NAME` or `NAME`, docs/modules.md), checked against its
    /// file: `--module` after its FILE.
    pub modules: Vec<String>,
    /// A PROFINET device's access point, checked against its GSDML: `--access-point`.
    pub access_point: Option<String>,
    /// Where it is in the machine file (a byte offset), for the problems found across devices.
    pub(super) at: usize,
}

/// What a device is built from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// A bundled card, by name.
    Card(&'static str),
    /// A description file (relative paths are resolved against the machine file), and for an
    /// ESI file with several devices, which one (`#xCODE` or `#NAME`).
    File(PathBuf, Option<String>),
}

/// A device's address on its bus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Address {
    /// A CANopen node-ID.
    NodeId(u8),
    /// A PROFIBUS station address.
    Station(u8),
    /// An EtherCAT SubDevice's position in the segment (0 first).
    Position(usize),
    /// A PROFINET name of station and, when given, an IP address with prefix.
    Pn {
        /// The name of station (`name`, else the card's default).
        name: Option<String>,
        /// `ip`, `ADDR/PREFIX`.
        ip: Option<String>,
    },
    /// An EtherNet/IP adapter's IP address.
    Ip(String),
}

impl std::fmt::Display for Address {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Address::NodeId(id) => write!(f, "node {id}"),
            Address::Station(a) => write!(f, "station {a}"),
            Address::Position(p) => write!(f, "position {p}"),
            Address::Pn { name, ip } => {
                write!(f, "name {}", name.as_deref().unwrap_or("(the GSDML's)"))?;
                match ip {
                    Some(ip) => write!(f, ", IP {ip}"),
                    None => f.write_str(", IP of the interface"),
                }
            }
            Address::Ip(ip) => write!(f, "address {ip}"),
        }
    }
}
