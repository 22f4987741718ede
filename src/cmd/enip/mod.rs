//! `edsgen enip list|get|set|service|io`: an EtherNet/IP scanner at the bench. `list [ADDR]`
//! sends ListIdentity over UDP (to ADDR, else broadcast; from `--from ADDR`) with a maximum
//! delay of 1 s and prints each identity that answers within 1.5 s, matched to an ODVA EDS with
//! `--eds FILE` (exit 1 when one does not match); `get ADDR @CLASS/INST/ATTR` and `set ADDR
//! @CLASS/INST/ATTR HEX` are Get/Set_Attribute_Single by explicit messaging (RegisterSession,
//! SendRRData), `get ADDR @CLASS/INST` Get_Attributes_All, `service` any service;
//! `get|set ADDR PARAM-NAME [VALUE] --eds FILE` do the same for a parameter of the
//! EDS, typed, scaled and range-checked ([`param`]); `io` is a class-1 connection from the EDS
//! ([`io`]). Exit 0 ok, 1 a refusal (the CIP status is printed) or no identity, 2 bad usage or
//! I/O. The bytes are the runtime's (`edsgen_runtime::enip`), carried by [`link`]; values are
//! typed by [`cip_value`]. `edsgen simulate --enip` serves an adapter ([`simulate`]).

use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use edsgen_model::model::{Cip, Format};
use edsgen_runtime::enip::originator::Session;
use edsgen_runtime::enip::wire::cpf::{item, Items};
use edsgen_runtime::enip::wire::encap::{EncapRepr, IdentityItem};
use edsgen_runtime::enip::wire::epath::LogicalPath;
use edsgen_runtime::enip::wire::message::{general, RequestRepr};
use edsgen_runtime::enip::wire::Emit;

use self::cip_value::{get_bits, put_bits};
use self::link::{Link, LinkError, CONTEXT};
use self::param::Access;

pub mod cip_value;
pub mod io;
mod link;
pub mod param;
pub mod simulate;

