//! `edsgen enip list|get|set`: an EtherNet/IP scanner at the bench. `list [ADDR]` sends
//! ListIdentity over UDP (to ADDR, else broadcast) and prints each identity that answers within a
//! second, matched to an ODVA EDS with `--eds FILE`; `get ADDR @CLASS/INST/ATTR` and `set ADDR
//! @CLASS/INST/ATTR HEX` are Get/Set_Attribute_Single by explicit messaging (RegisterSession,
//! SendRRData). Exit 0 ok, 1 a refusal (the CIP status is printed) or no identity, 2 bad usage or
//! I/O. The wire formats are the simulated adapter's (`edsgen_sim::enip::wire`).

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs, UdpSocket};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use edsgen_sim::enip::wire::{emit_items, item, parse_items, EncapError, Encapsulation};

/// `edsgen enip`.
#[derive(Debug, clap::Subcommand)]
pub enum Args {
    /// List the identities that answer ListIdentity (at ADDR, else by broadcast).
    List {
        /// The device (`IP` or `IP:PORT`); broadcast when absent.
        addr: Option<String>,
        /// An ODVA EDS to match the identities against (vendor, device type, product code,
        /// major revision).
        #[arg(long)]
        eds: Option<PathBuf>,
    },
    /// Read an attribute: `@CLASS/INSTANCE/ATTRIBUTE` (decimal, or hex with 0x).
    Get {
        /// The device (`IP` or `IP:PORT`).
        addr: String,
        /// The attribute.
        path: String,
    },
    /// Write an attribute: its bytes in hex (`0A 00` or `0a00`).
    Set {
        /// The device (`IP` or `IP:PORT`).
        addr: String,
        /// The attribute.
        path: String,
        /// The value's bytes, in hex.
        value: String,
    },
    /// A class-1 connection from the EDS: set outputs by name, print the inputs each RPI.
    Io(super::enip_io::Args),
}

fn usage(message: String) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(2)
}

pub(super) fn address(text: &str) -> Result<SocketAddr, String> {
    let with_port = if text.contains(':') {
        text.to_owned()
    } else {
        format!("{text}:44818")
    };
    with_port
        .to_socket_addrs()
        .ok()
        .and_then(|mut a| a.next())
        .ok_or_else(|| format!("`{text}` is not an address: write IP or IP:PORT"))
}

