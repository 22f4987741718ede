//! A simulated PROFINET IO device built from a GSDML model, one module per protocol machine as
//! p-net names them: [`dcp`] (discovery and naming), [`ar`] (connection management: the DCE/RPC
//! endpoint and the application relation), [`cyclic`] (the cyclic consumer with its watchdog and
//! the provider, on the layout a Connect gives), [`alarm`] (the AlarmCR's alarm transport and
//! acknowledgement; its transport state, shared with [`controller_alarm`], in [`rta`]);
//! [`application`] is what sits behind a device ([`application::IoApplication`],
//! the Goodrive350's PKW/PZD drive one), [`drive`] puts it behind the cyclic data and makes its
//! faults diagnosis alarms; [`device`] joins them into one device; wire formats apart in
//! [`wire`]; the raw-socket and UDP driver in [`driver`], [`segment`] serving several devices on
//! one interface; [`station`] derives what the device
//! says about itself from the GSDML; [`controller`] builds a controller's requests (the demo's,
//! the tests' and `edsgen pn io`'s), [`controller_alarm`] takes and acknowledges a device's alarms.
//!
//! Alarms: the card's drive faults only (Diagnosis appears and disappears), over layer 2.
//!
//! What is no_std already, in the runtime (`edsgen_runtime::profinet`): every wire format
//! (Ethernet, DCP with the name rules, RT frames, DCE/RPC, the block framing, the Connect's
//! blocks as checked views with their lists as iterators, the record access and control
//! blocks, the RTA-PDU, AlarmAck and AlarmNotification) and the AlarmCR's transport state for
//! each priority (`rta`: sequence numbers, ACK/NACK, retransmission), which the device's and
//! the controller's alarm machines here use with a `Vec` as the frame they keep.
//!
//! What remains std here, and why:
//! - The Connect's blocks as the machines keep them (an AR's accepted request, a controller's
//!   expected configuration) are owned reprs with `Vec` lists, behind the runtime's `alloc`.
//! - [`ar`] (connection management) is a DCE/RPC server over UDP: it answers datagrams with
//!   whole PDUs it builds in `Vec`s, keeps the last answer to repeat it, and the written
//!   records of any length; without a UDP/IP stack on the target there is nothing to bind it
//!   to, and a fixed-size pool for answers and records would be the first step.
//! - [`ar::config`] and [`station`] read the GSDML model, which is std (XML, strings).
//! - [`dcp`] keeps the station name and type as `String`s and builds answers in `Vec`s.
//! - [`cyclic`]'s layout (data objects per Connect) and produced frames are `Vec`s: any
//!   number of submodules a Connect asks for.
//! - [`alarm`] and [`controller_alarm`] queue alarms, frames and events in `VecDeque`s (their
//!   ALPMI/ALPMR logic is small; the transport under it is the runtime's).
//! - [`device`] joins them with an outbox of `Vec` frames and datagrams; [`driver`] and
//!   [`iface`] are sockets.

pub mod alarm;
pub mod application;
pub mod ar;
pub mod controller;
pub mod controller_alarm;
pub mod cyclic;
pub mod dcp;
pub mod device;
pub mod drive;
pub mod driver;
pub mod iface;
pub mod rta;
pub mod segment;
pub mod station;
pub mod wire;