/// `edsgen enip`.
#[derive(Debug, clap::Subcommand)]
pub enum Args {
    /// List the identities that answer ListIdentity (at ADDR, else by broadcast).
    List {
        /// The device (`IP` or `IP:PORT`), or a (directed) broadcast address; 255.255.255.255
        /// when absent.
        addr: Option<String>,
        /// The local address to send from (an address of the interface to broadcast on; needed
        /// when there is no default route).
        #[arg(long, value_name = "ADDR")]
        from: Option<std::net::Ipv4Addr>,
        /// An ODVA EDS to match the identities against (vendor, device type, product code,
        /// major revision).
        #[arg(long)]
        eds: Option<PathBuf>,
    },
    /// Read an attribute (`@CLASS/INSTANCE/ATTRIBUTE`, decimal or hex with 0x), all of an
    /// instance's (`@CLASS/INSTANCE`: Get_Attributes_All), or a parameter of the --eds file by
    /// name, its value typed, scaled and named as the file says.
    Get {
        /// The device (`IP` or `IP:PORT`).
        addr: String,
        /// `@CLASS/INSTANCE/ATTRIBUTE`, `@CLASS/INSTANCE`, or a parameter's name in the --eds
        /// file (a unique prefix will do, case and spaces do not matter; `ParamN` too).
        path: String,
        /// The device's ODVA EDS: names, types and places its parameters.
        #[arg(long, value_name = "FILE")]
        eds: Option<PathBuf>,
    },
    /// Write an attribute (its bytes in hex: `0A 00` or `0a00`), or a parameter of the --eds
    /// file by name (a number, an engineering value when the parameter is scaled, or its
    /// enumeration's text), checked against its type and limits before it is sent.
    Set {
        /// The device (`IP` or `IP:PORT`).
        addr: String,
        /// `@CLASS/INSTANCE/ATTRIBUTE`, or a parameter's name in the --eds file.
        path: String,
        /// The value.
        #[arg(allow_negative_numbers = true)]
        value: String,
        /// The device's ODVA EDS: names, types and places its parameters.
        #[arg(long, value_name = "FILE")]
        eds: Option<PathBuf>,
    },
    /// Any CIP service by explicit messaging: its reply's data printed in hex (empty line when
    /// there is none).
    Service {
        /// The device (`IP` or `IP:PORT`).
        addr: String,
        /// The service code, decimal or hex with 0x (0x01 Get_Attributes_All, 0x05 Reset,
        /// 0x0E Get_Attribute_Single, ...).
        service: String,
        /// `@CLASS/INSTANCE` or `@CLASS/INSTANCE/ATTRIBUTE`.
        path: String,
        /// The request's data in hex (`0A 00` or `0a00`).
        data: Option<String>,
    },
    /// A class-1 connection from the EDS: set outputs by name, print the inputs each RPI.
    Io(io::Args),
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

/// `@CLASS/INSTANCE/ATTRIBUTE` (or `@CLASS/INSTANCE` when `whole` allows it) as a padded
/// EPATH.
fn epath(text: &str, whole: bool) -> Result<Vec<u8>, String> {
    let bad = || match whole {
        true => format!("`{text}` is not @CLASS/INSTANCE[/ATTRIBUTE]"),
        false => format!("`{text}` is not @CLASS/INSTANCE/ATTRIBUTE"),
    };
    let parts: Vec<u32> = text
        .strip_prefix('@')
        .ok_or_else(bad)?
        .split('/')
        .map(number)
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    let (class, instance, attribute) = match parts[..] {
        [class, instance, attribute] => (class, instance, Some(attribute)),
        [class, instance] if whole => (class, instance, None),
        _ => return Err(bad()),
    };
    if parts.iter().any(|p| *p > 0xFFFF) {
        return Err(bad());
    }
    let path = LogicalPath {
        class,
        instance,
        attribute,
    };
    path.to_vec().map_err(|_| bad())
}

/// A number in decimal or hex with 0x.
fn number(text: &str) -> Option<u32> {
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}

/// Bytes in hex (`0A 00` or `0a00`); `None` when they are not.
fn hex_bytes(text: &str) -> Option<Vec<u8>> {
    let digits: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    (0..digits.len())
        .step_by(2)
        .map(|i| {
            digits
                .get(i..i + 2)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        })
        .collect()
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
        Args::List { addr, from, eds } => list(addr.as_deref(), from, eds),
        Args::Io(args) => io::run(args),
        Args::Get { addr, path, eds } if !path.starts_with('@') => {
            parameter(&addr, &path, None, eds)
        }
        Args::Set {
            addr,
            path,
            value,
            eds,
        } if !path.starts_with('@') => parameter(&addr, &path, Some(&value), eds),
        Args::Get { addr, path, eds } => {
            unused_eds(eds.as_deref());
            // Two numbers: the instance's Get_Attributes_All.
            let service = match path.matches('/').count() {
                1 => 0x01,
                _ => 0x0E,
            };
            explicit(&addr, &path, service, Vec::new(), true)
        }
        Args::Set {
            addr,
            path,
            value,
            eds,
        } => {
            unused_eds(eds.as_deref());
            match hex_bytes(&value) {
                Some(bytes) if !bytes.is_empty() => explicit(&addr, &path, 0x10, bytes, false),
                _ => usage(format!("`{value}` is not hex bytes")),
            }
        }
        Args::Service {
            addr,
            service,
            path,
            data,
        } => {
            let code = match number(&service) {
                Some(code @ 0..=0x7F) => code as u8,
                _ => {
                    return usage(format!(
                        "`{service}` is not a CIP service code (0..0x7F, decimal or hex with 0x)"
                    ))
                }
            };
            match hex_bytes(data.as_deref().unwrap_or("")) {
                Some(bytes) => explicit(&addr, &path, code, bytes, true),
                None => usage(format!("`{}` is not hex bytes", data.unwrap_or_default())),
            }
        }
    }
}

