//! A simulated EtherNet/IP adapter: the protocol core, sans-IO (bytes and time in, bytes out),
//! layered as OpENer is: the encapsulation ([`adapter`]: ListIdentity, ListServices,
//! RegisterSession, UnRegisterSession, SendRRData) knows nothing of objects and hands Message
//! Router requests to the objects ([`objects`]: Identity, Message Router, Assembly, Connection
//! Manager with Forward_Open, Large_Forward_Open and Forward_Close, TCP/IP Interface, Ethernet
//! Link, and the Parameter object in [`parameter`]); class-1 I/O (O→T with its 32-bit run/idle header and sequence count, T→O at the RPI,
//! the connection closed after its timeout) lives in the adapter too. Wire formats are in
//! [`wire`]. Every refusal carries the status CIP or the encapsulation defines; bad bytes never
//! panic.
//!
//! [`driver`] serves it on sockets (TCP and UDP 44818, UDP 2222), [`device`] builds it from any
//! ODVA EDS or as the Goodrive350 card with its drive. Class-3 connected explicit messaging
//! (Forward_Open to the Message Router, SendUnitData) is in [`class3`].

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
mod tests_parameter;
#[cfg(test)]
mod tests_scanner;
#[cfg(test)]
mod tests_support;
