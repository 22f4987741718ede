//! The blocking master refuses, at compile time, a typed write of a read-only (CP301
//! statusword) or constant (Goodrive350 device name) entry and a typed read of a write-only one
//! (RD11 F16.00 save-at-power-down).

use edsgen_sim::cards::{cp301, goodrive350, rd11};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::memory::MemoryEndpoint;
use edsgen_runtime::FixedBytes;

fn refused(master: &mut Master<MemoryEndpoint>) -> Result<(), MasterError> {
    master.write(3, cp301::od::STATUSWORD, 0x0237)?;
    master.write(4, goodrive350::od::MANUFACTURER_DEVICE_NAME, FixedBytes::from_slice(b"GD"))?;
    let _: u16 = master.read(5, rd11::od::f16_save::F16_SAVE_00)?;
    Ok(())
}

fn main() {}
