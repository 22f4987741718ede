//! edsgen-runtime: a lean, sans-IO CANopen stack for the object dictionaries edsgen generates.
//!
//! `no_std` and allocation-free. Protocol cores take frames and timestamps and hand back frames,
//! deadlines and events; they never block, read a clock or allocate. Transports that need an
//! operating system (socketcand, SocketCAN, candump traces, in-memory buses) and the threaded
//! master drivers live in the `edsgen-host` crate.
//!
//! Cargo features:
//! - `sdo-block` (default): SDO block upload and download with CRC-16. Without it the SDO server
//!   offers expedited and segmented transfers only and answers a block request (command
//!   specifier 5 or 6) with abort 0504 0001 (command specifier not valid or unknown).
//! - `node-guarding` (default): node guarding and life guarding (100Ch × 100Dh, the answer to an
//!   RTR on 700h + node-ID, `Event::LifeGuardingLost` and EMCY 8130h). Without it that RTR is
//!   ignored and 100Ch/100Dh are ordinary entries; heartbeat is the error-control protocol.
//! - `dp`: PROFIBUS-DP, the FDL telegrams and the DP-V0 slave (module `dp`).
//! - `profinet`: PROFINET IO's wire formats as views (module `profinet`).
//! - `ethercrab`: code generated from an EtherCAT ESI file on the ethercrab MainDevice: process
//!   images as ethercrab-wire types, typed CoE SDO access (`ethercat::ethercrab`).
//! - `enip`: EtherNet/IP and CIP wire formats (module `enip`), `no_std` like the rest.
//! - `alloc`: conveniences that return vectors (`enip::wire::Emit::to_vec`), for hosts.
//! - `ethercat-wire`: EtherCAT's frames, datagrams, mailbox and CoE headers as views
//!   (`ethercat::wire`), for SubDevices, masters and decoders.
//! - `ethercat-subdevice` (with `ethercat-wire`): an EtherCAT SubDevice's cores: CoE SDO on the
//!   SDO server (`ethercat::sdo`).
//!
//! Without `sdo-block` and `node-guarding` the node offers what CANopenNode v4's default
//! configuration does (segmented SDO server without block transfer, no node guarding), in less
//! flash.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod cia402;
#[cfg(feature = "dp")]
pub mod dp;
#[cfg(feature = "enip")]
pub mod enip;
pub mod ethercat;
pub mod frame;
pub mod master;
pub mod node;
pub mod od;
pub mod pkw_pzd;
#[cfg(feature = "profinet")]
pub mod profinet;
pub mod sdo;
pub mod time;
pub mod wire;

mod macros;
#[doc(hidden)]
pub mod support;

pub use frame::{CanFrame, CanId};
pub use node::{Event, NmtState, Node, NodeHooks, ResetKind};
pub use od::entry::{AnyDictionary, Entry, OdValue};
pub use od::typed::{FixedBytes, PdoError};
pub use od::{Access, DataType, EntryDescriptor, EntryKind, ObjectDictionary, SdoAbort, Services};
pub use time::{Duration, Instant};
