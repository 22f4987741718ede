//! DP slaves on a serial line (an RS-485 adapter, or a pseudo-terminal for tests), each at its
//! own address: a thin driver around the sans-IO [`DpSlave`]. A reader thread hands the line's bytes over with the
//! time they came; the runtime's [`LineReceiver`] cuts them into telegrams under FDL's idle rule
//! (after a bad telegram nothing counts until the line goes idle; an idle line ends an
//! unfinished telegram), the loop answers each at once and runs the watchdog, all on the
//! machine's monotonic clock. The operating system hands bytes over in chunks, so the idle
//! time is [`IDLE`], longer than Tsyn at any rate DP runs at.
//!
//! The line is used as it is set: for a real bus, set its rate and parity (8E1) first, e.g.
//! `stty -F /dev/ttyUSB0 19200 raw parenb -parodd cs8`; a test's pseudo-terminal is set raw by
//! whoever made it.

use std::fs::File;
use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use edsgen_runtime::dp::fdl::MAX_TELEGRAM_LEN;
use edsgen_runtime::dp::{DpApplication, DpSlave, Event, LineReceiver};
use edsgen_runtime::Instant;

/// The line's silence that counts as idle: 20 ms (a USB adapter delivers a telegram's bytes in
/// chunks up to 16 ms apart; a master's retry comes later than that).
pub const IDLE: edsgen_runtime::Duration = edsgen_runtime::Duration::from_millis(20);

/// Serves `slaves` (each at its own address) on the line `port` until `stop` is set or the line
/// closes (an error then); `on_event` sees each slave's events as they come, with its address.
pub fn serve<A: DpApplication>(
    port: File,
    slaves: &mut [DpSlave<A>],
    stop: &AtomicBool,
    mut on_event: impl FnMut(u8, Event),
) -> std::io::Result<()> {
    let mut writer = port.try_clone()?;
    let mut reader = port;
    let origin = std::time::Instant::now();
    let clock = move || Instant::from_micros(origin.elapsed().as_micros() as u64);
    let (tx, rx) = mpsc::channel::<std::io::Result<(Instant, Vec<u8>)>>();
    std::thread::spawn(move || {
        let mut buf = [0u8; 512];
        loop {
            let result = reader.read(&mut buf).map(|n| (clock(), buf[..n].to_vec()));
            let end = !matches!(&result, Ok((_, bytes)) if !bytes.is_empty());
            if tx.send(result).is_err() || end {
                return;
            }
        }
    });
    let mut answer = [0u8; MAX_TELEGRAM_LEN];
    let mut line = LineReceiver::new(IDLE);
    while !stop.load(Ordering::Relaxed) {
        let mut received = None;
        match rx.recv_timeout(Duration::from_millis(5)) {
            Ok(Ok((at, bytes))) if !bytes.is_empty() => received = Some((at, bytes)),
            Ok(Ok(_)) => {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    "the line closed",
                ))
            }
            Ok(Err(e)) => return Err(e),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(std::io::Error::other("the reader stopped"))
            }
        }
        for slave in slaves.iter_mut() {
            slave.handle_timeout(clock());
            while let Some(event) = slave.poll_event() {
                on_event(slave.config().address, event);
            }
        }
        let Some((at, bytes)) = received else {
            continue;
        };
        let mut written = Ok(());
        line.receive(at, &bytes, |telegram| {
            // Each slave takes what is addressed to it (and broadcasts); one answers at most.
            for slave in slaves.iter_mut() {
                slave.handle(clock(), telegram);
                if let Some(n) = slave.poll_transmit(clock(), &mut answer) {
                    if written.is_ok() {
                        written = writer.write_all(&answer[..n]).and_then(|()| writer.flush());
                    }
                }
                while let Some(event) = slave.poll_event() {
                    on_event(slave.config().address, event);
                }
            }
        });
        written?;
    }
    Ok(())
}
