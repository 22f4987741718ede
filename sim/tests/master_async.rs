//! The async master on tokio against device nodes serving the generated cp301 card (the driver
//! on the in-memory bus): typed reads and writes as futures, transfers to different nodes
//! running side by side, waiting for boot-ups, a silent node's timeout not holding up the
//! others, a watched node's events (boot-up, state change, heartbeat loss and recovery,
//! emergency) while transfers to another node (the simulated device's domain) run, node
//! guarding, and the timeouts and read retries the blocking master has.

mod sim_support;

use std::cell::Cell;
use std::time::{Duration, Instant};

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::master::blocking::{MasterError, MasterEvent};
use edsgen_host::master::concurrent::AsyncMaster;
use edsgen_host::memory::{MemoryBus, MemoryEndpoint};
use edsgen_host::Transport;
use edsgen_runtime::master::{Emergency, Mode, MonitorEvent, SdoError, Watch};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::heartbeat::NmtState;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_sim::canopen::RuntimeDictionary;
use edsgen_sim::cards::cp301::{self, od};

fn nodes(bus: &MemoryBus, ids: &[u8]) -> Vec<DriverHandle<MemoryEndpoint, Node<cp301::Od>>> {
    ids.iter()
        .map(|&id| {
            let clock = MonotonicClock::new();
            let node = Node::new(cp301::Od::new(id), id, clock.now()).unwrap();
            Driver::with_clock(bus.endpoint(), node, clock)
                .spawn()
                .unwrap()
        })
        .collect()
}

#[tokio::test]
async fn transfers_to_three_nodes_run_side_by_side() {
    let bus = MemoryBus::new();
    // The master's endpoint first, so that it hears the boot-ups.
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    let handles = nodes(&bus, &[3, 4, 5]);
    let work = |id: u8| {
        let master = &master;
        async move {
            for i in 0..50i16 {
                let velocity = i * 10 + i16::from(id);
                master.write(id, od::VL_TARGET_VELOCITY, velocity).await?;
                let back = master.read(id, od::VL_TARGET_VELOCITY).await?;
                assert_eq!(back, velocity);
            }
            master
                .read(id, od::rpdo1_communication_parameter::COB_ID_USED_BY_RPDO)
                .await
        }
    };
    for id in [3, 4, 5] {
        master
            .wait_for_boot(id, Duration::from_secs(5))
            .await
            .unwrap();
    }
    let (a, b, c) = tokio::join!(work(3), work(4), work(5));
    assert_eq!((a.unwrap(), b.unwrap(), c.unwrap()), (0x203, 0x204, 0x205));
    master.nmt(NmtCommand::Start, 0).await.unwrap();
    master.nmt(NmtCommand::ResetNode, 4).await.unwrap();
    master
        .wait_for_boot(4, Duration::from_secs(5))
        .await
        .unwrap();
    let silent = master.wait_for_boot(9, Duration::from_millis(50)).await;
    assert!(matches!(silent, Err(MasterError::Timeout)), "{silent:?}");
    drop(master);
    for handle in handles {
        let (_, _, node) = handle.stop();
        // Node 4 was reset: a reset node restores the dictionary's power-on values (6042h = 0).
        let expected = match node.node_id() {
            4 => 0,
            id => 490 + i16::from(id),
        };
        assert_eq!(node.od().get(od::VL_TARGET_VELOCITY), expected);
    }
}

#[tokio::test]
async fn a_silent_node_times_out_without_holding_up_the_others() {
    let bus = MemoryBus::new();
    let handles = nodes(&bus, &[3]);
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    master.set_timeout(9, Duration::from_millis(300)).unwrap();
    let start = Instant::now();
    let silent = async {
        let result = master.read(9, od::STATUSWORD).await;
        (result, start.elapsed())
    };
    let busy = async {
        for _ in 0..20 {
            master.read(3, od::STATUSWORD).await.unwrap();
        }
        start.elapsed()
    };
    let ((silent, silent_took), busy_took) = tokio::join!(silent, busy);
    assert!(matches!(
        silent,
        Err(MasterError::Sdo {
            node_id: 9,
            error: SdoError::Timeout,
            ..
        })
    ));
    assert!(silent_took >= Duration::from_millis(300), "{silent_took:?}");
    assert!(busy_took < silent_took, "{busy_took:?} vs {silent_took:?}");
    drop(master);
    for handle in handles {
        let _ = handle.stop();
    }
}

