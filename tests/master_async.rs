//! The async master on tokio against three device nodes serving the generated cp301 card (the
//! driver on the in-memory bus): typed reads and writes as futures, transfers to different
//! nodes running side by side, waiting for boot-ups, and a silent node's timeout not holding up
//! the others.

use std::time::{Duration, Instant};

use edsgen::cards::cp301::{self, od};
use edsgen_runtime::master::blocking::MasterError;
use edsgen_runtime::master::concurrent::AsyncMaster;
use edsgen_runtime::master::SdoError;
use edsgen_runtime::node::Node;
use edsgen_runtime::transport::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_runtime::transport::memory::{MemoryBus, MemoryEndpoint};
use edsgen_runtime::wire::nmt::NmtCommand;

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
                .read(id, od::RPDO1_COMMUNICATION_PARAMETER_COB_ID_USED_BY_RPDO)
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
