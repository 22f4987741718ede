//! The EtherCAT MainDevice side (feature `ethercrab`) shared by `edsgen ecat` and `edsgen demo
//! --ethercat`: ethercrab on a tokio runtime of the current thread, its frames carried by a task
//! on that runtime, through a raw socket on a network interface (root or CAP_NET_RAW).

use std::time::Duration;

use edsgen_sim::ethercat::raw_socket::open_error;
use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, SubDeviceGroup, Timeouts};

const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
/// The frames' storage: one MainDevice per process.
static PDU_STORAGE: PduStorage<16, MAX_PDU_DATA> = PduStorage::new();

/// A group of every SubDevice found, in Pre-Op: up to 64, with up to 4 KiB of process data.
pub type Group = SubDeviceGroup<64, 4096>;

/// The async runtime the MainDevice runs on.
pub fn runtime() -> Result<tokio::runtime::Runtime, String> {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|err| format!("cannot start the async runtime: {err}"))
}

/// ethercrab's MainDevice on `iface` (its frames carried by a task on the current runtime) and
/// every SubDevice it found there, in Pre-Op. Once per process: the second call fails.
pub async fn discover(iface: &str) -> Result<(MainDevice<'static>, Group), String> {
    let (tx, rx, pdu_loop) = PDU_STORAGE
        .try_split()
        .map_err(|_| "the PDU storage is split once".to_owned())?;
    // Generous timeouts: a SubDevice simulated on a loaded machine answers late, not never.
    let timeouts = Timeouts {
        pdu: Duration::from_millis(500),
        state_transition: Duration::from_secs(10),
        mailbox_response: Duration::from_secs(2),
        eeprom: Duration::from_secs(2),
        mailbox_echo: Duration::from_millis(500),
        ..Timeouts::default()
    };
    let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    let task = tx_rx_task(iface, tx, rx).map_err(|e| open_error(iface, &e))?;
    tokio::spawn(task);
    let group = maindevice
        .init_single_group::<64, 4096>(ethercat_now)
        .await
        .map_err(|e| format!("discovery: {e}"))?;
    Ok((maindevice, group))
}
