//! A master driving a simulated CP301 card through CiA 402 velocity mode with the typed API:
//! the drive (`edsgen_sim::drives::Cp301`: the generated `cp301::Od` served by a device node, with the
//! runtime's CiA 402 drive behind it) runs on its own thread on an in-memory bus; the master
//! boots it, checks its identity against the card's constants, starts it, enables operation, sets
//! a target velocity and the ramp, reads the speed back, and switches the drive off again.
//!
//! `cargo run --example cp301_velocity`. Over a real bus, build the `Master` on a
//! `SocketcandClient` (or SocketCAN) instead of the memory endpoint; the rest is the same.

use std::time::Duration;

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::memory::MemoryBus;
use edsgen_runtime::cia402::State;
use edsgen_runtime::master::ExpectedIdentity;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_sim::cards::cp301::{self, od};
use edsgen_sim::drives::Cp301;

const NODE_ID: u8 = 3;
const STEP: Duration = Duration::from_secs(1);

fn main() -> Result<(), MasterError> {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());

    // The simulated drive, on its own thread.
    let clock = MonotonicClock::new();
    let cp301 = Cp301::new(NODE_ID, clock.now()).expect("node-ID 3");
    let drive = Driver::with_clock(bus.endpoint(), cp301, clock)
        .spawn()
        .map_err(MasterError::Io)?;

    master.wait_for_boot(NODE_ID, Duration::from_secs(2))?;
    println!("node {NODE_ID} booted");

    // The boot-up check against the constants generated from cp301.eds.
    let expected = ExpectedIdentity {
        vendor_id: Some(cp301::VENDOR_ID),
        product_code: Some(cp301::PRODUCT_CODE),
        revision_number: Some(cp301::REVISION_NUMBER),
        ..ExpectedIdentity::default()
    };
    let mismatches = master.check_identity(NODE_ID, &expected)?;
    println!("identity: {} mismatch(es)", mismatches.len());

    master.nmt(NmtCommand::Start, NODE_ID)?;
    master.enable_operation(NODE_ID, STEP)?;
    let status: u16 = master.read(NODE_ID, od::STATUSWORD)?;
    println!(
        "statusword 0x{status:04X}: {:?}",
        State::from_statusword(status)
    );

    // Typed: VL_TARGET_VELOCITY is an `Entry<i16>`; writing a u16 or an i32 would not compile.
    // A 300 ms ramp to 1500 rpm, then the vl bits 4-6 (7Fh) start it.
    master.write(NODE_ID, od::VL_RAMP_FUNCTION_TIME, 300)?;
    master.write(NODE_ID, od::VL_TARGET_VELOCITY, 1500)?;
    master.write(NODE_ID, od::CONTROLWORD, 0x7F)?;
    master.listen(Duration::from_millis(400))?;
    let actual: i16 = master.read(NODE_ID, od::VL_VELOCITY_ACTUAL_VALUE)?;
    println!("vl target velocity 1500, actual {actual} after the ramp");
    assert_eq!(actual, 1500);

    master.disable_drive(NODE_ID, STEP)?;
    let state = master.drive_state(NODE_ID)?;
    let demand: i16 = master.read(NODE_ID, od::VL_VELOCITY_DEMAND)?;
    println!("drive {state:?}, demand {demand}");
    assert_eq!(
        (state, demand, mismatches.len()),
        (State::SwitchOnDisabled, 0, 0)
    );
    let _ = drive.stop();
    Ok(())
}
