//! A minimal CANopen device on a Cortex-M4F: the edsgen runtime's `Node` (NMT, heartbeat, SDO
//! server, 4 RPDOs + 4 TPDOs, SYNC, EMCY) serving an object dictionary, in the shape a real
//! firmware has: a loop that feeds received frames and the time in, and sends what comes out.
//!
//! There is no CAN peripheral driver here (that is the HAL's job): the "mailbox" below stands in
//! for it, through `black_box`, so that the compiler keeps every path a real driver would reach.
//! `scripts/firmware-size.sh` builds it and prints its flash and RAM use.
#![no_std]
#![no_main]

mod od;

use core::hint::black_box;
use core::panic::PanicInfo;
use cortex_m_rt::entry;
use edsgen_runtime::{CanFrame, Instant, Node};

const NODE_ID: u8 = 3;

/// The node's RAM (its state and the OD's values), which lives on `main`'s stack rather than in
/// `.bss`; kept in the image so that `scripts/firmware-size.sh` can report it.
#[used]
#[export_name = "EDSGEN_NODE_RAM_BYTES"]
static NODE_RAM_BYTES: u32 = core::mem::size_of::<Node<od::MinimalOd>>() as u32;

/// Stands in for the CAN controller's receive FIFO and the microsecond timer.
fn receive() -> (Instant, Option<CanFrame>) {
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

#[entry]
fn main() -> ! {
    let (now, _) = receive();
    let Ok(mut node) = Node::new(od::MinimalOd::new(NODE_ID), NODE_ID, now) else {
        panic!("node-ID out of range");
    };
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
