//! A dictionary that reports which optional services it has the objects of
//! (`ObjectDictionary::services`, as the generated ones do) gets a node that builds no code for
//! the others and behaves exactly as one that assumes every service: the same frames for the
//! same traffic.

mod node_support;

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::Node;
use edsgen_runtime::od::{EntryDescriptor, ObjectDictionary, SdoAbort, Services};
use edsgen_runtime::CanFrame;
use node_support::node_od::TestOd;
use node_support::{at_ms, frame, ms, sdo_read, sdo_write, sent};

/// The objects of the optional services, which CANopenNode's default CP301 dictionary lacks too.
const OPTIONAL: [u16; 8] = [
    0x1003, 0x1006, 0x1007, 0x100C, 0x100D, 0x1015, 0x1019, 0x1201,
];

/// The test device without the optional services' objects, reporting `services`.
struct Lacking {
    od: TestOd,
    services: Services,
}

impl ObjectDictionary for Lacking {
    fn entry_count(&self) -> usize {
        self.od.entry_count()
    }

    fn entry(&self, position: usize) -> Option<EntryDescriptor> {
        self.od.entry(position)
    }
    fn services(&self) -> Services {
        self.services
    }
    fn value_len(&self, index: u16, sub: u8) -> Result<usize, SdoAbort> {
        self.od.value_len(index, sub)
    }
    fn read(&self, index: u16, sub: u8, offset: usize, buf: &mut [u8]) -> Result<usize, SdoAbort> {
        self.od.read(index, sub, offset, buf)
    }
    fn write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoAbort> {
        self.od.write(index, sub, data)
    }
    fn restore_defaults(&mut self, indices: core::ops::RangeInclusive<u16>, node_id: u8) -> bool {
        self.od.restore_defaults(indices, node_id)
    }
}

/// Boots a node over the device without the optional objects, reporting `services`, and drives
/// it through SDO, NMT, SYNC, EMCY, PDOs, error control and timers: every frame it sends.
fn traffic(services: Services) -> Vec<(u64, String)> {
    let od = Lacking {
        od: TestOd::with_second_sdo(3).without(&OPTIONAL),
        services,
    };
    let mut node = Node::new(od, 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    bus.run_until(ms(0), &mut [&mut node]);
    // The optional objects are absent; the others served.
    bus.inject(sdo_read(0x1003, 0), &mut [&mut node]);
    bus.inject(sdo_write(0x1006, 0, 1000, 4), &mut [&mut node]);
    bus.inject(sdo_write(0x1017, 0, 100, 2), &mut [&mut node]);
    // No second SDO server: no answer on 640h.
    bus.inject(
        frame(0x643, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]),
        &mut [&mut node],
    );
    // Operational; a SYNC without counter (TPDO2 is synchronous), one with a counter (8240h),
    // an RPDO, a guard request.
    bus.inject(frame(0x000, &[0x01, 3]), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    bus.inject(frame(0x080, &[5]), &mut [&mut node]);
    bus.inject(frame(0x080, &[]), &mut [&mut node]);
    bus.inject(frame(0x203, &[0x34, 0x12]), &mut [&mut node]);
    bus.inject(CanFrame::remote(0x703, 1), &mut [&mut node]);
    node.raise_error(0x5000, 0x01, [1, 2, 3, 4, 5]);
    bus.run_until(ms(250), &mut [&mut node]);
    node.clear_error(0x5000);
    bus.run_until(ms(300), &mut [&mut node]);
    sent(&mut bus)
}

#[test]
fn a_node_without_the_optional_services_sends_what_one_assuming_them_sends() {
    let lacking = Services {
        error_history: false,
        sync_period: false,
        sync_window: false,
        sync_counter: false,
        emcy_inhibit: false,
        life_guarding: false,
        second_sdo: false,
        streamed_writes: false,
    };
    let frames = traffic(lacking);
    assert_eq!(frames, traffic(Services::ALL));
    let mut expected = vec![
        (0, "703: 00"),
        // 1003h and 1006h: no object (0602 0000).
        (0, "583: 80 03 10 00 00 00 02 06"),
        (0, "583: 80 06 10 00 00 00 02 06"),
        (0, "583: 60 17 10 00 00 00 00 00"),
        // Operational: TPDO1 (event-driven), then the SYNC's TPDO2.
        (0, "183: 00 00"),
        (0, "283: 00 00 00 00"),
        // A SYNC with a counter while 1019h is absent: 8240h, cleared by the next SYNC.
        (0, "083: 40 82 11 01 00 00 00 00"),
        (0, "083: 00 00 00 00 00 00 00 00"),
        (0, "283: 00 00 00 00"),
    ];
    // The answer to the guard request (no life guarding without 100Ch/100Dh).
    if cfg!(feature = "node-guarding") {
        expected.push((0, "703: 05"));
    }
    expected.extend([
        (0, "083: 00 50 01 01 02 03 04 05"),
        (100, "703: 05"),
        (200, "703: 05"),
        (250, "083: 00 00 00 00 00 00 00 00"),
        (300, "703: 05"),
    ]);
    assert_eq!(frames, at_ms(&expected));
}
