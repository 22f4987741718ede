//! Simulated drives behind the bundled cards: each card's behaviour as its manual describes it,
//! on the card's generated bindings and the device runtime, so that a master can be written and
//! tested before a drive is wired.
//!
//! Each CANopen card is a [`edsgen_host::vbus::BusDevice`]: it runs on
//! the in-memory bus in tests, and on any transport through the runtime's driver. The EtherCAT
//! card [`ec_tx508`] exchanges its process images with a master's cycle instead.

pub mod cp301;
pub mod ec_tx508;
pub mod goodrive350;
pub mod hd1e;
pub mod ms300;
pub mod pdo1;
pub mod pkw_pzd;
pub mod rd11;
pub mod vfd;

use std::path::Path;

use edsgen_host::vbus::BusDevice;
use edsgen_model::load::{self, Loaded};
use edsgen_model::model::Device;
use edsgen_runtime::node::InvalidNodeId;
use edsgen_runtime::{Instant, ObjectDictionary};

pub use self::cp301::Cp301;
pub use self::ec_tx508::EcTx508;
pub use self::goodrive350::Goodrive350;
pub use self::hd1e::Hd1e;
pub use self::ms300::Ms300;
pub use self::pkw_pzd::PkwPzdDrive;
pub use self::rd11::Rd11;

/// A bundled card: its name, its EDS (compiled in), the node-ID it takes unless told otherwise,
/// and its simulated drive.
pub struct Card {
    /// The name `edsgen simulate --card` takes.
    pub name: &'static str,
    /// Where its EDS is in the repository.
    pub eds_path: &'static str,
    /// The EDS file's bytes.
    pub eds: &'static [u8],
    /// The overlay beside the EDS (`eds/NAME.toml`), when the card has one.
    pub overlay: Option<&'static str>,
    /// The default node-ID: distinct for the five cards, so that all can share one bus.
    pub default_node_id: u8,
    /// Powers up the simulated drive at a node-ID.
    pub power_up: fn(u8, Instant) -> Result<Box<dyn BusDevice + Send>, InvalidNodeId>,
}

impl Card {
    /// The card's EDS loaded as `edsgen validate` loads it: read, its overlay applied, judged.
    pub fn loaded(&self) -> Loaded {
        load::load_bundled(Path::new(self.eds_path), self.eds, self.overlay)
    }

    /// The card's model, its overlay applied (for decoding its frames by name).
    pub fn model(&self) -> Device {
        self.loaded().device
    }

    /// The card by name.
    pub fn named(name: &str) -> Option<&'static Card> {
        CARDS.iter().find(|card| card.name == name)
    }
}

fn boxed<D: BusDevice + Send + 'static>(
    device: Result<D, InvalidNodeId>,
) -> Result<Box<dyn BusDevice + Send>, InvalidNodeId> {
    device.map(|d| Box::new(d) as Box<dyn BusDevice + Send>)
}

/// The five bundled CANopen cards (the EtherCAT card, [`EcTx508`], has no bus of its own here).
pub static CARDS: [Card; 5] = [
    Card {
        name: "cp301",
        eds_path: "eds/cp301.eds",
        eds: include_bytes!("../../../eds/cp301.eds"),
        overlay: None,
        default_node_id: 2,
        power_up: |id, now| boxed(Cp301::new(id, now)),
    },
    Card {
        name: "ms300",
        eds_path: "eds/ms300.eds",
        eds: include_bytes!("../../../eds/ms300.eds"),
        overlay: None,
        default_node_id: 1,
        power_up: |id, now| boxed(Ms300::new(id, now)),
    },
    Card {
        name: "goodrive350",
        eds_path: "eds/goodrive350.eds",
        eds: include_bytes!("../../../eds/goodrive350.eds"),
        overlay: None,
        default_node_id: 3,
        power_up: |id, now| boxed(Goodrive350::new(id, now)),
    },
    Card {
        name: "rd11",
        eds_path: "eds/rd11.eds",
        eds: include_bytes!("../../../eds/rd11.eds"),
        overlay: Some(include_str!("../../../eds/rd11.toml")),
        default_node_id: 4,
        power_up: |id, now| boxed(Rd11::new(id, now)),
    },
    Card {
        name: "hd1e",
        eds_path: "eds/hd1e.eds",
        eds: include_bytes!("../../../eds/hd1e.eds"),
        overlay: None,
        default_node_id: 5,
        power_up: |id, now| boxed(Hd1e::new(id, now)),
    },
];

/// The earlier of two optional deadlines.
fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// An UNSIGNED16 of a card's dictionary, 0 if absent: the generated dictionaries have every
/// object the cards name, which the card tests check.
fn read_u16<O: ObjectDictionary>(od: &O, index: u16, sub: u8) -> u16 {
    let mut bytes = [0u8; 2];
    match od.read(index, sub, 0, &mut bytes) {
        Ok(2) => u16::from_le_bytes(bytes),
        _ => 0,
    }
}

/// Writes an UNSIGNED16 of a card's dictionary that takes any value (a monitored value, a
/// status word): a refusal is a bug in the simulation, caught by the tests' debug builds.
fn write_u16<O: ObjectDictionary>(od: &mut O, index: u16, sub: u8, value: u16) {
    let written = od.write(index, sub, &value.to_le_bytes());
    debug_assert_eq!(
        written,
        Ok(()),
        "{index:04X}h:{sub:02X}h takes any UNSIGNED16"
    );
}

/// [`write_u16`], and whether the value changed.
fn replace_u16<O: ObjectDictionary>(od: &mut O, index: u16, sub: u8, value: u16) -> bool {
    let changed = read_u16(od, index, sub) != value;
    if changed {
        write_u16(od, index, sub, value);
    }
    changed
}
