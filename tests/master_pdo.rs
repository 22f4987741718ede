//! PDOs from the master against a device node serving the generated cp301 card (the driver on
//! the in-memory bus): TPDO1 and RPDO1 configured by SDO in the CiA 301 order, TPDOs decoded into
//! the generated `Tpdo1` by a `pdo_dispatch!` enum, an RPDO sent from the generated `Rpdo1`, and
//! a mapping the node refuses reported with its abort code and meaning.

use std::time::Duration;

use edsgen::cards::cp301::{self, od, pdo};
use edsgen_runtime::master::blocking::{Master, MasterError};
use edsgen_runtime::master::{PdoConfig, PdoKind, SdoError};
use edsgen_runtime::node::Node;
use edsgen_runtime::transport::driver::{Driver, MonotonicClock};
use edsgen_runtime::transport::memory::MemoryBus;
use edsgen_runtime::wire::nmt::NmtCommand;

edsgen_runtime::pdo_dispatch! {
    /// The TPDOs of a CP301 (it has one).
    enum Cp301Tpdo {
        Tpdo1(pdo::Tpdo1),
    }
}

#[test]
fn pdos_are_configured_sent_and_decoded_into_the_generated_structs() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let clock = MonotonicClock::new();
    let mut od = cp301::Od::new(3);
    od.set(od::STATUSWORD, 0x0237).unwrap();
    let node = Node::new(od, 3, clock.now()).unwrap();
    let handle = Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap();
    master.wait_for_boot(3, Duration::from_secs(2)).unwrap();

    // TPDO1: on an event timer of 20 ms instead of every 5th SYNC.
    let tpdo1 = PdoConfig {
        kind: PdoKind::Transmit,
        number: 1,
        cob_id: pdo::Tpdo1::cob_id(3).into(),
        transmission_type: 254,
        event_timer: Some(20),
        mapping: &[0x6041_0010, 0x6043_0010],
    };
    master.configure_pdo(3, &tpdo1).unwrap();
    // RPDO1: applied on arrival (255) instead of at the next SYNC.
    let rpdo1 = PdoConfig {
        kind: PdoKind::Receive,
        number: 1,
        cob_id: pdo::Rpdo1::cob_id(3).into(),
        transmission_type: 255,
        event_timer: None,
        mapping: &[0x6040_0010, 0x6042_0010],
    };
    master.configure_pdo(3, &rpdo1).unwrap();
    master.nmt(NmtCommand::Start, 3).unwrap();

    let received = master
        .receive(Duration::from_secs(2), |frame| Cp301Tpdo::decode(3, frame))
        .unwrap();
    assert_eq!(
        received,
        Some(Ok(Cp301Tpdo::Tpdo1(pdo::Tpdo1 {
            statusword: 0x0237,
            vl_velocity_demand: 0
        })))
    );

    let command = pdo::Rpdo1 {
        controlword: 0x000F,
        vl_target_velocity: -1500,
    };
    master
        .send_pdo(pdo::Rpdo1::cob_id(3), &command.encode())
        .unwrap();
    master.listen(Duration::from_millis(20)).unwrap();
    assert_eq!(master.read(3, od::CONTROLWORD).unwrap(), 0x000F);
    assert_eq!(master.read(3, od::VL_TARGET_VELOCITY).unwrap(), -1500);

    // The device type cannot be mapped: the node's abort, with its meaning.
    master.nmt(NmtCommand::EnterPreOperational, 3).unwrap();
    let refused = master.configure_pdo(
        3,
        &PdoConfig {
            mapping: &[0x1000_0020],
            ..tpdo1
        },
    );
    let Err(error @ MasterError::Sdo { .. }) = refused else {
        panic!("{refused:?}");
    };
    assert!(matches!(
        error,
        MasterError::Sdo {
            error: SdoError::Server(0x0604_0041),
            ..
        }
    ));
    assert_eq!(
        error.to_string(),
        "SDO 1A00h:01h on node 3: node aborted with 0604 0041h (object cannot be mapped to the PDO)"
    );
    let _ = handle.stop();
}
