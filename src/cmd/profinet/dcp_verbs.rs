//! `pn list`, `pn set-name`, `pn set-ip` and `pn blink`: DCP at the bench, as a controller, and
//! what the other verbs share of it (the request frames, the answers, finding a device by
//! name, the name check). `list` sends Identify all with a ResponseDelayFactor of its window
//! (the devices spread their answers over it, as the standard has them) and listens that long
//! and half a second more, said on standard error.

use std::io;
use std::net::Ipv4Addr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use edsgen_runtime::profinet::wire::dcp::{self, response_blocks, DcpHeader};
use edsgen_runtime::profinet::wire::{Ethernet, Mac};
use edsgen_sim::profinet::driver::RawSocket;

use super::super::fail;

pub(super) fn parse_mac(text: &str) -> Option<Mac> {
    let bytes: Vec<u8> = text
        .split([':', '-'])
        .map(|p| u8::from_str_radix(p, 16).ok())
        .collect::<Option<_>>()?;
    bytes.try_into().ok()
}

pub(super) fn show_mac(mac: &Mac) -> String {
    mac.iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(":")
}

/// The DCP answers to transaction `xid` that reach `socket` before `until`: (sender, blocks).
pub(super) type Answer = (Mac, Vec<((u8, u8), u16, Vec<u8>)>);

pub(super) fn answers(
    socket: &mut RawSocket,
    xid: u32,
    until: Instant,
    first_only: bool,
) -> Vec<Answer> {
    let mut found = Vec::new();
    let mut buf = vec![0u8; 1600];
    while Instant::now() < until {
        let Ok(Some(n)) = socket.recv(&mut buf) else {
            continue;
        };
        let frame = &buf[..n];
        let Some(eth) = Ethernet::parse(frame).filter(|e| e.dst == socket.mac()) else {
            continue;
        };
        let Some((header, blocks)) = frame.get(eth.payload..).and_then(DcpHeader::parse) else {
            continue;
        };
        if header.xid != xid || header.service_type != dcp::TYPE_RESPONSE {
            continue;
        }
        let blocks = response_blocks(blocks)
            .map(|(o, i, d)| (o, i, d.to_vec()))
            .collect();
        found.push((eth.src, blocks));
        if first_only {
            break;
        }
    }
    found
}

/// The GSDML files' (VendorID, DeviceID, path).
fn gsdml_ids(files: &[PathBuf]) -> Result<Vec<(u16, u16, String)>, String> {
    files
        .iter()
        .map(|path| {
            let read = super::super::load(path, None)?;
            let pn = read
                .device
                .profinet()
                .ok_or_else(|| format!("`{}` is not a GSDML file", path.display()))?;
            match (&pn.vendor_id, &pn.device_id) {
                (Some(v), Some(d)) => Ok((v.value, d.value, path.display().to_string())),
                _ => Err(format!("`{}` has no VendorID/DeviceID", path.display())),
            }
        })
        .collect()
}

/// How long after a device's delay `list` still listens: its answer on the way.
const SLACK: Duration = Duration::from_millis(500);

/// The ResponseDelayFactor of a window of `window` (10 ms steps, 1 to 6400), and how long
/// to listen for the answers.
pub(super) fn identify_window(window: Duration) -> (u16, Duration) {
    let factor = (window.as_millis() / 10).clamp(1, 6400) as u16;
    (
        factor,
        Duration::from_millis(u64::from(factor) * 10) + SLACK,
    )
}

