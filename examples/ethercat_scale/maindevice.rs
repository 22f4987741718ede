//! The MainDevice, in the namespace: N SubDevices to Op, then the cycles at [`PERIOD`], one
//! line of figures. How it reaches the wire ([`TxRx`]) and how large its frames are ([`Pdu`])
//! are chosen by two variables, so that each setting can be measured against the others.

use std::future::Future;
use std::time::{Duration, Instant};

use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduRx, PduStorage, PduTx, Timeouts};

use crate::wire::Wire;
use crate::{Ticker, Times, IMAGE, MAX_SUBDEVICES, PERIOD};

/// How many frames may be in flight, a power of two as ethercrab asks. ethercrab 0.7's
/// `SubDeviceGroup::tx_rx` sends a cycle's frames one after the other: it builds the next LRW
/// chunk only once the previous frame came back, so a cycle costs one round trip per frame,
/// and fewer, larger frames ([`FULL_PDU`]) are the one lever on that from outside.
const FRAMES: usize = 16;
/// The largest PDU data ethercrab's own `tx_rx_task` takes back whole: it reads a frame into a
/// buffer of the interface's MTU (1,500 bytes), not MTU + 14 for the Ethernet header, so a
/// full 1,514-byte frame (1,486 bytes of data) comes back cut short and its task ends with
/// `ReceiveFrame` (measured: `Timeout(Pdu)` at the first cycle). [`PduStorage::element_size`]
/// adds the 28 bytes of Ethernet, EtherCAT and datagram headers: 1,500-byte frames. At 64
/// EC-TX508s (2,816 bytes of images, plus ethercrab's 14-byte AL status read per SubDevice in
/// every cycle: 3,712 bytes) a cycle is 3 frames, against 4 at ethercrab's usual 1,100.
const FULL_PDU: usize = 1472;
/// ethercrab's examples' size.
const SMALL_PDU: usize = 1100;

static PDU_FULL: PduStorage<FRAMES, { PduStorage::element_size(FULL_PDU) }> = PduStorage::new();
static PDU_SMALL: PduStorage<FRAMES, { PduStorage::element_size(SMALL_PDU) }> = PduStorage::new();

/// How the MainDevice's frames reach the wire (`EDSGEN_SCALE_TXRX`).
#[derive(Debug, Clone, Copy)]
pub enum TxRx {
    /// `inline` (the default): on the cycle's own thread ([`Wire`]), one wake-up per answer;
    /// the cycle's timer is an absolute `nanosleep` ([`Ticker`]). Measured beside `tokio` at
    /// load 9 to 12, 64 SubDevices, 3,000 cycles a run: under the ordinary policy (three runs)
    /// p50 358 to 382 µs, p99 3.1 to 3.8 ms, 73 to 104 cycles over 1 ms, against `tokio` with
    /// 1,100-byte PDUs 407 to 533 µs, 8.5 to 12.5 ms, 364 to 434; under `SCHED_FIFO` (two
    /// runs) p50 401 and 406 µs, p99 490 and 500 µs, 3 and 5 over 1 ms, against `tokio` with
    /// 1,472-byte PDUs 397 and 426 µs, 534 and 535 µs, 5 and 8.
    Inline,
    /// `tokio`: ethercrab's `tx_rx_task` spawned on a tokio current_thread runtime, as its
    /// README shows; an answer wakes async-io's reactor thread, then the tokio thread. The timer
    /// is a tokio `interval`, whose wheel counts whole milliseconds: it woke more than 1 ms late
    /// on 1,700 to 8,700 of 10,000 cycles, so this setup never quite ran at 1 kHz.
    Tokio,
}

/// The PDU size (`EDSGEN_SCALE_PDU`): `1472` (the default, [`FULL_PDU`]) or `1100`.
#[derive(Debug, Clone, Copy)]
pub enum Pdu {
    Full,
    Small,
}

