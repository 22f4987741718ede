//! PDOs from the master against a device node serving the generated cp301 card (the driver on
//! the in-memory bus): TPDO1 and RPDO1 configured by SDO in the CiA 301 order from the generated
//! `Tpdo1` and `Rpdo1` (their `MappedPdo` mapping), with the exact SDO frames; TPDOs decoded into
//! the generated `Tpdo1` by a `pdo_dispatch!` enum, an RPDO sent from the generated `Rpdo1`, and
//! a mapping the node refuses reported with its abort code and meaning.

mod drive_support;

use std::time::Duration;

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::memory::MemoryBus;
use edsgen_host::Transport;
use edsgen_runtime::master::{MappedPdo, PdoConfig, PdoKind, SdoError};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_sim::cards::cp301::{self, od, pdo};

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
    let tpdo1 = PdoConfig::of::<pdo::Tpdo1>(pdo::Tpdo1::cob_id(3).into(), 254, Some(20));
    master.configure_pdo(3, &tpdo1).unwrap();
    // RPDO1: applied on arrival (255) instead of at the next SYNC.
    let rpdo1 = PdoConfig::of::<pdo::Rpdo1>(pdo::Rpdo1::cob_id(3).into(), 255, None);
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
        .send_pdo(pdo::Rpdo1::cob_id(3), &command.to_bytes())
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

#[test]
fn generated_pdo_structs_know_their_mapping() {
    assert_eq!(
        (pdo::Tpdo1::KIND, pdo::Tpdo1::NUMBER, pdo::Tpdo1::MAPPING),
        (PdoKind::Transmit, 1, &[0x6041_0010, 0x6043_0010][..])
    );
    assert_eq!(
        (pdo::Rpdo1::KIND, pdo::Rpdo1::NUMBER, pdo::Rpdo1::MAPPING),
        (PdoKind::Receive, 1, &[0x6040_0010, 0x6042_0010][..])
    );
}

/// A node whose application mapped only the statusword into TPDO1 (2 bytes, which `Tpdo1`
/// does not decode): the master maps it as the generated `Tpdo1` says, with exactly these SDO
/// frames, and the TPDO the node then sends decodes into `Tpdo1` with the node's values.
#[test]
fn a_tpdo_configured_from_the_generated_struct_decodes_into_it() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let mut sniffer = bus.endpoint();
    let clock = MonotonicClock::new();
    let mut od = cp301::Od::new(3);
    od.set(od::STATUSWORD, 0x0237).unwrap();
    od.set(od::VL_VELOCITY_DEMAND, -250).unwrap();
    od.set(od::tpdo1_mapping_parameter::NUMBER_OF_MAPPED_OBJECTS, 1)
        .unwrap();
    let node = Node::new(od, 3, clock.now()).unwrap();
    let handle = Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap();
    master.wait_for_boot(3, Duration::from_secs(2)).unwrap();

    let tpdo1 = PdoConfig::of::<pdo::Tpdo1>(pdo::Tpdo1::cob_id(3).into(), 254, Some(20));
    master.configure_pdo(3, &tpdo1).unwrap();
    // The SDO frames the configuration took, as a third node on the bus saw them (the last
    // response may reach it just after it reached the master).
    let mut sdo = Vec::new();
    while sdo.len() < 16 {
        let Some(frame) = sniffer.recv_timeout(Duration::from_secs(1)).unwrap() else {
            break;
        };
        if matches!(frame.std_id(), Some(0x603 | 0x583)) {
            sdo.push(drive_support::show(&frame));
        }
    }
    assert_eq!(
        sdo,
        [
            // 1800h sub 1: the COB-ID with bit 31 set, the PDO disabled.
            "603: 23 00 18 01 83 01 00 80",
            "583: 60 00 18 01 00 00 00 00",
            // Sub 2: transmission type 254; sub 5: event timer 20 ms.
            "603: 2F 00 18 02 FE 00 00 00",
            "583: 60 00 18 02 00 00 00 00",
            "603: 2B 00 18 05 14 00 00 00",
            "583: 60 00 18 05 00 00 00 00",
            // 1A00h: count 0, Tpdo1's two entries (6041h and 6043h, 16 bits each), count 2.
            "603: 2F 00 1A 00 00 00 00 00",
            "583: 60 00 1A 00 00 00 00 00",
            "603: 23 00 1A 01 10 00 41 60",
            "583: 60 00 1A 01 00 00 00 00",
            "603: 23 00 1A 02 10 00 43 60",
            "583: 60 00 1A 02 00 00 00 00",
            "603: 2F 00 1A 00 02 00 00 00",
            "583: 60 00 1A 00 00 00 00 00",
            // 1800h sub 1: the COB-ID valid.
            "603: 23 00 18 01 83 01 00 00",
            "583: 60 00 18 01 00 00 00 00",
        ]
    );

    master.nmt(NmtCommand::Start, 3).unwrap();
    let received = master
        .receive(Duration::from_secs(2), |frame| Cp301Tpdo::decode(3, frame))
        .unwrap();
    assert_eq!(
        received,
        Some(Ok(Cp301Tpdo::Tpdo1(pdo::Tpdo1 {
            statusword: 0x0237,
            vl_velocity_demand: -250
        })))
    );
    let _ = handle.stop();
}
