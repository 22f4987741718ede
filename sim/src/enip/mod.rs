//! A simulated EtherNet/IP adapter: the protocol core, sans-IO (bytes and time in, bytes out).
//! Three layers, each importing only the ones below: [`adapter`], the encapsulation (sessions,
//! ListIdentity, ListServices, SendRRData and SendUnitData, class-1 I/O); [`message_router`],
//! which dispatches a request to the [`CipObject`] of its class in a [`Registry`] ([`cip`]); the
//! objects, one type per file: [`identity`], [`message_router`], [`assembly`],
//! [`connection_manager`] (class-1 and class-3 connections), [`parameter`], [`tcp_ip`] and
//! [`ethernet_link`]. What the objects share (identity, assemblies' bytes, parameters,
//! connections, events) is one [`DeviceState`] ([`state`]) they borrow. The byte layouts are the
//! runtime's (`edsgen_runtime::enip::wire`); every refusal carries the status CIP or the
//! encapsulation defines; bad bytes never panic.
//!
//! Unlike the runtime's `no_std` wire formats this core uses `std` collections: its tables are
//! built at run time from any ODVA EDS (assemblies, parameters of any size and number), and it
//! keeps a session per TCP client. [`application`] is what sits behind it ([`EnipApplication`]:
//! the Goodrive350's PKW/PZD drive, the same card application DP and PROFINET serve);
//! [`driver`] serves it on sockets (TCP and UDP 44818, UDP 2222), [`device`] builds it from an
//! ODVA EDS or as the Goodrive350 card with its drive.

pub mod adapter;
pub mod application;
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

pub use adapter::{Adapter, Peer};
pub use application::{Ending, EnipApplication, Reaction};
pub use cip::{Call, CipObject, Registry};
pub use state::{Assembly, DeviceState, Event, ExplicitConnection, Identity, IoConnection};

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_class3;
#[cfg(test)]
mod tests_drive;
#[cfg(test)]
mod tests_parameter;
#[cfg(test)]
mod tests_registry;
#[cfg(test)]
mod tests_scanner;
#[cfg(test)]
mod tests_support;