pub(super) fn list(iface: &str, gsdml: &[PathBuf], window: Duration) -> ExitCode {
    let known = match gsdml_ids(gsdml) {
        Ok(known) => known,
        Err(message) => return fail(message),
    };
    let mut socket = match RawSocket::open(iface, Duration::from_millis(100)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}`: {e}")),
    };
    let xid = std::process::id();
    let (factor, listen) = identify_window(window);
    let mut frame = request(
        dcp::MULTICAST_IDENTIFY,
        socket.mac(),
        dcp::FRAME_IDENTIFY_REQUEST,
        dcp::SERVICE_IDENTIFY,
        xid,
        &[0xFF, 0xFF, 0, 0],
    );
    set_response_delay(&mut frame, factor);
    if let Err(e) = socket.send(&frame) {
        return fail(format!("cannot send on `{iface}`: {e}"));
    }
    eprintln!(
        "listening {:.1} s for DCP Identify answers on {iface} (ResponseDelayFactor {factor}: devices answer within {:.2} s)",
        listen.as_secs_f64(),
        (listen - SLACK).as_secs_f64()
    );
    let mut found = answers(&mut socket, xid, Instant::now() + listen, false);
    // One line per device, by MAC: the order the answers came in is the devices' delays.
    found.sort_by_key(|a| a.0);
    found.dedup_by(|a, b| a.0 == b.0);
    for (mac, blocks) in &found {
        let get = |option| {
            blocks
                .iter()
                .find(|b| b.0 == option)
                .map(|b| b.2.clone())
                .unwrap_or_default()
        };
        let text = |option| String::from_utf8_lossy(&get(option)).into_owned();
        let ids = get(dcp::DEVICE_ID);
        let (vendor, device) = match ids[..] {
            [a, b, c, d, ..] => (u16::from_be_bytes([a, b]), u16::from_be_bytes([c, d])),
            _ => (0, 0),
        };
        let ip = get(dcp::IP_PARAMETER);
        let ip = ip.get(..4).map_or("-".to_owned(), |a| {
            format!("{}.{}.{}.{}", a[0], a[1], a[2], a[3])
        });
        let mut line = format!(
            "{}\t{}\t{vendor:04x}:{device:04x}\t{ip}\t{}",
            show_mac(mac),
            text(dcp::NAME_OF_STATION),
            text(dcp::TYPE_OF_STATION)
        );
        if !known.is_empty() {
            let matched = known
                .iter()
                .find(|(v, d, _)| (*v, *d) == (vendor, device))
                .map_or("-", |k| k.2.as_str());
            line.push('\t');
            line.push_str(matched);
        }
        println!("{line}");
    }
    if found.is_empty() {
        eprintln!("no PROFINET device answered on `{iface}`");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

pub(super) fn set_name(iface: &str, mac: &str, name: &str) -> ExitCode {
    let Some(mac) = parse_mac(mac) else {
        return fail(format!("`{mac}` is not a MAC address (aa:bb:cc:dd:ee:ff)"));
    };
    if let Err(message) = check_name(name) {
        return fail(message);
    }
    let mut value = vec![0x00, 0x01];
    value.extend_from_slice(name.as_bytes());
    let said = format!("name of station set to `{name}`");
    set(
        iface,
        Target::Mac(mac),
        dcp::NAME_OF_STATION,
        &value,
        "the name",
        &said,
    )
}

/// `pn set-ip IFACE NAME|MAC ADDR/PREFIX [GATEWAY]`: DCP Set IP parameter, permanent unless
/// `temporary` (BlockQualifier 1 or 0: a device forgets a temporary one at power-off).
pub(super) fn set_ip(
    iface: &str,
    who: &str,
    address: &str,
    gateway: Option<&str>,
    temporary: bool,
) -> ExitCode {
    let bad = || format!("`{address}` is not ADDR/PREFIX (such as 10.0.0.5/24)");
    let Some((ip, prefix)) = address.split_once('/') else {
        return fail(bad());
    };
    let (Ok(ip), Ok(prefix)) = (ip.parse::<Ipv4Addr>(), prefix.parse::<u32>()) else {
        return fail(bad());
    };
    if !(1..=32).contains(&prefix) {
        return fail(bad());
    }
    let mask = Ipv4Addr::from(u32::MAX << (32 - prefix));
    let gateway = match gateway.map(str::parse::<Ipv4Addr>) {
        None => Ipv4Addr::UNSPECIFIED,
        Some(Ok(gateway)) => gateway,
        Some(Err(_)) => {
            return fail(format!(
                "`{}` is not an IPv4 gateway address",
                gateway.unwrap_or_default()
            ))
        }
    };
    let target = match Target::parse(who) {
        Ok(target) => target,
        Err(message) => return fail(message),
    };
    let mut value = vec![0x00, u8::from(!temporary)];
    for a in [ip, mask, gateway] {
        value.extend_from_slice(&a.octets());
    }
    let said = format!(
        "IP set to {ip} mask {mask} gateway {gateway} ({})",
        if temporary { "temporary" } else { "permanent" }
    );
    set(iface, target, dcp::IP_PARAMETER, &value, "the IP", &said)
}

/// `pn blink IFACE NAME|MAC`: DCP Control Signal (the device flashes its LED, as a real one
/// does to be found in a cabinet).
pub(super) fn blink(iface: &str, who: &str) -> ExitCode {
    let target = match Target::parse(who) {
        Ok(target) => target,
        Err(message) => return fail(message),
    };
    // BlockQualifier 0, SignalValue 0x0100: flash once.
    let value = [0x00, 0x00, 0x01, 0x00];
    let said = "flashing its LED (DCP Control Signal)";
    set(
        iface,
        target,
        dcp::CONTROL_SIGNAL,
        &value,
        "the signal",
        said,
    )
}

/// A device as the command line names it: by MAC address or by name of station.
#[derive(Debug, Clone)]
pub(super) enum Target {
    Mac(Mac),
    Name(String),
}

impl Target {
    /// A MAC address (`aa:bb:cc:dd:ee:ff`), else a name of station (checked).
    pub(super) fn parse(text: &str) -> Result<Target, String> {
        if let Some(mac) = parse_mac(text) {
            return Ok(Target::Mac(mac));
        }
        check_name(text)?;
        Ok(Target::Name(text.to_owned()))
    }
}

/// How long a DCP answer to one device may take.
const ANSWER_WAIT: Duration = Duration::from_secs(2);

/// DCP Identify by name (ResponseDelayFactor 1): the answer of the device named `name`.
pub(super) fn find_by_name(socket: &mut RawSocket, name: &str) -> io::Result<Option<Answer>> {
    let mut filter = vec![0; 4 + name.len() + 1];
    let n = dcp::emit_plain_block(&mut filter, dcp::NAME_OF_STATION, name.as_bytes()).unwrap_or(0);
    filter.truncate(n);
    let xid = std::process::id();
    let frame = request(
        dcp::MULTICAST_IDENTIFY,
        socket.mac(),
        dcp::FRAME_IDENTIFY_REQUEST,
        dcp::SERVICE_IDENTIFY,
        xid,
        &filter,
    );
    socket.send(&frame)?;
    Ok(answers(socket, xid, Instant::now() + ANSWER_WAIT, true)
        .into_iter()
        .next())
}

/// Sets `option` to `value` (BlockQualifier first) on the device `target` and says `said`
/// after its MAC when it accepts; exit 1 when it refuses (`what` names what it refused), does
/// not answer or is not found; 2 for I/O problems.
fn set(
    iface: &str,
    target: Target,
    option: (u8, u8),
    value: &[u8],
    what: &str,
    said: &str,
) -> ExitCode {
    let mut socket = match RawSocket::open(iface, Duration::from_millis(100)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}`: {e}")),
    };
    let mac = match target {
        Target::Mac(mac) => mac,
        Target::Name(name) => match find_by_name(&mut socket, &name) {
            Ok(Some((mac, _))) => mac,
            Ok(None) => {
                eprintln!("no device named `{name}` answered on {iface} within 2 s");
                return ExitCode::from(1);
            }
            Err(e) => return fail(format!("cannot send on `{iface}`: {e}")),
        },
    };
    let xid = std::process::id().wrapping_add(1);
    let mut block = vec![0; 4 + value.len() + 1];
    let n = dcp::emit_plain_block(&mut block, option, value).unwrap_or(0);
    block.truncate(n);
    let frame = request(
        mac,
        socket.mac(),
        dcp::FRAME_GET_SET,
        dcp::SERVICE_SET,
        xid,
        &block,
    );
    if let Err(e) = socket.send(&frame) {
        return fail(format!("cannot send on `{iface}`: {e}"));
    }
    let answer = answers(&mut socket, xid, Instant::now() + ANSWER_WAIT, true);
    let error = answer
        .first()
        .and_then(|(_, blocks)| blocks.iter().find(|b| b.0 == dcp::CONTROL_RESPONSE))
        .and_then(|b| b.2.first().copied());
    match error {
        Some(0) => {
            println!("{}: {said}", show_mac(&mac));
            ExitCode::SUCCESS
        }
        Some(code) => {
            eprintln!(
                "{}: the device refused {what} (BlockError {code})",
                show_mac(&mac)
            );
            ExitCode::from(1)
        }
        None => {
            eprintln!("{}: no answer within 2 s", show_mac(&mac));
            ExitCode::from(1)
        }
    }
}

