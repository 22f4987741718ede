//! The sans-IO SDO client refuses, at compile time, a typed write of a read-only or constant
//! entry and a typed read of a write-only one.

use edsgen_sim::cards::{cp301, goodrive350, rd11};
use edsgen_runtime::master::{SdoClient, StartError};
use edsgen_runtime::{FixedBytes, Instant};

fn refused(client: &mut SdoClient, now: Instant) -> Result<(), StartError> {
    client.write(now, cp301::od::STATUSWORD, &0x0237)?;
    client.write(now, goodrive350::od::MANUFACTURER_DEVICE_NAME, &FixedBytes::from_slice(b"GD"))?;
    client.read(now, rd11::od::f16_save::F16_SAVE_00)?;
    Ok(())
}

fn main() {}
