//! The cycle a MainDevice sustains against a SubDevice: ethercrab brings the group on `IFACE` to
//! Op and times `tx_rx` (one frame out and back per cycle) back to back, then prints the
//! median, 99th percentile and worst round trip. Against `edsgen simulate --ethercat` on a veth
//! pair this measures the simulator and the kernel's veth, not a wire.
//!
//! ```sh
//! cargo build --release --example ethercat_cycles --features ethercrab
//! sudo target/release/examples/ethercat_cycles ecm 100000
//! ```

use std::time::{Duration, Instant};

use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
static PDU_STORAGE: PduStorage<16, MAX_PDU_DATA> = PduStorage::new();

#[tokio::main(flavor = "current_thread")]
async fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let interface = args.next().ok_or("usage: ethercat_cycles IFACE [CYCLES]")?;
    let cycles: usize = args.next().map_or(Ok(100_000), |n| n.parse())?;
    let (tx, rx, pdu_loop) = PDU_STORAGE
        .try_split()
        .map_err(|_| "the PDU storage is split once")?;
    let timeouts = Timeouts {
        pdu: Duration::from_millis(500),
        ..Timeouts::default()
    };
    let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    tokio::spawn(tx_rx_task(&interface, tx, rx)?);
    let group = maindevice
        .init_single_group::<4, 256>(ethercat_now)
        .await?
        .into_op(&maindevice)
        .await?;
    let mut times = Vec::with_capacity(cycles);
    for _ in 0..cycles {
        let start = Instant::now();
        group.tx_rx(&maindevice).await?;
        times.push(start.elapsed());
    }
    times.sort();
    let at = |q: f64| times[((times.len() - 1) as f64 * q) as usize];
    println!(
        "{cycles} cycles: p50 {:?}, p99 {:?}, max {:?}",
        at(0.5),
        at(0.99),
        at(1.0)
    );
    Ok(())
}