/// The next event about `node_id`, within 5 s (other nodes' events are skipped).
async fn next_of(master: &AsyncMaster, node_id: u8) -> MasterEvent {
    let about = |event: &MasterEvent| match *event {
        MasterEvent::Monitor(
            MonitorEvent::BootUp { node_id: id }
            | MonitorEvent::StateChanged { node_id: id, .. }
            | MonitorEvent::Lost { node_id: id }
            | MonitorEvent::Recovered { node_id: id, .. },
        ) => id,
        MasterEvent::Emergency(Emergency { node_id: id, .. }) => id,
        MasterEvent::BootUp(id) => id,
        MasterEvent::IdentityMismatch(m) => m.node_id,
    };
    let wait = async {
        loop {
            let event = master.next_event().await.expect("the driver runs");
            if about(&event) == node_id {
                return event;
            }
        }
    };
    tokio::time::timeout(Duration::from_secs(5), wait)
        .await
        .expect("an event within 5 s")
}

#[tokio::test]
async fn a_watched_nodes_events_arrive_while_transfers_to_another_node_run() {
    let bus = MemoryBus::new();
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    // Lost after 400 ms without a heartbeat (the node will produce one every 50 ms).
    let consumer = edsgen_runtime::Duration::from_millis(400);
    master.watch(3, Watch::Heartbeat(consumer)).await.unwrap();
    let refused = master.watch(0, Watch::Heartbeat(consumer)).await;
    assert!(
        matches!(refused, Err(MasterError::NodeId(0))),
        "{refused:?}"
    );
    let clock = MonotonicClock::new();
    let node = Node::new(cp301::Od::new(3), 3, clock.now()).unwrap();
    let watched = Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap();
    let sim = {
        let clock = MonotonicClock::new();
        let od = RuntimeDictionary::new(&sim_support::test_device(), 4);
        let node = Node::new(od, 4, clock.now()).unwrap();
        Driver::with_clock(bus.endpoint(), node, clock)
            .spawn()
            .unwrap()
    };
    let events_done = Cell::new(false);
    let script = async {
        let mut seen = vec![next_of(&master, 3).await, next_of(&master, 3).await];
        master
            .write(3, od::PRODUCER_HEARTBEAT_TIME, 50)
            .await
            .unwrap();
        master.nmt(NmtCommand::Start, 3).await.unwrap();
        seen.push(next_of(&master, 3).await);
        let raised = watched.with_device(|node, _| node.raise_error(0x2310, 0x03, *b"edsgn"));
        assert!(raised);
        seen.push(next_of(&master, 3).await);
        // The node stops (its driver does), then resumes where it was.
        let (_, endpoint, node) = watched.stop();
        seen.push(next_of(&master, 3).await);
        let resumed = Driver::with_clock(endpoint, node, clock).spawn().unwrap();
        seen.push(next_of(&master, 3).await);
        events_done.set(true);
        (seen, resumed)
    };
    // Meanwhile values of unknown length go to node 4's domain and come back, again and again.
    let transfers = async {
        let program = Multiplexer::new(0x2001, 0);
        let mut rounds = 0;
        while !events_done.get() || rounds < 2 {
            let len = [64 * 1024, 1000][rounds % 2];
            let value: Vec<u8> = (0..len).map(|i| (i * 7 + i / 251) as u8).collect();
            let mode = [Mode::Block, Mode::Normal][rounds % 2];
            let written = master
                .download_from(4, program, mode, std::io::Cursor::new(value.clone()))
                .await
                .unwrap();
            assert_eq!(written as usize, len);
            let back = master.upload(4, program, Mode::Block).await.unwrap();
            assert!(back == value, "round {rounds}: {len} bytes read back");
            rounds += 1;
        }
        rounds
    };
    let ((seen, resumed), rounds) = tokio::join!(script, transfers);
    let (boot, state) = (Some(NmtState::PreOperational), NmtState::Operational);
    assert_eq!(
        seen,
        [
            MasterEvent::Monitor(MonitorEvent::BootUp { node_id: 3 }),
            MasterEvent::BootUp(3),
            MasterEvent::Monitor(MonitorEvent::StateChanged {
                node_id: 3,
                from: boot,
                to: state
            }),
            MasterEvent::Emergency(Emergency {
                node_id: 3,
                code: 0x2310,
                register: 0x03,
                manufacturer: *b"edsgn",
            }),
            MasterEvent::Monitor(MonitorEvent::Lost { node_id: 3 }),
            MasterEvent::Monitor(MonitorEvent::Recovered { node_id: 3, state }),
        ]
    );
    let MasterEvent::Emergency(emergency) = seen[3] else {
        unreachable!()
    };
    assert_eq!(
        emergency.meaning(),
        "continuous over-current (device output side)"
    );
    assert!(rounds >= 2, "{rounds} rounds of transfers");
    drop(master);
    let _ = resumed.stop();
    let _ = sim.stop();
}

