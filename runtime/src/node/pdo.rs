//! PDO state: the mapping a PDO packs or unpacks, the receive and transmit PDOs' configuration as
//! read from 1400h–1BFFh, and the checks a mapping entry must pass (CiA 301 §7.4.7).
//!
//! Mappings are byte-granular: each mapped object takes its whole size in whole bytes (a mapping
//! length that is not a multiple of 8 is refused with 0604 0041). At most [`MAX_MAPPED`] objects
//! per PDO.

mod mapping;
mod params;
mod rpdo;
mod tpdo;

pub use mapping::MAX_MAPPED;
pub(crate) use mapping::{check_mapping, Mapping};
pub(crate) use rpdo::Rpdo;
pub(crate) use tpdo::Tpdo;
