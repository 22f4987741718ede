//! The master side: the protocol cores a CANopen master runs against remote nodes, sans-IO
//! like the device side (frames and timestamps in; frames, deadlines, results and events out).
//!
//! [`SdoClient`] reads and writes remote dictionaries, typed through the generated
//! [`Entry`](crate::Entry) addresses.

mod fifo;
pub mod sdo_client;

pub use sdo_client::{Completed, Mode, SdoClient, SdoError, StartError};

#[cfg(feature = "std")]
impl<const BUF: usize> crate::vbus::BusDevice for SdoClient<BUF> {
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
