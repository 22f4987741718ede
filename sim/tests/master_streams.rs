//! Downloads of a value whose length the master does not know up front (read from a source to
//! its end, the size not indicated) into the DOMAIN of a simulated device (`edsgen_sim::canopen`
//! serving an EDS, on the in-memory bus): segmented and block, by the blocking and the async
//! master, each value read back byte for byte.

mod sim_support;

use std::io;

use edsgen_host::driver::{Driver, DriverHandle, MonotonicClock};
use edsgen_host::master::blocking::{Master, MasterError};
use edsgen_host::master::concurrent::AsyncMaster;
use edsgen_host::memory::{MemoryBus, MemoryEndpoint};
use edsgen_runtime::master::{Mode, SdoError};
use edsgen_runtime::node::Node;
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_sim::canopen::RuntimeDictionary;

/// The simulated device's DOMAIN (2001h, "Program", up to 64 KiB).
const PROGRAM: Multiplexer = Multiplexer::new(0x2001, 0);

/// The simulated device as node `node_id`, run by a driver thread on `bus`.
fn sim_node(bus: &MemoryBus, node_id: u8) -> DriverHandle<MemoryEndpoint, Node<RuntimeDictionary>> {
    let clock = MonotonicClock::new();
    let od = RuntimeDictionary::new(&sim_support::test_device(), node_id);
    let node = Node::new(od, node_id, clock.now()).unwrap();
    Driver::with_clock(bus.endpoint(), node, clock)
        .spawn()
        .unwrap()
}

/// `len` bytes that show misplaced ones: byte i is (i * 7 + i / 251) mod 256.
fn pattern(len: usize) -> Vec<u8> {
    (0..len).map(|i| (i * 7 + i / 251) as u8).collect()
}

/// A reader that gives at most `chunk` bytes per read, as a pipe or a file read in pieces
/// would: the master cannot know the length before the end.
struct Trickle {
    data: Vec<u8>,
    at: usize,
    chunk: usize,
}

impl io::Read for Trickle {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = buf.len().min(self.chunk).min(self.data.len() - self.at);
        buf[..n].copy_from_slice(&self.data[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

fn trickle(data: &[u8], chunk: usize) -> Trickle {
    Trickle {
        data: data.to_vec(),
        at: 0,
        chunk,
    }
}

/// A reader that fails after `ok` bytes.
struct Failing {
    ok: usize,
}

impl io::Read for Failing {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.ok == 0 {
            return Err(io::Error::other("disk gone"));
        }
        let n = buf.len().min(self.ok);
        buf[..n].fill(0xAA);
        self.ok -= n;
        Ok(n)
    }
}

#[test]
fn the_blocking_master_downloads_values_of_unknown_length_segmented_and_by_block() {
    let bus = MemoryBus::new();
    let mut master = Master::new(bus.endpoint());
    let handle = sim_node(&bus, 4);
    for (len, mode) in [
        (1000, Mode::Normal),
        (64 * 1024, Mode::Block),
        (0, Mode::Normal),
    ] {
        let value = pattern(len);
        let written = master
            .download_from(4, PROGRAM, mode, &mut trickle(&value, 100))
            .unwrap();
        assert_eq!(written as usize, len, "{mode:?}");
        let back = master.upload(4, PROGRAM, Mode::Block).unwrap();
        assert!(back == value, "{len} bytes {mode:?} read back");
    }
    // One byte more than the domain takes: the node aborts with 0607 0012 (too long).
    let too_long = pattern(64 * 1024 + 1);
    let refused = master.download_from(4, PROGRAM, Mode::Block, &mut too_long.as_slice());
    assert!(
        matches!(
            refused,
            Err(MasterError::Sdo {
                node_id: 4,
                error: SdoError::Server(0x0607_0012),
                ..
            })
        ),
        "{refused:?}"
    );
    // The source failing: the transfer is aborted with 0800 0000, the error returned.
    let failed = master.download_from(4, PROGRAM, Mode::Normal, &mut Failing { ok: 30 });
    assert!(
        matches!(&failed, Err(MasterError::Io(e)) if e.to_string() == "disk gone"),
        "{failed:?}"
    );
    // The channel is free again, and the node took the abort.
    let value = b"after".to_vec();
    let written = master.download_from(4, PROGRAM, Mode::Normal, &mut value.as_slice());
    assert_eq!(written.unwrap(), 5);
    assert_eq!(master.upload(4, PROGRAM, Mode::Normal).unwrap(), value);
    let _ = handle.stop();
}

#[tokio::test]
async fn the_async_master_downloads_values_of_unknown_length_segmented_and_by_block() {
    let bus = MemoryBus::new();
    let master = AsyncMaster::spawn(bus.endpoint()).unwrap();
    let handle = sim_node(&bus, 4);
    for (len, mode) in [(1000, Mode::Normal), (64 * 1024, Mode::Block)] {
        let value = pattern(len);
        let written = master
            .download_from(4, PROGRAM, mode, trickle(&value, 100))
            .await
            .unwrap();
        assert_eq!(written as usize, len, "{mode:?}");
        let back = master.upload(4, PROGRAM, Mode::Block).await.unwrap();
        assert!(back == value, "{len} bytes {mode:?} read back");
    }
    let failed = master
        .download_from(4, PROGRAM, Mode::Block, Failing { ok: 30 })
        .await;
    assert!(
        matches!(&failed, Err(MasterError::Io(e)) if e.to_string() == "disk gone"),
        "{failed:?}"
    );
    drop(master);
    let _ = handle.stop();
}