/// The settings, from the environment.
pub fn setup() -> Result<(TxRx, Pdu), String> {
    let txrx = match std::env::var("EDSGEN_SCALE_TXRX").as_deref() {
        Err(_) | Ok("inline") => TxRx::Inline,
        Ok("tokio") => TxRx::Tokio,
        Ok(other) => return Err(format!("EDSGEN_SCALE_TXRX: `{other}` is inline or tokio")),
    };
    let pdu = match std::env::var("EDSGEN_SCALE_PDU").as_deref() {
        Err(_) | Ok("1472") => Pdu::Full,
        Ok("1100") => Pdu::Small,
        Ok(other) => return Err(format!("EDSGEN_SCALE_PDU: `{other}` is 1472 or 1100")),
    };
    Ok((txrx, pdu))
}

/// The settings, as the figures print them.
pub fn describe((txrx, pdu): (TxRx, Pdu)) -> String {
    let size = match pdu {
        Pdu::Full => FULL_PDU,
        Pdu::Small => SMALL_PDU,
    };
    let txrx = match txrx {
        TxRx::Inline => "on the cycle's thread (inline)",
        TxRx::Tokio => "tx_rx_task on tokio current_thread",
    };
    format!("MainDevice: frames {txrx}, PDU {size} bytes")
}

/// `n` SubDevices to Op, then `cycles` cycles; prints one line of figures.
pub fn run(n: usize, cycles: usize) -> Result<(), String> {
    let (txrx, pdu) = setup()?;
    match pdu {
        Pdu::Full => chain(&PDU_FULL, txrx, n, cycles),
        Pdu::Small => chain(&PDU_SMALL, txrx, n, cycles),
    }
}

fn chain<const DATA: usize>(
    storage: &'static PduStorage<FRAMES, DATA>,
    txrx: TxRx,
    n: usize,
    cycles: usize,
) -> Result<(), String> {
    let (tx, rx, pdu_loop) = storage
        .try_split()
        .map_err(|_| "the PDU storage is split once")?;
    let timeouts = Timeouts {
        pdu: Duration::from_millis(500),
        state_transition: Duration::from_secs(30),
        mailbox_response: Duration::from_secs(2),
        eeprom: Duration::from_secs(2),
        ..Timeouts::default()
    };
    let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    match txrx {
        TxRx::Inline => {
            let mut drive = Inline {
                wire: Wire::open("ecm", tx, rx)?,
                ticker: Ticker::new(),
            };
            drive_chain(&mut drive, &maindevice, n, cycles)
        }
        TxRx::Tokio => drive_chain(&mut Tokio::new(tx, rx)?, &maindevice, n, cycles),
    }
}

/// What runs ethercrab's futures and times the cycles.
trait Drive {
    /// Runs `future` to its end.
    fn block_on<F: Future>(&mut self, future: F) -> Result<F::Output, String>;
    /// Waits for the next cycle; returns how late it woke.
    fn tick(&mut self) -> Duration;
    /// The frames answered and the time spent waiting for their answers since the last call,
    /// where it is known.
    fn take_counts(&mut self) -> Option<(u64, Duration)> {
        None
    }
    /// Called once the SubDevices are in Op, before the cycles.
    fn settle(&mut self) {}
    /// The thread left out of the time waited for a CPU: one the cycle does not wait on.
    fn idle_thread(&self) -> Option<&'static str> {
        None
    }
}

struct Inline {
    wire: Wire<'static>,
    ticker: Ticker,
}

impl Drive for Inline {
    fn block_on<F: Future>(&mut self, future: F) -> Result<F::Output, String> {
        self.wire.run(future)
    }
    fn tick(&mut self) -> Duration {
        self.ticker.tick()
    }
    fn take_counts(&mut self) -> Option<(u64, Duration)> {
        Some(self.wire.take_counts())
    }
    /// ethercrab's timeouts are async-io timers: every frame's timer wakes async-io's thread
    /// to note itself, though nothing here waits on that thread (a frame's timeout is seen when
    /// the cycle's thread polls it). Under `SCHED_FIFO` that thread, woken 3,000 times a second
    /// at the cycle's own priority, takes the CPU an answer would wake the cycle's thread on: it
    /// goes back to the ordinary policy.
    fn idle_thread(&self) -> Option<&'static str> {
        Some("async-io")
    }
    fn settle(&mut self) {
        if crate::fifo_priority().is_none() {
            return;
        }
        let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
            return;
        };
        for task in tasks.flatten() {
            let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
            if comm.trim() == "async-io" {
                let _ = std::process::Command::new("chrt")
                    .args(["-o", "-p", "0"])
                    .arg(task.file_name())
                    .status();
            }
        }
    }
}

