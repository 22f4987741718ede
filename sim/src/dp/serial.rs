//! The DP slave on a serial line (an RS-485 adapter, or a pseudo-terminal for tests): a thin
//! driver around the sans-IO [`DpSlave`]. A reader thread hands the line's bytes over; the loop
//! cuts them into telegrams (a byte is dropped where none parses, as a receiver resynchronising
//! does), answers each at once, and runs the watchdog on the machine's monotonic clock.
//!
//! The line is used as it is set: for a real bus, set its rate and parity (8E1) first, e.g.
//! `stty -F /dev/ttyUSB0 19200 raw parenb -parodd cs8`; a test's pseudo-terminal is set raw by
//! whoever made it.

use std::fs::File;
use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use edsgen_host::driver::MonotonicClock;
use edsgen_runtime::dp::fdl::{self, FdlError, MAX_TELEGRAM_LEN};
use edsgen_runtime::dp::{DpApplication, DpSlave, Event};

/// Serves `slave` on the line `port` until `stop` is set or the line closes (an error then);
/// `on_event` sees the slave's events as they come.
pub fn serve<A: DpApplication>(
    port: File,
    slave: &mut DpSlave<A>,
    stop: &AtomicBool,
    mut on_event: impl FnMut(Event),
) -> std::io::Result<()> {
    let mut writer = port.try_clone()?;
    let mut reader = port;
    let (tx, rx) = mpsc::channel::<std::io::Result<Vec<u8>>>();
    std::thread::spawn(move || {
        let mut buf = [0u8; 512];
        loop {
            let result = reader.read(&mut buf).map(|n| buf[..n].to_vec());
            let end = !matches!(&result, Ok(bytes) if !bytes.is_empty());
            if tx.send(result).is_err() || end {
                return;
            }
        }
    });
    let clock = MonotonicClock::new();
    let mut answer = [0u8; MAX_TELEGRAM_LEN];
    let mut pending: Vec<u8> = Vec::new();
    while !stop.load(Ordering::Relaxed) {
        match rx.recv_timeout(Duration::from_millis(5)) {
            Ok(Ok(bytes)) if !bytes.is_empty() => pending.extend(bytes),
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
        slave.handle_timeout(clock.now());
        while let Some(event) = slave.poll_event() {
            on_event(event);
        }
        loop {
            match fdl::parse(&pending) {
                Ok((_, used)) => {
                    let telegram: Vec<u8> = pending.drain(..used).collect();
                    slave.handle(clock.now(), &telegram);
                    if let Some(n) = slave.poll_transmit(clock.now(), &mut answer) {
                        writer.write_all(&answer[..n])?;
                        writer.flush()?;
                    }
                    while let Some(event) = slave.poll_event() {
                        on_event(event);
                    }
                }
                Err(FdlError::Incomplete) => break,
                Err(_) => {
                    pending.remove(0);
                }
            }
        }
    }
    Ok(())
}
