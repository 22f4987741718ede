//! `edsgen simulate --profinet IFACE (FILE.xml | --card goodrive350-pn)`: a PROFINET IO device
//! from a GSDML on a network interface (root, or `CAP_NET_RAW`). It says Hello, then answers
//! DCP (identify, get, set name of station and IP, signal) as the GSDML's default access point,
//! printing what a controller sets, until it is stopped.

use std::path::Path;
use std::process::ExitCode;

use edsgen_codegen::{read, validate};
use edsgen_sim::profinet::dcp::{Dcp, DcpEvent};
use edsgen_sim::profinet::{driver, station};

use super::fail;

/// The bundled PROFINET card's GSDML, in the binary so that `--card` works anywhere.
const GOODRIVE350_PN: &[u8] = include_bytes!("../../eds/goodrive350-pn.xml");

/// Runs the device on `iface`; exit 2 for bad usage, a file that is not a readable GSDML, or an
/// interface that cannot be opened.
pub fn run(iface: &str, files: &[String], cards: &[String]) -> ExitCode {
    let (name, bytes) = match (files, cards) {
        ([file], []) => match std::fs::read(file) {
            Ok(bytes) => (file.clone(), bytes),
            Err(e) => return fail(format!("cannot read `{file}`: {e}")),
        },
        ([], [card]) if card == "goodrive350-pn" => {
            ("eds/goodrive350-pn.xml".to_owned(), GOODRIVE350_PN.to_vec())
        }
        ([], [card]) => {
            return fail(format!(
                "no PROFINET card `{card}`: the bundled PROFINET card is goodrive350-pn"
            ))
        }
        _ => return fail("--profinet takes one GSDML FILE or one --card"),
    };
    let read = read::read_bytes(Path::new(&name), &bytes);
    let errors = read
        .diagnostics
        .iter()
        .chain(&validate::validate(&read.device))
        .filter(|d| d.severity == edsgen_codegen::diag::Severity::Error)
        .count();
    let Some(pn) = read.device.profinet.as_ref().filter(|_| errors == 0) else {
        return fail(format!(
            "`{name}` is not a GSDML file without errors (run `edsgen validate {name}`)"
        ));
    };
    let mut socket = match driver::RawSocket::open(iface, std::time::Duration::from_millis(200)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}` for PROFINET: {e}")),
    };
    let station = station::from_gsdml(pn, socket.mac());
    let mac: Vec<String> = station.mac.iter().map(|b| format!("{b:02x}")).collect();
    println!(
        "PROFINET device `{}` (VendorID {:#06x}, DeviceID {:#06x}) on {iface}, MAC {}",
        station.name_of_station,
        station.vendor_id,
        station.device_id,
        mac.join(":")
    );
    let mut dcp = Dcp::new(station);
    let served = driver::serve_dcp(&mut socket, &mut dcp, None, |event| {
        match event {
            DcpEvent::NameSet(name) => println!("name of station set to `{name}`"),
            DcpEvent::IpSet([ip, mask, gw]) => println!(
                "IP set to {}.{}.{}.{} mask {}.{}.{}.{} gateway {}.{}.{}.{}",
                ip[0],
                ip[1],
                ip[2],
                ip[3],
                mask[0],
                mask[1],
                mask[2],
                mask[3],
                gw[0],
                gw[1],
                gw[2],
                gw[3]
            ),
            DcpEvent::Signal => println!("signal: flashing the LED"),
            DcpEvent::ResetToFactory => println!("reset to factory"),
        }
        use std::io::Write;
        let _ = std::io::stdout().flush();
    });
    match served {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(format!("PROFINET on `{iface}`: {e}")),
    }
}
