//! A [`Drive`] run against the CiA 402 objects of an object dictionary: the inputs a master
//! writes are read from it, the outputs a master reads are written to it.

use super::Drive;
use crate::od::{ObjectDictionary, SdoAbort};
use crate::time::Instant;

impl Drive {
    /// Reads the drive's inputs from `od` (6040h controlword, 6042h target, and the parameters
    /// 604Fh, 6050h, 6051h, 605Ah, 605Bh, 605Ch, 605Eh, 6007h), advances to `now`, and writes its
    /// outputs (6041h statusword, 6043h demand, 6044h actual, 6061h mode display). Objects the
    /// dictionary lacks are skipped: the drive keeps its own value of a parameter.
    ///
    /// Call it when the node reports a write to one of these objects (`Event::Written`), so that
    /// each controlword is seen, and at [`next_update`](Drive::next_update) while the drive moves.
    /// A controlword equal to the last one seen is not a new command (a fault reset needs bit 7
    /// to rise).
    ///
    /// Errors: a value the dictionary refuses (a statusword outside 6041h's limits), which is a
    /// mistake in the dictionary, not in the drive.
    pub fn run_on<O: ObjectDictionary + ?Sized>(
        &mut self,
        od: &mut O,
        now: Instant,
    ) -> Result<(), SdoAbort> {
        let config = self.config_mut();
        read_into(od, 0x604F, &mut config.ramp_time_ms)?;
        read_into(od, 0x6050, &mut config.slow_down_time_ms)?;
        read_into(od, 0x6051, &mut config.quick_stop_time_ms)?;
        read_into(od, 0x605A, &mut config.quick_stop_option)?;
        read_into(od, 0x605B, &mut config.shutdown_option)?;
        read_into(od, 0x605C, &mut config.disable_operation_option)?;
        read_into(od, 0x605E, &mut config.fault_reaction_option)?;
        read_into(od, 0x6007, &mut config.abort_connection_option)?;

        let mut target = self.target();
        read_into(od, 0x6042, &mut target)?;
        if target != self.target() {
            self.set_target(now, target);
        }
        let mut word = self.controlword();
        read_into(od, 0x6040, &mut word)?;
        if word != self.controlword() {
            self.set_controlword(now, word);
        }
        self.update(now);

        write_if_present(od, 0x6041, &self.statusword().to_le_bytes())?;
        write_if_present(od, 0x6043, &self.velocity_demand().to_le_bytes())?;
        write_if_present(od, 0x6044, &self.velocity_actual().to_le_bytes())?;
        // A request for a mode the drive does not run leaves the display where it was.
        let mut requested = self.mode();
        read_into(od, 0x6060, &mut requested)?;
        self.set_mode(now, requested);
        write_if_present(od, 0x6061, &[self.mode() as u8])?;
        Ok(())
    }
}

/// A value the drive reads from sub-index 0 of an object.
trait Le: Sized {
    const SIZE: usize;
    fn from_le(bytes: [u8; 4]) -> Self;
}

macro_rules! le {
    ($($t:ty),*) => {$(
        impl Le for $t {
            const SIZE: usize = core::mem::size_of::<$t>();
            fn from_le(bytes: [u8; 4]) -> Self {
                let mut raw = [0u8; core::mem::size_of::<$t>()];
                raw.copy_from_slice(&bytes[..Self::SIZE]);
                <$t>::from_le_bytes(raw)
            }
        }
    )*};
}
le!(i8, u16, i16, u32);

/// Overwrites `value` with sub-index 0 of `index`, if the dictionary has it with `value`'s size.
fn read_into<O: ObjectDictionary + ?Sized, T: Le>(
    od: &O,
    index: u16,
    value: &mut T,
) -> Result<(), SdoAbort> {
    let mut bytes = [0u8; 4];
    match od.read(index, 0, 0, &mut bytes[..T::SIZE]) {
        Ok(n) if n == T::SIZE => {
            *value = T::from_le(bytes);
            Ok(())
        }
        Ok(_) => Err(SdoAbort::LengthMismatch),
        Err(SdoAbort::NoObject | SdoAbort::NoSubIndex) => Ok(()),
        Err(abort) => Err(abort),
    }
}

/// Writes sub-index 0 of `index`, if the dictionary has it.
fn write_if_present<O: ObjectDictionary + ?Sized>(
    od: &mut O,
    index: u16,
    data: &[u8],
) -> Result<(), SdoAbort> {
    match od.write(index, 0, data) {
        Err(SdoAbort::NoObject | SdoAbort::NoSubIndex) => Ok(()),
        result => result,
    }
}
