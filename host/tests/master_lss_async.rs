//! The async master's LSS services (CiA 305) against unconfigured LSS slave nodes on the
//! in-memory bus: a scan that finds several nodes and gives each an ID (each then boots up and
//! answers SDO there), selective switching, inquiries and refusals, listing without assigning,
//! a scan while SDO transfers run, and a scan ended by its callback's error. Futures run on a small `block_on` of this file.

#[path = "../../runtime/tests/node_support/mod.rs"]
mod node_support;

use std::cell::Cell;
use std::future::{poll_fn, Future};
use std::pin::pin;
use std::sync::Arc;
use std::task::{Context, Poll, Wake, Waker};
use std::thread::{self, Thread};
use std::time::{Duration as StdDuration, Instant};

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::master::blocking::MasterError;
use edsgen_host::master::concurrent::AsyncMaster;
use edsgen_host::memory::{MemoryBus, MemoryEndpoint};
use edsgen_runtime::master::lss::{LssMasterError, LssOutcome, LssService};
use edsgen_runtime::master::sdo_client::Mode;
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::lss::{LssError, LssMode};
use edsgen_runtime::wire::sdo::Multiplexer;
use node_support::node_od::TestOd;

const VENDOR: u32 = 0x0000_04D8;
const PROBE: StdDuration = StdDuration::from_millis(30);
const SERIAL: Multiplexer = Multiplexer::new(0x1018, 4);

/// Runs `future` to its end on this thread, parked while it waits.
fn block_on<F: Future>(future: F) -> F::Output {
    struct Unpark(Thread);
    impl Wake for Unpark {
        fn wake(self: Arc<Self>) {
            self.0.unpark();
        }
    }
    let waker = Waker::from(Arc::new(Unpark(thread::current())));
    let mut cx = Context::from_waker(&waker);
    let mut future = pin!(future);
    loop {
        if let Poll::Ready(output) = future.as_mut().poll(&mut cx) {
            return output;
        }
        thread::park();
    }
}

/// Runs two futures side by side until both end.
async fn join<A: Future, B: Future>(a: A, b: B) -> (A::Output, B::Output) {
    let (mut a, mut b) = (pin!(a), pin!(b));
    let (mut done_a, mut done_b) = (None, None);
    poll_fn(|cx| {
        if done_a.is_none() {
            done_a = match a.as_mut().poll(cx) {
                Poll::Ready(output) => Some(output),
                Poll::Pending => None,
            };
        }
        if done_b.is_none() {
            done_b = match b.as_mut().poll(cx) {
                Poll::Ready(output) => Some(output),
                Poll::Pending => None,
            };
        }
        match (done_a.take(), done_b.take()) {
            (Some(a), Some(b)) => Poll::Ready((a, b)),
            (a, b) => {
                (done_a, done_b) = (a, b);
                Poll::Pending
            }
        }
    })
    .await
}

/// Unconfigured nodes (node-ID FFh) with these serial numbers, served on `bus`.
fn unconfigured(
    bus: &MemoryBus,
    serials: &[u32],
) -> Vec<DriverHandle<MemoryEndpoint, Node<TestOd>>> {
    serials
        .iter()
        .map(|&serial| {
            let clock = MonotonicClock::new();
            let node = Node::new(TestOd::new(1).with_serial(serial), 0xFF, clock.now()).unwrap();
            Driver::with_clock(bus.endpoint(), node, clock)
                .spawn()
                .unwrap()
        })
        .collect()
}

fn serials(addresses: &[[u32; 4]]) -> Vec<u32> {
    addresses.iter().map(|a| a[3]).collect()
}

#[test]
fn a_scan_finds_three_nodes_and_each_answers_at_the_id_it_was_given() {
    let bus = MemoryBus::new();
    // The master's endpoint first, so that it hears the boot-ups.
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    let handles = unconfigured(&bus, &[5, 2, 7]);
    let next_id = Cell::new(20u8);
    let master = &master;
    block_on(async {
        let found = master
            .lss_scan_all(PROBE, |address| {
                let id = next_id.get();
                next_id.set(id + 1);
                async move {
                    assert_eq!(address[0], VENDOR);
                    let inquired = master.lss(LssService::InquireAddress).await?;
                    assert_eq!(inquired, LssOutcome::Address(address));
                    let configured = master.lss(LssService::ConfigureNodeId(id)).await?;
                    assert_eq!(configured, LssOutcome::Done);
                    let stored = master.lss(LssService::Store).await;
                    assert!(matches!(
                        stored,
                        Err(MasterError::Lss(LssMasterError::Refused(
                            LssError::StoreNotSupported
                        )))
                    ));
                    Ok(true)
                }
            })
            .await
            .unwrap();
        // Lowest address first.
        assert_eq!(serials(&found), [2, 5, 7]);
        for (id, serial) in [(20u8, 2u32), (21, 5), (22, 7)] {
            master
                .wait_for_boot(id, StdDuration::from_secs(2))
                .await
                .unwrap_or_else(|e| panic!("node {id} boots up: {e}"));
            let read = master.upload(id, SERIAL, Mode::Normal).await.unwrap();
            assert_eq!(read, serial.to_le_bytes(), "node {id}");
        }
        let none = master.lss(LssService::InquireNodeId).await;
        assert!(matches!(
            none,
            Err(MasterError::Lss(LssMasterError::NoAnswer))
        ));
        let unconfigured = master.lss(LssService::IdentifyNonConfigured).await.unwrap();
        assert_eq!(unconfigured, LssOutcome::Identified(false));
    });
    drop(handles);
}

