//! `pn list` and `pn set-name`: DCP at the bench, as a controller, and what the other verbs
//! share of it (the request frames, the answers, the name check).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use edsgen_runtime::profinet::wire::dcp::{self, response_blocks, DcpHeader};
use edsgen_runtime::profinet::wire::{Ethernet, Mac};
use edsgen_sim::profinet::driver::RawSocket;

use super::super::fail;

fn parse_mac(text: &str) -> Option<Mac> {
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
type Answer = (Mac, Vec<((u8, u8), u16, Vec<u8>)>);

fn answers(socket: &mut RawSocket, xid: u32, until: Instant, first_only: bool) -> Vec<Answer> {
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

pub(super) fn list(iface: &str, gsdml: &[PathBuf], timeout: Duration) -> ExitCode {
    let known = match gsdml_ids(gsdml) {
        Ok(known) => known,
        Err(message) => return fail(message),
    };
    let mut socket = match RawSocket::open(iface, Duration::from_millis(100)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}`: {e}")),
    };
    let xid = std::process::id();
    let frame = request(
        dcp::MULTICAST_IDENTIFY,
        socket.mac(),
        dcp::FRAME_IDENTIFY_REQUEST,
        dcp::SERVICE_IDENTIFY,
        xid,
        &[0xFF, 0xFF, 0, 0],
    );
    if let Err(e) = socket.send(&frame) {
        return fail(format!("cannot send on `{iface}`: {e}"));
    }
    let found = answers(&mut socket, xid, Instant::now() + timeout, false);
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
    let mut socket = match RawSocket::open(iface, Duration::from_millis(100)) {
        Ok(socket) => socket,
        Err(e) => return fail(format!("cannot open `{iface}`: {e}")),
    };
    let xid = std::process::id();
    let mut value = vec![0x00, 0x01];
    value.extend_from_slice(name.as_bytes());
    let mut block = vec![0; 4 + value.len() + 1];
    let n = dcp::emit_plain_block(&mut block, dcp::NAME_OF_STATION, &value).unwrap_or(0);
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
    let answer = answers(
        &mut socket,
        xid,
        Instant::now() + Duration::from_secs(2),
        true,
    );
    let error = answer
        .first()
        .and_then(|(_, blocks)| blocks.iter().find(|b| b.0 == dcp::CONTROL_RESPONSE))
        .and_then(|b| b.2.first().copied());
    match error {
        Some(0) => {
            println!("{}: name of station set to `{name}`", show_mac(&mac));
            ExitCode::SUCCESS
        }
        Some(code) => {
            eprintln!(
                "{}: the device refused the name (BlockError {code})",
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
pub(super) fn request(dst: Mac, src: Mac, frame_id: u16, service: u8, xid: u32, blocks: &[u8]) -> Vec<u8> {
    let mut frame = vec![0; 14 + dcp::HEADER_LEN + blocks.len()];
    let n = dcp::request(&mut frame, dst, src, frame_id, service, xid, blocks).unwrap_or(0);
    frame.truncate(n);
    frame
}
