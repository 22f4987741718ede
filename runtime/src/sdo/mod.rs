//! SDO (service data object) protocol machines (CiA 301 §7.2.4).
//!
//! [`SdoServer`] serves an [`ObjectDictionary`](crate::ObjectDictionary) to one SDO client:
//! expedited, segmented and (with the `sdo-block` feature) block transfers in both directions. It
//! is sans-IO: feed it request payloads and timestamps, take response payloads. Frame layouts live
//! in [`crate::wire::sdo`]; the block-transfer CRC in `crc` (with `sdo-block`).
//!
//! ```
//! use edsgen_runtime::sdo::{SdoEvent, SdoServer};
//! use edsgen_runtime::{Access, DataType, Duration, EntryDescriptor, Instant};
//! use edsgen_runtime::{ObjectDictionary, SdoAbort};
//!
//! /// One UNSIGNED16 at 1017h:00 (producer heartbeat time).
//! struct Heartbeat(u16);
//!
//! const ENTRIES: [EntryDescriptor; 1] = [EntryDescriptor::new(
//!     0x1017,
//!     0,
//!     DataType::Unsigned16,
//!     Access::Rw,
//!     false,
//! )];
//!
//! impl ObjectDictionary for Heartbeat {
//!     fn entry_count(&self) -> usize {
//!         ENTRIES.len()
//!     }
//!     fn entry(&self, position: usize) -> Option<EntryDescriptor> {
//!         ENTRIES.get(position).copied()
//!     }
//!     fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
//!         self.find(index, sub).map(|_| 2)
//!     }
//!     fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
//!         self.find(index, sub)?;
//!         let bytes = self.0.to_le_bytes();
//!         let rest = bytes.get(offset..).unwrap_or(&[]);
//!         let len = rest.len().min(buf.len());
//!         buf[..len].copy_from_slice(&rest[..len]);
//!         Ok(len)
//!     }
//!     fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
//!         self.find(index, sub)?;
//!         let bytes: [u8; 2] = data.try_into().map_err(|_| SdoAbort::LengthMismatch)?;
//!         self.0 = u16::from_le_bytes(bytes);
//!         Ok(())
//!     }
//! }
//!
//! let mut od = Heartbeat(0);
//! let mut server = SdoServer::new(Duration::from_millis(500));
//! let now = Instant::from_millis(0);
//!
//! // Write 1017h:00 = 1000 (expedited, 2 bytes).
//! let event = server.handle(now, &[0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0], &mut od);
//! assert_eq!(event, Some(SdoEvent::Written { index: 0x1017, sub: 0 }));
//! assert_eq!(server.poll_transmit(now, &od), Some([0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]));
//!
//! // Read it back.
//! server.handle(now, &[0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0], &mut od);
//! assert_eq!(server.poll_transmit(now, &od), Some([0x4B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0]));
//! assert_eq!(server.poll_timeout(), None);
//! ```

#[cfg(feature = "sdo-block")]
pub mod crc;
pub mod server;

pub use server::{SdoEvent, SdoServer};
