//! The LSS master (CiA 305) against LSS slave nodes: the sans-IO core on the virtual bus
//! (fastscan finds three unconfigured nodes in turn, each given an ID then boots up there;
//! inquiries; refusals as errors), and the blocking master over the in-memory bus.

#[path = "../../runtime/tests/node_support/mod.rs"]
mod node_support;

use std::time::Duration as StdDuration;

use edsgen_host::driver::{Driver, MonotonicClock};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::memory::MemoryBus;
use edsgen_host::vbus::{BusDevice, VirtualBus};
use edsgen_runtime::master::lss::{LssMaster, LssMasterError, LssOutcome, LssService};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::lss::{LssError, LssMode};
use edsgen_runtime::Duration;
use node_support::node_od::TestOd;
use node_support::{ms, sent};

const VENDOR: u32 = 0x0000_04D8;

fn unconfigured(serial: u32) -> Node<TestOd> {
    Node::new(TestOd::new(1).with_serial(serial), 0xFF, ms(0)).unwrap()
}

/// Runs `service` on the virtual bus until it ends.
fn run(
    bus: &mut VirtualBus,
    master: &mut LssMaster,
    nodes: &mut [Node<TestOd>],
    service: LssService,
) -> Result<LssOutcome, LssMasterError> {
    master.start(service).unwrap();
    loop {
        let until = bus.now() + Duration::from_millis(10);
        let mut devices: Vec<&mut dyn BusDevice> = vec![master as &mut dyn BusDevice];
        devices.extend(nodes.iter_mut().map(|n| n as &mut dyn BusDevice));
        bus.run_until(until, &mut devices);
        if let Some(result) = master.poll_result() {
            return result;
        }
    }
}

#[test]
fn fastscan_finds_every_unconfigured_node_and_each_boots_up_at_its_new_id() {
    let mut nodes = [unconfigured(7), unconfigured(8), unconfigured(3)];
    let mut bus = VirtualBus::new(ms(0));
    let mut master = LssMaster::new();
    let mut found = Vec::new();
    loop {
        let outcome = run(&mut bus, &mut master, &mut nodes, LssService::Fastscan).unwrap();
        let LssOutcome::Scanned(Some(address)) = outcome else {
            assert_eq!(outcome, LssOutcome::Scanned(None));
            break;
        };
        assert_eq!(address[0], VENDOR);
        let id = 10 + found.len() as u8;
        let inquired = run(
            &mut bus,
            &mut master,
            &mut nodes,
            LssService::InquireAddress,
        );
        assert_eq!(inquired, Ok(LssOutcome::Address(address)));
        let configured = run(
            &mut bus,
            &mut master,
            &mut nodes,
            LssService::ConfigureNodeId(id),
        );
        assert_eq!(configured, Ok(LssOutcome::Done));
        let waiting = LssService::SwitchGlobal(LssMode::Waiting);
        assert_eq!(
            run(&mut bus, &mut master, &mut nodes, waiting),
            Ok(LssOutcome::Done)
        );
        found.push((address[3], id));
        assert!(found.len() <= 3);
    }
    // Lowest address first: serial 3, 7, 8.
    assert_eq!(found, [(3, 10), (7, 11), (8, 12)]);
    let ids: Vec<u8> = nodes.iter().map(|n| n.node_id()).collect();
    assert_eq!(ids, [11, 12, 10]);
    let boot_ups: Vec<String> = sent(&mut bus)
        .into_iter()
        .map(|(_, f)| f)
        .filter(|f| f.starts_with("70") || f.starts_with("71"))
        .collect();
    assert_eq!(boot_ups, ["70A: 00", "70B: 00", "70C: 00"]);
    let none = run(
        &mut bus,
        &mut master,
        &mut nodes,
        LssService::IdentifyNonConfigured,
    );
    assert_eq!(none, Ok(LssOutcome::Identified(false)));
}

#[test]
fn selective_switch_identify_and_refusals() {
    let mut nodes = [unconfigured(7), unconfigured(8)];
    let mut bus = VirtualBus::new(ms(0));
    let mut master = LssMaster::new();
    let identify = LssService::IdentifyRemote {
        vendor: VENDOR,
        product: 0,
        revision: (0, 0),
        serial: (8, 100),
    };
    assert_eq!(
        run(&mut bus, &mut master, &mut nodes, identify),
        Ok(LssOutcome::Identified(true))
    );
    assert_eq!(
        run(&mut bus, &mut master, &mut nodes, LssService::InquireNodeId),
        Err(LssMasterError::NoAnswer),
        "no slave in configuration"
    );
    let select = LssService::SwitchSelective([VENDOR, 0, 0, 8]);
    assert_eq!(
        run(&mut bus, &mut master, &mut nodes, select),
        Ok(LssOutcome::Done)
    );
    assert!(nodes[1].lss_configuration() && !nodes[0].lss_configuration());
    assert_eq!(
        run(
            &mut bus,
            &mut master,
            &mut nodes,
            LssService::ConfigureNodeId(128)
        ),
        Err(LssMasterError::Refused(LssError::OutOfRange))
    );
    let timing = LssService::ConfigureBitTiming { table: 0, index: 5 };
    assert_eq!(
        run(&mut bus, &mut master, &mut nodes, timing),
        Err(LssMasterError::Refused(LssError::OutOfRange))
    );
    assert_eq!(
        run(&mut bus, &mut master, &mut nodes, LssService::Store),
        Err(LssMasterError::Refused(LssError::StoreNotSupported))
    );
    assert_eq!(
        run(&mut bus, &mut master, &mut nodes, LssService::InquireNodeId),
        Ok(LssOutcome::NodeId(0xFF))
    );
}

#[test]
fn the_blocking_master_scans_and_assigns_over_the_memory_bus() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let clock = MonotonicClock::new();
    let mut handles = Vec::new();
    for serial in [5, 2] {
        let node = Node::new(TestOd::new(1).with_serial(serial), 0xFF, clock.now()).unwrap();
        handles.push(
            Driver::with_clock(bus.endpoint(), node, clock)
                .spawn()
                .unwrap(),
        );
    }
    let mut next_id = 20;
    let found = master
        .lss_scan_all(StdDuration::from_millis(30), |master, _address| {
            master.lss(LssService::ConfigureNodeId(next_id))?;
            next_id += 1;
            Ok(true)
        })
        .unwrap();
    let serials: Vec<u32> = found.iter().map(|a| a[3]).collect();
    assert_eq!(serials, [2, 5]);
    master
        .wait_for_boot(21, StdDuration::from_secs(2))
        .expect("serial 5 boots up as node 21");
    let none = master.lss(LssService::InquireNodeId);
    assert!(matches!(
        none,
        Err(MasterError::Lss(LssMasterError::NoAnswer))
    ));
    // Listing only: every one is found, none keeps a node-ID.
    let clock2 = MonotonicClock::new();
    for serial in [9, 4, 6] {
        let node = Node::new(TestOd::new(1).with_serial(serial), 0xFF, clock2.now()).unwrap();
        handles.push(
            Driver::with_clock(bus.endpoint(), node, clock2)
                .spawn()
                .unwrap(),
        );
    }
    let listed = master
        .lss_scan_all(StdDuration::from_millis(30), |_, _| Ok(false))
        .unwrap();
    let serials: Vec<u32> = listed.iter().map(|a| a[3]).collect();
    assert_eq!(serials, [4, 6, 9]);
    let again = master
        .lss_scan_all(StdDuration::from_millis(30), |_, _| Ok(false))
        .unwrap();
    assert_eq!(again.len(), 3, "back in waiting, still unconfigured");
    drop(handles);
}
