//! `edsgen simulate --profinet IFACE (FILE.xml[@NAME] | --card goodrive350-pn[@NAME])...
//! [--ip ADDR[/PREFIX]]...`: PROFINET IO devices from GSDMLs on one network interface (root, or
//! `CAP_NET_RAW`), the cards first, then the files, each with its own MAC
//! ([`segment::device_mac`]), name of station, IP, ARs, alarms and cyclic data. Each says Hello,
//! then answers DCP (identify, get, set name of station and IP, signal) as its GSDML's
//! configuration's access point (a file's: the overlay's `[modules]`, else `--access-point` and
//! `--module`, else the default; docs/modules.md), with its modules, serves connection management on UDP 34964 at its own IP (Connect, Read,
//! Write, PrmEnd, ApplicationReady, Release) and the cyclic RT_CLASS_1 exchange of its AR, with
//! the Goodrive350's drive behind a card, whose faults are Diagnosis alarms on the AR's
//! AlarmCR (`--faults-on-stdin`: `fault` and `clear` lines on standard input switch them,
//! `fault NAME` one device's); it prints what a controller sets, each step of an AR and each
//! alarm acknowledged (each line after `NAME: ` when there are several devices), until SIGINT,
//! SIGTERM or SIGHUP, then says `stopped:` (on stderr) with the number of ARs it served.

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
use edsgen_sim::profinet::dcp::{DcpEvent, Station};
use edsgen_sim::profinet::device::{Device, DeviceEvent};
use edsgen_sim::profinet::segment::{self, Segment};
use edsgen_sim::profinet::{driver, iface, station};

use crate::cmd::fail;

/// The bundled PROFINET card's GSDML, in the binary so that `--card` works anywhere.
const GOODRIVE350_PN: &[u8] = include_bytes!("../../../eds/goodrive350-pn.xml");

/// The bundled PROFINET card.
const CARD: &str = "goodrive350-pn";

/// One device to simulate, as the command line gives it.
struct Planned {
    station: Station,
    config: DeviceConfig,
    /// The access point and modules, when chosen (the overlay's or the command line's).
    chosen: Option<String>,
    /// The card's drive, or none for a GSDML file.
    card: bool,
}

