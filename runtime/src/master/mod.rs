//! The master side: the protocol cores a CANopen master runs against remote nodes, sans-IO
//! like the device side (frames and timestamps in; frames, deadlines, results and events out).
//!
//! [`SdoClient`] reads and writes remote dictionaries, typed through the generated
//! [`Entry`](crate::Entry) addresses; [`nmt`] commands nodes and watches them (heartbeat
//! consumer, guarding master); [`emcy`] decodes emergencies; [`sync`] produces SYNC;
//! [`cia402`] walks drives through their state machine, by cyclic process data
//! ([`cia402::Controller`]) or over SDO. The `edsgen-host` crate's blocking and async masters
//! run them all on an operating system's transport.

pub mod cia402;
pub mod dcf;
pub mod emcy;
mod fifo;
pub mod identity;
pub mod lss;
pub mod nmt;
pub mod pdo;
pub mod sdo_client;
pub mod sync;

pub use emcy::Emergency;
pub use identity::{ExpectedIdentity, IdentityMismatch};
pub use lss::{LssMaster, LssMasterError, LssOutcome, LssService};
pub use nmt::{nmt_frame, MonitorEvent, NodeMonitor, Watch};
pub use pdo::{MappedPdo, PdoConfig, PdoKind};
pub use sdo_client::{Completed, Mode, SdoClient, SdoError, StartError, Transfer};
pub use sync::SyncProducer;