/// Why `name` cannot be a name of station (a device would refuse it with BlockError 3), in
/// words; with uppercase letters, the lowercase name to use.
pub(super) fn check_name(name: &str) -> Result<(), String> {
    let Some(problem) = dcp::name_problem(name) else {
        return Ok(());
    };
    let lower = name.to_ascii_lowercase();
    let hint = match problem {
        dcp::NameProblem::Uppercase if dcp::valid_name(&lower) => format!(": use `{lower}`"),
        _ => String::new(),
    };
    Err(format!(
        "`{name}` is not a PROFINET name of station: it has {problem}{hint}"
    ))
}

/// A DCP request frame (see [`dcp::request`]).
pub(super) fn request(
    dst: Mac,
    src: Mac,
    frame_id: u16,
    service: u8,
    xid: u32,
    blocks: &[u8],
) -> Vec<u8> {
    let mut frame = vec![0; 14 + dcp::HEADER_LEN + blocks.len()];
    let n = dcp::request(&mut frame, dst, src, frame_id, service, xid, blocks).unwrap_or(0);
    frame.truncate(n);
    frame
}

/// Sets the ResponseDelayFactor of an Identify request `frame`.
fn set_response_delay(frame: &mut [u8], factor: u16) {
    let Some(pdu) = frame.get_mut(14..) else {
        return;
    };
    if let Some((mut header, _)) = DcpHeader::parse(pdu) {
        header.response_delay = factor;
        let _ = header.emit(pdu);
    }
}
