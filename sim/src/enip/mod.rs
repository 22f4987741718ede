//! A simulated EtherNet/IP adapter: the protocol core, sans-IO (bytes and time in, bytes out).
//! [`adapter`] holds the device (identity, assemblies, sessions, connections) and serves the
//! encapsulation (ListIdentity, ListServices, RegisterSession, UnRegisterSession, SendRRData)
//! and class-1 I/O (O→T with its 32-bit run/idle header and sequence count, T→O at the RPI, the
//! connection closed after its timeout); [`objects`] routes Message Router requests to Identity,
//! Message Router, Assembly, Connection Manager (Forward_Open, Large_Forward_Open,
//! Forward_Close), TCP/IP Interface and Ethernet Link; [`parameter`] is the Parameter object;
//! [`class3`] the class-3 connections (SendUnitData). All four are `impl Adapter` on the one
//! device state (not yet one type per object). The byte layouts are the runtime's
//! (`edsgen_runtime::enip::wire`); every refusal carries the status CIP or the encapsulation
//! defines; bad bytes never panic.
//!
//! Unlike the runtime's `no_std` wire formats this core uses `std` collections: its tables are
//! built at run time from any ODVA EDS (assemblies, parameters of any size and number), and it
//! keeps a session per TCP client. [`driver`] serves it on sockets (TCP and UDP 44818, UDP
//! 2222), [`device`] builds it from an ODVA EDS or as the Goodrive350 card with its drive.

pub mod adapter;
mod bytes;
pub mod class3;
pub mod device;
pub mod driver;
pub mod objects;
pub mod parameter;

pub use adapter::{Adapter, Assembly, Event, Identity, IoConnection};
pub use class3::ExplicitConnection;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_class3;
#[cfg(test)]
mod tests_drive;
#[cfg(test)]
mod tests_parameter;
#[cfg(test)]
mod tests_scanner;
#[cfg(test)]
mod tests_support;