/// `--eds` with `@CLASS/INSTANCE/ATTRIBUTE`: said to be unused (the attribute's bytes are in
/// hex whatever the file says; a parameter's name types them).
fn unused_eds(eds: Option<&Path>) {
    if let Some(eds) = eds {
        eprintln!(
            "warning: --eds {} is not used with @CLASS/INSTANCE/ATTRIBUTE (its bytes are in \
             hex): name a parameter to have its value typed",
            eds.display()
        );
    }
}

/// The CIP part of the ODVA EDS at `path` (every `enip` verb and `simulate --enip` read it so).
pub(super) fn read_cip(path: &Path) -> Result<Cip, String> {
    cip_of(path, &super::read_device(path)?)
}

/// The CIP part of the model read from `path`, or the message saying it is not an ODVA EDS.
pub(super) fn cip_of(path: &Path, device: &edsgen_model::model::Device) -> Result<Cip, String> {
    device
        .cip()
        .cloned()
        .filter(|_| device.source.format == Format::OdvaEds)
        .ok_or_else(|| format!("`{}` is not an ODVA EDS", path.display()))
}

/// The maximum delay ListIdentity asks the targets to answer within (CIP Vol 2 §2-4.2.3: each
/// waits a random time up to it, so that many answering a broadcast do not collide).
pub(super) const MAX_DELAY_MS: u16 = 1000;

/// How long `list` listens: the maximum delay and half a second for the answers to travel.
pub(super) const LISTEN: Duration = Duration::from_millis(MAX_DELAY_MS as u64 + 500);

