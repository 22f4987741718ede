//! Drives an INVT EC-TX508 (the Goodrive350's EtherCAT card) through CiA 402 with ethercrab and
//! the bindings generated from `eds/ec-tx508.xml` (`edsgen_sim::cards::ec_tx508`).
//!
//! The card is found by its identity; cyclic synchronous velocity mode (manual 6.5.2.4: 6060h =
//! 9) is set by a typed SDO write; then every cycle the typed outputs image (1600h: control
//! word, target velocity, ...) is packed into the SubDevice's outputs and its inputs unpacked
//! into the typed inputs image (1A00h: status word, actual speed, ...). The runtime's cyclic
//! CiA 402 controller (`master::cia402::Controller`) gives the control word that walks the drive
//! to operation enabled (a fault reset by a proper bit 7 edge on the way) and holds 6060h until
//! 6061h shows it; the target speed ramps to 300 rpm (60FFh, in rpm by 6.5.2.4) and back to 0,
//! and the controller walks the drive back to switch on disabled.
//!
//! ```sh
//! cargo build --example ec_tx508_ethercrab --features ethercrab
//! sudo target/debug/examples/ec_tx508_ethercrab eth0   # a raw socket on the EtherCAT port
//! ```
//!
//! The VFD must take its commands from EtherCAT (manual 6.5.2: P00.01 = 2, P00.02 = 3).

use std::time::Duration;

use edsgen_runtime::cia402::State;
use edsgen_runtime::ethercat::ethercrab::SdoExt;
use edsgen_runtime::master::cia402::{state_of, Controller, Outcome};
use edsgen_sim::cards::ec_tx508::{ethercat, od};
use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{EtherCrabWireRead, EtherCrabWireWrite};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

const MAX_SUBDEVICES: usize = 8;
const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
const MAX_FRAMES: usize = 16;
/// Room for the card's 21 output and 23 input bytes, and a few more devices.
const PDI_LEN: usize = 256;
/// The bus cycle: 1 ms, one of the cycles of the manual's Table 6-1.
const CYCLE: Duration = Duration::from_millis(1);
/// Cyclic synchronous velocity mode (manual 6.5.2.4).
const CSV: i8 = 9;
/// The cycles a CiA 402 transition or the mode confirmation may take: 1 s.
const STEP_LIMIT: u32 = 1_000;

static PDU_STORAGE: PduStorage<MAX_FRAMES, MAX_PDU_DATA> = PduStorage::new();

#[tokio::main(flavor = "current_thread")]
async fn main() -> Result<(), Box<dyn std::error::Error>> {
    let interface = std::env::args()
        .nth(1)
        .ok_or("usage: ec_tx508_ethercrab NETWORK_INTERFACE")?;
    let (tx, rx, pdu_loop) = PDU_STORAGE
        .try_split()
        .map_err(|_| "the PDU storage is split once")?;
    let maindevice = MainDevice::new(pdu_loop, Timeouts::default(), MainDeviceConfig::default());
    tokio::spawn(tx_rx_task(&interface, tx, rx)?);

    let group = maindevice
        .init_single_group::<MAX_SUBDEVICES, PDI_LEN>(ethercat_now)
        .await?;
    let position = group
        .iter(&maindevice)
        .position(|sd| ethercat::IDENTITY.matches_subdevice(&sd))
        .ok_or("no EC-TX508 (vendor 0x4D8, product 0x9252) on the bus")?;
    {
        // Pre-Op: SDO by typed address (an i8 for 6060h: another type would not compile).
        let card = group.subdevice(&maindevice, position)?;
        card.write_entry(od::OPERATION_MODE, CSV).await?;
        let assigned: u16 = card
            .read_entry(od::rx_pdo_assignment::RX_PDO_ASSIGNED_OBJECT_INDEX)
            .await?;
        println!("{}: RxPDO {assigned:04X}h assigned", card.name());
    }
    let group = group.into_op(&maindevice).await?;
    let card = group.subdevice(&maindevice, position)?;
    println!(
        "outputs {} bytes (expected {}), inputs {} bytes (expected {})",
        card.outputs_raw().len(),
        ethercat::Outputs::SIZE,
        card.inputs_raw().len(),
        ethercat::Inputs::SIZE
    );

    let mut outputs = ethercat::Outputs::default();
    let mut drive = Controller::new(State::OperationEnabled)
        .with_mode(CSV)
        .with_limit(STEP_LIMIT);
    let mut interval = tokio::time::interval(CYCLE);
    for cycle in 0u32..12_000 {
        group.tx_rx(&maindevice).await?;
        let inputs = ethercat::Inputs::unpack_from_slice(&card.inputs_raw())?;
        let status = inputs.tx_pdo_1a00;
        if cycle == 11_500 {
            drive.set_target(State::SwitchOnDisabled);
        }
        let step = drive.cycle(status.status_word, status.operation_mode_display);
        match step.outcome {
            Outcome::Stuck { state } => return Err(format!("the drive stays in {state:?}").into()),
            Outcome::ModeNotConfirmed { wanted, shown } => {
                return Err(format!("mode {wanted} requested, the drive shows {shown}").into())
            }
            Outcome::Busy | Outcome::Reached => {}
        }
        let enabled = step.outcome == Outcome::Reached && drive.target() == State::OperationEnabled;
        // 0 to 300 rpm over 3 s once enabled, held, back to 0, then disabled (from cycle 11 500).
        let target = match cycle {
            0..=1_999 => 0,
            2_000..=4_999 => (cycle - 2_000) as i32 / 10,
            5_000..=7_999 => 300,
            8_000..=10_999 => (11_000 - cycle) as i32 / 10,
            _ => 0,
        };
        let rx = &mut outputs.rx_pdo_1600;
        rx.control_word = step.controlword;
        rx.operation_mode = step.mode.unwrap_or(CSV);
        rx.target_speed = if enabled { target } else { 0 };
        outputs.pack_to_slice(&mut card.outputs_raw_mut())?;
        if cycle % 500 == 0 {
            println!(
                "{cycle:>6} ms: {:?}, mode {}, target {} rpm, actual speed {}, torque {}",
                state_of(status.status_word),
                status.operation_mode_display,
                outputs.rx_pdo_1600.target_speed,
                status.actual_speed,
                status.actual_torque
            );
        }
        interval.tick().await;
    }
    let group = group.into_safe_op(&maindevice).await?;
    let group = group.into_pre_op(&maindevice).await?;
    group.into_init(&maindevice).await?;
    Ok(())
}