/// Runs the devices of `cards` (`goodrive350-pn[@NAME]`, first) and `files` (`FILE[@NAME]`)
/// on `iface`, each with the MAC [`segment::device_mac`] gives its position and the IP of
/// `ips` at that position (or the interface's address at that position when `ips` is empty).
/// `chosen` is the `--module` lists and the `--access-point`s of the files, one each in the
/// order of `files` (an empty list or `None`: the overlay's choice, else the default).
/// Exit 2 for bad usage, a file that is not a readable GSDML, or an interface that cannot be
/// opened. With `faults_on_stdin`, the card devices' drives' faults are switched by `fault`
/// and `clear` lines on standard input (`fault NAME` for the device of that name of station).
pub fn run(
    iface: &str,
    files: &[String],
    cards: &[String],
    chosen: (&[Vec<String>], &[Option<String>]),
    ips: &[String],
    faults_on_stdin: bool,
    allow: &Policy,
) -> ExitCode {
    let count = files.len() + cards.len();
    if count == 0 {
        return fail(format!(
            "--profinet serves IO devices: --card {CARD}[@NAME] or FILE.xml[@NAME], one or more"
        ));
    }
    // The descriptions are judged first: a file with errors is refused whatever the interface.
    let (modules, access_points) = chosen;
    let beyond = files.len();
    if modules.iter().skip(beyond).any(|m| !m.is_empty())
        || access_points.iter().skip(beyond).any(Option::is_some)
    {
        return fail(
            "--module and --access-point choose the configuration of a FILE.xml, not of a card",
        );
    }
    let entries = cards
        .iter()
        .map(|c| (c, None))
        .chain(files.iter().enumerate().map(|(n, f)| (f, Some(n))));
    let mut planned: Vec<Planned> = Vec::new();
    for (entry, file) in entries {
        let choice = file.map(|n| {
            let access_point = access_points.get(n).and_then(Option::as_deref);
            (modules.get(n).map_or(&[][..], Vec::as_slice), access_point)
        });
        let device = match plan(entry, choice, allow) {
            Ok(device) => device,
            Err(e) => return fail(e),
        };
        let name = &device.station.name_of_station;
        if !name.is_empty() && planned.iter().any(|p| &p.station.name_of_station == name) {
            return fail(format!(
                "two devices named `{name}`: give each its own name of station (`--card {CARD}@drive-a`, `FILE.xml@drive-b`)"
            ));
        }
        planned.push(device);
    }
    if faults_on_stdin && !planned.iter().any(|p| p.card) {
        return fail(format!(
            "--faults-on-stdin switches the faults of --card {CARD}'s drive"
        ));
    }
    let addresses = match addresses(iface, ips, count) {
        Ok(addresses) => addresses,
        Err(e) => return fail(e),
    };
    let iface_mac = match edsgen_sim::packet_socket::interface_mac(iface) {
        Ok(mac) => mac,
        Err(e) => return fail(format!("cannot open `{iface}` for PROFINET: {e}")),
    };
    for (position, device) in planned.iter_mut().enumerate() {
        device.station.mac = segment::device_mac(iface_mac, position);
    }
    // Before the first line: a signal that comes once the device is announced stops it cleanly.
    if let Err(message) = crate::cmd::signals::install() {
        return fail(message);
    }
    let socket = match driver::RawSocket::open(iface, std::time::Duration::from_millis(1)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}` for PROFINET: {e}")),
    };
    let mut devices = Vec::new();
    for (mut plan, (ip, source)) in planned.into_iter().zip(addresses) {
        if let Some(ip) = ip {
            plan.station.ip = ip;
        }
        announce(iface, &plan, &source);
        let drive = plan
            .card
            .then(|| PkwPzdDrive::bus_controlled(Bus::Profinet, Default::default()));
        devices.push(Device::new(plan.station, plan.config, drive));
    }
    let several = devices.len() > 1;
    let mut segment = match Segment::new(iface, socket, devices) {
        Ok(segment) => segment,
        Err(e) => return fail(format!("PROFINET on `{iface}`: {e}")),
    };
    let faults = faults_on_stdin.then(faults_from_stdin);
    let tick = |devices: &mut [Device], now| {
        if crate::cmd::signals::requested() {
            return ControlFlow::Break(());
        }
        for (fault, name) in faults.iter().flat_map(|f| f.try_iter()) {
            switch_fault(devices, now, fault, name.as_deref(), several);
        }
        ControlFlow::Continue(())
    };
    let mut connected = 0u32;
    let served = segment.serve(None, tick, |_, station, event| {
        connected += u32::from(matches!(event, DeviceEvent::Ar(ArEvent::Connected { .. })));
        let line = event_line(iface, event);
        if several {
            println!("{}: {line}", who(station));
        } else {
            println!("{line}");
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

/// A device's name for the lines of several: its name of station, or its MAC without one.
fn who(station: &Station) -> String {
    if station.name_of_station.is_empty() {
        mac_text(&station.mac)
    } else {
        station.name_of_station.clone()
    }
}

fn mac_text(mac: &[u8; 6]) -> String {
    let bytes: Vec<String> = mac.iter().map(|b| format!("{b:02x}")).collect();
    bytes.join(":")
}

/// The two lines a device starts with: what and where it is, and its RPC address (`source`
/// says where that came from), or why it has none yet.
fn announce(iface: &str, plan: &Planned, source: &str) {
    let station = &plan.station;
    println!(
        "PROFINET device `{}` (VendorID {:#06x}, DeviceID {:#06x}) on {iface}, MAC {}",
        station.name_of_station,
        station.vendor_id,
        station.device_id,
        mac_text(&station.mac)
    );
    if let Some(chosen) = &plan.chosen {
        println!("{chosen}");
    }
    let [a, m, _] = station.ip;
    if a == [0; 4] {
        println!("no IP yet ({source}): RPC on UDP 34964 answers once {iface} has the address");
    } else {
        println!(
            "RPC on UDP 34964 at {}.{}.{}.{} mask {}.{}.{}.{}{source}",
            a[0], a[1], a[2], a[3], m[0], m[1], m[2], m[3]
        );
    }
}

/// One device of the command line: its GSDML loaded and judged, its station (the
/// `@NAME` given, else the GSDML's name) and configuration (a file's: the overlay's, else
/// `choice`'s modules and access point, else the default). `choice` is `None` for a card.
fn plan(
    entry: &str,
    choice: Option<(&[String], Option<&str>)>,
    allow: &Policy,
) -> Result<Planned, String> {
    let is_card = choice.is_none();
    let (what, given) = match entry.rsplit_once('@') {
        Some((what, given)) => {
            if let Some(problem) = edsgen_runtime::profinet::wire::dcp::name_problem(given) {
                return Err(format!(
                    "`{given}` is not a PROFINET name of station: {problem}"
                ));
            }
            (what, Some(given))
        }
        None => (entry, None),
    };
    let (path, read) = if is_card {
        if what != CARD {
            return Err(format!(
                "no PROFINET card `{what}`: the bundled PROFINET card is {CARD}"
            ));
        }
        let path = "eds/goodrive350-pn.xml";
        let read = load::load_bundled(
            Path::new(path),
            GOODRIVE350_PN,
            Some(include_str!("../../../eds/goodrive350-pn.toml")),
        );
        (path.to_owned(), read)
    } else {
        match load::load(Path::new(what), None) {
            Ok(loaded) => (what.to_owned(), loaded),
            Err(LoadError::Read(read::ReadError::Io(_, e))) => {
                return Err(format!("cannot read `{what}`: {e}"))
            }
            Err(e) => return Err(e.to_string()),
        }
    };
    crate::cmd::simulate::servable(&read, &path, allow)?;
    let Some(pn) = read.device.profinet() else {
        return Err(format!("`{path}` is not a GSDML file"));
    };
    let (modules, access_point) = choice.unwrap_or_default();
    let pn = &super::configured(pn, &path, modules, access_point)?;
    // Its MAC comes with the interface's (`run`).
    let mut station = station::from_gsdml(pn, [0; 6]);
    if let Some(name) = given {
        station.name_of_station = name.to_owned();
    }
    let chosen = pn.chosen.as_ref().map(|c| {
        let dap = c.access_point(pn).map_or("", |a| a.id.as_str());
        let modules = c.slots.iter().filter_map(|p| {
            let module = pn.modules.get(p.module)?;
            let ident = module.module_ident.as_ref().map_or(0, |m| m.value);
            Some(format!("slot {} {} ({ident:#010x})", p.slot, module.id))
        });
        let modules: Vec<String> = modules.collect();
        format!("access point {dap}, modules: {}", modules.join(", "))
    });
    Ok(Planned {
        station,
        config: DeviceConfig::from_gsdml(pn),
        chosen,
        card: is_card,
    })
}

/// Raises (`fault`) or removes the cause of a drive fault on the card devices, on the one named
/// `name` if a name is given.
fn switch_fault(
    devices: &mut [Device],
    now: edsgen_runtime::Instant,
    fault: bool,
    name: Option<&str>,
    several: bool,
) {
    let mut found = false;
    for device in devices.iter_mut() {
        if device.drive().is_none() {
            continue;
        }
        if name.is_some_and(|n| n != device.station().name_of_station) {
            continue;
        }
        found = true;
        let line = if fault {
            device.inject_fault(now, FAULT_OC1);
            format!("drive fault {FAULT_OC1} (OC1) raised")
        } else {
            device.remove_fault_cause();
            "drive fault cause removed: a fault reset (CW command 7) clears it".to_owned()
        };
        if several {
            println!("{}: {line}", who(device.station()));
        } else {
            println!("{line}");
        }
    }
    if let (false, Some(name)) = (found, name) {
        eprintln!("no card device named `{name}` on this interface");
    }
}

/// The line of one event.
fn event_line(iface: &str, event: &DeviceEvent) -> String {
    match event {
        DeviceEvent::Ar(event) => ar_line(event),
        DeviceEvent::Dcp(DcpEvent::NameSet(name)) => format!("name of station set to `{name}`"),
        DeviceEvent::Dcp(DcpEvent::IpSet([ip, mask, gw])) => {
            let dotted = |a: &[u8; 4]| std::net::Ipv4Addr::from(*a).to_string();
            if !has_address(iface, *ip) && *ip != [0; 4] {
                eprintln!(
                    "note: `{iface}` does not have {}: RPC reaches the device once it has it (ip addr add {}/{} dev {iface})",
                    dotted(ip),
                    dotted(ip),
                    u32::from_be_bytes(*mask).count_ones()
                );
            }
            format!(
                "IP set to {} mask {} gateway {}",
                dotted(ip),
                dotted(mask),
                dotted(gw)
            )
        }
        DeviceEvent::Dcp(DcpEvent::Signal) => "signal: flashing the LED".to_owned(),
        DeviceEvent::Dcp(DcpEvent::ResetToFactory) => "reset to factory".to_owned(),
        DeviceEvent::Alarm(AlarmEvent::Acknowledged(ack)) => format!(
            "alarm {:#06x} of slot {} subslot {} acknowledged (sequence {}, PNIOStatus {})",
            ack.source.alarm_type,
            ack.source.slot,
            ack.source.subslot,
            ack.source.specifier & 0x07FF,
            hex(&ack.status.0)
        ),
        DeviceEvent::Alarm(AlarmEvent::Aborted(status)) => {
            format!("alarm CR over (PNIOStatus {})", hex(&status.0))
        }
    }
}

/// The fault a `fault` line raises: P07.27's type 4, OC1 (overcurrent while accelerating).
const FAULT_OC1: u16 = 4;

/// `fault` (true) and `clear` (false) lines of standard input, each with the name after it
/// (`fault drive-a`) if any, read by a thread of their own.
fn faults_from_stdin() -> mpsc::Receiver<(bool, Option<String>)> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::stdin().lock().lines() {
            let Ok(line) = line else { break };
            let mut words = line.split_whitespace();
            let fault = match words.next() {
                Some("fault") => true,
                Some("clear") => false,
                _ => {
                    eprintln!(
                        "ignored on standard input: `{}` (fault or clear, optionally followed by a name of station)",
                        line.trim()
                    );
                    continue;
                }
            };
            if tx.send((fault, words.next().map(str::to_owned))).is_err() {
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

/// The line of one step of an AR.
fn ar_line(event: &ArEvent) -> String {
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
            line
        }
        ArEvent::RecordWritten {
            slot,
            subslot,
            index,
            data,
        } => format!(
            "record {index} of slot {slot} subslot {subslot} written ({} bytes)",
            data.len()
        ),
        ArEvent::PrmEnd => "PrmEnd: ApplicationReady sent".to_owned(),
        ArEvent::DataStart => "ApplicationReady confirmed: cyclic data exchange".to_owned(),
        ArEvent::Released => "AR released".to_owned(),
        ArEvent::Aborted => "AR aborted".to_owned(),
    }
}

/// IP, mask and gateway, as DCP carries them.
type IpParameter = [[u8; 4]; 3];

/// The IP, mask and (no) gateway of each of `count` devices, and where they come from (said
/// after the address), `None` for a device without one. `ips` gives one per device in the
/// same order, or none: then each device takes the interface's IPv4 address at its position
/// (the first its first, as one device always did; a second device the interface's second
/// address, if it has one), and a device past the interface's addresses has none until a DCP
/// Set gives it one; so has a device whose `--ip` is `-`. See [`address`] for one `--ip`.
/// With an address, the text says where it came from; without, why there is none.
fn addresses(
    iface: &str,
    ips: &[String],
    count: usize,
) -> Result<Vec<(Option<IpParameter>, String)>, String> {
    if ips.is_empty() {
        let own = iface::ipv4_addresses(iface).unwrap_or_default();
        return Ok((0..count)
            .map(|i| match own.get(i) {
                Some(&(a, m)) => (Some([a, m, [0; 4]]), format!(" ({iface}'s address)")),
                None if i == 0 => (
                    None,
                    format!("{iface} has no IPv4 address; --ip ADDR[/PREFIX], or a DCP Set"),
                ),
                None => (
                    None,
                    format!(
                        "{iface} has no IPv4 address number {}; --ip for each device, or a DCP Set",
                        i + 1
                    ),
                ),
            })
            .collect());
    }
    if ips.len() != count {
        let given = match ips.len() {
            1 => "once".to_owned(),
            n => format!("{n} times"),
        };
        return Err(format!(
            "--ip is given {given} for {count} devices: give one per device, in the order of the devices (the cards first, then the files), or none to take {iface}'s addresses in that order"
        ));
    }
    let mut found: Vec<(Option<IpParameter>, String)> = Vec::new();
    for text in ips {
        if text == "-" {
            found.push((None, "--ip -: a DCP Set gives one".to_owned()));
            continue;
        }
        let (ip, source) = address(iface, text)?;
        if found
            .iter()
            .any(|(other, _)| other.is_some_and(|o| o[0] == ip[0]))
        {
            return Err(format!(
                "--ip {} is given twice: each device has its own address",
                std::net::Ipv4Addr::from(ip[0])
            ));
        }
        found.push((Some(ip), source));
    }
    Ok(found)
}

/// The IP, mask and (no) gateway of `--ip TEXT`, and where they come from: `ADDR/PREFIX` as
/// given; `ADDR` with the prefix the interface has for that address (a bare address must be
/// one of the interface's, and the kernel's netmask is the one datagrams to it are routed by:
/// assuming /24, as p-net's sample does for a missing mask, could report a mask the interface
/// does not use). An address the interface does not have is refused: RPC datagrams to it
/// would never reach the device (the addresses are required, not added: the host's own
/// addresses are the user's to choose).
fn address(iface: &str, text: &str) -> Result<(IpParameter, String), String> {
    let own = iface::ipv4_addresses(iface).unwrap_or_default();
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
    Ok(([addr.octets(), mask, [0; 4]], source))
}

/// Whether `iface` has the IPv4 address `ip`.
fn has_address(iface: &str, ip: [u8; 4]) -> bool {
    iface::ipv4_addresses(iface).is_ok_and(|own| own.iter().any(|(a, _)| *a == ip))
}
