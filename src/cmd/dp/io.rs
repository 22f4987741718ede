//! `edsgen dp io`: one slave brought to data exchange by profirust's DP master from its GSD
//! (see the parent module).

use std::fs::OpenOptions;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use edsgen_runtime::pkw_pzd::{ByteOrder, InputImage, WordLayout};
use profirust::{dp, fdl, Baudrate};

use super::super::fail;
use super::phy::TtyPhy;

/// The arguments of `edsgen dp io`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The serial line.
    tty: String,
    /// The slave's GSD file (its overlay beside it applies).
    #[arg(long, value_name = "FILE")]
    gsd: PathBuf,
    /// The slave's station address.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(0..=125))]
    address: u8,
    /// This master's station address.
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u8).range(0..=125))]
    master: u8,
    /// How long to exchange data before printing the inputs.
    #[arg(long, default_value_t = 1)]
    seconds: u64,
    /// Outputs to set: NAME=VALUE (decimal or 0x hex), a 16-bit word each.
    #[arg(value_name = "NAME=VALUE")]
    outputs: Vec<String>,
}

const PKW_PZD_NAMES: [&str; 16] = [
    "pkw1", "pkw2", "pkw3", "pkw4", "cw", "pzd2", "pzd3", "pzd4", "pzd5", "pzd6", "pzd7", "pzd8",
    "pzd9", "pzd10", "pzd11", "pzd12",
];

/// The name of word `n` of an image.
fn word_name(n: usize, pkw_pzd: bool, input: bool) -> String {
    match (pkw_pzd, n) {
        (true, 4) if input => "sw".to_owned(),
        (true, n) if n < 16 => PKW_PZD_NAMES[n].to_owned(),
        _ => format!("w{n}"),
    }
}

fn number(text: &str) -> Option<u16> {
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u16::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}

/// Runs `edsgen dp io`.
pub fn run(args: &Args) -> ExitCode {
    let read = match crate::cmd::load(&args.gsd, None) {
        Ok(read) => read,
        Err(e) => return fail(e),
    };
    let Some(gsd) = read.device.dp() else {
        return fail(format!("{}: not a GSD file", args.gsd.display()));
    };
    let Some(ident) = gsd.ident_number.as_ref().map(|i| i.value) else {
        return fail(format!("{}: no Ident_Number", args.gsd.display()));
    };
    let Some(module) = gsd.modules.iter().find(|m| !m.identifiers().is_empty()) else {
        return fail(format!("{}: no module", args.gsd.display()));
    };
    let pkw_pzd = gsd.pkw_pzd_module.as_deref() == Some(module.name.as_str());
    let (input_len, output_len) = module.io_lengths();
    let (input_len, output_len) = (input_len as usize, output_len as usize);
    let mut outputs = vec![0u8; output_len];
    for assignment in &args.outputs {
        let Some((name, value)) = assignment.split_once('=') else {
            return fail(format!("`{assignment}` is not NAME=VALUE"));
        };
        let index = (0..output_len / 2)
            .find(|n| word_name(*n, pkw_pzd, false) == name.to_ascii_lowercase());
        let (Some(index), Some(value)) = (index, number(value)) else {
            return fail(format!(
                "`{assignment}`: no output word `{name}` or not a 16-bit value"
            ));
        };
        outputs[2 * index..2 * index + 2].copy_from_slice(&value.to_be_bytes());
    }
    let port = match OpenOptions::new().read(true).write(true).open(&args.tty) {
        Ok(port) => port,
        Err(e) => return fail(format!("cannot open {}: {e}", args.tty)),
    };
    let baud = Baudrate::B19200;
    let mut phy = match TtyPhy::new(port, baud) {
        Ok(phy) => phy,
        Err(e) => return fail(format!("{}: {e}", args.tty)),
    };
    let max_tsdr = gsd
        .baud_rates
        .iter()
        .find(|b| b.rate.bits_per_second() == 19_200)
        .and_then(|b| b.max_tsdr)
        .unwrap_or(60);
    let user = gsd.default_user_prm_data();
    let mut inputs = vec![0u8; input_len];
    let mut out_buffer = vec![0u8; output_len];
    let mut master = dp::DpMaster::new(vec![]);
    let handle = master.add(dp::Peripheral::new(
        args.address,
        dp::PeripheralOptions {
            ident_number: ident,
            max_tsdr: u16::try_from(max_tsdr).unwrap_or(u16::MAX),
            user_parameters: Some(&user),
            config: Some(&module.config),
            ..Default::default()
        },
        &mut inputs[..],
        &mut out_buffer[..],
    ));
    let mut station = fdl::FdlActiveStation::new(
        fdl::ParametersBuilder::new(args.master, baud)
            .slot_bits(4000)
            .max_retry_limit(3)
            .watchdog_timeout(profirust::time::Duration::from_secs(1))
            .build_verified(&master),
    );
    station.set_online();
    master.enter_operate();
    let start = Instant::now();
    let mut exchanging_since = None;
    while start.elapsed() < Duration::from_secs(10 + args.seconds) {
        station.poll(profirust::time::Instant::now(), &mut phy, &mut master);
        let peripheral = master.get_mut(handle);
        if peripheral.is_running() {
            peripheral.pi_q_mut().copy_from_slice(&outputs);
            let since = *exchanging_since.get_or_insert_with(Instant::now);
            if since.elapsed() >= Duration::from_secs(args.seconds) {
                print_inputs(peripheral.pi_i(), pkw_pzd);
                return ExitCode::SUCCESS;
            }
        }
        std::thread::sleep(Duration::from_micros(500));
    }
    eprintln!("station {}: no data exchange", args.address);
    ExitCode::from(1)
}

fn print_inputs(inputs: &[u8], pkw_pzd: bool) {
    for (n, pair) in inputs.chunks_exact(2).enumerate() {
        let word = u16::from_be_bytes([pair[0], pair[1]]);
        println!("{} = {word} (0x{word:04X})", word_name(n, pkw_pzd, true));
    }
    if let (true, Ok(bytes)) = (pkw_pzd, <&[u8; 32]>::try_from(inputs)) {
        match InputImage::parse(bytes, ByteOrder::BigEndian) {
            Ok(image) => {
                println!("pkw: {:?}", image.pkw);
                println!(
                    "sw: {:?}, ready {}, {:?}",
                    image.status.state(WordLayout::ByByte),
                    image.status.ready(),
                    image.status.run_stop_mode()
                );
            }
            Err(e) => println!("pkw: {e:?}"),
        }
    }
}
