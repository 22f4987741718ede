//! `edsgen ecat` (feature `ethercrab`): the bench side of EtherCAT, an ethercrab MainDevice on a
//! network interface (root or CAP_NET_RAW). `ecat scan --iface IFACE [--esi FILE...]` lists the
//! SubDevices: position, configured address, identity, the name from their SII, and the ESI
//! device whose identity matches among the files given.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args as ClapArgs, Subcommand};
use edsgen_codegen::model::Device;
use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, Timeouts};

use super::{fail, print_stdout};

/// `edsgen ecat ...`.
#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(subcommand)]
    command: EcatCommand,
}

#[derive(Subcommand, Debug)]
enum EcatCommand {
    /// List the SubDevices on a network interface, with the ESI device each matches.
    Scan {
        /// The network interface of the EtherCAT segment.
        #[arg(long, value_name = "IFACE")]
        iface: String,
        /// ESI files to match the SubDevices against (every device of each file).
        #[arg(long, value_name = "FILE")]
        esi: Vec<PathBuf>,
    },
}

const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
static PDU_STORAGE: PduStorage<16, MAX_PDU_DATA> = PduStorage::new();

/// Runs `edsgen ecat`.
pub fn run(args: Args) -> ExitCode {
    let EcatCommand::Scan { iface, esi } = args.command;
    let mut described = Vec::new();
    for path in &esi {
        let bytes = match std::fs::read(path) {
            Ok(bytes) => bytes,
            Err(err) => return fail(format!("cannot read `{}`: {err}", path.display())),
        };
        for (device, _) in edsgen_codegen::read::esi::read_all(path, &bytes) {
            if device.ethercat.is_some() {
                described.push((path.clone(), device));
            }
        }
    }
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(runtime) => runtime,
        Err(err) => return fail(format!("cannot start the async runtime: {err}")),
    };
    match runtime.block_on(scan(&iface, &described)) {
        Ok(text) => {
            print_stdout(&text);
            ExitCode::SUCCESS
        }
        Err(message) => fail(format!("{iface}: {message}")),
    }
}

async fn scan(iface: &str, described: &[(PathBuf, Device)]) -> Result<String, String> {
    let (tx, rx, pdu_loop) = PDU_STORAGE
        .try_split()
        .map_err(|_| "the PDU storage is split once")?;
    let timeouts = Timeouts {
        pdu: Duration::from_millis(500),
        ..Timeouts::default()
    };
    let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    let task = tx_rx_task(iface, tx, rx).map_err(|e| format!("cannot open: {e}"))?;
    tokio::spawn(task);
    let group = maindevice
        .init_single_group::<64, 4096>(ethercat_now)
        .await
        .map_err(|e| format!("discovery: {e}"))?;
    let mut text = String::new();
    for (position, sub) in group.iter(&maindevice).enumerate() {
        let id = sub.identity();
        let matched = described.iter().find(|(_, d)| {
            let n = |v: &Option<edsgen_codegen::model::Spanned<u32>>| v.as_ref().map(|v| v.value);
            n(&d.device_info.vendor_number) == Some(id.vendor_id)
                && n(&d.device_info.product_number) == Some(id.product_id)
                && n(&d.device_info.revision_number) == Some(id.revision)
        });
        let esi = matched.map_or(String::new(), |(path, d)| {
            let name = d.ethercat.as_ref().map_or("", |ec| ec.type_name.as_str());
            format!(" = {name} ({})", path.display())
        });
        text.push_str(&format!(
            "{position}: {:#06x} vendor {:#010x} product {:#010x} revision {:#010x} \"{}\"{esi}\n",
            sub.configured_address(),
            id.vendor_id,
            id.product_id,
            id.revision,
            sub.name(),
        ));
    }
    if text.is_empty() {
        text.push_str("no SubDevices\n");
    }
    Ok(text)
}
