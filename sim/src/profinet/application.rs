//! What sits behind a simulated PROFINET IO device ([`IoApplication`]): the data of the card's
//! module (slot 1, subslot 1, 32 bytes each way), its records and its faults. The Goodrive350's
//! PKW/PZD drive is one ([`PkwPzdDrive`], the same card application the DP slave serves); a
//! device built from any other GSDML has none and loops its outputs back to its inputs
//! ([`super::cyclic::Cyclic::looped_back`]).

use edsgen_runtime::pkw_pzd::{ByteOrder, IMAGE_BYTES};
use edsgen_runtime::Instant;

use crate::drives::pkw_pzd::{FaultChange, PkwPzdDrive};

/// The card's record of the received PZD meanings (P16.32-P16.42).
pub const RECORD_RECEIVED_PZD: u16 = 256;
/// The card's record of the transmitted PZD meanings (P16.43-P16.53).
pub const RECORD_TRANSMITTED_PZD: u16 = 257;

/// The application of a device's module (see the module comment).
pub trait IoApplication {
    /// The module's records the device serves from power-up: (index, bytes).
    fn records(&self) -> Vec<(u16, Vec<u8>)>;
    /// The controller wrote the module's record `index`.
    fn write_record(&mut self, index: u16, data: &[u8]);
    /// The input data now.
    fn inputs(&self) -> [u8; IMAGE_BYTES];
    /// One cycle at `now`: the output data in, the input data out.
    fn exchange(&mut self, now: Instant, outputs: &[u8; IMAGE_BYTES]) -> [u8; IMAGE_BYTES];
    /// The cyclic watchdog expired at `now`: the controller is gone.
    fn communication_lost(&mut self, now: Instant);
    /// When the application next wants [`IoApplication::handle_timeout`].
    fn poll_timeout(&self) -> Option<Instant>;
    /// Time passed to `now`.
    fn handle_timeout(&mut self, now: Instant);
    /// The next change of its faults, for a Diagnosis alarm.
    fn poll_fault_change(&mut self) -> Option<FaultChange>;
    /// A new AR starts: nothing has been reported to it.
    fn forget_reported_fault(&mut self);
}

impl IoApplication for PkwPzdDrive {
    fn records(&self) -> Vec<(u16, Vec<u8>)> {
        [
            (RECORD_RECEIVED_PZD, self.bus().received_pzd2()),
            (RECORD_TRANSMITTED_PZD, self.bus().transmitted_pzd2()),
        ]
        .into_iter()
        .map(|(index, first)| {
            let words = (0..11)
                .flat_map(|i| self.parameter(first + i).unwrap_or(0).to_be_bytes())
                .collect();
            (index, words)
        })
        .collect()
    }

    /// Records 256 and 257 set the drive's PZD parameters, word by word.
    fn write_record(&mut self, index: u16, data: &[u8]) {
        let first = match index {
            RECORD_RECEIVED_PZD => self.bus().received_pzd2(),
            RECORD_TRANSMITTED_PZD => self.bus().transmitted_pzd2(),
            _ => return,
        };
        for (i, word) in data.chunks_exact(2).enumerate() {
            // A value the drive refuses leaves the parameter as it was (the record keeps it).
            let _ = self.set_parameter(first + i as u16, u16::from_be_bytes([word[0], word[1]]));
        }
    }

    fn inputs(&self) -> [u8; IMAGE_BYTES] {
        PkwPzdDrive::inputs(self).emit(ByteOrder::BigEndian)
    }

    fn exchange(&mut self, now: Instant, outputs: &[u8; IMAGE_BYTES]) -> [u8; IMAGE_BYTES] {
        self.exchange_bytes(now, outputs, ByteOrder::BigEndian)
    }

    fn communication_lost(&mut self, now: Instant) {
        PkwPzdDrive::communication_lost(self, now);
    }

    fn poll_timeout(&self) -> Option<Instant> {
        PkwPzdDrive::poll_timeout(self)
    }

    fn handle_timeout(&mut self, now: Instant) {
        PkwPzdDrive::handle_timeout(self, now);
    }

    fn poll_fault_change(&mut self) -> Option<FaultChange> {
        PkwPzdDrive::poll_fault_change(self)
    }

    fn forget_reported_fault(&mut self) {
        PkwPzdDrive::forget_reported_fault(self);
    }
}
