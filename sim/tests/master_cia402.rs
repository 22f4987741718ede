//! The blocking master's CiA 402 helpers against the simulated MS300 and CP301 drives (the
//! runtime's device-side `cia402::Drive` behind the generated dictionaries), on the in-memory bus
//! with the driver on its own thread: to operation enabled and back, a fault reset that clears
//! and one that does not, the mode of operation set and confirmed.

use std::time::Duration;

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::memory::{MemoryBus, MemoryEndpoint};
use edsgen_host::vbus::BusDevice;
use edsgen_runtime::cia402::State;
use edsgen_runtime::master::cia402::{mode, CONTROLWORD};
use edsgen_runtime::Entry;
use edsgen_sim::cards::ms300;
use edsgen_sim::drives::{Cp301, Ms300};

const STEP: Duration = Duration::from_secs(2);

fn run<D: BusDevice + Send + 'static>(
    bus: &MemoryBus,
    power_up: impl FnOnce(edsgen_runtime::Instant) -> D,
) -> DriverHandle<MemoryEndpoint, D> {
    let clock = MonotonicClock::new();
    let device = power_up(clock.now());
    Driver::with_clock(bus.endpoint(), device, clock)
        .spawn()
        .unwrap()
}

#[test]
fn enable_operation_walks_the_drive_there_and_disable_walks_it_back() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let ms = run(&bus, |now| Ms300::new(4, now).unwrap());
    // Pr. 00-21 = 3: the MS300 takes its commands from CANopen (manual 15-3-2-1).
    master.write(4, Entry::<u16>::new(0x2000, 22), 3).unwrap();
    assert_eq!(master.drive_state(4).unwrap(), State::SwitchOnDisabled);
    master.set_mode(4, mode::VELOCITY, STEP).unwrap();
    master.enable_operation(4, STEP).unwrap();
    assert_eq!(master.drive_state(4).unwrap(), State::OperationEnabled);
    assert_eq!(
        ms.with_device(|d, _| d.drive().state()),
        State::OperationEnabled
    );
    // A ramp of 0 ms, the target, and the vl bits 4-6: the demand follows at once.
    master
        .write(4, ms300::od::VL_RAMP_FUNCTION_TIME, 0)
        .unwrap();
    master.write(4, ms300::od::VL_TARGET_VELOCITY, 300).unwrap();
    master.write(4, CONTROLWORD, 0x7F).unwrap();
    let demand: i16 = master.read(4, ms300::od::VL_VELOCITY_DEMAND).unwrap();
    assert_eq!(demand, 300);
    master.disable_drive(4, STEP).unwrap();
    assert_eq!(master.drive_state(4).unwrap(), State::SwitchOnDisabled);
    let demand: i16 = master.read(4, ms300::od::VL_VELOCITY_DEMAND).unwrap();
    assert_eq!(demand, 0);
    let _ = ms.stop();
}

#[test]
fn a_fault_reset_clears_a_fault_and_reports_one_that_stays() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let cp = run(&bus, |now| Cp301::new(3, now).unwrap());
    master.enable_operation(3, STEP).unwrap();
    // OC1 whose cause is gone by the time the master resets it.
    cp.with_device(|d, now| {
        d.raise_alarm(now, "OC1").unwrap();
        d.remove_alarm_cause();
    });
    assert_eq!(master.drive_state(3).unwrap(), State::Fault);
    master.enable_operation(3, STEP).unwrap();
    assert_eq!(master.drive_state(3).unwrap(), State::OperationEnabled);
    // OC1 whose cause stays: the reset cannot clear it.
    cp.with_device(|d, now| d.raise_alarm(now, "OC1").unwrap());
    let stays = master.fault_reset(3, Duration::from_millis(100));
    assert!(
        matches!(
            stays,
            Err(MasterError::DriveStuck {
                node_id: 3,
                state: State::Fault
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
    let cp = run(&bus, |now| Cp301::new(3, now).unwrap());
    // CP301 has no 6060h: it runs vl only.
    let error = master.set_mode(3, mode::VELOCITY, STEP).unwrap_err();
    assert!(error.to_string().contains("0602 0000h"), "{error}");
    let _ = cp.stop();
}
