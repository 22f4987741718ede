//! `edsgen simulate --enip ADDR[,ADDR...] --card goodrive350-enip` and `edsgen simulate --enip
//! ADDR[,ADDR...] FILE.eds`: an EtherNet/IP adapter on each `ADDR` (an IPv4 address of the host,
//! optionally `:PORT`, 44818 by default; class-1 I/O on UDP 2222 of that address; with several,
//! each line starts with its address), serving the Goodrive350 card with its drive or any ODVA
//! EDS's identity and assemblies (filled with their parameters' defaults) and its Parameter
//! object. Runs until SIGINT, SIGTERM or SIGHUP, then says `stopped:` with what it
//! served and exits 0. Exit 2 for bad usage, a file that is not an ODVA EDS, or an address it cannot
//! bind.

use std::net::{IpAddr, SocketAddr};
use std::path::Path;
use std::process::ExitCode;

use edsgen_model::lint::Policy;
use edsgen_model::model::Cip;
use edsgen_runtime::Instant;
use edsgen_sim::enip::{device, driver, Adapter, EnipApplication};

/// The card name `--card` takes with `--enip`.
pub const CARD: &str = "goodrive350-enip";

fn fail(message: String) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(2)
}

/// `ADDR` as a socket address: `IP` or `IP:PORT`.
fn address(text: &str) -> Option<SocketAddr> {
    text.parse::<SocketAddr>().ok().or_else(|| {
        text.parse::<IpAddr>()
            .ok()
            .map(|ip| SocketAddr::new(ip, 44818))
    })
}

/// What each adapter serves.
enum Device {
    /// The Goodrive350 card with its drive.
    Card,
    /// An ODVA EDS file's device (its name for the first line).
    Eds(Box<Cip>, String),
}

/// Runs an adapter on each address of `addrs` (comma-separated), each serving the device of
/// the arguments, until a signal.
pub fn run(addrs: &str, files: &[String], cards: &[String], allow: &Policy) -> ExitCode {
    let mut addresses = Vec::new();
    for addr in addrs.split(',') {
        let Some(address) = address(addr.trim()) else {
            return fail(format!("`{addr}` is not an address: write IP or IP:PORT"));
        };
        if !address.is_ipv4() {
            return fail("EtherNet/IP needs an IPv4 address".to_owned());
        }
        if addresses.contains(&address) {
            return fail(format!("{address} is given twice"));
        }
        addresses.push(address);
    }
    let device = match (files, cards) {
        ([], [card]) if card == CARD => Device::Card,
        ([], [other]) => return fail(format!("--enip serves the card `{CARD}`, not `{other}`")),
        ([file], []) => {
            let path = Path::new(file);
            let loaded = crate::cmd::simulate::load_servable(path, None, allow);
            match loaded.and_then(|loaded| super::cip_of(path, &loaded.device)) {
                Ok(cip) => Device::Eds(Box::new(cip), file.clone()),
                Err(message) => return fail(message),
            }
        }
        _ => return fail("--enip serves one ODVA EDS file or --card goodrive350-enip".to_owned()),
    };
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    let several = addresses.len() > 1;
    let mut bound = Vec::new();
    for &address in &addresses {
        let log = move |line: String| log_line(several, address, &line);
        match driver::bind(address, log) {
            Ok(sockets) => bound.push((address, sockets)),
            Err(err) => {
                return fail(format!(
                    "cannot serve on {address}: {err}{}",
                    super::socket_hint(&err)
                ))
            }
        }
    }
    std::thread::scope(|scope| {
        for (address, sockets) in bound {
            let device = &device;
            scope.spawn(move || {
                let ip = match address.ip() {
                    IpAddr::V4(v4) => v4.octets(),
                    IpAddr::V6(_) => return,
                };
                let now = Instant::from_micros(0);
                match device {
                    Device::Card => {
                        let what = format!("card {CARD}");
                        let adapter = device::goodrive350(ip, now);
                        serve(several, address, sockets, adapter, &what);
                    }
                    Device::Eds(cip, file) => {
                        let what = format!("`{file}`");
                        serve(several, address, sockets, device::from_cip(cip, ip), &what);
                    }
                }
            });
        }
    });
    ExitCode::SUCCESS
}

/// A line of the adapter at `address`, with the address first when there are several.
fn log_line(several: bool, address: SocketAddr, line: &str) {
    if several {
        eprintln!("{address}: {line}");
    } else {
        eprintln!("{line}");
    }
}

/// Serves `adapter` (`what` it serves, for the first line) on its bound `sockets` until a
/// signal.
fn serve<A: EnipApplication>(
    several: bool,
    address: SocketAddr,
    sockets: driver::Sockets,
    adapter: Adapter<A>,
    what: &str,
) {
    eprintln!(
        "serving {what} on {address} (EtherNet/IP; class-1 I/O on UDP {})",
        driver::IO_PORT
    );
    let log = |line: String| log_line(several, address, &line);
    let served = driver::run(sockets, adapter, crate::cmd::signals::flag(), log);
    log_line(
        several,
        address,
        &format!(
            "stopped: {} clients served, {} connections opened",
            served.clients, served.connections
        ),
    );
}
