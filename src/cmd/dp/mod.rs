//! `edsgen dp`: a PROFIBUS-DP master at the bench, through profirust (the Rust DP master) on a
//! serial line ([`TtyPhy`]).
//!
//! - `edsgen dp scan TTY [--master N]`: every address 0 to 125 asked once (FDL status, then
//!   Slave_Diag of those that answer) with a per-address timeout from the baud rate and the
//!   slowest Tsdr, so the sweep's time is known and said first; one line per station that
//!   answered: address, Ident_Number, the master it is locked to. Exit 0 when at least one
//!   answered, 1 when none did, 2 for bad usage or a line that cannot be opened.
//! - `edsgen dp io TTY --gsd FILE --address N [--module [SLOT=]NAME]... [SETTING...] [--cycles N]
//!   [--no-watchdog]`: a session. The station's Slave_Diag first (a missing station or an
//!   Ident_Number mismatch is named at once), then it is parameterised and configured from its
//!   GSD (Ident_Number, default User_Prm_Data, Chk_Cfg with every module of its configuration in
//!   slot order: `--module`, else the overlay's `[modules]`, else the GSD's first module; a
//!   refusal is named from its diagnosis) and exchanges data until Ctrl-C or `--cycles`, the
//!   inputs printed whenever they change. Settings (`NAME=VALUE`, and `reset`, `run`, `stop` on
//!   a PKW/PZD module: CW commands 7, 1, 5) come as arguments and as lines on standard input.
//!   Names ([`fields`]) are the words `w0`, `w1`, ... of a word module, the bytes `b0`, `b1`,
//!   ... of a byte module, prefixed `slotN.` when the configuration has several modules; a module the
//!   overlay marks as PKW/PZD (`[pkw_pzd]`) has `pkw1`–`pkw4`, `cw`/`sw`, `pzd2`–`pzd12`, and its
//!   PKW response and status word are put in words. Exit 0 after the session, 1 if the station
//!   is missing, refuses or stops answering, 2 for bad usage.

use std::fs::OpenOptions;
use std::process::ExitCode;
use std::time::Duration;

use edsgen_host::dp_line::{self, TtyPhy};
use profirust::Baudrate;

use super::fail;

mod fields;
mod io;
pub mod simulate;

/// The arguments of `edsgen dp`.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Ask every address 0 to 125 on a serial line (in the time it states first).
    Scan {
        /// The serial line (set to 19200 baud, 8E1, raw, for an RS-485 adapter).
        tty: String,
        /// This master's station address.
        #[arg(long, value_name = "N", default_value_t = 1,
              value_parser = clap::value_parser!(u8).range(0..=125))]
        master: u8,
    },
    /// A session with one slave from its GSD: settings by name (arguments and standard input),
    /// the inputs printed as they change, until Ctrl-C or --cycles.
    Io(io::Args),
}

/// Runs `edsgen dp`.
pub fn run(command: Command) -> ExitCode {
    match command {
        Command::Scan { tty, master } => scan(&tty, master),
        Command::Io(args) => io::run(&args),
    }
}

/// The bench's baud rate.
const BAUD: u32 = 19_200;
/// The slowest station's delay before it answers (max Tsdr), in bit times: DP's 60 at 19.2 kbit/s.
const MAX_TSDR_BITS: u32 = 60;
/// What the operating system adds to a request and its answer (scheduling, a USB adapter's
/// latency, a pseudo-terminal's relay).
const HOST_LATENCY: Duration = Duration::from_millis(20);

/// How long `dp scan` waits for one address: a 6-byte request and a 6-byte answer (11 bits a
/// byte) and max Tsdr at the baud rate, plus the host's latency.
fn per_address_timeout(baud: u32) -> Duration {
    let bits = u64::from(2 * 6 * 11 + MAX_TSDR_BITS);
    Duration::from_micros(bits * 1_000_000 / u64::from(baud)) + HOST_LATENCY
}

fn scan(tty: &str, master: u8) -> ExitCode {
    use edsgen_runtime::dp::fdl::request as function;
    let port = match OpenOptions::new().read(true).write(true).open(tty) {
        Ok(port) => port,
        Err(e) => return fail(format!("cannot open {tty}: {e}")),
    };
    let mut phy = match TtyPhy::new(port, Baudrate::B19200) {
        Ok(phy) => phy,
        Err(e) => return fail(format!("{tty}: {e}")),
    };
    let timeout = per_address_timeout(BAUD);
    let addresses: Vec<u8> = (0..=125).filter(|&a| a != master).collect();
    let total = timeout * addresses.len() as u32;
    eprintln!(
        "scanning addresses 0 to 125 on {tty} at {BAUD} baud: {} ms an address, {:.1} s",
        timeout.as_millis(),
        total.as_secs_f64()
    );
    let mut found = 0;
    for address in addresses {
        let status = dp_line::request(master, address, function::FDL_STATUS, None);
        if phy.request(&status, address, master, timeout).is_none() {
            continue;
        }
        found += 1;
        match phy.slave_diag(master, address, timeout) {
            Some(d) => {
                let locked = match d[3] {
                    255 => "no master".to_owned(),
                    m => format!("master {m}"),
                };
                let ident = u16::from_be_bytes([d[4], d[5]]);
                println!("station {address}: Ident_Number {ident:04X}h, {locked}");
            }
            None => println!("station {address}: answers FDL status, not Slave_Diag"),
        }
    }
    if found == 0 {
        eprintln!("no DP slave answered on {tty}");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}
