//! The async master refuses, at compile time, a typed write of a read-only or constant entry
//! and a typed read of a write-only one.

use edsgen_sim::cards::{cp301, goodrive350, rd11};
use edsgen_host::master::concurrent::AsyncMaster;
use edsgen_host::master::blocking::MasterError;
use edsgen_runtime::FixedBytes;

async fn refused(master: &AsyncMaster) -> Result<(), MasterError> {
    master.write(3, cp301::od::STATUSWORD, 0x0237).await?;
    master
        .write(4, goodrive350::od::MANUFACTURER_DEVICE_NAME, FixedBytes::from_slice(b"GD"))
        .await?;
    let _: u16 = master.read(5, rd11::od::f16_save::F16_SAVE_00).await?;
    Ok(())
}

fn main() {}
