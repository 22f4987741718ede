//! The baseline with neither the simulator nor ethercrab: one thread sends a frame every period
//! on `ecm` (with the chain's timer, [`Ticker`]) and waits for it, another echoes it from `ecs`,
//! both on `poll(2)`-based packet sockets. Its round trips over a period are the stalls of the
//! machine and the kernel alone, to set beside the EtherCAT figures of the same run.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use edsgen_sim::packet_socket::PacketSocket;

use crate::{Ticker, Times, PERIOD};

/// IEEE 802's EtherType for local experiments: nothing else in the namespace takes it.
const ETHERTYPE: u16 = 0x88B5;
/// The first payload byte: a request to echo, or the echo.
const REQUEST: u8 = 1;
const REPLY: u8 = 2;
/// A full Ethernet frame, as the chain's largest LRW frame.
const FRAME_LEN: usize = 1514;

/// Runs `cycles` round trips at [`PERIOD`] and prints one line of figures.
pub fn baseline(cycles: usize) -> Result<(), String> {
    let mut echo = PacketSocket::open("ecs", ETHERTYPE, Duration::from_millis(50))
        .map_err(|e| format!("ecs: {e}"))?;
    let mut ping = PacketSocket::open("ecm", ETHERTYPE, Duration::from_millis(50))
        .map_err(|e| format!("ecm: {e}"))?;
    let stop = Arc::new(AtomicBool::new(false));
    let echoing = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || -> std::io::Result<()> {
            let mut buf = vec![0u8; 2048];
            while !stop.load(Ordering::Relaxed) {
                // A packet socket also sees the frames it sends: only requests are echoed.
                if let Some(n) = echo.recv(&mut buf)? {
                    if n > 14 && buf[14] == REQUEST {
                        buf[14] = REPLY;
                        echo.send(&buf[..n])?;
                    }
                }
            }
            Ok(())
        })
    };
    let mut frame = vec![0u8; FRAME_LEN];
    frame[..6].fill(0xff);
    frame[6..12].copy_from_slice(&[0x10; 6]);
    frame[12..14].copy_from_slice(&ETHERTYPE.to_be_bytes());
    let mut buf = vec![0u8; 2048];
    let mut times = Times::with_capacity(cycles);
    let mut lost = 0;
    let mut late = 0;
    let mut ticker = Ticker::new();
    for seq in 0..cycles as u32 {
        if ticker.tick() > PERIOD {
            late += 1;
        }
        frame[14] = REQUEST;
        frame[15..19].copy_from_slice(&seq.to_be_bytes());
        let start = Instant::now();
        ping.send(&frame).map_err(|e| format!("ecm: {e}"))?;
        let answered = loop {
            match ping.recv(&mut buf).map_err(|e| format!("ecm: {e}"))? {
                Some(n) if n > 18 && buf[14] == REPLY && buf[15..19] == seq.to_be_bytes() => {
                    break true
                }
                Some(_) => {}
                None => break false,
            }
        };
        if !answered {
            lost += 1;
        }
        times.push(start.elapsed());
    }
    stop.store(true, Ordering::Relaxed);
    let echoed = echoing.join().map_err(|_| "the echo thread panicked")?;
    echoed.map_err(|e| format!("ecs: {e}"))?;
    println!(
        "echo baseline: lost {lost}, {}, its threads waited for a CPU {} ms",
        times.summary(PERIOD, late),
        crate::host::waited_for_cpu("self", None).as_millis()
    );
    Ok(())
}
