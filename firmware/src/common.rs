//! The firmware loop shared by the examples: feed received frames and the time to the node, run
//! its timers, send what it offers, take its events.
//!
//! There is no CAN peripheral driver here (that is the HAL's job): `receive` and `transmit`
//! stand in for it, through `black_box`, so that the compiler keeps every path a real driver
//! would reach.

use core::hint::black_box;
use core::panic::PanicInfo;
use edsgen_runtime::{CanFrame, Instant, Node, ObjectDictionary};

/// The node-ID of the examples.
pub const NODE_ID: u8 = 3;

/// Stands in for the CAN controller's receive FIFO and the microsecond timer.
pub fn receive() -> (Instant, Option<CanFrame>) {
    let now = Instant::from_micros(black_box(0));
    let frame = CanFrame::new(
        black_box(0x603),
        black_box(&[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]),
    );
    (now, black_box(frame))
}

/// Stands in for the CAN controller's transmit mailbox.
fn transmit(frame: CanFrame) {
    black_box(frame);
}

/// Runs a node forever.
pub fn run<O: ObjectDictionary>(node: &mut Node<O>) -> ! {
    loop {
        let (now, frame) = receive();
        if let Some(frame) = frame {
            node.handle_frame(now, &frame);
        }
        if node.poll_timeout().is_some_and(|at| at <= now) {
            node.handle_timeout(now);
        }
        while let Some(frame) = node.poll_transmit(now) {
            transmit(frame);
        }
        while let Some(event) = node.poll_event() {
            black_box(event);
        }
        if black_box(false) {
            node.raise_error(0x5000, 0x01, [0; 5]);
            node.clear_error(0x5000);
            node.trigger_tpdo(0);
        }
    }
}

#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    loop {}
}
