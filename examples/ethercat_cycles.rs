//! The cycle a MainDevice sustains against a SubDevice, next to the bus's own limit: ethercrab
//! brings the group on `IFACE` to Op and times `tx_rx` (one frame out and back per cycle) back to
//! back, then prints the median, 99th percentile and worst round trip; a packet socket on the
//! same interface captures one cycle's frame, whose wire time at 100 Mbit/s (with preamble, FCS
//! and inter-frame gap) is the shortest cycle a real segment could carry it in. Against `edsgen
//! simulate --ethercat` on a veth pair this measures the simulator and the kernel's veth, not a
//! wire. `scripts/ethercat-cycles.sh` runs it in a private network namespace.
//!
//! ```sh
//! cargo build --release --example ethercat_cycles --features ethercrab
//! sudo target/release/examples/ethercat_cycles ecm 100000
//! ```

use std::time::{Duration, Instant};

use edsgen_sim::ethercat::raw_socket::RawSocket;
use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
static PDU_STORAGE: PduStorage<16, MAX_PDU_DATA> = PduStorage::new();

/// Bits of one frame on a 100BASE-TX wire: the frame (padded to Ethernet's 60-byte minimum),
/// its 4-byte FCS, 8 bytes of preamble and start delimiter, and the 12-byte inter-frame gap.
fn wire_bits(frame_len: usize) -> usize {
    8 * (frame_len.max(60) + 4 + 8 + 12)
}

#[tokio::main(flavor = "current_thread")]
async fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let interface = args.next().ok_or("usage: ethercat_cycles IFACE [CYCLES]")?;
    let cycles: usize = args.next().map_or(Ok(100_000), |n| n.parse())?;
    if cycles == 0 {
        return Err("CYCLES must be at least 1".into());
    }
    let (tx, rx, pdu_loop) = PDU_STORAGE
        .try_split()
        .map_err(|_| "the PDU storage is split once")?;
    let timeouts = Timeouts {
        pdu: Duration::from_millis(500),
        eeprom: Duration::from_millis(500),
        mailbox_response: Duration::from_secs(2),
        ..Timeouts::default()
    };
    let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    tokio::spawn(tx_rx_task(&interface, tx, rx)?);
    let group = maindevice
        .init_single_group::<4, 256>(ethercat_now)
        .await?
        .into_op(&maindevice)
        .await?;
    let sub = group.subdevice(&maindevice, 0)?;
    let outputs = sub.outputs_raw().len();
    let inputs = sub.inputs_raw().len();
    // One cycle's frame, as the interface carries it (outgoing frames reach packet sockets too).
    let mut capture = RawSocket::open(&interface, Duration::from_millis(200))?;
    group.tx_rx(&maindevice).await?;
    let mut buf = [0u8; 1600];
    let frame_len = capture.recv(&mut buf)?.ok_or("no cycle frame captured")?;
    drop(capture);

    let mut times = Vec::with_capacity(cycles);
    let run = Instant::now();
    for _ in 0..cycles {
        let start = Instant::now();
        group.tx_rx(&maindevice).await?;
        times.push(start.elapsed());
    }
    let total = run.elapsed();
    times.sort();
    let at = |q: f64| times[((times.len() - 1) as f64 * q) as usize];
    let us = |d: Duration| d.as_secs_f64() * 1e6;
    let bits = wire_bits(frame_len);
    println!(
        "{cycles} cycles, {outputs}/{inputs}-byte images, a {frame_len}-byte frame: \
         p50 {:.1} us, p99 {:.1} us, max {:.1} us ({:.0} cycles/s); \
         the frame's wire time at 100 Mbit/s: {:.2} us ({bits} bits with preamble, FCS and gap)",
        us(at(0.5)),
        us(at(0.99)),
        us(at(1.0)),
        cycles as f64 / total.as_secs_f64(),
        bits as f64 / 100.0,
    );
    Ok(())
}
