//! `edsgen simulate --enip ADDR --card goodrive350-enip` and `edsgen simulate --enip ADDR
//! FILE.eds`: an EtherNet/IP adapter on `ADDR` (an IPv4 address, optionally `:PORT`, 44818 by
//! default; class-1 I/O on UDP 2222 of that address), serving the Goodrive350 card with its drive
//! or any ODVA EDS's identity and assemblies (filled with their parameters' defaults) and its
//! Parameter object. Runs until SIGINT, SIGTERM or SIGHUP, then says `stopped:` with what it
//! served and exits 0. Exit 2 for bad usage, a file that is not an ODVA EDS, or an address it cannot
//! bind.

use std::net::{IpAddr, SocketAddr};
use std::path::Path;
use std::process::ExitCode;

use edsgen_codegen::lint::Policy;
use edsgen_runtime::Instant;
use edsgen_sim::enip::{device, driver};

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

/// Runs the adapter.
pub fn run(addr: &str, files: &[String], cards: &[String], allow: &Policy) -> ExitCode {
    let Some(address) = address(addr) else {
        return fail(format!("`{addr}` is not an address: write IP or IP:PORT"));
    };
    let ip = match address.ip() {
        IpAddr::V4(v4) => v4.octets(),
        IpAddr::V6(_) => return fail("EtherNet/IP needs an IPv4 address".to_owned()),
    };
    let (adapter, card, what) = match (files, cards) {
        ([], [card]) if card == CARD => {
            let (adapter, card) = device::goodrive350(ip, Instant::from_micros(0));
            (adapter, Some(card), format!("card {CARD}"))
        }
        ([], [other]) => {
            return fail(format!("--enip serves the card `{CARD}`, not `{other}`"));
        }
        ([file], []) => {
            let path = Path::new(file);
            let loaded = crate::cmd::simulate::load_servable(path, None, allow);
            let cip = match loaded.and_then(|loaded| super::cip_of(path, &loaded.device)) {
                Ok(cip) => cip,
                Err(message) => return fail(message),
            };
            (device::from_cip(&cip, ip), None, format!("`{file}`"))
        }
        _ => return fail("--enip serves one ODVA EDS file or --card goodrive350-enip".to_owned()),
    };
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    let log = |line: String| eprintln!("{line}");
    let sockets = match driver::bind(address, log) {
        Ok(sockets) => sockets,
        Err(err) => {
            return fail(format!(
                "cannot serve on {address}: {err}{}",
                super::socket_hint(&err)
            ))
        }
    };
    eprintln!(
        "serving {what} on {address} (EtherNet/IP; class-1 I/O on UDP {})",
        driver::IO_PORT
    );
    let served = driver::run(sockets, adapter, card, crate::cmd::signals::flag(), log);
    eprintln!(
        "stopped: {} clients served, {} connections opened",
        served.clients, served.connections
    );
    ExitCode::SUCCESS
}
