//! `edsgen dp io`: one slave brought to data exchange by profirust's DP master from its GSD, as
//! a session (see the parent module): settings from the arguments and from lines on standard
//! input, the inputs printed whenever they change, until Ctrl-C or `--cycles`. Before the
//! master starts, the slave's own diagnosis (Slave_Diag) names a missing station or an
//! Ident_Number mismatch at once; a refused configuration or parameterisation is named from the
//! diagnosis profirust reads; a station that stops answering is said so (and again when it
//! answers), the session going on.

use std::fs::OpenOptions;
use std::io::BufRead;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use edsgen_runtime::pkw_pzd::{ByteOrder, InputImage, PkwResponse, RunState, WordLayout};
use profirust::dp::{DiagnosticFlags, PeripheralEvent};
use profirust::{dp, fdl, Baudrate};

use edsgen_model::model::modules::{choose_dp, parse_choices};

use super::super::fail;
use super::fields::{changed, Layout};
use edsgen_host::dp_line::TtyPhy;

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
    /// Stop after N data exchanges (default: until Ctrl-C).
    #[arg(long, value_name = "N")]
    cycles: Option<u64>,
    /// Parameterise the slave without its watchdog (it then keeps its outputs when this
    /// master stops).
    #[arg(long)]
    no_watchdog: bool,
    /// The module in a slot of a modular slave (`SLOT=NAME`, or `NAME` for the slot after the
    /// previous one; repeatable, docs/modules.md): Chk_Cfg sends them all in slot order. Default:
    /// the overlay's `[modules]`, else the GSD's first module.
    #[arg(long = "module", value_name = "[SLOT=]NAME")]
    modules: Vec<String>,
    /// Outputs to set: NAME=VALUE (decimal or 0x hex), or `reset`, `run`, `stop` on a PKW/PZD
    /// module; more come as lines on standard input.
    #[arg(value_name = "SETTING")]
    settings: Vec<String>,
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
    let configuration = if args.modules.is_empty() {
        gsd.configuration()
    } else {
        let chosen = parse_choices(&args.modules)
            .and_then(|choices| choose_dp(gsd, &choices).map_err(|problems| problems.join("\n  ")));
        match chosen {
            Ok(configuration) => configuration,
            Err(message) => return fail(format!("{}: --module: {message}", args.gsd.display())),
        }
    };
    if configuration.slots.is_empty() {
        return fail(format!("{}: no module", args.gsd.display()));
    }
    let layout = Layout::new(gsd, &configuration);
    let config = configuration.config_bytes(gsd);
    let (input_len, output_len) = configuration.io_lengths(gsd);
    let (input_len, output_len) = (input_len as usize, output_len as usize);
    let mut outputs = vec![0u8; output_len];
    for setting in &args.settings {
        if let Err(message) = layout.apply(setting, &mut outputs) {
            return fail(message);
        }
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
    if let Err(message) = check_station(&mut phy, args, ident) {
        eprintln!("{message}");
        return ExitCode::from(1);
    }
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    let max_tsdr = gsd
        .baud_rates
        .iter()
        .find(|b| b.rate.bits_per_second() == 19_200)
        .and_then(|b| b.max_tsdr)
        .unwrap_or(60);
    // The slave's own parameters, then each module's in slot order (Ext_Module_Prm_Data_Len).
    let user = configuration.user_prm_data(gsd);
    let mut inputs = vec![0u8; input_len];
    let mut out_buffer = outputs.clone();
    let mut master = dp::DpMaster::new(vec![]);
    let handle = master.add(dp::Peripheral::new(
        args.address,
        dp::PeripheralOptions {
            ident_number: ident,
            max_tsdr: u16::try_from(max_tsdr).unwrap_or(u16::MAX),
            user_parameters: Some(&user),
            config: Some(&config),
            ..Default::default()
        },
        &mut inputs[..],
        &mut out_buffer[..],
    ));
    let mut parameters = fdl::ParametersBuilder::new(args.master, baud);
    parameters.slot_bits(4000).max_retry_limit(3);
    if !args.no_watchdog {
        parameters.watchdog_timeout(profirust::time::Duration::from_secs(1));
    }
    let mut station = fdl::FdlActiveStation::new(parameters.build_verified(&master));
    station.set_online();
    master.enter_operate();
    let lines = stdin_lines();
    let start = Instant::now();
    let mut shown: Option<Vec<u8>> = None;
    let mut cycles = 0u64;
    let mut silent = false;
    while !crate::cmd::signals::requested() {
        station.poll(profirust::time::Instant::now(), &mut phy, &mut master);
        let events = master.take_last_events();
        let peripheral = master.get_mut(handle);
        match events.peripheral.map(|(_, event)| event) {
            Some(PeripheralEvent::ConfigError | PeripheralEvent::ParameterError) => {
                eprintln!("{}", refused(args.address, peripheral.last_diagnostics()));
                return ExitCode::from(1);
            }
            Some(PeripheralEvent::Offline) if shown.is_some() && !silent => {
                // profirust takes it up again when it answers.
                eprintln!("station {}: stopped answering", args.address);
                silent = true;
            }
            Some(PeripheralEvent::DataExchanged) => {
                if std::mem::take(&mut silent) {
                    eprintln!("station {}: answers again", args.address);
                }
                cycles += 1;
                let now = peripheral.pi_i().to_vec();
                print_changes(shown.as_deref(), &now, &layout);
                shown = Some(now);
                // One line of standard input a cycle, so that each setting reaches the slave
                // (a reset, then a run command).
                if let Ok(line) = lines.try_recv() {
                    if let Err(message) = layout.apply(&line, &mut outputs) {
                        eprintln!("{message}");
                    }
                }
            }
            _ => {}
        }
        if peripheral.is_running() {
            peripheral.pi_q_mut().copy_from_slice(&outputs);
        }
        if args.cycles.is_some_and(|n| cycles >= n) {
            return ExitCode::SUCCESS;
        }
        if shown.is_none() && start.elapsed() > Duration::from_secs(10) {
            eprintln!("station {}: no data exchange within 10 s", args.address);
            return ExitCode::from(1);
        }
        std::thread::sleep(Duration::from_micros(500));
    }
    ExitCode::SUCCESS
}

