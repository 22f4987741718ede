//! A node serving a generated `Od` on the virtual bus: what the generated code provides to the
//! runtime beyond reads and writes (the defaults NMT resets restore).

use edsgen_host::vbus::VirtualBus;
use edsgen_runtime::node::Node;
use edsgen_runtime::{CanFrame, Instant};
use edsgen_sim::cards::goodrive350::{od, Od};

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn ms(millis: u64) -> Instant {
    Instant::from_millis(millis)
}

#[test]
fn resets_restore_the_generated_defaults_of_their_area() {
    let mut node = Node::new(Od::new(3), 3, ms(0)).unwrap();
    let mut bus = VirtualBus::new(ms(0));
    // 1017h = 100 ms by SDO; the application's 2100h:03 and the EMCY COB-ID ($NODEID+0x80)
    // changed by the application.
    bus.inject(
        frame(0x603, &[0x2B, 0x17, 0x10, 0x00, 0x64, 0x00, 0x00, 0x00]),
        &mut [&mut node],
    );
    node.od_mut().set(od::control_data::SETTING_1, 5).unwrap();
    node.od_mut().set(od::COB_ID_EMCY, 0x8000_0083).unwrap();
    // Reset communication: 1000h-1FFFh back to their defaults, 2100h:03 kept.
    bus.inject(frame(0x000, &[0x82, 0x03]), &mut [&mut node]);
    assert_eq!(node.od().get(od::PRODUCER_HEARTBEAT_TIME), 0);
    assert_eq!(node.od().get(od::COB_ID_EMCY), 0x83);
    assert_eq!(node.od().get(od::control_data::SETTING_1), 5);
    // Reset node: everything.
    bus.inject(frame(0x000, &[0x81, 0x03]), &mut [&mut node]);
    assert_eq!(node.od().get(od::control_data::SETTING_1), 0);
    assert_eq!(node.od(), &Od::new(3));
}