struct Tokio {
    runtime: tokio::runtime::Runtime,
    interval: tokio::time::Interval,
}

impl Tokio {
    fn new(tx: PduTx<'static>, rx: PduRx<'static>) -> Result<Self, String> {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .map_err(|e| e.to_string())?;
        runtime.spawn(tx_rx_task("ecm", tx, rx).map_err(|e| format!("ecm: {e}"))?);
        let interval = runtime.block_on(async {
            let mut interval = tokio::time::interval(PERIOD);
            interval.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
            interval
        });
        Ok(Tokio { runtime, interval })
    }
}

impl Drive for Tokio {
    fn block_on<F: Future>(&mut self, future: F) -> Result<F::Output, String> {
        // The current_thread runtime runs the spawned tx_rx_task while it blocks on `future`.
        Ok(self.runtime.block_on(future))
    }
    fn tick(&mut self) -> Duration {
        let due = self.runtime.block_on(self.interval.tick());
        due.elapsed()
    }
}

fn drive_chain(
    drive: &mut impl Drive,
    maindevice: &MainDevice<'static>,
    n: usize,
    cycles: usize,
) -> Result<(), String> {
    let group = drive
        .block_on(
            maindevice
                .init_single_group::<MAX_SUBDEVICES, { MAX_SUBDEVICES * IMAGE }>(ethercat_now),
        )?
        .map_err(|e| format!("discovery: {e:?}"))?;
    if group.len() != n {
        return Err(format!("{} SubDevices found, {n} served", group.len()));
    }
    let group = drive
        .block_on(group.into_op(maindevice))?
        .map_err(|e| format!("Op: {e:?}"))?;
    drive.settle();
    // Every SubDevice counts 3 on each LRW that reaches its images: once, or twice when
    // ethercrab's chunks of the image (a frame's worth each) split its images.
    let expected = drive
        .block_on(group.tx_rx(maindevice))?
        .map_err(|e| format!("the first cycle: {e:?}"))?
        .working_counter;
    if usize::from(expected) < 3 * n {
        return Err(format!("working counter {expected} of {n} SubDevices"));
    }
    drive.take_counts();
    let mut times = Times::with_capacity(cycles);
    let mut missed = 0;
    let mut late = 0;
    for _ in 0..cycles {
        if drive.tick() > PERIOD {
            late += 1;
        }
        let start = Instant::now();
        let answer = drive.block_on(group.tx_rx(maindevice))?;
        let took = start.elapsed();
        let counted = answer.is_ok_and(|a| a.working_counter == expected);
        if !counted || took > PERIOD {
            missed += 1;
        }
        times.push(took);
    }
    // Where a cycle's time goes, on average: waiting for the answers, and the rest (ethercrab).
    let split = match drive.take_counts() {
        Some((frames, waited)) if cycles > 0 => {
            let total: Duration = times.total();
            format!(
                "; per cycle {:.1} frames, {:.0} µs waiting for answers, {:.0} µs in ethercrab",
                frames as f64 / cycles as f64,
                waited.as_secs_f64() * 1e6 / cycles as f64,
                total.saturating_sub(waited).as_secs_f64() * 1e6 / cycles as f64
            )
        }
        _ => String::new(),
    };
    println!(
        "missed {missed}, {}, its threads waited for a CPU {} ms{split}",
        times.summary(PERIOD, late),
        crate::host::waited_for_cpu("self", drive.idle_thread()).as_millis()
    );
    Ok(())
}
