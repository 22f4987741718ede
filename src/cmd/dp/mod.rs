//! `edsgen dp`: a PROFIBUS-DP master at the bench, through profirust (the Rust DP master) on a
//! serial line ([`phy::TtyPhy`]).
//!
//! - `edsgen dp scan TTY [--master N] [--seconds S]`: the slaves that answer (profirust's
//!   `DpScanner`: FDL status, then Slave_Diag), one line each: address, Ident_Number, the master
//!   it is locked to. Exit 0 when at least one answered, 1 when none did, 2 for bad usage or a
//!   line that cannot be opened.
//! - `edsgen dp io TTY --gsd FILE --address N [NAME=VALUE...]`: parameterise and configure the
//!   slave from its GSD (Ident_Number, default User_Prm_Data, its first module's Chk_Cfg bytes),
//!   exchange data for `--seconds` with the outputs set by name, then print the inputs by name.
//!   Names are the 16-bit words `w0`, `w1`, ... of the images; a module the overlay marks as
//!   PKW/PZD (`[pkw_pzd]`) has `pkw1`–`pkw4`, `cw`/`sw`, `pzd2`–`pzd12`, and its PKW response and
//!   status word are decoded. Exit 0 after the exchange, 1 if data exchange was not reached, 2 for
//!   bad usage.

use std::fs::OpenOptions;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use profirust::dp::scan::{DpScanEvent, DpScanner};
use profirust::{fdl, Baudrate};

use super::fail;

mod io;
pub mod phy;
pub mod simulate;

/// The arguments of `edsgen dp`.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// List the DP slaves that answer on a serial line.
    Scan {
        /// The serial line (set to 19200 baud, 8E1, raw, for an RS-485 adapter).
        tty: String,
        /// This master's station address.
        #[arg(long, value_name = "N", default_value_t = 1,
              value_parser = clap::value_parser!(u8).range(0..=125))]
        master: u8,
        /// How long to listen.
        #[arg(long, default_value_t = 3)]
        seconds: u64,
    },
    /// Bring a slave to data exchange from its GSD, set outputs by name, print its inputs.
    Io(io::Args),
}

/// Runs `edsgen dp`.
pub fn run(command: Command) -> ExitCode {
    match command {
        Command::Scan {
            tty,
            master,
            seconds,
        } => scan(&tty, master, Duration::from_secs(seconds)),
        Command::Io(args) => io::run(&args),
    }
}

fn scan(tty: &str, master: u8, time: Duration) -> ExitCode {
    let port = match OpenOptions::new().read(true).write(true).open(tty) {
        Ok(port) => port,
        Err(e) => return fail(format!("cannot open {tty}: {e}")),
    };
    let baud = Baudrate::B19200;
    let mut phy = match phy::TtyPhy::new(port, baud) {
        Ok(phy) => phy,
        Err(e) => return fail(format!("{tty}: {e}")),
    };
    let mut scanner = DpScanner::new();
    let mut station = fdl::FdlActiveStation::new(
        fdl::ParametersBuilder::new(master, baud)
            .slot_bits(4000)
            .max_retry_limit(3)
            .gap_wait_rotations(1)
            .build(),
    );
    station.set_online();
    let start = Instant::now();
    let mut found = 0;
    while start.elapsed() < time {
        station.poll(profirust::time::Instant::now(), &mut phy, &mut scanner);
        if let Some(DpScanEvent::PeripheralFound(desc)) = scanner.take_last_event() {
            found += 1;
            let locked = desc
                .master_address
                .map_or("no master".to_owned(), |m| format!("master {m}"));
            println!(
                "station {}: Ident_Number {:04X}h, {locked}",
                desc.address, desc.ident
            );
        }
        std::thread::sleep(Duration::from_micros(500));
    }
    if found == 0 {
        eprintln!("no DP slave answered on {tty} within {time:?}");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}
