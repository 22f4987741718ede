//! A segment on a wire: frames read from a [`RawSocket`], processed by every SubDevice in
//! turn ([`Segment`]), and sent back from the last one, until a stop flag is raised. Frames
//! whose source address has the locally-administered bit set (0x02 in its first byte) are not
//! taken: they are frames a SubDevice already processed (another segment's answers, or our own
//! where the kernel shows a packet socket what it sends), as in a real ring.

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};

use edsgen_runtime::Instant;

use super::raw_socket::RawSocket;
use super::segment::Segment;
use super::Application;

/// What a run served.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Served {
    /// Frames answered.
    pub frames: u64,
    /// Frames ignored (not EtherCAT, or already processed).
    pub ignored: u64,
}

/// Serves `segment` on `socket` until `stop` is set (checked at least every read timeout).
pub fn serve<A: Application>(
    socket: &mut RawSocket,
    segment: &mut Segment<A>,
    stop: &AtomicBool,
) -> io::Result<Served> {
    let start = std::time::Instant::now();
    let now = || Instant(start.elapsed().as_micros() as u64);
    let mut buf = vec![0u8; 2048];
    let mut served = Served::default();
    while !stop.load(Ordering::Relaxed) {
        let Some(len) = socket.recv(&mut buf)? else {
            segment.poll(now());
            continue;
        };
        let frame = &mut buf[..len];
        if frame.len() < 14 || frame[6] & 0x02 != 0 {
            served.ignored += 1;
            continue;
        }
        if segment.process_frame(now(), frame) {
            socket.send(frame)?;
            served.frames += 1;
        } else {
            served.ignored += 1;
        }
    }
    Ok(served)
}
