//! The runtime's CiA 402 drive on the CP301's generated dictionary: the manual's velocity-mode
//! sequence (CP301 §5.3) by SDO, frame for frame, with the statusword and the ramp read back.

use edsgen_runtime::cia402::{Drive, DriveConfig};
use edsgen_runtime::{CanFrame, Event, Instant, Node};
use edsgen_sim::cards::cp301::Od;

const NODE: u8 = 3;

/// The node, the drive behind it, and the time.
struct Cp301 {
    node: Node<Od>,
    drive: Drive,
    now: Instant,
}

impl Cp301 {
    fn new() -> Self {
        let now = Instant::from_millis(0);
        let mut node = Node::new(Od::new(NODE), NODE, now).expect("node-ID 3 is valid");
        while node.poll_transmit(now).is_some() {} // boot-up
                                                   // Ramp times refer to 3000 rpm (parameter 01-09 of a 50 Hz, 2-pole motor).
        let drive = Drive::new(DriveConfig::new(3000), now);
        Cp301 { node, drive, now }
    }

    /// Sends an SDO request at the current time, lets the drive see what was written, and
    /// returns the response's bytes.
    fn sdo(&mut self, request: [u8; 8]) -> [u8; 8] {
        let frame = CanFrame::new(0x600 + u16::from(NODE), &request).expect("valid frame");
        self.node.handle_frame(self.now, &frame);
        while let Some(event) = self.node.poll_event() {
            if matches!(
                event,
                Event::Written {
                    index: 0x6000..=0x67FF,
                    ..
                }
            ) {
                self.drive
                    .run_on(self.node.od_mut(), self.now)
                    .expect("the CP301 dictionary takes the drive's outputs");
            }
        }
        let response = self.node.poll_transmit(self.now).expect("an SDO response");
        assert_eq!(response.std_id(), Some(0x580 + u16::from(NODE)));
        response.data().try_into().expect("8 bytes")
    }

    /// Advances the time, running the drive on the way as a firmware loop would.
    fn wait_until(&mut self, ms: u64) {
        self.now = Instant::from_millis(ms);
        self.drive
            .run_on(self.node.od_mut(), self.now)
            .expect("the CP301 dictionary takes the drive's outputs");
    }
}

#[test]
fn cp301_velocity_mode_sequence_of_the_manual() {
    let mut card = Cp301::new();
    // 6042h = 1500 rpm, 604Fh = 5000 ms, 6050h = 10000 ms.
    assert_eq!(
        card.sdo([0x2B, 0x42, 0x60, 0, 0xDC, 0x05, 0, 0]),
        [0x60, 0x42, 0x60, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        card.sdo([0x23, 0x4F, 0x60, 0, 0x88, 0x13, 0, 0]),
        [0x60, 0x4F, 0x60, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        card.sdo([0x23, 0x50, 0x60, 0, 0x10, 0x27, 0, 0]),
        [0x60, 0x50, 0x60, 0, 0, 0, 0, 0]
    );

    let read_statusword = [0x40, 0x41, 0x60, 0, 0, 0, 0, 0];
    // 6040h = 06h, 07h, 0Fh: ready to switch on, switched on, operation enabled.
    for (controlword, statusword) in [(0x06u8, 0x0631u16), (0x07, 0x0633), (0x0F, 0x0637)] {
        card.sdo([0x2B, 0x40, 0x60, 0, controlword, 0, 0, 0]);
        let [lo, hi] = statusword.to_le_bytes();
        assert_eq!(
            card.sdo(read_statusword),
            [0x4B, 0x41, 0x60, 0, lo, hi, 0, 0]
        );
    }
    // 7Fh: the ramp runs towards 1500 rpm at 600 rpm/s; target not reached yet.
    card.sdo([0x2B, 0x40, 0x60, 0, 0x7F, 0, 0, 0]);
    assert_eq!(
        card.sdo(read_statusword),
        [0x4B, 0x41, 0x60, 0, 0x37, 0x02, 0, 0]
    );

    card.wait_until(1_000);
    // 6043h demand and 6044h actual: 600 rpm (0258h).
    assert_eq!(
        card.sdo([0x40, 0x43, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x43, 0x60, 0, 0x58, 0x02, 0, 0]
    );
    assert_eq!(
        card.sdo([0x40, 0x44, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x44, 0x60, 0, 0x58, 0x02, 0, 0]
    );

    card.wait_until(2_500);
    assert_eq!(
        card.sdo([0x40, 0x44, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x44, 0x60, 0, 0xDC, 0x05, 0, 0]
    );
    assert_eq!(
        card.sdo(read_statusword),
        [0x4B, 0x41, 0x60, 0, 0x37, 0x06, 0, 0]
    );

    // 6042h = -1500 reverses: 5 s down to 0 on 6050h, then 2.5 s up on the other side.
    card.sdo([0x2B, 0x42, 0x60, 0, 0x24, 0xFA, 0, 0]);
    card.wait_until(7_500);
    assert_eq!(
        card.sdo([0x40, 0x44, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x44, 0x60, 0, 0, 0, 0, 0]
    );
    card.wait_until(10_000);
    assert_eq!(
        card.sdo([0x40, 0x44, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x44, 0x60, 0, 0x24, 0xFA, 0, 0]
    );

    // Quick stop (6040h = 7Bh) with 605Ah = 2: 6051h is 1 s from 3000 rpm, so 0.5 s from
    // -1500 rpm, then switch on disabled.
    card.sdo([0x2B, 0x40, 0x60, 0, 0x7B, 0, 0, 0]);
    assert_eq!(
        card.sdo(read_statusword),
        [0x4B, 0x41, 0x60, 0, 0x17, 0x02, 0, 0]
    );
    card.wait_until(10_250);
    assert_eq!(
        card.sdo([0x40, 0x44, 0x60, 0, 0, 0, 0, 0]),
        [0x4B, 0x44, 0x60, 0, 0x12, 0xFD, 0, 0]
    );
    card.wait_until(10_500);
    assert_eq!(
        card.sdo(read_statusword),
        [0x4B, 0x41, 0x60, 0, 0x50, 0x06, 0, 0]
    );
}