fn list(addr: Option<&str>, from: Option<std::net::Ipv4Addr>, eds: Option<PathBuf>) -> ExitCode {
    let key = match eds {
        Some(path) => match read_cip(&path) {
            Ok(cip) => Some((path, cip.identity)),
            Err(message) => return usage(message),
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
    let local = SocketAddr::from((from.unwrap_or(std::net::Ipv4Addr::UNSPECIFIED), 0));
    let socket = match UdpSocket::bind(local) {
        Ok(s) => s,
        Err(err) => {
            return usage(format!(
                "cannot open a UDP socket on {}: {err}{}",
                local.ip(),
                socket_hint(&err)
            ))
        }
    };
    let _ = socket.set_broadcast(true);
    let mut request = [0; 24];
    let len = Session::new(CONTEXT)
        .list_identity(MAX_DELAY_MS, &mut request)
        .unwrap_or_default();
    if let Err(err) = socket.send_to(&request[..len], target) {
        let hint = match (err.raw_os_error(), from) {
            // ENETUNREACH: no route to the target.
            (Some(101), None) => {
                "; with no default route, name an address of the interface to send from \
                 with --from ADDR"
            }
            _ => socket_hint(&err),
        };
        return usage(format!("cannot send to {target}: {err}{hint}"));
    }
    eprintln!(
        "listening {:.1} s for ListIdentity answers from {target} (maximum delay {MAX_DELAY_MS} ms)",
        LISTEN.as_secs_f32()
    );
    let deadline = std::time::Instant::now() + LISTEN;
    let mut found = 0;
    let mut mismatched = false;
    let mut buf = [0u8; 1500];
    loop {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        if left.is_zero() || socket.set_read_timeout(Some(left)).is_err() {
            break;
        }
        let Ok((n, from)) = socket.recv_from(&mut buf) else {
            break;
        };
        let Ok((reply, _)) = EncapRepr::parse_prefix(&buf[..n]) else {
            continue;
        };
        let Ok(items) = Items::parse(reply.data) else {
            continue;
        };
        for body in items.iter().filter(|i| i.kind == item::IDENTITY) {
            let Ok(identity) = IdentityItem::parse(body.data) else {
                continue;
            };
            let name = String::from_utf8_lossy(identity.name);
            found += 1;
            let mut line = format!(
                "{}\tvendor {}\tdevice type {}\tproduct code {}\trevision {}.{}\tserial {:#010x}\t{}",
                from.ip(),
                identity.vendor,
                identity.device_type,
                identity.product_code,
                identity.revision.0,
                identity.revision.1,
                identity.serial,
                name
            );
            if let Some((path, id)) = &key {
                let same = id.vendor_code.as_ref().map(|v| v.value) == Some(identity.vendor)
                    && id.product_type.as_ref().map(|v| v.value) == Some(identity.device_type)
                    && id.product_code.as_ref().map(|v| v.value) == Some(identity.product_code)
                    && id.major_revision.as_ref().map(|v| v.value) == Some(identity.revision.0);
                mismatched |= !same;
                line.push_str(&format!(
                    "\t{} {}",
                    if same { "matches" } else { "does not match" },
                    path.display()
                ));
            }
            println!("{line}");
        }
    }
    if found == 0 {
        eprintln!(
            "no identity answered at {target} within {:.1} s",
            LISTEN.as_secs_f32()
        );
        return ExitCode::from(1);
    }
    if mismatched {
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

/// What a socket error asks of the user: root (or the capability) for a permission, a local
/// address for one the host does not have.
pub(super) fn socket_hint(err: &std::io::Error) -> &'static str {
    match err.kind() {
        std::io::ErrorKind::PermissionDenied => {
            "; run as root (or with CAP_NET_BIND_SERVICE for a port below 1024, CAP_NET_RAW for \
             raw sockets), or check the firewall"
        }
        std::io::ErrorKind::AddrNotAvailable => ": it is not an address of this host",
        _ => "",
    }
}

/// A Get or Set request on `link`: `Ok(Ok(data))` on success, `Ok(Err(general status))` on a
/// refusal, `Err` when the exchange itself fails.
fn request(
    link: &mut Link,
    service: u8,
    path: &[u8],
    data: &[u8],
) -> Result<Result<Vec<u8>, u8>, String> {
    let request = RequestRepr {
        service,
        path,
        data,
    };
    let response = link.request(&request, &[]).map_err(LinkError::text)?;
    Ok(match response.status {
        general::SUCCESS => Ok(response.data),
        status => Err(status),
    })
}

/// The exit of a refusal: its general status printed, exit 1.
fn refused(what: &str, status: u8) -> ExitCode {
    eprintln!(
        "error: {what}: {} (general status {status:#04x})",
        general::text(status)
    );
    ExitCode::from(1)
}

/// One explicit request, `service` at `path` with `data`; a reply's data printed in hex (for
/// every service but Set_Attribute_Single). `whole`: the path may name an instance alone.
fn explicit(addr: &str, path: &str, service: u8, data: Vec<u8>, whole: bool) -> ExitCode {
    let target = match address(addr) {
        Ok(a) => a,
        Err(m) => return usage(m),
    };
    let epath = match epath(path, whole) {
        Ok(p) => p,
        Err(m) => return usage(m),
    };
    let result = Link::open(target)
        .map_err(LinkError::text)
        .and_then(|mut link| request(&mut link, service, &epath, &data));
    match result {
        Err(message) => usage(message),
        Ok(Err(status)) => refused(path, status),
        Ok(Ok(data)) => {
            if service != 0x10 {
                println!("{}", hex(&data));
            }
            ExitCode::SUCCESS
        }
    }
}

/// `get|set ADDR PARAM-NAME [VALUE] --eds FILE`: the parameter read (and shown typed) or written
/// (typed and range-checked first). A member of an assembly is read from the assembly, and
/// written by reading the assembly and writing it back with the member's bits replaced.
fn parameter(addr: &str, name: &str, value: Option<&str>, eds: Option<PathBuf>) -> ExitCode {
    let Some(eds) = eds else {
        return usage(format!(
            "`{name}` is not @CLASS/INSTANCE/ATTRIBUTE: give a parameter name with --eds FILE"
        ));
    };
    let cip = match read_cip(&eds) {
        Ok(cip) => cip,
        Err(message) => return usage(message),
    };
    let param = match param::resolve(&cip, name) {
        Ok(p) => p,
        Err(message) => return usage(message),
    };
    let label = param.label();
    let typed = param.typed;
    // Values wider than 64 bits (strings, ...) are bytes in hex.
    let wide = typed.bits > 64;
    let raw = match value {
        Some(v) if wide => super::value::Kind::Bytes.encode(v).map(Some),
        Some(v) => typed.parse(v).map(|raw| Some(typed.bytes(raw))),
        None => Ok(None),
    };
    let raw = match raw {
        Ok(raw) => raw,
        Err(message) => return usage(format!("{label}: {message}")),
    };
    if raw.is_some() && param.param.read_only() {
        return usage(format!("{label} is read-only (its descriptor's bit 4)"));
    }
    let target = match address(addr) {
        Ok(a) => a,
        Err(m) => return usage(m),
    };
    let mut session = match Link::open(target).map_err(LinkError::text) {
        Ok(s) => s,
        Err(message) => return usage(message),
    };
    let shown = |raw: u64| typed.full(raw);
    let result = match (&param.access, raw) {
        (Access::Attribute(path), None) => request(&mut session, 0x0E, path, &[]).map(|r| {
            r.map(|data| match wide {
                true => Ok(hex(&data)),
                false => typed.raw(&data).map(shown),
            })
        }),
        (Access::Attribute(path), Some(bytes)) => {
            request(&mut session, 0x10, path, &bytes).map(|r| r.map(|_| Ok(String::new())))
        }
        (
            &Access::Member {
                instance,
                offset,
                bits,
            },
            raw,
        ) => {
            let path = assembly_path(instance);
            let short = |data: &[u8]| {
                format!(
                    "assembly {instance} has {} bytes, too few for {label} (bits {offset}..{})",
                    data.len(),
                    offset + bits
                )
            };
            let at = offset as u64;
            match request(&mut session, 0x0E, &path, &[]) {
                Ok(Ok(data)) if 8 * data.len() < offset + bits => Err(short(&data)),
                Ok(Ok(data)) => match raw {
                    None if wide => Ok(Ok(Ok(show_wide(&data, at, bits)))),
                    None => Ok(Ok(Ok(shown(get_bits(&data, at, bits as u32))))),
                    Some(bytes) => {
                        let mut data = data;
                        for (i, byte) in bytes.iter().enumerate() {
                            let left = bits.saturating_sub(8 * i).min(8) as u32;
                            put_bits(&mut data, at + 8 * i as u64, left, u64::from(*byte));
                        }
                        request(&mut session, 0x10, &path, &data)
                            .map(|r| r.map(|_| Ok(String::new())))
                    }
                },
                other => other.map(|r| r.map(|_| Ok(String::new()))),
            }
        }
    };
    match (result, value) {
        (Err(message), _) => usage(message),
        (Ok(Err(status)), _) => refused(&label, status),
        (Ok(Ok(_)), Some(_)) => {
            println!("{label} written");
            ExitCode::SUCCESS
        }
        (Ok(Ok(Ok(text))), None) => {
            println!("{label} = {text}");
            ExitCode::SUCCESS
        }
        (Ok(Ok(Err(message))), None) => {
            eprintln!("error: {label}: {message}");
            ExitCode::from(1)
        }
    }
}

/// The path of an assembly's data (attribute 3).
fn assembly_path(instance: u32) -> Vec<u8> {
    LogicalPath::assembly_data(instance)
        .to_vec()
        .unwrap_or_default()
}

/// A member wider than 64 bits as its bytes in hex.
fn show_wide(data: &[u8], at: u64, bits: usize) -> String {
    let bytes: Vec<u8> = (0..bits.div_ceil(8) as u64)
        .map(|i| get_bits(data, at + 8 * i, 8) as u8)
        .collect();
    hex(&bytes)
}