/// Lines of standard input, as they come (none when it is closed or not given).
fn stdin_lines() -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::stdin().lock().lines() {
            let Ok(line) = line else { return };
            if !line.trim().is_empty() && tx.send(line).is_err() {
                return;
            }
        }
    });
    rx
}

/// The station's own diagnosis before the master starts: it answers, and with the GSD's
/// Ident_Number.
fn check_station(phy: &mut TtyPhy, args: &Args, ident: u16) -> Result<(), String> {
    let address = args.address;
    // Five tries of 100 ms: at once for a person, patient with a loaded host.
    let timeout = Duration::from_millis(100);
    let diag = (0..5).find_map(|_| phy.slave_diag(args.master, address, timeout));
    let Some(diag) = diag else {
        return Err(format!(
            "station {address} does not answer on {} (station missing)",
            args.tty
        ));
    };
    let theirs = u16::from_be_bytes([diag[4], diag[5]]);
    if theirs != ident {
        return Err(format!(
            "station {address} is Ident_Number {theirs:04X}h, the GSD file's is {ident:04X}h \
             (Ident_Number mismatch)"
        ));
    }
    Ok(())
}

/// Why the station refused to enter data exchange, from its diagnosis.
fn refused(address: u8, diag: Option<dp::PeripheralDiagnostics<'_>>) -> String {
    let flags = diag.map(|d| d.flags).unwrap_or(DiagnosticFlags::empty());
    let why = if flags.contains(DiagnosticFlags::CONFIGURATION_FAULT) {
        "configuration fault: it refused the Chk_Cfg bytes of the modules chosen"
    } else if flags.contains(DiagnosticFlags::PARAMETER_FAULT) {
        "parameter fault: it refused Set_Prm (Ident_Number or User_Prm_Data)"
    } else if flags.contains(DiagnosticFlags::NOT_SUPPORTED) {
        "it does not support a function the parameters ask for"
    } else {
        "it refused the parameters or the configuration"
    };
    format!("station {address}: {why}")
}

/// Prints the fields of `now` that differ from `before` (all of them the first time), then, on
/// a PKW/PZD module, the PKW response and the status word in words when they changed.
fn print_changes(before: Option<&[u8]>, now: &[u8], layout: &Layout) {
    for line in layout.changes(before, now) {
        println!("{line}");
    }
    let Some((at, _)) = layout.pkw_pzd else {
        return;
    };
    let Some(Ok(bytes)) = now.get(at..at + 32).map(<&[u8; 32]>::try_from) else {
        return;
    };
    let (pkw, sw) = (
        changed(before, now, at..at + 8),
        changed(before, now, at + 8..at + 10),
    );
    match InputImage::parse(bytes, ByteOrder::BigEndian) {
        Ok(image) => {
            if pkw {
                println!("pkw: {}", pkw_text(image.pkw));
            }
            if sw {
                println!("sw: {}", sw_text(&image));
            }
        }
        Err(_) if pkw => println!("pkw: not a PKW response"),
        Err(_) => {}
    }
}

fn pkw_text(pkw: PkwResponse) -> String {
    match pkw {
        PkwResponse::None => "no response".to_owned(),
        PkwResponse::Word { address, value } => {
            format!("parameter {} = {value}", parameter_name(address))
        }
        PkwResponse::DoubleWord { address, value } => {
            format!("parameter {} = {value}", parameter_name(address))
        }
        PkwResponse::Refused { address, error } | PkwResponse::RefusedWrite { address, error } => {
            format!(
                "parameter {} refused: error {} ({})",
                parameter_name(address),
                error.code(),
                error.text()
            )
        }
    }
}

/// A parameter address as the manual writes it: P00.10 for 000Ah (group, number).
fn parameter_name(address: u16) -> String {
    format!("P{:02}.{:02}", address >> 8, address & 0xFF)
}

fn sw_text(image: &InputImage) -> String {
    let state = match image.status.state(WordLayout::ByByte) {
        Some(RunState::Forward) => "running forward",
        Some(RunState::Reverse) => "running reverse",
        Some(RunState::Stopped) => "stopped",
        Some(RunState::Fault) => "fault",
        Some(RunState::PowerOff) => "power off (POFF)",
        Some(RunState::PreExcitation) => "pre-excitation",
        None => "state unknown",
    };
    let ready = if image.status.ready() {
        "ready"
    } else {
        "not ready"
    };
    format!("{state}, {ready}")
}
