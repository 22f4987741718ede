//! The blocking master's CiA 402 helpers against simulated drives serving the generated ms300
//! and cp301 cards (the device-side state machine of `SimulatedDrive`), on the in-memory bus
//! with the driver on its own thread: to operation enabled and back, a fault reset that clears
//! and one that does not, the mode of operation set and confirmed.

use std::time::Duration;

use edsgen::cards::{cp301, ms300};
use edsgen_runtime::master::blocking::{Master, MasterError};
use edsgen_runtime::master::cia402::{mode, DriveState, SimulatedDrive};
use edsgen_runtime::node::Node;
use edsgen_runtime::transport::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_runtime::transport::memory::{MemoryBus, MemoryEndpoint};
use edsgen_runtime::ObjectDictionary;

const STEP: Duration = Duration::from_secs(2);

fn drive<O: ObjectDictionary + Send + 'static>(
    bus: &MemoryBus,
    od: O,
    node_id: u8,
) -> DriverHandle<MemoryEndpoint, SimulatedDrive<O>> {
    let clock = MonotonicClock::new();
    let node = Node::new(od, node_id, clock.now()).unwrap();
    Driver::with_clock(bus.endpoint(), SimulatedDrive::new(node), clock)
        .spawn()
        .unwrap()
}

#[test]
fn enable_operation_walks_the_drive_there_and_disable_walks_it_back() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let ms = drive(&bus, ms300::Od::new(4), 4);
    assert_eq!(master.drive_state(4).unwrap(), DriveState::SwitchOnDisabled);
    master.set_mode(4, mode::VELOCITY, STEP).unwrap();
    master.enable_operation(4, STEP).unwrap();
    assert_eq!(master.drive_state(4).unwrap(), DriveState::OperationEnabled);
    assert_eq!(
        ms.with_device(|d, _| d.model.state),
        DriveState::OperationEnabled
    );
    master.write(4, ms300::od::VL_TARGET_VELOCITY, 300).unwrap();
    let demand: i16 = master.read(4, ms300::od::VL_VELOCITY_DEMAND).unwrap();
    assert_eq!(demand, 300);
    master.disable_drive(4, STEP).unwrap();
    assert_eq!(master.drive_state(4).unwrap(), DriveState::SwitchOnDisabled);
    let _ = ms.stop();
}

#[test]
fn a_fault_reset_clears_a_fault_and_reports_one_that_stays() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let cp = drive(&bus, cp301::Od::new(3), 3);
    master.enable_operation(3, STEP).unwrap();
    cp.with_device(|d, _| {
        d.model.fault();
        d.update();
    });
    assert_eq!(master.drive_state(3).unwrap(), DriveState::Fault);
    master.enable_operation(3, STEP).unwrap();
    assert_eq!(master.drive_state(3).unwrap(), DriveState::OperationEnabled);
    cp.with_device(|d, _| {
        d.model.fault();
        d.model.fault_persists = true;
        d.update();
    });
    let stays = master.fault_reset(3, Duration::from_millis(100));
    assert!(
        matches!(
            stays,
            Err(MasterError::DriveStuck {
                node_id: 3,
                state: DriveState::Fault
            })
        ),
        "{stays:?}"
    );
    let _ = cp.stop();
}

#[test]
fn a_mode_the_drive_does_not_have_is_an_sdo_error() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let cp = drive(&bus, cp301::Od::new(3), 3);
    // CP301 has no 6060h: it runs vl only.
    let error = master.set_mode(3, mode::VELOCITY, STEP).unwrap_err();
    assert!(error.to_string().contains("0602 0000h"), "{error}");
    let _ = cp.stop();
}
