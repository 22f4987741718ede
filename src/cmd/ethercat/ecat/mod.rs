//! `edsgen ecat` (feature `ethercrab`): the bench side of EtherCAT, an ethercrab MainDevice on a
//! network interface (root or CAP_NET_RAW). `ecat scan --iface IFACE [--esi FILE...]` lists the
//! SubDevices: position, configured address, identity, the name from their SII, and the ESI
//! device whose identity matches among the files given. `ecat sdo read|write`: one CoE SDO
//! transfer, by index or by name through the ESI ([`sdo`]).
//! `ecat pdo --iface IFACE --esi FILE [--cycles N]`: the SubDevice brought to Op, its inputs
//! printed by name (the ESI's default TxPDO entries) every 1 ms cycle until Ctrl-C or N cycles.
//! `ecat check --iface IFACE --esi FILE`: the SubDevice judged against its ESI ([`check`]).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args as ClapArgs, Subcommand};
use edsgen_demo::ecat::{discover, runtime};
use edsgen_model::model::Device;

use crate::cmd::{fail, print_stdout};

mod check;
mod sdo;

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
    /// Read or write one object by SDO (CoE), by index or by name through the ESI.
    Sdo(sdo::SdoArgs),
    /// Bring the SubDevice to Op, set its outputs by name (the ESI's default RxPDOs) and print
    /// its inputs by name (the default TxPDOs), one line per cycle, until Ctrl-C or `--cycles`.
    Pdo {
        #[command(flatten)]
        sub_device: SubDeviceArgs,
        /// Stop after this many cycles (1 ms each).
        #[arg(long, value_name = "N")]
        cycles: Option<u64>,
        /// Outputs to set, `NAME=VALUE` ("Operation mode=9"; a unique prefix of the name will
        /// do, case and spaces do not matter; decimal or 0x hex); the others stay 0.
        #[arg(value_name = "NAME=VALUE", allow_negative_numbers = true)]
        outputs: Vec<String>,
    },
    /// Judge a SubDevice against its ESI (identity, SyncManagers, PDO assignment, every
    /// readable object), in the validator's format.
    Check(check::CheckArgs),
}

/// One SubDevice and its ESI: the options `ecat pdo` and `ecat check` share.
#[derive(clap::Args, Debug)]
pub struct SubDeviceArgs {
    /// The network interface of the EtherCAT segment.
    #[arg(long, value_name = "IFACE")]
    iface: String,
    /// The SubDevice's ESI file.
    #[arg(long, value_name = "FILE")]
    esi: PathBuf,
    /// The device of an ESI file with several (type name or `#x` product code).
    #[arg(long, value_name = "NAME|#xCODE")]
    device: Option<String>,
    /// The SubDevice's position on the segment (0 first).
    #[arg(long, value_name = "N", default_value_t = 0)]
    position: usize,
}

/// Runs `edsgen ecat`.
pub fn run(args: Args) -> ExitCode {
    let (iface, esi) = match args.command {
        EcatCommand::Scan { iface, esi } => (iface, esi),
        EcatCommand::Sdo(args) => return sdo::run(&args),
        EcatCommand::Pdo {
            sub_device,
            cycles,
            outputs,
        } => return pdo(&sub_device, cycles, &outputs),
        EcatCommand::Check(args) => return check::run(&args),
    };
    let mut described = Vec::new();
    for path in &esi {
        let bytes = match std::fs::read(path) {
            Ok(bytes) => bytes,
            Err(err) => return fail(format!("cannot read `{}`: {err}", path.display())),
        };
        for (device, _) in edsgen_model::read::esi::read_all(path, &bytes) {
            if device.ethercat().is_some() {
                described.push((path.clone(), device));
            }
        }
    }
    let runtime = match runtime() {
        Ok(runtime) => runtime,
        Err(message) => return fail(message),
    };
    match runtime.block_on(scan(&iface, &described)) {
        Ok(text) => {
            print_stdout(&text);
            ExitCode::SUCCESS
        }
        Err(message) => fail(format!("{iface}: {message}")),
    }
}