#[test]
fn selective_switch_inquiries_and_refusals() {
    let bus = MemoryBus::new();
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    let handles = unconfigured(&bus, &[7, 8]);
    block_on(async {
        let identify = LssService::IdentifyRemote {
            vendor: VENDOR,
            product: 0,
            revision: (0, 0),
            serial: (8, 100),
        };
        assert_eq!(
            master.lss(identify).await.unwrap(),
            LssOutcome::Identified(true)
        );
        let nobody = master.lss(LssService::InquireNodeId).await;
        assert!(
            matches!(nobody, Err(MasterError::Lss(LssMasterError::NoAnswer))),
            "no slave in configuration"
        );
        let select = LssService::SwitchSelective([VENDOR, 0, 0, 8]);
        assert_eq!(master.lss(select).await.unwrap(), LssOutcome::Done);
        assert_eq!(
            master.lss(LssService::InquireAddress).await.unwrap(),
            LssOutcome::Address([VENDOR, 0, 0, 8])
        );
        assert_eq!(
            master.lss(LssService::InquireNodeId).await.unwrap(),
            LssOutcome::NodeId(0xFF)
        );
        let out_of_range = master.lss(LssService::ConfigureNodeId(128)).await;
        assert!(matches!(
            out_of_range,
            Err(MasterError::Lss(LssMasterError::Refused(
                LssError::OutOfRange
            )))
        ));
        let timing = LssService::ConfigureBitTiming { table: 0, index: 5 };
        assert!(matches!(
            master.lss(timing).await,
            Err(MasterError::Lss(LssMasterError::Refused(
                LssError::OutOfRange
            )))
        ));
        assert_eq!(
            master.lss(LssService::ConfigureNodeId(40)).await.unwrap(),
            LssOutcome::Done
        );
        let waiting = LssService::SwitchGlobal(LssMode::Waiting);
        assert_eq!(master.lss(waiting).await.unwrap(), LssOutcome::Done);
        master
            .wait_for_boot(40, StdDuration::from_secs(2))
            .await
            .expect("serial 8 boots up as node 40");
        let read = master.upload(40, SERIAL, Mode::Normal).await.unwrap();
        assert_eq!(read, 8u32.to_le_bytes());
        // Serial 7 is still unconfigured and the only one a scan finds, while node 40 answers
        // SDO reads on the same driver thread.
        let scan = async {
            let listed = master.lss_scan_all(PROBE, |_| async { Ok(false) }).await;
            (listed, Instant::now())
        };
        let reads = async {
            let mut serials = Vec::new();
            for _ in 0..20 {
                serials.push(master.upload(40, SERIAL, Mode::Normal).await.unwrap());
            }
            (serials, Instant::now())
        };
        let ((listed, scanned_at), (read, read_at)) = join(scan, reads).await;
        assert_eq!(serials(&listed.unwrap()), [7]);
        assert_eq!(read, vec![8u32.to_le_bytes().to_vec(); 20]);
        assert!(read_at < scanned_at, "the reads did not wait for the scan");
    });
    drop(handles);
}

#[test]
fn listing_assigns_nothing_and_an_error_ends_the_scan_with_every_node_back_in_waiting() {
    let bus = MemoryBus::new();
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    let handles = unconfigured(&bus, &[9, 4]);
    block_on(async {
        let listed = master.lss_scan_all(PROBE, |_| async { Ok(false) }).await;
        assert_eq!(serials(&listed.unwrap()), [4, 9]);
        let again = master.lss_scan_all(PROBE, |_| async { Ok(false) }).await;
        assert_eq!(serials(&again.unwrap()), [4, 9], "back in waiting");
        let calls = Cell::new(0);
        let failed = master
            .lss_scan_all(PROBE, |_| {
                calls.set(calls.get() + 1);
                async { Err(MasterError::Timeout) }
            })
            .await;
        assert!(matches!(failed, Err(MasterError::Timeout)));
        assert_eq!(calls.get(), 1, "the first error ends the scan");
        assert_eq!(
            master.lss(LssService::IdentifyNonConfigured).await.unwrap(),
            LssOutcome::Identified(true)
        );
        let nobody = master.lss(LssService::InquireNodeId).await;
        assert!(
            matches!(nobody, Err(MasterError::Lss(LssMasterError::NoAnswer))),
            "none left in configuration"
        );
    });
    drop(handles);
}
