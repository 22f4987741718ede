//! `edsgen simulate --profinet IFACE (FILE.xml | --card goodrive350-pn) [--ip ADDR[/PREFIX]]`: a
//! PROFINET IO device from a GSDML on a network interface (root, or `CAP_NET_RAW`). It says
//! Hello, then answers DCP (identify, get, set name of station and IP, signal) as the GSDML's
//! default access point, serves connection management on UDP 34964 (Connect, Read, Write,
//! PrmEnd, ApplicationReady, Release) and the cyclic RT_CLASS_1 exchange of the AR, with the
//! Goodrive350's drive behind the card, whose faults are Diagnosis alarms on the AR's AlarmCR
//! (`--faults-on-stdin`: `fault` and `clear` lines on standard input switch one); it prints what
//! a controller sets, each step of an AR and each alarm acknowledged, until SIGINT, SIGTERM or
//! SIGHUP, then says `stopped:` (on stderr) with the number of ARs it served.

use std::io::BufRead;
use std::ops::ControlFlow;
use std::path::Path;
use std::process::ExitCode;
use std::sync::mpsc;

use edsgen_model::lint::Policy;
use edsgen_model::load::{self, LoadError};
use edsgen_model::read;
use edsgen_sim::drives::pkw_pzd::{Bus, PkwPzdDrive};
use edsgen_sim::profinet::alarm::AlarmEvent;
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::ar::ArEvent;
use edsgen_sim::profinet::dcp::DcpEvent;
use edsgen_sim::profinet::device::{Device, DeviceEvent};
use edsgen_sim::profinet::{driver, iface, station};

use crate::cmd::fail;

/// The bundled PROFINET card's GSDML, in the binary so that `--card` works anywhere.
const GOODRIVE350_PN: &[u8] = include_bytes!("../../../eds/goodrive350-pn.xml");

