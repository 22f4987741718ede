//! The master side: the protocol cores a CANopen master runs against remote nodes, sans-IO
//! like the device side (frames and timestamps in; frames, deadlines, results and events out).
//!
//! [`SdoClient`] reads and writes remote dictionaries, typed through the generated
//! [`Entry`](crate::Entry) addresses; [`nmt`] commands nodes and watches them (heartbeat
//! consumer, guarding master); [`emcy`] decodes emergencies; [`sync`] produces SYNC;
//! [`cia402`] walks drives through their state machine, by cyclic process data
//! ([`cia402::Controller`]) or over SDO. With `std`, `blocking::Master` runs them all on a
//! transport.

#[cfg(feature = "std")]
pub mod blocking;
pub mod cia402;
#[cfg(feature = "std")]
pub mod concurrent;
pub mod dcf;
#[cfg(feature = "std")]
mod drive;
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

#[cfg(feature = "std")]
impl<const BUF: usize> crate::transport::vbus::BusDevice for SdoClient<BUF> {
    fn handle_frame(&mut self, now: crate::Instant, frame: &crate::CanFrame) {
        SdoClient::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: crate::Instant) -> Option<crate::CanFrame> {
        SdoClient::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<crate::Instant> {
        SdoClient::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: crate::Instant) {
        SdoClient::handle_timeout(self, now)
    }
}

#[cfg(feature = "std")]
impl<const N: usize> crate::transport::vbus::BusDevice for NodeMonitor<N> {
    fn handle_frame(&mut self, now: crate::Instant, frame: &crate::CanFrame) {
        NodeMonitor::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: crate::Instant) -> Option<crate::CanFrame> {
        NodeMonitor::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<crate::Instant> {
        NodeMonitor::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: crate::Instant) {
        NodeMonitor::handle_timeout(self, now)
    }
}

#[cfg(feature = "std")]
impl crate::transport::vbus::BusDevice for SyncProducer {
    fn handle_frame(&mut self, _now: crate::Instant, _frame: &crate::CanFrame) {}
    fn poll_transmit(&mut self, now: crate::Instant) -> Option<crate::CanFrame> {
        SyncProducer::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<crate::Instant> {
        SyncProducer::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: crate::Instant) {
        SyncProducer::handle_timeout(self, now)
    }
}

#[cfg(feature = "std")]
impl crate::transport::vbus::BusDevice for LssMaster {
    fn handle_frame(&mut self, now: crate::Instant, frame: &crate::CanFrame) {
        LssMaster::handle_frame(self, now, frame)
    }
    fn poll_transmit(&mut self, now: crate::Instant) -> Option<crate::CanFrame> {
        LssMaster::poll_transmit(self, now)
    }
    fn poll_timeout(&self) -> Option<crate::Instant> {
        LssMaster::poll_timeout(self)
    }
    fn handle_timeout(&mut self, now: crate::Instant) {
        LssMaster::handle_timeout(self, now)
    }
}