/// `@CLASS/INSTANCE/ATTRIBUTE` as a padded EPATH.
fn epath(text: &str) -> Result<Vec<u8>, String> {
    let bad = || format!("`{text}` is not @CLASS/INSTANCE/ATTRIBUTE");
    let parts: Vec<u32> = text
        .strip_prefix('@')
        .ok_or_else(bad)?
        .split('/')
        .map(|p| match p.strip_prefix("0x") {
            Some(hex) => u32::from_str_radix(hex, 16).ok(),
            None => p.parse().ok(),
        })
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    let [class, instance, attribute] = parts[..] else {
        return Err(bad());
    };
    let mut path = Vec::new();
    for (kind, value) in [(0x20u8, class), (0x24, instance), (0x30, attribute)] {
        match u8::try_from(value) {
            Ok(v) => path.extend_from_slice(&[kind, v]),
            Err(_) => {
                let v = u16::try_from(value).map_err(|_| bad())?;
                path.extend_from_slice(&[kind | 1, 0]);
                path.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    Ok(path)
}

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs `edsgen enip`.
pub fn run(args: Args) -> ExitCode {
    match args {
        Args::List { addr, eds } => list(addr.as_deref(), eds),
        Args::Io(args) => super::enip_io::run(args),
        Args::Get { addr, path } => explicit(&addr, &path, 0x0E, Vec::new()),
        Args::Set { addr, path, value } => {
            let digits: String = value.chars().filter(|c| !c.is_whitespace()).collect();
            let bytes: Option<Vec<u8>> = (0..digits.len())
                .step_by(2)
                .map(|i| {
                    digits
                        .get(i..i + 2)
                        .and_then(|h| u8::from_str_radix(h, 16).ok())
                })
                .collect();
            match bytes {
                Some(bytes) if !bytes.is_empty() => explicit(&addr, &path, 0x10, bytes),
                _ => usage(format!("`{value}` is not hex bytes")),
            }
        }
    }
}

fn list(addr: Option<&str>, eds: Option<PathBuf>) -> ExitCode {
    let key = match eds {
        Some(path) => match edsgen_codegen::read::read_file(&path) {
            Ok(read) => match read.device.cip {
                Some(cip) => Some((path, cip.identity)),
                None => return usage(format!("`{}` is not an ODVA EDS", path.display())),
            },
            Err(err) => return usage(err.to_string()),
        },
        None => None,
    };
    let target = match addr {
        Some(a) => match address(a) {
            Ok(a) => a,
            Err(m) => return usage(m),
        },
        None => SocketAddr::from(([255, 255, 255, 255], 44818)),
    };
    let socket = match UdpSocket::bind("0.0.0.0:0") {
        Ok(s) => s,
        Err(err) => return usage(format!("cannot open a UDP socket: {err}")),
    };
    let _ = socket.set_broadcast(true);
    let _ = socket.set_read_timeout(Some(Duration::from_secs(1)));
    let request = Encapsulation {
        command: 0x63,
        session: 0,
        status: 0,
        context: [0; 8],
        options: 0,
        data: Vec::new(),
    };
    if let Err(err) = socket.send_to(&request.emit(), target) {
        return usage(format!("cannot send to {target}: {err}"));
    }
    let mut found = 0;
    let mut buf = [0u8; 1500];
    while let Ok((n, from)) = socket.recv_from(&mut buf) {
        let Ok((reply, _)) = Encapsulation::parse(&buf[..n]) else {
            continue;
        };
        let Some(items) = parse_items(&reply.data) else {
            continue;
        };
        for (_, body) in items.iter().filter(|(k, _)| *k == item::IDENTITY) {
            let Some(identity) = Identity::parse(body) else {
                continue;
            };
            found += 1;
            let mut line = format!(
                "{}\tvendor {}\tdevice type {}\tproduct code {}\trevision {}.{}\tserial {:#010x}\t{}",
                from.ip(),
                identity.vendor,
                identity.device_type,
                identity.product_code,
                identity.major,
                identity.minor,
                identity.serial,
                identity.name
            );
            if let Some((path, id)) = &key {
                let same = id.vendor_code.as_ref().map(|v| v.value) == Some(identity.vendor)
                    && id.product_type.as_ref().map(|v| v.value) == Some(identity.device_type)
                    && id.product_code.as_ref().map(|v| v.value) == Some(identity.product_code)
                    && id.major_revision.as_ref().map(|v| v.value) == Some(identity.major);
                line.push_str(&format!(
                    "\t{} {}",
                    if same { "matches" } else { "does not match" },
                    path.display()
                ));
            }
            println!("{line}");
        }
        if addr.is_some() {
            break;
        }
    }
    if found == 0 {
        eprintln!("no identity answered at {target} within 1 s");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

/// A ListIdentity item's fields.
struct Identity {
    vendor: u16,
    device_type: u16,
    product_code: u16,
    major: u8,
    minor: u8,
    serial: u32,
    name: String,
}

impl Identity {
    fn parse(b: &[u8]) -> Option<Identity> {
        use edsgen_sim::enip::wire::{u16_at, u32_at};
        let len = usize::from(*b.get(32)?);
        Some(Identity {
            vendor: u16_at(b, 18)?,
            device_type: u16_at(b, 20)?,
            product_code: u16_at(b, 22)?,
            major: *b.get(24)?,
            minor: *b.get(25)?,
            serial: u32_at(b, 28)?,
            name: String::from_utf8_lossy(b.get(33..33 + len)?).into_owned(),
        })
    }
}

/// One message and its reply over `stream`.
fn exchange(stream: &mut TcpStream, message: &Encapsulation) -> Result<Encapsulation, String> {
    stream
        .write_all(&message.emit())
        .map_err(|e| e.to_string())?;
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        match Encapsulation::parse(&got) {
            Ok((reply, _)) => return Ok(reply),
            Err(EncapError::Incomplete | EncapError::Truncated { .. }) => {}
        }
        let n = stream.read(&mut buf).map_err(|e| e.to_string())?;
        if n == 0 {
            return Err("the device closed the connection".into());
        }
        got.extend_from_slice(&buf[..n]);
    }
}

fn general_status_text(code: u8) -> &'static str {
    match code {
        0x01 => "connection failure",
        0x04 => "path segment error",
        0x05 => "path destination unknown",
        0x08 => "service not supported",
        0x09 => "invalid attribute value",
        0x0E => "attribute not settable",
        0x0F => "privilege violation",
        0x10 => "device state conflict",
        0x13 => "not enough data",
        0x14 => "attribute not supported",
        0x15 => "too much data",
        0x16 => "object does not exist",
        _ => "error",
    }
}

fn explicit(addr: &str, path: &str, service: u8, data: Vec<u8>) -> ExitCode {
    let target = match address(addr) {
        Ok(a) => a,
        Err(m) => return usage(m),
    };
    let epath = match epath(path) {
        Ok(p) => p,
        Err(m) => return usage(m),
    };
    let result = (|| -> Result<Vec<u8>, String> {
        let mut stream = TcpStream::connect_timeout(&target, Duration::from_secs(3))
            .map_err(|e| format!("cannot connect to {target}: {e}"))?;
        stream
            .set_read_timeout(Some(Duration::from_secs(3)))
            .map_err(|e| e.to_string())?;
        let register = Encapsulation {
            command: 0x65,
            session: 0,
            status: 0,
            context: *b"edsgen  ",
            options: 0,
            data: vec![1, 0, 0, 0],
        };
        let registered = exchange(&mut stream, &register)?;
        if registered.status != 0 {
            return Err(format!(
                "RegisterSession refused: encapsulation status {:#06x}",
                registered.status
            ));
        }
        let mut request = vec![service, (epath.len() / 2) as u8];
        request.extend_from_slice(&epath);
        request.extend_from_slice(&data);
        let mut body = vec![0; 6];
        body.extend(emit_items(&[
            (item::NULL_ADDRESS, &[]),
            (item::UNCONNECTED_DATA, &request),
        ]));
        let message = Encapsulation {
            command: 0x6F,
            session: registered.session,
            status: 0,
            context: *b"edsgen  ",
            options: 0,
            data: body,
        };
        let reply = exchange(&mut stream, &message)?;
        if reply.status != 0 {
            return Err(format!(
                "SendRRData refused: encapsulation status {:#06x}",
                reply.status
            ));
        }
        let items = reply
            .data
            .get(6..)
            .and_then(parse_items)
            .ok_or("a malformed reply")?;
        let response = items
            .iter()
            .find(|(k, _)| *k == item::UNCONNECTED_DATA)
            .map(|(_, d)| d.to_vec())
            .ok_or("a reply without a response")?;
        Ok(response)
    })();
    let response = match result {
        Ok(r) => r,
        Err(message) => return usage(message),
    };
    let (Some(&status), Some(&extra)) = (response.get(2), response.get(3)) else {
        return usage("a response shorter than its header".into());
    };
    if status != 0 {
        eprintln!(
            "error: {path}: {} (general status {status:#04x})",
            general_status_text(status)
        );
        return ExitCode::from(1);
    }
    let data = response.get(4 + 2 * usize::from(extra)..).unwrap_or(&[]);
    if service == 0x0E {
        println!("{}", hex(data));
    }
    ExitCode::SUCCESS
}