/// Runs the device on `iface`; exit 2 for bad usage, a file that is not a readable GSDML, or an
/// interface that cannot be opened.
/// With `faults_on_stdin` (the card only), its drive's faults are switched by `fault` and
/// `clear` lines on standard input.
pub fn run(
    iface: &str,
    files: &[String],
    cards: &[String],
    ip: Option<&str>,
    faults_on_stdin: bool,
    allow: &Policy,
) -> ExitCode {
    let (ip, source) = match address(iface, ip) {
        Ok(ip) => ip,
        Err(e) => return fail(e),
    };
    let (files, file_name) = match station_name(files) {
        Ok(split) => split,
        Err(e) => return fail(e),
    };
    let (cards, card_name) = match station_name(cards) {
        Ok(split) => split,
        Err(e) => return fail(e),
    };
    let (files, cards) = (files.as_slice(), cards.as_slice());
    let station_name = file_name.or(card_name);
    let card = cards.first().is_some_and(|c| c == "goodrive350-pn");
    if faults_on_stdin && !card {
        return fail("--faults-on-stdin switches the faults of --card goodrive350-pn's drive");
    }
    let (name, read) = match (files, cards) {
        ([file], []) => match load::load(Path::new(file), None) {
            Ok(loaded) => (file.clone(), loaded),
            Err(LoadError::Read(read::ReadError::Io(_, e))) => {
                return fail(format!("cannot read `{file}`: {e}"))
            }
            Err(e) => return fail(e),
        },
        ([], [card]) if card == "goodrive350-pn" => {
            let name = "eds/goodrive350-pn.xml";
            let read = load::load_bundled(
                Path::new(name),
                GOODRIVE350_PN,
                Some(include_str!("../../../eds/goodrive350-pn.toml")),
            );
            (name.to_owned(), read)
        }
        ([], [card]) => {
            return fail(format!(
                "no PROFINET card `{card}`: the bundled PROFINET card is goodrive350-pn"
            ))
        }
        _ => return fail("--profinet takes one GSDML FILE or one --card"),
    };
    if let Err(message) = crate::cmd::simulate::servable(&read, &name, allow) {
        return fail(message);
    }
    let Some(pn) = read.device.profinet() else {
        return fail(format!("`{name}` is not a GSDML file"));
    };
    // Before the first line: a signal that comes once the device is announced stops it cleanly.
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    let mut socket = match driver::RawSocket::open(iface, std::time::Duration::from_millis(1)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}` for PROFINET: {e}")),
    };
    let rpc = match driver::RpcSocket::open(iface) {
        Ok(rpc) => rpc,
        Err(e) => return fail(format!("cannot bind UDP 34964 on `{iface}`: {e}")),
    };
    let mut station = station::from_gsdml(pn, socket.mac());
    if let Some(name) = station_name {
        station.name_of_station = name;
    }
    if let Some(ip) = ip {
        station.ip = ip;
    }
    let mac: Vec<String> = station.mac.iter().map(|b| format!("{b:02x}")).collect();
    println!(
        "PROFINET device `{}` (VendorID {:#06x}, DeviceID {:#06x}) on {iface}, MAC {}",
        station.name_of_station,
        station.vendor_id,
        station.device_id,
        mac.join(":")
    );
    match ip {
        Some([a, m, _]) => println!(
            "RPC on UDP 34964 at {}.{}.{}.{} mask {}.{}.{}.{}{source}",
            a[0], a[1], a[2], a[3], m[0], m[1], m[2], m[3]
        ),
        None => println!(
            "no IP yet ({iface} has no IPv4 address; --ip ADDR[/PREFIX], or a DCP Set): RPC on UDP 34964 answers once {iface} has the address"
        ),
    }
    let config = DeviceConfig::from_gsdml(pn);
    let drive = card.then(|| PkwPzdDrive::bus_controlled(Bus::Profinet, Default::default()));
    let mut device = Device::new(station, config, drive);
    let faults = faults_on_stdin.then(faults_from_stdin);
    let tick = |device: &mut Device, now| {
        if crate::cmd::signals::requested() {
            return ControlFlow::Break(());
        }
        for fault in faults.iter().flat_map(|f| f.try_iter()) {
            if fault {
                device.inject_fault(now, FAULT_OC1);
                println!("drive fault {FAULT_OC1} (OC1) raised");
            } else {
                device.remove_fault_cause();
                println!("drive fault cause removed: a fault reset (CW command 7) clears it");
            }
        }
        ControlFlow::Continue(())
    };
    let mut connected = 0u32;
    let served = driver::serve_with(&mut socket, &rpc, &mut device, None, tick, |event| {
        match event {
            DeviceEvent::Ar(event) => {
                connected += u32::from(matches!(event, ArEvent::Connected { .. }));
                print_ar(event)
            }
            DeviceEvent::Dcp(DcpEvent::NameSet(name)) => {
                println!("name of station set to `{name}`")
            }
            DeviceEvent::Dcp(DcpEvent::IpSet([ip, mask, gw])) => {
                let dotted = |a: &[u8; 4]| std::net::Ipv4Addr::from(*a).to_string();
                println!(
                    "IP set to {} mask {} gateway {}",
                    dotted(ip),
                    dotted(mask),
                    dotted(gw)
                );
                if !has_address(iface, *ip) {
                    eprintln!(
                        "note: `{iface}` does not have {}: RPC reaches the device once it has it",
                        dotted(ip)
                    );
                }
            }
            DeviceEvent::Dcp(DcpEvent::Signal) => println!("signal: flashing the LED"),
            DeviceEvent::Dcp(DcpEvent::ResetToFactory) => println!("reset to factory"),
            DeviceEvent::Alarm(AlarmEvent::Acknowledged(ack)) => println!(
                "alarm {:#06x} of slot {} subslot {} acknowledged (sequence {}, PNIOStatus {})",
                ack.source.alarm_type,
                ack.source.slot,
                ack.source.subslot,
                ack.source.specifier & 0x07FF,
                hex(&ack.status.0)
            ),
            DeviceEvent::Alarm(AlarmEvent::Aborted(status)) => {
                println!("alarm CR over (PNIOStatus {})", hex(&status.0))
            }
        }
        use std::io::Write;
        let _ = std::io::stdout().flush();
    });
    match served {
        Ok(()) => {
            eprintln!("stopped: {connected} ARs connected");
            ExitCode::SUCCESS
        }
        Err(e) => fail(format!("PROFINET on `{iface}`: {e}")),
    }
}

/// The fault a `fault` line raises: P07.27's type 4, OC1 (overcurrent while accelerating).
const FAULT_OC1: u16 = 4;

/// `fault` (true) and `clear` (false) lines of standard input, read by a thread of their own.
fn faults_from_stdin() -> mpsc::Receiver<bool> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::stdin().lock().lines() {
            let Ok(line) = line else { break };
            let fault = match line.trim() {
                "fault" => true,
                "clear" => false,
                other => {
                    eprintln!("ignored on standard input: `{other}` (fault or clear)");
                    continue;
                }
            };
            if tx.send(fault).is_err() {
                break;
            }
        }
    });
    rx
}

/// Bytes as hex digits.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02X}")).collect()
}

/// Prints one step of an AR.
fn print_ar(event: &ArEvent) {
    match event {
        ArEvent::Connected {
            ar_type,
            layout,
            diff,
        } => {
            let mut line = format!("AR connected (ARType {ar_type:#06x})");
            if let Some(l) = layout {
                line += &format!(
                    ": input FrameID {:#06x}, output FrameID {:#06x}, every {} us",
                    l.input_frame_id,
                    l.output_frame_id,
                    l.interval.as_micros()
                );
            }
            if *diff {
                line += ", with module differences";
            }
            println!("{line}");
        }
        ArEvent::RecordWritten {
            slot,
            subslot,
            index,
            data,
        } => println!(
            "record {index} of slot {slot} subslot {subslot} written ({} bytes)",
            data.len()
        ),
        ArEvent::PrmEnd => println!("PrmEnd: ApplicationReady sent"),
        ArEvent::DataStart => println!("ApplicationReady confirmed: cyclic data exchange"),
        ArEvent::Released => println!("AR released"),
        ArEvent::Aborted => println!("AR aborted"),
    }
}

/// IP, mask and gateway, as DCP carries them.
type IpParameter = [[u8; 4]; 3];

/// The IP, mask and (no) gateway the device reports, and where they come from (said after
/// the address): `--ip ADDR/PREFIX` as given; `--ip ADDR` with the prefix the interface has
/// for that address (a bare address must be one of the interface's, and the kernel's netmask
/// is the one datagrams to it are routed by: assuming /24, as p-net's sample does for a
/// missing mask, could report a mask the interface does not use); without `--ip`, the
/// interface's first IPv4 address and its prefix (`None` when it has none). An address the
/// interface does not have is refused: RPC datagrams to it would never reach the device.
fn address(iface: &str, ip: Option<&str>) -> Result<(Option<IpParameter>, String), String> {
    let own = iface::ipv4_addresses(iface).unwrap_or_default();
    let Some(text) = ip else {
        return Ok(match own.first() {
            Some(&(a, m)) => (Some([a, m, [0; 4]]), format!(" ({iface}'s address)")),
            None => (None, String::new()),
        });
    };
    let bad = || format!("--ip `{text}` is not ADDR or ADDR/PREFIX (such as 10.0.0.2/24)");
    let (addr, prefix) = match text.split_once('/') {
        Some((addr, prefix)) => (addr, Some(prefix)),
        None => (text, None),
    };
    let addr: std::net::Ipv4Addr = addr.parse().map_err(|_| bad())?;
    let Some(&(_, own_mask)) = own.iter().find(|(a, _)| *a == addr.octets()) else {
        let list: Vec<String> = own
            .iter()
            .map(|(a, m)| {
                format!(
                    "{}/{}",
                    std::net::Ipv4Addr::from(*a),
                    u32::from_be_bytes(*m).count_ones()
                )
            })
            .collect();
        return Err(format!(
            "`{iface}` does not have the address {addr} ({}): RPC datagrams to it would not reach the device; add it (ip addr add {addr}/24 dev {iface}) or leave --ip out to take the interface's",
            if list.is_empty() {
                "it has no IPv4 address".to_owned()
            } else {
                format!("it has {}", list.join(", "))
            }
        ));
    };
    let (mask, source) = match prefix {
        Some(prefix) => {
            let prefix: u32 = prefix.parse().map_err(|_| bad())?;
            if !(1..=32).contains(&prefix) {
                return Err(bad());
            }
            ((u32::MAX << (32 - prefix)).to_be_bytes(), String::new())
        }
        None => (own_mask, format!(" ({iface}'s prefix for it)")),
    };
    Ok((Some([addr.octets(), mask, [0; 4]]), source))
}

/// Whether `iface` has the IPv4 address `ip`.
fn has_address(iface: &str, ip: [u8; 4]) -> bool {
    iface::ipv4_addresses(iface).is_ok_and(|own| own.iter().any(|(a, _)| *a == ip))
}

/// `FILE@NAME` or `--card goodrive350-pn@NAME`: the entries without their `@NAME`, and the name
/// of station given (checked against the PROFINET name rules).
fn station_name(entries: &[String]) -> Result<(Vec<String>, Option<String>), String> {
    let mut name = None;
    let mut stripped = Vec::new();
    for entry in entries {
        match entry.rsplit_once('@') {
            Some((what, given)) => {
                if let Some(problem) = edsgen_runtime::profinet::wire::dcp::name_problem(given) {
                    return Err(format!(
                        "`{given}` is not a PROFINET name of station: {problem}"
                    ));
                }
                name = Some(given.to_owned());
                stripped.push(what.to_owned());
            }
            None => stripped.push(entry.clone()),
        }
    }
    Ok((stripped, name))
}
