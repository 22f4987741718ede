//! PROFIBUS-DP (feature `dp`): the FDL telegrams ([`fdl`]), the line's receiver that cuts bytes
//! into telegrams under FDL's idle rule ([`mod@line`]) and the DP-V0 slave's state machine
//! ([`slave`]), sans-IO, no_std and allocation-free. The application behind the slave (the
//! cyclic data's owner) implements [`DpApplication`]: an application trait per bus, as
//! PROFINET's `IoApplication` and EtherNet/IP's `EnipApplication` in the simulator, and one
//! PKW/PZD card application (`PkwPzdDrive`) serves all three. A driver puts the slave on a line.

pub mod fdl;
pub mod line;
pub mod slave;

pub use line::LineReceiver;
pub use slave::{DpApplication, DpSlave, DpState, Event, SlaveConfig};

/// Up to 244 bytes of DP data (the most a DP-V0 telegram carries in each direction: outputs,
/// inputs, configuration bytes), kept inline.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct DpData {
    bytes: [u8; DpData::CAPACITY],
    len: u8,
}

impl DpData {
    /// The most bytes a `DpData` holds.
    pub const CAPACITY: usize = 244;

    /// A copy of `bytes`; `None` when they are more than [`DpData::CAPACITY`].
    pub fn new(bytes: &[u8]) -> Option<Self> {
        if bytes.len() > Self::CAPACITY {
            return None;
        }
        let mut data = DpData::zeroed(bytes.len());
        data.as_mut_slice().copy_from_slice(bytes);
        Some(data)
    }

    /// `len` zero bytes (at most [`DpData::CAPACITY`]).
    pub fn zeroed(len: usize) -> Self {
        DpData {
            bytes: [0; Self::CAPACITY],
            // CAPACITY < 256.
            len: len.min(Self::CAPACITY) as u8,
        }
    }

    /// The bytes.
    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..usize::from(self.len)]
    }

    /// The bytes, to change.
    pub fn as_mut_slice(&mut self) -> &mut [u8] {
        &mut self.bytes[..usize::from(self.len)]
    }

    /// How many bytes.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl core::fmt::Debug for DpData {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.as_slice().fmt(f)
    }
}
