//! SDO (service data object) protocol machines (CiA 301 §7.2.4).
//!
//! [`SdoServer`] serves an [`ObjectDictionary`](crate::ObjectDictionary) to one SDO client:
//! expedited, segmented and block transfers in both directions. It is sans-IO: feed it request
//! payloads and timestamps, take response payloads. Frame layouts live in [`crate::wire::sdo`];
//! the block-transfer CRC in [`crc`].

pub mod crc;
pub mod server;

pub use server::{SdoEvent, SdoServer};
