//! The firmware loop shared by the examples: feed received frames and the time to the node, run
//! its timers, send what it offers, take its events. Also the device part of the vector table.
//!
//! There is no CAN peripheral driver here (that is the HAL's job): `receive` and `transmit`
//! stand in for it, through `black_box`, so that the compiler keeps every path a real driver
//! would reach.

use core::hint::black_box;
use core::panic::PanicInfo;
use edsgen_runtime::{CanFrame, Instant, Node, ObjectDictionary};

/// The number of device interrupts of the target: an STM32F407 has 82 (IRQ 0 to 81).
const DEVICE_INTERRUPTS: usize = 82;

extern "C" {
    /// cortex-m-rt's handler of every exception and interrupt the application does not handle.
    fn DefaultHandler();
}

/// The device part of the vector table. Without its `device` feature cortex-m-rt reserves the
/// architecture's maximum of 240 vectors (960 B of flash); a device crate (PAC) provides a table
/// of the part's own size instead, and this is that table for an STM32F4-class part, every
/// interrupt going to `DefaultHandler` as in cortex-m-rt's generic table. A real firmware takes
/// it from its PAC.
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
static __INTERRUPTS: [unsafe extern "C" fn(); DEVICE_INTERRUPTS] =
    [DefaultHandler; DEVICE_INTERRUPTS];

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
        if let Some(frame) = &frame {
            node.handle_frame(now, frame);
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

/// The image's memory copy, move and fill, in place of compiler_builtins' speed-tuned ones
/// (about 1 KB of word-at-a-time paths for every alignment, 1.5 KB more for `memmove`): byte
/// loops, as newlib-nano's size-optimised `memcpy`/`memmove`/`memset` are. The node copies a
/// few bytes at a time (a frame, a value), the SubDevice a mailbox's, so speed is not what
/// these cost. They are the ARM EABI's entry points, which the
/// compiler calls (compiler_builtins defines them weak). Volatile accesses keep the compiler
/// from turning the loops back into calls of the functions they define.
mod mem {
    /// Copies `n` bytes.
    ///
    /// # Safety
    /// `n` readable bytes at `src`, `n` writable at `dest`, not overlapping.
    // Inlined: shared with `copy_overlapping`, it would otherwise stay out of line and cost the
    // CANopen images, which have no memmove, a call in memcpy (12 B).
    #[inline(always)]
    unsafe fn copy(dest: *mut u8, src: *const u8, n: usize) {
        for i in 0..n {
            // SAFETY: the caller's contract.
            unsafe { dest.add(i).write_volatile(src.add(i).read_volatile()) };
        }
    }

    /// Copies `n` bytes between places that may overlap: forwards when the destination lies
    /// before the source, backwards otherwise, so that no byte is overwritten before it is read.
    ///
    /// # Safety
    /// `n` readable bytes at `src`, `n` writable at `dest`.
    unsafe fn copy_overlapping(dest: *mut u8, src: *const u8, n: usize) {
        if (dest as usize) < (src as usize) {
            // SAFETY: the caller's contract; forwards, each byte is read before it is written.
            unsafe { copy(dest, src, n) }
        } else {
            for i in (0..n).rev() {
                // SAFETY: the caller's contract; backwards, as above.
                unsafe { dest.add(i).write_volatile(src.add(i).read_volatile()) };
            }
        }
    }

    /// Fills `n` bytes with `byte`.
    ///
    /// # Safety
    /// `n` writable bytes at `dest`.
    unsafe fn fill(dest: *mut u8, n: usize, byte: u8) {
        for i in 0..n {
            // SAFETY: the caller's contract.
            unsafe { dest.add(i).write_volatile(byte) };
        }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memcpy(dest: *mut u8, src: *const u8, n: usize) {
        // SAFETY: the EABI's contract for memcpy.
        unsafe { copy(dest, src, n) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memcpy4(dest: *mut u8, src: *const u8, n: usize) {
        // SAFETY: as for `__aeabi_memcpy` (the alignment is a promise it need not use).
        unsafe { copy(dest, src, n) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memcpy8(dest: *mut u8, src: *const u8, n: usize) {
        // SAFETY: as for `__aeabi_memcpy`.
        unsafe { copy(dest, src, n) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memmove(dest: *mut u8, src: *const u8, n: usize) {
        // SAFETY: the EABI's contract for memmove.
        unsafe { copy_overlapping(dest, src, n) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memmove4(dest: *mut u8, src: *const u8, n: usize) {
        // SAFETY: as for `__aeabi_memmove`.
        unsafe { copy_overlapping(dest, src, n) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memmove8(dest: *mut u8, src: *const u8, n: usize) {
        // SAFETY: as for `__aeabi_memmove`.
        unsafe { copy_overlapping(dest, src, n) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memclr(dest: *mut u8, n: usize) {
        // SAFETY: the EABI's contract for memset.
        unsafe { fill(dest, n, 0) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memclr4(dest: *mut u8, n: usize) {
        // SAFETY: as for `__aeabi_memclr`.
        unsafe { fill(dest, n, 0) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memclr8(dest: *mut u8, n: usize) {
        // SAFETY: as for `__aeabi_memclr`.
        unsafe { fill(dest, n, 0) }
    }

    #[no_mangle]
    unsafe extern "C" fn __aeabi_memset(dest: *mut u8, n: usize, byte: i32) {
        // SAFETY: the EABI's contract for memset (its arguments in this order).
        unsafe { fill(dest, n, byte as u8) }
    }
}