/// Runs `edsgen ecat pdo`.
fn pdo(sub_device: &SubDeviceArgs, cycles: Option<u64>, settings: &[String]) -> ExitCode {
    let SubDeviceArgs {
        iface,
        esi,
        device,
        position,
    } = sub_device;
    let (iface, position) = (iface.as_str(), *position);
    let read = match crate::cmd::load(esi, device.as_deref()) {
        Ok(read) => read,
        Err(err) => return fail(err),
    };
    let Some(ec) = read.device.ethercat().filter(|_| !read.nothing_read) else {
        return fail(format!("{}: not an ESI device", esi.display()));
    };
    let entries = default_entries(&ec.tx_pdos);
    let mut outputs = vec![0u8; image_len(&default_entries(&ec.rx_pdos))];
    for setting in settings {
        if let Err(message) = set_output(&mut outputs, &default_entries(&ec.rx_pdos), setting) {
            return fail(message);
        }
    }
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = std::sync::Arc::clone(&stop);
    let _ = ctrlc::set_handler(move || flag.store(true, std::sync::atomic::Ordering::Relaxed));
    let runtime = match runtime() {
        Ok(runtime) => runtime,
        Err(message) => return fail(message),
    };
    let result: Result<(), String> = runtime.block_on(async {
        let (maindevice, group) = discover(iface).await?;
        let group = group
            .into_op(&maindevice)
            .await
            .map_err(|e| format!("to Op: {e}"))?;
        let sub_device = group
            .subdevice(&maindevice, position)
            .map_err(|_| format!("no SubDevice at position {position}"))?;
        let mut cycle = 0u64;
        while !stop.load(std::sync::atomic::Ordering::Relaxed) && cycles.is_none_or(|n| cycle < n) {
            let mut image = sub_device.outputs_raw_mut();
            let len = image.len().min(outputs.len());
            image[..len].copy_from_slice(&outputs[..len]);
            drop(image);
            group
                .tx_rx(&maindevice)
                .await
                .map_err(|e| format!("cycle {cycle}: {e}"))?;
            let line = inputs_line(&sub_device.inputs_raw(), &entries);
            print_stdout(&format!("{cycle}: {line}\n"));
            cycle += 1;
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
        Ok(())
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {iface}: {message}");
            ExitCode::from(1)
        }
    }
}

/// (name, bit length, signed) of each entry of the PDOs assigned by default, in image order.
fn default_entries(pdos: &[edsgen_model::model::EcPdo]) -> Vec<(String, u16, bool)> {
    pdos.iter()
        .filter(|p| p.sm.is_some())
        .flat_map(|p| &p.entries)
        .map(|e| {
            let signed = matches!(
                e.data_type.as_deref(),
                Some("SINT" | "INT" | "DINT" | "LINT")
            );
            (e.name.clone(), e.bit_len, signed)
        })
        .collect()
}

/// An image's length in bytes.
fn image_len(entries: &[(String, u16, bool)]) -> usize {
    entries
        .iter()
        .map(|e| usize::from(e.1))
        .sum::<usize>()
        .div_ceil(8)
}

/// Sets one `NAME=VALUE` in the outputs image `image` laid out by `entries`: the name exact or
/// a unique prefix (case and spaces aside), the value in the entry's range.
fn set_output(
    image: &mut [u8],
    entries: &[(String, u16, bool)],
    setting: &str,
) -> Result<(), String> {
    let Some((name, text)) = setting.split_once('=') else {
        return Err(format!("`{setting}` is not NAME=VALUE"));
    };
    let key = |s: &str| s.to_lowercase().replace(' ', "");
    let wanted = key(name);
    let named: Vec<&(String, u16, bool)> = entries.iter().filter(|e| !e.0.is_empty()).collect();
    let exact: Vec<_> = named.iter().filter(|e| key(&e.0) == wanted).collect();
    let prefixed: Vec<_> = named
        .iter()
        .filter(|e| key(&e.0).starts_with(&wanted))
        .collect();
    let all = || {
        named
            .iter()
            .map(|e| e.0.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let entry = match (exact.as_slice(), prefixed.as_slice()) {
        ([one], _) | ([], [one]) => **one,
        ([], []) => {
            return Err(format!(
                "no output named `{name}`: the outputs are {}",
                all()
            ))
        }
        _ => {
            let names: Vec<&str> = prefixed.iter().map(|e| e.0.as_str()).collect();
            return Err(format!("`{name}` names {}: say which", names.join(", ")));
        }
    };
    let (entry_name, bits, signed) = (&entry.0, usize::from(entry.1), entry.2);
    let value = crate::cmd::value::parse_int(text.trim())
        .ok_or_else(|| format!("{entry_name}: `{text}` is not a number"))?;
    let (low, high) = if signed {
        (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
    } else {
        (0, (1i128 << bits) - 1)
    };
    if value < low || value > high {
        return Err(format!(
            "{entry_name}: {value} is out of its range {low}..={high} ({bits} bits)"
        ));
    }
    let at: usize = entries
        .iter()
        .take_while(|e| !std::ptr::eq(*e, entry))
        .map(|e| usize::from(e.1))
        .sum();
    for bit in 0..bits {
        let target = at + bit;
        let byte = &mut image[target / 8];
        if value >> bit & 1 != 0 {
            *byte |= 1 << (target % 8);
        } else {
            *byte &= !(1 << (target % 8));
        }
    }
    Ok(())
}

/// The inputs image as `name=value` pairs, little-endian, bit by bit.
fn inputs_line(image: &[u8], entries: &[(String, u16, bool)]) -> String {
    let mut at = 0usize;
    let mut parts = Vec::new();
    for (name, bits, signed) in entries {
        let bits = usize::from(*bits).min(64);
        let mut value = 0u64;
        for bit in 0..bits {
            let source = at + bit;
            if image
                .get(source / 8)
                .is_some_and(|b| b >> (source % 8) & 1 != 0)
            {
                value |= 1 << bit;
            }
        }
        at += bits;
        if name.is_empty() {
            continue;
        }
        let shown = if *signed && bits > 0 && bits < 64 && value >> (bits - 1) & 1 != 0 {
            format!("{}", value as i64 - (1i64 << bits))
        } else {
            format!("{value}")
        };
        parts.push(format!("{name}={shown}"));
    }
    parts.join(", ")
}

/// A current-thread async runtime for one command, or the message to print.
async fn scan(iface: &str, described: &[(PathBuf, Device)]) -> Result<String, String> {
    let (maindevice, group) = discover(iface).await?;
    let mut text = String::new();
    for (position, sub) in group.iter(&maindevice).enumerate() {
        let id = sub.identity();
        let matched = described.iter().find(|(_, d)| {
            let n = |v: &Option<edsgen_model::model::Spanned<u32>>| v.as_ref().map(|v| v.value);
            n(&d.device_info.vendor_number) == Some(id.vendor_id)
                && n(&d.device_info.product_number) == Some(id.product_id)
                && n(&d.device_info.revision_number) == Some(id.revision)
        });
        let esi = matched.map_or(String::new(), |(path, d)| {
            let name = d.ethercat().map_or("", |ec| ec.type_name.as_str());
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

#[cfg(test)]
mod tests {
    use super::*;

    fn entries() -> Vec<(String, u16, bool)> {
        vec![
            ("Control word".into(), 16, false),
            ("Target speed".into(), 32, true),
            ("Operation mode".into(), 8, true),
            ("Probe control".into(), 16, false),
        ]
    }

    #[test]
    fn outputs_are_set_by_name_at_their_bits() {
        let mut image = vec![0u8; image_len(&entries())];
        assert_eq!(image.len(), 9);
        set_output(&mut image, &entries(), "control word=0x000F").unwrap();
        set_output(&mut image, &entries(), "Target speed=-2").unwrap();
        set_output(&mut image, &entries(), "Operation mode=9").unwrap();
        assert_eq!(image, [0x0F, 0, 0xFE, 0xFF, 0xFF, 0xFF, 9, 0, 0]);
    }

    #[test]
    fn a_wrong_setting_says_why() {
        let mut image = vec![0u8; 9];
        let e = entries();
        assert_eq!(
            set_output(&mut image, &e, "Speed=1"),
            Err(
                "no output named `Speed`: the outputs are Control word, Target speed, \
                 Operation mode, Probe control"
                    .into()
            )
        );
        assert_eq!(
            set_output(&mut image, &e, "Operation mode=200"),
            Err("Operation mode: 200 is out of its range -128..=127 (8 bits)".into())
        );
        assert_eq!(
            set_output(&mut image, &e, "Control word"),
            Err("`Control word` is not NAME=VALUE".into())
        );
        assert_eq!(set_output(&mut image, &e, "P=1"), Ok(()));
        assert_eq!(image[7..], [1, 0]);
    }
}
