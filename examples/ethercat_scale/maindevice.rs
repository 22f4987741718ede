//! The MainDevice, in the namespace: N SubDevices to Op, then the cycles at [`PERIOD`], one
//! line of figures. How it reaches the wire ([`TxRx`]) and how large its frames are ([`Pdu`])
//! are chosen by two variables, so that each setting can be measured against the others.

use std::future::Future;
use std::time::{Duration, Instant};

use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduRx, PduStorage, PduTx, Timeouts};

use crate::wire::Wire;
use crate::{Ticker, Times, IMAGE, MAX_SUBDEVICES, PERIOD};

/// How many frames may be in flight: ethercrab sends a cycle's frames one after the other, so
/// one would do; a power of two, as ethercrab asks.
const FRAMES: usize = 16;
/// The largest EtherCAT payload a standard Ethernet frame carries: 1,500 bytes of Ethernet
/// payload less the 2-byte EtherCAT header, the 10-byte datagram header and the 2-byte working
/// counter ([`PduStorage::element_size`] adds those and the Ethernet header: 1,514 bytes).
/// At 64 EC-TX508s (2,816 bytes of images, plus ethercrab's 14-byte AL status read per
/// SubDevice in every cycle) a cycle is 3 frames, against 4 at ethercrab's usual 1,100.
const FULL_PDU: usize = 1486;
/// ethercrab's examples' size.
const SMALL_PDU: usize = 1100;

static PDU_FULL: PduStorage<FRAMES, { PduStorage::element_size(FULL_PDU) }> = PduStorage::new();
static PDU_SMALL: PduStorage<FRAMES, { PduStorage::element_size(SMALL_PDU) }> = PduStorage::new();

/// How the MainDevice's frames reach the wire (`EDSGEN_SCALE_TXRX`).
#[derive(Debug, Clone, Copy)]
pub enum TxRx {
    /// `inline` (the default): on the cycle's own thread ([`Wire`]), one wake-up per answer;
    /// the cycle's timer is an absolute `nanosleep` ([`Ticker`]).
    Inline,
    /// `tokio`: ethercrab's `tx_rx_task` spawned on a tokio current_thread runtime, as its
    /// README shows; an answer wakes async-io's reactor thread, then the tokio thread. The timer
    /// is a tokio `interval` (whose wheel counts whole milliseconds).
    Tokio,
}

/// The PDU size (`EDSGEN_SCALE_PDU`): `1486` (the default, a full frame) or `1100`.
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
        Err(_) | Ok("1486") => Pdu::Full,
        Ok("1100") => Pdu::Small,
        Ok(other) => return Err(format!("EDSGEN_SCALE_PDU: `{other}` is 1486 or 1100")),
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
    // Every SubDevice counts 3 on each LRW that reaches its images: once, or twice when
    // ethercrab's chunks of the image (a frame's worth each) split its images.
    let expected = drive
        .block_on(group.tx_rx(maindevice))?
        .map_err(|e| format!("the first cycle: {e:?}"))?
        .working_counter;
    if usize::from(expected) < 3 * n {
        return Err(format!("working counter {expected} of {n} SubDevices"));
    }
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
    println!(
        "missed {missed}, {}, its threads waited for a CPU {} ms",
        times.summary(PERIOD, late),
        crate::host::waited_for_cpu("self").as_millis()
    );
    Ok(())
}
