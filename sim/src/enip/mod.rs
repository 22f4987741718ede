//! A simulated EtherNet/IP adapter: the protocol core, sans-IO (bytes and time in, bytes out).
//! [`adapter`] holds the device (identity, assemblies, sessions, connections) and serves the
//! encapsulation (ListIdentity, ListServices, RegisterSession, UnRegisterSession, SendRRData)
//! and class-1 I/O (O→T with its 32-bit run/idle header and sequence count, T→O at the RPI, the
//! connection closed after its timeout); [`message_router`] routes requests to [`identity`],
//! [`assembly`], [`connection_manager`] (Forward_Open, Large_Forward_Open, Forward_Close),
//! [`parameter`], [`tcp_ip`] and [`ethernet_link`]; [`class3`] serves the class-3 connections
//! (SendUnitData). The byte layouts are the runtime's (`edsgen_runtime::enip::wire`); every
//! refusal carries the status CIP or the encapsulation defines; bad bytes never panic.
//!
//! Unlike the runtime's `no_std` wire formats this core uses `std` collections: its tables are
//! built at run time from any ODVA EDS (assemblies, parameters of any size and number), and it
//! keeps a session per TCP client. [`driver`] serves it on sockets (TCP and UDP 44818, UDP
//! 2222), [`device`] builds it from an ODVA EDS or as the Goodrive350 card with its drive.

pub mod adapter;
pub mod assembly;
mod bytes;
pub mod cip;
pub mod connection_manager;
pub mod device;
pub mod driver;
pub mod ethernet_link;
pub mod identity;
pub mod message_router;
pub mod parameter;
pub mod state;
pub mod tcp_ip;

pub use adapter::{Adapter, Event};
pub use assembly::Assembly;
pub use cip::{Call, CipObject, Registry};
pub use connection_manager::{ExplicitConnection, IoConnection};
pub use identity::Identity;
pub use state::DeviceState;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_drive;
#[cfg(test)]
mod tests_parameter;
#[cfg(test)]
mod tests_scanner;
#[cfg(test)]
mod tests_support;
