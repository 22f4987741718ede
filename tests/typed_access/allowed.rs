//! What the access markers still allow: a master reads read-only and constant entries, writes
//! write-only and read-write ones, and reads and writes an address built by hand (access
//! unknown); the device application gets and sets its entries whatever their access.

use edsgen_sim::cards::{cp301, goodrive350, rd11};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::master::concurrent::AsyncMaster;
use edsgen_runtime::master::{SdoClient, StartError};
use edsgen_host::memory::MemoryEndpoint;
use edsgen_runtime::{Entry, FixedBytes, Instant};

const HAND_BUILT: Entry<u16> = Entry::new(0x6041, 0);

fn blocking(master: &mut Master<MemoryEndpoint>) -> Result<(), MasterError> {
    master.write(3, cp301::od::VL_TARGET_VELOCITY, 1500)?;
    let _: u16 = master.read(3, cp301::od::STATUSWORD)?;
    let _: FixedBytes<12> = master.read(4, goodrive350::od::MANUFACTURER_DEVICE_NAME)?;
    master.write(5, rd11::od::f16_save::F16_SAVE_00, 1)?;
    master.write(3, HAND_BUILT, 0)?;
    let _: u16 = master.read(3, HAND_BUILT)?;
    Ok(())
}

async fn concurrent(master: &AsyncMaster) -> Result<(), MasterError> {
    master.write(3, cp301::od::VL_TARGET_VELOCITY, 1500).await?;
    let _: u16 = master.read(3, cp301::od::STATUSWORD).await?;
    master.write(5, rd11::od::f16_save::F16_SAVE_00, 1).await?;
    master.write(3, HAND_BUILT, 0).await?;
    Ok(())
}

fn sans_io(client: &mut SdoClient, now: Instant) -> Result<(), StartError> {
    client.read(now, goodrive350::od::MANUFACTURER_DEVICE_NAME)?;
    client.write(now, rd11::od::f16_save::F16_SAVE_00, &1)?;
    client.write(now, HAND_BUILT, &0)?;
    client.read(now, HAND_BUILT)
}

fn main() {
    let _ = (blocking, concurrent, sans_io);
    let mut od = cp301::Od::new(3);
    od.set(cp301::od::STATUSWORD, 0x0237).unwrap();
    assert_eq!(od.get(cp301::od::STATUSWORD), 0x0237);
    assert_eq!(od.get_checked(HAND_BUILT), Some(0x0237));
    let mut drive = rd11::Od::new(5);
    drive.set(rd11::od::f16_save::F16_SAVE_00, 7).unwrap();
    assert_eq!(drive.get(rd11::od::f16_save::F16_SAVE_00), 7);
}
