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
//! What is no_std already: the wire views of the runtime (`edsgen_runtime::profinet::wire`:
//! Ethernet, DCP with the name rules, RT frames, DCE/RPC, the block framing, the RTA-PDU and
//! AlarmAck and AlarmNotification, the record access and control blocks). What remains here,
//! and why: the PNIO blocks of the Connect and its answer are owned structs ([`wire::blocks`])
//! the machines keep (an AR's accepted request): they need views with borrowed lists first; the
//! machines ([`dcp`], [`ar`], [`cyclic`], [`alarm`], [`controller_alarm`]) queue their frames
//! and datagrams in `Vec`s and `VecDeque`s (they could live behind the runtime's `alloc`
//! feature once the blocks are views); [`ar::config`] and [`station`] read the GSDML model,
//! which is std; [`driver`] and [`iface`] are sockets.

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
