//! edsgen-runtime: a lean, sans-IO CANopen stack for the object dictionaries edsgen generates.
//!
//! `no_std` and allocation-free. Protocol cores take frames and timestamps and hand back frames,
//! deadlines and events; they never block, read a clock or allocate. Transports that need an
//! operating system live behind the `std` feature.
#![cfg_attr(not(feature = "std"), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod entry;
pub mod frame;
pub mod node;
pub mod od;
pub mod sdo;
pub mod time;
pub mod typed;
#[cfg(feature = "std")]
pub mod vbus;
pub mod wire;

mod macros;

pub use entry::{Entry, OdValue};
pub use frame::{CanFrame, CanId};
pub use node::{Event, NmtState, Node, NodeHooks, ResetKind};
pub use od::{Access, DataType, EntryDescriptor, ObjectDictionary, SdoAbort};
pub use time::{Duration, Instant};
pub use typed::{FixedBytes, PdoError};
