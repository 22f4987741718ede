//! The blocking master's PDOs: configuring them by SDO, sending them and receiving them.

use std::time::Duration as StdDuration;

use crate::Transport;
use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::master::pdo::PdoConfig;
use edsgen_runtime::master::sdo_client::Mode;

use super::{to_duration, Master, MasterError, MAX_WAIT};

impl<T: Transport> Master<T> {
    /// Configures a PDO of `node_id` by SDO in CiA 301's safe order (see
    /// [`PdoConfig::writes`]); the first write the node refuses is the error. For the PDO a
    /// generated struct describes: `PdoConfig::of::<cp301::pdo::Tpdo1>(cob_id, 254, Some(20))`.
    pub fn configure_pdo(&mut self, node_id: u8, config: &PdoConfig) -> Result<(), MasterError> {
        for (mux, value, len) in config.writes() {
            let bytes = value.to_le_bytes();
            self.download(node_id, mux, &bytes[..usize::from(len)], Mode::Normal)?;
        }
        Ok(())
    }

    /// Sends a PDO: `payload` (a generated struct's `encode()`) on `cob_id` (its `cob_id(node)`:
    /// an 11-bit identifier as `u16`, or a 29-bit one as `u32` above 7FFh).
    pub fn send_pdo(&mut self, cob_id: impl Into<u32>, payload: &[u8]) -> Result<(), MasterError> {
        let cob_id = cob_id.into();
        let frame = match u16::try_from(cob_id) {
            Ok(id) if id <= 0x7FF => CanFrame::new(id, payload),
            _ => CanFrame::new_extended(cob_id, payload),
        };
        self.transport.send(&frame.ok_or(MasterError::Value)?)?;
        Ok(())
    }

    /// Waits at most `timeout` for a frame `accept` takes (a PDO decoded by a
    /// [`pdo_dispatch!`](edsgen_runtime::pdo_dispatch) enum), handling everything else as usual.
    pub fn receive<R>(
        &mut self,
        timeout: StdDuration,
        mut accept: impl FnMut(&CanFrame) -> Option<R>,
    ) -> Result<Option<R>, MasterError> {
        let deadline = self.clock.now() + to_duration(timeout);
        loop {
            let now = self.clock.now();
            if now >= deadline {
                return Ok(None);
            }
            let wait = StdDuration::from_micros((deadline - now).as_micros()).min(MAX_WAIT);
            if let Some(frame) = self.transport.recv_timeout(wait)? {
                self.dispatch(&frame);
                if let Some(taken) = accept(&frame) {
                    return Ok(Some(taken));
                }
            }
        }
    }
}