/// The frames `listener` heard, in the manuals' notation.
fn heard(listener: &mut MemoryEndpoint) -> Vec<String> {
    let mut frames = Vec::new();
    while let Some(frame) = listener.recv_timeout(Duration::ZERO).unwrap() {
        let bytes: Vec<String> = frame.data().iter().map(|b| format!("{b:02X}")).collect();
        frames.push(format!(
            "{:03X}: {}",
            frame.std_id().unwrap(),
            bytes.join(" ")
        ));
    }
    frames
}

#[tokio::test]
async fn timeouts_per_node_and_by_default_and_read_retries_as_the_blocking_master() {
    let bus = MemoryBus::new();
    let mut listener = bus.endpoint();
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    // Node 9's own timeout outlives a default set afterwards; node 10 takes the default.
    master.set_timeout(9, Duration::from_millis(300)).unwrap();
    master
        .set_default_timeout(Duration::from_millis(40))
        .unwrap();
    let (nine, ten) = tokio::join!(
        master.read(9, od::STATUSWORD),
        master.read(10, od::STATUSWORD)
    );
    for (result, node) in [(nine, 9), (ten, 10)] {
        assert!(
            matches!(result, Err(MasterError::Sdo { node_id, error: SdoError::Timeout, .. }) if node_id == node),
            "{result:?}"
        );
    }
    // Each read is tried twice (one retry by default); node 10's two tries end before node 9's
    // first.
    let (upload, abort) = ("40 41 60 00 00 00 00 00", "80 41 60 00 00 00 04 05");
    assert_eq!(
        heard(&mut listener),
        [
            format!("609: {upload}"),
            format!("60A: {upload}"),
            format!("60A: {abort}"),
            format!("60A: {upload}"),
            format!("60A: {abort}"),
            format!("609: {abort}"),
            format!("609: {upload}"),
            format!("609: {abort}"),
        ]
    );
    // Without retries a read is tried once; a write is never repeated.
    master.set_read_retries(0).unwrap();
    assert!(master.read(10, od::STATUSWORD).await.is_err());
    assert!(master.write(10, od::CONTROLWORD, 0x000F).await.is_err());
    assert_eq!(
        heard(&mut listener),
        [
            format!("60A: {upload}"),
            format!("60A: {abort}"),
            "60A: 2B 40 60 00 0F 00 00 00".to_string(),
            "60A: 80 40 60 00 00 00 04 05".to_string(),
        ]
    );
}

#[tokio::test]
async fn a_guarded_node_is_lost_when_it_stops_answering_and_recovers_when_it_resumes() {
    let bus = MemoryBus::new();
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    let clock = MonotonicClock::new();
    let node = Node::new(cp301::Od::new(5), 5, clock.now()).unwrap();
    let guarded = Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap();
    master
        .wait_for_boot(5, Duration::from_secs(5))
        .await
        .unwrap();
    let guarding = Watch::Guarding {
        guard_time: edsgen_runtime::Duration::from_millis(30),
        life_factor: 2,
    };
    master.watch(5, guarding).await.unwrap();
    // The boot-up (an event of any node, watched or not), then the first answer to an RTR.
    let mut seen = vec![next_of(&master, 5).await, next_of(&master, 5).await];
    let (_, endpoint, node) = guarded.stop();
    seen.push(next_of(&master, 5).await);
    let resumed = Driver::with_clock(endpoint, node, clock).spawn().unwrap();
    seen.push(next_of(&master, 5).await);
    let state = NmtState::PreOperational;
    assert_eq!(
        seen,
        [
            MasterEvent::BootUp(5),
            MasterEvent::Monitor(MonitorEvent::StateChanged {
                node_id: 5,
                from: None,
                to: state
            }),
            MasterEvent::Monitor(MonitorEvent::Lost { node_id: 5 }),
            MasterEvent::Monitor(MonitorEvent::Recovered { node_id: 5, state }),
        ]
    );
    drop(master);
    let _ = resumed.stop();
}
